"""The blind benchmark's cases on the independent bench: conditions, hidden effects, key, oracle.

Every case runs `musclesim.benchmark.benches.sma`'s bench (physics written apart from the
library) with its conditions drawn around the model's values (`conditions`: ambient +-5 K, wire
length, h +-20 %, resistivity +-5 %, lead resistance, clamp contact, emissivity, load, PI gains,
sensor dynamics, gains, offsets, noise and latency) and, by kind:

- ``effect``: one of `LIBRARY`, the library's effects implemented here independently (`hidden`),
  the key its library name;
- ``decoy``: the hidden half of a pair with a look-alike in the library (the ``decoys`` given,
  `musclesim.benchmark.blind.DECOYS`), the key its name;
- ``none``: nothing hidden beyond the conditions, the key None;
- ``outside``: a change the library does not hold (`OUTSIDE`), the key its name.

The bench's ambient is stated to the diagnosis (``[conditions]`` "wire.T_amb", read by a room
thermometer to +-0.2 K) in a share `KNOWN_AMBIENT` of the cases, as a user would measure it.
The crawler's cases (`plan_crawler`, ids ``case-c000``, ...) run
`musclesim.benchmark.benches.crawler`'s bench up the 7.5 deg board for `CRAWLER_DURATION`,
their conditions drawn around the model's (`crawler_conditions`: incline, masses, stiffness and
its hardening, damping, the pressure's effective area, friction, the contact's thresholds and
spreading, pumps, valves, the air's heat exchange, PI gains, sensor tubes, video), with the
crawler's library effects (`CRAWLER_LIBRARY`), decoys (`CRAWLER_DECOYS`), none, and changes
outside the library (`CRAWLER_OUTSIDE`); the model they name is `CRAWLER_SCENARIO` with the
controllers' duties replayed.
"""
from __future__ import annotations

import itertools
import math
from typing import Any

import numpy as np

from musclesim.benchmark.benches import crawler
from musclesim.benchmark.benches.sma import LENGTH, STRESS, Bench, run
from musclesim.cosim import ParamRef, Signal
from musclesim.diagnosis import (HELD_OUT, TRAIN, Failed, Free, Problem, calibration,
                                 find_effect, fit, gap, residuals, simulate_unit,
                                 values_of)

BENCH = "independent"
SCENARIO = "sma-bench-tracking"  # the model the data sets name (its reference, PID, 125 MPa)
INPUTS = [Signal("pid", "y")]
OUTPUTS = [Signal("thermocouple", "T_meas"), Signal("wire", "strain")]
AMBIENT = ParamRef("wire", "T_amb")  # the condition a room thermometer states
DURATION = 120.0  # s
LIBRARY = ("thermocouple lag", "thermocouple bias", "latent heat", "convection change",
           "clamp heat loss")
OUTSIDE = ("clamp slip", "gauge drift", "draught", "two effects")
KNOWN_AMBIENT = 0.5  # share of the cases whose data set states the ambient temperature
SHARES = {"none": 0.15, "outside": 0.15, "decoy": 0.15}  # the rest: effect (as in `blind`)


def _log_uniform(rng: np.random.Generator, lo: float, hi: float) -> float:
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def conditions(rng: np.random.Generator) -> dict[str, Any]:
    """The bench's conditions drawn from `rng` around the model's values: {Bench field:
    value}."""
    u = rng.uniform
    return {
        "ambient": 293.15 + u(-5, 5), "clamp_offset": u(-0.5, 0.5),
        "length": LENGTH * (1 + u(-0.015, 0.015)),  # measured to about 1 mm
        "h": 100.0 * u(0.8, 1.2), "resistivity_factor": u(0.95, 1.05),
        "lead_resistance": u(0.0, 0.1),  # Ohm: leads and contacts (2 % of the wire's 4.6 Ohm)
        # insulating terminals: a weak path into the clamps, a tenth of the wire's own fin
        "contact": _log_uniform(rng, 5e-6, 3e-5), "emissivity": u(0.05, 0.3),
        "stress": STRESS * (1 + u(-0.02, 0.02)), "kp": 0.07 * u(0.8, 1.2),
        "ki": 0.1 * u(0.8, 1.2), "tc_position": u(0.4, 0.6),
        # a fast junction on the wire: both stages under a sample
        "tc_tau_sheath": u(0.01, 0.03), "tc_tau_junction": u(0.003, 0.01),
        "tc_gain": 1 + u(-0.005, 0.005), "tc_offset": u(-0.3, 0.3),
        "tc_noise": u(0.05, 0.12), "tc_quantum": 0.05,
        "gauge_tau": u(0.003, 0.015), "gauge_gain": 1 + u(-0.01, 0.01),
        "gauge_offset": u(-5e-5, 5e-5), "gauge_noise": u(1.5e-5, 3e-5), "gauge_quantum": 1e-5,
        "latency": int(rng.integers(0, 3)), "seed": int(rng.integers(0, 2**31)),
    }


def hidden(effect: str, rng: np.random.Generator, duration: float) -> dict[str, Any]:
    """{Bench field: value} of `effect` (a `LIBRARY` or `OUTSIDE` name) at a magnitude drawn
    from `rng` (times within the run's `duration` [s]), on top of a case's conditions; "two
    effects" also gives "pair"."""
    u = rng.uniform
    if effect == "thermocouple lag":  # a thick coat: a slow sheath, a slower junction
        return {"tc_tau_sheath": u(0.1, 0.5), "tc_tau_junction": u(0.02, 0.08)}
    if effect == "thermocouple bias":  # the cold-junction compensation off
        return {"tc_bias": float(rng.choice([-1, 1]) * u(1.5, 5.0))}
    if effect == "latent heat":  # §sma-material: 12-24 kJ/kg, heating and cooling differ
        heat = u(12e3, 24e3)
        return {"latent_heating": heat, "latent_cooling": heat * u(0.8, 1.0)}
    if effect == "convection change":  # natural convection grows with the excess temperature
        return {"convection": "natural", "coat_diameter": _log_uniform(rng, 127e-6, 1e-3)}
    if effect == "clamp heat loss":  # metal clamps, good contact: the wire's ends cool
        return {"contact": _log_uniform(rng, 1e-3, 1e-2)}
    if effect == "clamp slip":  # the wire slides out of its clamp a few times
        times = np.sort(u(0.1, 0.95, size=int(rng.integers(2, 5)))) * duration
        return {"slips": [[float(t), float(u(2e-4, 8e-4))] for t in times]}
    if effect == "gauge drift":  # the strain gauge's offset drifts over the run (2.5-5 % of
        # the strain's range; a gain error would be the calibrated strain scale)
        return {"gauge_drift": float(rng.choice([-1, 1])) * u(1e-3, 2e-3)}
    if effect == "draught":  # a fan or an open door part-way through: h steps up
        return {"draught_time": u(0.25, 0.6) * duration, "draught_factor": u(1.3, 2.0)}
    if effect == "two effects":
        return _pair(LIBRARY, hidden, rng, duration)
    raise KeyError(f"no hidden effect {effect!r}")


def _pair(library: tuple[str, ...], draw: Any, rng: np.random.Generator,
          duration: float) -> dict[str, Any]:
    """Two distinct effects of `library`, each drawn by `draw`, with their names as "pair"."""
    pair = [str(e) for e in rng.choice(library, size=2, replace=False)]
    out = {"pair": pair}
    for e in pair:
        out.update(draw(e, rng, duration))
    return out


def _kinds(count: int, rng: np.random.Generator) -> list[str]:
    """`count` case kinds in `SHARES` (the rest effects), shuffled."""
    n = {k: max(1, round(share * count)) for k, share in SHARES.items()}
    kinds = (["none"] * n["none"] + ["outside"] * n["outside"] + ["decoy"] * n["decoy"]
             + ["effect"] * (count - sum(n.values())))[:count]
    rng.shuffle(kinds)
    return kinds


def _hide(case: dict[str, Any], pool: Any, draw: Any,
          rng: np.random.Generator) -> dict[str, Any]:
    """Draw `case`'s hidden effect from `pool` with `draw` (nothing when `pool` is None); a pair's
    names go to ``case["pair"]``."""
    if pool is not None:
        effect = str(pool[rng.integers(len(pool))])
        values = draw(effect, rng, case["duration"])
        case.update(effect=effect, values=values)
        if "pair" in values:
            case["pair"] = values.pop("pair")
    return case


def plan(count: int, seed: int, decoys: list[tuple[str, str]],
         duration: float = DURATION) -> list[dict[str, Any]]:
    """The hidden truths of `count` cases on the independent bench, drawn from `seed`, each run
    for `duration` [s]: a list of dicts (kind, effect (the key), values (the hidden Bench
    fields), conditions, ambient_known, ...). `decoys` are (hidden, look-alike) pairs of library
    names."""
    rng = np.random.default_rng([seed, 13])  # a stream apart from the own bench's plan
    cases = []
    for i, kind in enumerate(_kinds(count, rng)):
        base = conditions(rng)
        case = {"case": f"case-{i:03d}", "kind": kind, "bench": BENCH, "effect": None,
                "values": {}, "conditions": base, "duration": duration,
                "ambient_known": bool(rng.random() < KNOWN_AMBIENT),
                "ambient_read": base["ambient"] + float(rng.uniform(-0.2, 0.2))}
        pool = {"effect": LIBRARY, "decoy": [d[0] for d in decoys], "outside": OUTSIDE}.get(kind)
        cases.append(_hide(case, pool, hidden, rng))
    return cases


CRAWLER_SCENARIO = "crawler-gait-incline"
CRAWLER_INPUTS = [Signal(a, "duty") for a in ("act1", "actc", "act2")]
CRAWLER_OUTPUTS = [*(Signal(s, "p_meas") for s in ("sensor1", "sensorc", "sensor2")),
                   Signal("body", "flange_a.s"), Signal("body", "flange_b.s")]
CRAWLER_DURATION = 12.0  # s: the first stride and three more, as the own bench's crawler cases
CRAWLER_LIBRARY = ("valve delay", "supply-pressure drop", "chamber leakage",
                   "pressure-dependent stiffness", "actuator bending on an incline",
                   "friction decay")
# (hidden, look-alike): both lower the pressure an actuator holds; both lower the anchors' grip
CRAWLER_DECOYS = [("supply-pressure drop", "chamber leakage"),
                  ("friction decay", "actuator bending on an incline")]
CRAWLER_OUTSIDE = ("sensor tube", "surface change", "camera scale", "two effects")


def crawler_conditions(rng: np.random.Generator) -> dict[str, Any]:
    """The crawler bench's conditions drawn from `rng` around the model's values: {Crawler
    field: value}."""
    u = rng.uniform
    back = u(6e3, 8.5e3)  # Pa: the front actuator needs more to grip (§gait)
    return {
        "theta": math.radians(7.5 + u(-0.5, 0.5)), "m1": 0.2 * u(0.95, 1.05),
        "m2": 0.2 * u(0.95, 1.05), "k": 200.0 * u(0.85, 1.15),
        "k3": u(0.0, 0.15) / 0.04 ** 2,  # up to 15 % stiffer at 4 cm
        "c": 1.3 * u(0.7, 1.4), "area": crawler.S_A * u(0.85, 1.0), "bulge": u(0.0, 2e-6),
        "mu_s_high": u(0.85, 1.05), "mu_s_low": u(0.12, 0.145), "mu_ratio": u(0.7, 0.8),
        "bristle": _log_uniform(rng, 1e4, 4e4), "p_contact_back": back,
        "p_contact_front": u(back, min(back + 1.5e3, 9.5e3)), "contact_width": u(400.0, 1200.0),
        "tau_contact": u(0.02, 0.1), "dv_contact": u(2e-6, 4e-6),
        "p_supply": 40e3 * u(0.9, 1.1), "p_exhaust": -20e3 * u(0.9, 1.1),
        "valve_area": crawler.VALVE_AREA * u(0.8, 1.25), "tau_valve": u(1e-3, 3e-3),
        "pwm_phase": u(0.0, 1.0), "tau_wall": u(0.5, 2.0),
        "kp_central": 1.386e-3 * u(0.8, 1.2), "ki_central": 6.93e-3 * u(0.8, 1.2),
        "kp_extremal": 5.9e-5 * u(0.8, 1.2), "ki_extremal": 2.95e-4 * u(0.8, 1.2),
        "ref_factor": u(0.95, 1.05), "sensor_tau": u(5e-4, 2e-3),
        "sensor_gain": 1 + u(-0.01, 0.01), "sensor_noise": u(20.0, 40.0), "sensor_quantum": 10.0,
        "video_scale": 1 + u(-0.005, 0.005), "video_noise": u(1e-4, 3e-4),
        "video_quantum": 1e-4, "video_delay": u(0.0, 0.03), "seed": int(rng.integers(0, 2**31)),
    }


def crawler_hidden(effect: str, rng: np.random.Generator, duration: float) -> dict[str, Any]:
    """{Crawler field: value} of `effect` (a `CRAWLER_LIBRARY` or `CRAWLER_OUTSIDE` name) at a
    magnitude drawn from `rng` (times within the run's `duration` [s]); "two effects" also gives
    "pair"."""
    u = rng.uniform
    if effect == "valve delay":  # §valves: a few ms each way
        return {"open_delay": u(0.005, 0.015), "close_delay": u(0.005, 0.015)}
    if effect == "supply-pressure drop":  # a small pump: sags 25-50 % under a full valve's draw
        return {"pump_reserve": u(1.0, 3.0)}
    if effect == "chamber leakage":  # an extremal chamber's leak time 0.5-3 s
        return {"leak": 8.4e-11 / u(0.5, 3.0)}
    if effect == "pressure-dependent stiffness":
        return {"stiffening": float(rng.choice([-1, 1])) * u(0.15, 0.35)}
    if effect == "actuator bending on an incline":
        return {"bending": u(0.2, 0.45)}
    if effect == "friction decay":  # contamination that saturates: 7-23 % lost by 12 s
        return {"decay": u(0.15, 0.3), "decay_time": u(8.0, 20.0)}
    if effect == "sensor tube":  # long lines to the pressure sensors
        return {"sensor_tau": u(0.03, 0.08)}
    if effect == "surface change":  # onto a slicker board part-way (§gait's transitions)
        return {"surface_change": [u(0.3, 0.8) * duration, u(0.6, 0.8)]}
    if effect == "camera scale":  # the camera's distance misjudged
        return {"video_scale": 1 + float(rng.choice([-1, 1])) * u(0.04, 0.08)}
    if effect == "two effects":
        return _pair(CRAWLER_LIBRARY, crawler_hidden, rng, duration)
    raise KeyError(f"no hidden crawler effect {effect!r}")


def plan_crawler(count: int, seed: int,
                 duration: float = CRAWLER_DURATION) -> list[dict[str, Any]]:
    """The hidden truths of `count` crawler cases on the independent bench, drawn from `seed`,
    each run for `duration` [s], as `plan` (kinds in the same shares, ids ``case-c000``, ...;
    bench "independent-crawler")."""
    rng = np.random.default_rng([seed, 17])  # a stream apart from the SMA cases'
    cases = []
    for i, kind in enumerate(_kinds(count, rng)):
        case = {"case": f"case-c{i:03d}", "kind": kind, "bench": "independent-crawler",
                "effect": None, "values": {}, "conditions": crawler_conditions(rng),
                "duration": duration}
        pool = {"effect": CRAWLER_LIBRARY, "decoy": [d[0] for d in CRAWLER_DECOYS],
                "outside": CRAWLER_OUTSIDE}.get(kind)
        cases.append(_hide(case, pool, crawler_hidden, rng))
    return cases


def bench_of(case: dict[str, Any]) -> Bench:
    """The `Bench` of planned case `case` (conditions, then the hidden values over them)."""
    fields = {**case["conditions"], **case["values"]}
    if "slips" in fields:
        fields["slips"] = tuple(tuple(s) for s in fields["slips"])
    return Bench(**fields)


def record(case: dict[str, Any]) -> tuple[np.ndarray, dict[Signal, np.ndarray],
                                          dict[ParamRef, float]]:
    """Run `case`'s bench: (time, {column: values}, {condition: value} for the manifest)."""
    if case["bench"] == "independent-crawler":
        fields = {**case["conditions"], **case["values"]}
        if fields.get("surface_change") is not None:
            fields["surface_change"] = tuple(fields["surface_change"])
        out = crawler.run(crawler.Crawler(**fields), case["duration"])
        cols = {c: out["duty"][:, i] for i, c in enumerate(CRAWLER_INPUTS)}
        cols.update({c: out["p_meas"][:, i] for i, c in enumerate(CRAWLER_OUTPUTS[:3])})
        cols.update({c: out["x"][:, i] for i, c in enumerate(CRAWLER_OUTPUTS[3:])})
        return out["time"], cols, {}
    out = run(bench_of(case), case["duration"])
    cols = dict(zip(INPUTS + OUTPUTS, (out["u"], out["T_meas"], out["strain"])))
    stated = {AMBIENT: round(case["ambient_read"], 2)} if case["ambient_known"] else {}
    return out["time"], cols, stated


def oracle(args: tuple[dict[str, Any], Any, dict[str, Any], Any]) -> dict[str, float | None]:
    """Held-out gaps of the model with every measured signal replayed (the report's section 5):
    nominal and with our calibration and selected effects (from the report), and the oracle's:
    the key's library effect fitted on the training part together with the calibration
    parameters, from the report's calibrated values (the bench's truth has no values in the
    library's terms, and its conditions differ from the model's). The oracle is None for a case
    without a library key. (No oracle judges identifiability by the diagnosis's own rules: that
    would measure the rules, not the data.) `args`: (case, its data set, its report.json
    document, the FMU folder), as `musclesim.benchmark.blind.run` maps it."""
    case, ds, report, fmu_dir = args
    ours = report.get("shrinkage", {}).get("all")
    keyed = case["kind"] in ("effect", "decoy")
    if ours is not None and not keyed:
        return {"before": ours["before"], "oracle": None, "ours": ours["after"]}
    problem = Problem(ds, fmu_dir)
    unit = problem.replayed()
    if ours is None:  # no report section 5: the case failed, our model is the nominal one
        try:
            before = gap(unit, residuals(unit, simulate_unit(unit, {}, fmu_dir)), HELD_OUT)
        except Failed:
            before = math.inf
        ours = {"before": before, "after": before}
    best = None
    if keyed:
        effect = find_effect(case["effect"])
        insts = tuple(n for n, c in problem.components.items() if c == effect.component)
        free = [Free(insts, p.name, p.lower, p.upper, p.off) for p in effect.parameters]
        calib = calibration(problem, unit)
        table = report.get("calibration", {}).get("parameters", {})
        x_cal = [table.get(fr.key, {}).get("value", fr.start) for fr in calib]
        start = _scan(unit, free, fmu_dir, values_of(calib, x_cal))
        f = fit(unit, free + calib, fmu_dir, x0=start + x_cal, scan=0)
        best = f.heldout_gap
    return {"before": ours["before"], "oracle": best, "ours": ours["after"]}


def _scan(unit: Any, free: list[Free], fmu_dir: Any, fixed: dict) -> list[float]:
    """The best training point of a fine grid over `free`'s box (21 points for one parameter, 7
    per parameter else), the calibration held at `fixed`: the oracle's start. The fit's own
    coarse scan can miss a narrow optimum, and an oracle should not."""
    axes = [np.linspace(f.lower, f.upper, 21 if len(free) == 1 else 7) for f in free]
    best, start = math.inf, [f.start for f in free]
    for x in itertools.product(*axes):
        try:
            res = residuals(unit, simulate_unit(unit, {**fixed, **values_of(free, x)}, fmu_dir,
                                           part=TRAIN))
        except Failed:
            continue
        cost = gap(unit, res, TRAIN)
        if cost < best:
            best, start = cost, list(x)
    return start
