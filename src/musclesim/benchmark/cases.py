"""The own bench's cases of the blind benchmark: the benches, the hidden effects' magnitudes,
decoys and changes outside the library, and the plan drawing each case's hidden truth from a seed.

What the kinds of case are and how they are scored: `musclesim.benchmark.blind`.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from musclesim.cosim import ParamRef, Signal


def _signals(*names: str) -> list[Signal]:
    return [Signal.parse(n) for n in names]


# the benches: scenario, replayed inputs, observed outputs (Signals), the effects that can
# hide in them
BENCHES: dict[str, tuple[str, list[Signal], list[Signal], list[str]]] = {
    "tracking": ("sma-bench-tracking", _signals("reference.y"),
                 _signals("pid.y", "thermocouple.T_meas", "wire.strain"),
                 ["thermocouple lag", "thermocouple bias", "latent heat", "convection change",
                  "training drift"]),
    "stress": ("sma-bench-stress", _signals("wire.u", "wire.flange.f"),
               _signals("thermocouple.T_meas", "wire.strain"),
               ["stress dependence ignored", "thermocouple lag", "latent heat"]),
    "magnet": ("sma-bench-magnet", _signals("wire.u", "magnet.duty"),
               _signals("loadcell.f_meas", "thermocouple.T_meas", "laser.s_meas"),
               ["electromagnet force nonlinearity", "load-cell lag"]),
    # §capstan-multiplier's 150 g weight lifted by fast heating pulses, the laser on the weight
    "weight": ("sma-dead-weight", _signals("wire.u"), _signals("laser.s_meas"), ["load inertia"]),
    # the pneumatic crawler climbing 7.5 deg (where bending shows): the controllers' logged
    # duties replayed, the pressure sensors and the blocks' positions from video observed
    "crawler": ("crawler-gait-incline", _signals("act1.duty", "actc.duty", "act2.duty"),
                _signals("sensor1.p_meas", "sensorc.p_meas", "sensor2.p_meas", "body.flange_a.s",
                         "body.flange_b.s"),
                ["valve delay", "supply-pressure drop", "chamber leakage",
                 "pressure-dependent stiffness", "actuator bending on an incline",
                 "friction decay"]),
    # §multiplier-experiments's capstan multiplier under the 150 g weight, bang-bang heated: the
    # relay's voltage replayed, the middle segment's thermocouple and the laser on the weight
    # observed (only in the extra multiplier cases, `plan_multiplier`)
    "multiplier": ("sma-bench-multiplier", _signals("mult.u"),
                   _signals("thermocouple.T_meas", "laser.s_meas"),
                   ["capstan friction", "composition difference", "load inertia"]),
}
STOP_TIME = {"crawler": 12.0,  # s: the first stride and three more (the scenario runs 30 s)
             "weight": 6.0,  # s: two lifts, the second in the held-out part
             "multiplier": 6.0}  # s: the first lift and about ten relay cycles
LOAD_SHARE = 0.25  # of the effect cases move to a load bench, magnet or weight, with one of its
                   # effects (drawn from their own stream)
LOAD_BENCHES = ("magnet", "weight")
CRAWLER_SHARE = 0.25  # ... and, drawn from a third stream, to the crawler bench
# Not in the tracking bench's pool, so without a magnitude here: clamp heat loss (cold ends), the
# look-alike of the decoy pair below; the independent bench hides it
# (`musclesim.benchmark.plan`). hidden magnitudes: (instance, parameter, low, high), drawn
# uniformly (§sma-wire, §drift, §sma-material)
MAGNITUDES: dict[str, list[tuple[str | tuple[str, ...], str, float, float]]] = {
    "thermocouple lag": [("thermocouple", "tau", 0.1, 0.6)],
    "thermocouple bias": [("thermocouple", "bias", 1.5, 5.0)],  # sign drawn too
    "latent heat": [("wire", "latent_heat", 12e3, 24e3)],
    "convection change": [("wire", "h_exponent", 0.06, 0.15)],
    "training drift": [("wire", "drift_amplitude", 0.1, 0.2), ("wire", "drift_shift", 5.0, 10.0)],
    "stress dependence ignored": [("wire", "stress_blend", 0.5, 1.0)],
    "electromagnet force nonlinearity": [("magnet", "nonlinearity", 0.2, 0.5)],
    # a heavily filtered cell: lags of 1-2 samples (20-40 ms) are latency at this data rate
    "load-cell lag": [("loadcell", "tau", 0.1, 0.3)],
    "load inertia": [("weight", "inertia", 0.3, 1.0)],
    # one draw for several instances: the three valves, pumps and chambers are alike
    "valve delay": [(("act1", "actc", "act2"), "t_open_delay", 0.005, 0.02),
                    (("act1", "actc", "act2"), "t_close_delay", 0.005, 0.02)],
    "supply-pressure drop": [(("act1", "actc", "act2"), "supply_drop", 0.2, 0.5)],
    "chamber leakage": [(("act1", "actc", "act2"), "C_leak", 2e-11, 5e-11)],
    "pressure-dependent stiffness": [("body", "k_slope", 0.015, 0.04)],
    "actuator bending on an incline": [(("friction1", "friction2"), "bending", 1.5, 4.0)],
    "friction decay": [(("friction1", "friction2"), "mu_decay", 0.01, 0.02)],
    # a groove worn or dirty: 2-4 times §capstan-multiplier's 0.0237 +/- 0.0037
    "capstan friction": [("mult", "mu_f", 0.05, 0.1)],
    # transformation temperatures of NiTi move ~10 K per 0.1 at.% Ni; a few K between batches
    "composition difference": [("mult", "composition_shift", 3.0, 8.0)],  # sign drawn too
}
SIGNED = {"thermocouple bias", "training drift", "electromagnet force nonlinearity",
          "pressure-dependent stiffness", "composition difference"}
MULTIPLIER_NONE_SHARE = 0.2  # of the multiplier cases hide nothing (false alarms there)
# (hidden effect, its decoy in the library): both act at high temperatures, or both make the
# measured temperature trail the wire's model
DECOYS = [("convection change", "clamp heat loss"), ("thermocouple lag", "latent heat"),
          ("latent heat", "thermocouple lag")]
# Changes neither in the effect library nor in the calibration (a warmer room or a strain gauge's
# gain error are: the ambient and the strain scale are calibrated), applied to the recorded
# strain: the wire slips in its clamp 2-4 times (the reading steps down by this much each time),
# or the gauge's offset drifts linearly by this much over the run (2.5-5 % of the strain's
# range, beyond what its noise hides)
OUTSIDE = {
    "clamp slip": (3e-4, 8e-4),
    "gauge drift": (1e-3, 2e-3),
}


def plan(count: int, seed: int) -> list[dict[str, Any]]:
    """The hidden truths of `count` cases drawn from `seed`: a list of dicts (kind, bench,
    effect, values ({"instance.parameter": value}, as key.json has them), latency, ...)."""
    rng = np.random.default_rng(seed)
    # their own streams, so that moving a case to another bench changes no other case
    load_rng = np.random.default_rng([seed, 7])
    crawler_rng = np.random.default_rng([seed, 11])
    n_none = max(1, round(0.15 * count))
    n_out = max(1, round(0.15 * count))
    n_decoy = max(1, round(0.15 * count))
    kinds = (["none"] * n_none + ["outside"] * n_out + ["decoy"] * n_decoy
             + ["effect"] * (count - n_none - n_out - n_decoy))[:count]
    rng.shuffle(kinds)
    cases = []
    for i, kind in enumerate(kinds):
        bench = "stress" if kind == "effect" and rng.random() < 0.25 else "tracking"
        case: dict[str, Any] = {
            "case": f"case-{i:03d}", "kind": kind, "bench": bench, "effect": None,
            "values": {}, "latency_samples": int(rng.integers(0, 2)), "seed": int(
                rng.integers(0, 2**31))}
        if kind in ("effect", "decoy"):
            pool = BENCHES[bench][3] if kind == "effect" else [d[0] for d in DECOYS]
            effect = pool[rng.integers(len(pool))]
            case["effect"] = effect
            case["values"] = draw_values(effect, rng)
        if kind == "effect":  # moved to a load bench, then (the later draw wins) the crawler
            for benches, share, stream in ((LOAD_BENCHES, LOAD_SHARE, load_rng),
                                           (("crawler",), CRAWLER_SHARE, crawler_rng)):
                if stream.random() < share:
                    moves = [(b, e) for b in benches for e in BENCHES[b][3]]
                    bench, effect = moves[stream.integers(len(moves))]
                    case.update(bench=bench, effect=effect, values=draw_values(effect, stream))
        elif kind == "outside":
            name = list(OUTSIDE)[rng.integers(len(OUTSIDE))]
            case["effect"] = name
            if name == "clamp slip":  # (fraction of the run, strain lost) per slip
                case["slips"] = [[float(rng.uniform(0.1, 0.95)), float(rng.uniform(
                    *OUTSIDE[name]))] for _ in range(int(rng.integers(2, 5)))]
            else:
                case["strain_drift"] = float(rng.choice([-1, 1]) * rng.uniform(*OUTSIDE[name]))
        cases.append(case)
    return cases


def plan_multiplier(count: int, seed: int) -> list[dict[str, Any]]:
    """`count` extra cases on the multiplier bench, from a stream of `seed` of their own (so the
    cases of `plan` stay the same): a library effect of the bench at a random magnitude, or (a
    share `MULTIPLIER_NONE_SHARE`) none; ids ``case-m000``, ...

    Examples
    --------
    >>> [c["bench"] for c in plan_multiplier(2, 1)]
    ['multiplier', 'multiplier']
    """
    rng = np.random.default_rng([seed, 13])
    effects_ = BENCHES["multiplier"][3]
    cases = []
    for i in range(count):
        kind = "none" if rng.random() < MULTIPLIER_NONE_SHARE else "effect"
        case: dict[str, Any] = {
            "case": f"case-m{i:03d}", "kind": kind, "bench": "multiplier", "effect": None,
            "values": {}, "latency_samples": int(rng.integers(0, 2)),
            "seed": int(rng.integers(0, 2**31))}
        if kind == "effect":
            effect = effects_[rng.integers(len(effects_))]
            case.update(effect=effect, values=draw_values(effect, rng))
        cases.append(case)
    return cases


def draw_values(effect: str, rng: np.random.Generator) -> dict[str, float]:
    """{"instance.parameter": value} of `effect` at a random magnitude (and sign if signed)."""
    sign = -1.0 if effect in SIGNED and rng.random() < 0.5 else 1.0
    values = {}
    for inst, par, lo, hi in MAGNITUDES[effect]:
        v = float(sign * rng.uniform(lo, hi))
        values.update({str(ParamRef(i, par)): v  # key.json's form
                       for i in ((inst,) if isinstance(inst, str) else inst)})
    return values
