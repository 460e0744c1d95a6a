"""A family of SMA bench forms: the cases the diagnosis's sets are calibrated and scored on.

A real bench differs from the model in form, not only in values; a set calibrated on benches of
one form says nothing of another. Each case here draws every subsystem of the independent SMA
bench (`musclesim.benchmark.benches.sma`, physics written apart from the library) from several
forms (`FORMS`, each with its source), its conditions and noise around the model's values
(`musclesim.benchmark.plan.conditions`), and one hidden cause: structure is randomised as well
as parameters, as domain randomisation does (Tobin et al., "Domain randomization for transferring
deep neural networks from simulation to the real world", IROS 2017).

The causes (`CAUSES`) are the labels the diagnosis's sets are calibrated per: ``calibration
only`` (nothing hidden), each effect of the SMA wire's library (`LIBRARY`; those with a
look-alike in the library are the decoys), ``two effects`` (a pair of them) and ``outside the
library`` (`OUTSIDE`: a change the library does not hold). They come in equal shares. A form is
the bench's ordinary structure; a cause is a change of the size the library's effect names: the
natural convection of a bare wire changes h by about +-10 % over the run (a form), the cause
``convection change`` makes h grow as (excess / 50 K)^n with n of 0.25-0.6 on top of it. A cause
that needs a structure gets it (cold ends need conduction along the wire: ``clamp heat loss``
draws the 1-D wire).

Our own model is one member (`MODEL_SHARE` of the cases, drawn from a stream of their own so
that the other cases stay as drawn): the library's FMUs on the tracking scenario with the cause
hidden in their parameters (`MODEL_MAGNITUDES`, sized as the bench's causes), the controller in
the loop and the reference replayed, the sensors' noise and latency of the own blind bench
(`musclesim.benchmark.recording`); its forms are all ``model``, and it has no draught.

The family's version (`VERSION`) changes whenever a form, a draw or a cause changes; a
calibration records the version it was computed on. `SMA` is this family as the calibration
(`musclesim.benchmark.calibrate`) sees it: a `Family`, the type every family of bench forms
(also `musclesim.benchmark.family_crawler`) is described by.

>>> cases = plan(9, 1)
>>> sorted({c["cause"] for c in cases}) == sorted(CAUSES)
True
"""
from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from musclesim.benchmark import cases as own
from musclesim.benchmark import plan as independent
from musclesim.benchmark.benches.sma import Bench, run
from musclesim.benchmark.recording import bench_scenario
from musclesim.benchmark.recording import record as record_own
from musclesim.diagnosis import CALIBRATION_ONLY, OUTSIDE_LIBRARY, TWO_EFFECTS

VERSION = 2
BENCH = "family"
MODEL_SHARE = 0.125
MODEL = "model"  # the form of every subsystem of a case on our own model
# the causes on our own model: (instance, parameter, low, high), the sign drawn for those in
# `own.SIGNED`; sized as the bench's (`hidden`): a drift loses 3-8 % of the strain
MODEL_MAGNITUDES: dict[str, list[tuple[str, str, float, float]]] = {
    "thermocouple lag": [("thermocouple", "tau", 0.1, 0.6)],
    "thermocouple bias": [("thermocouple", "bias", 1.5, 5.0)],
    "latent heat": [("wire", "latent_heat", 12e3, 24e3)],
    "convection change": [("wire", "h_exponent", 0.25, 0.6)],
    "clamp heat loss": [("wire", "end_cooling", 0.3, 0.9)],
    "training drift": [("wire", "drift_amplitude", -0.08, -0.03), ("wire", "drift_shift", 2.0, 6.0)],
}
DURATION = independent.DURATION
# subsystem -> form -> its source
FORMS: dict[str, dict[str, str]] = {
    "hysteresis": {
        "cosine": "phase kinetics, two grain populations, cosine shape (Liang & Rogers, J. "
                  "Intell. Mater. Syst. Struct. 1, 1990)",
        "exponential": "phase kinetics, two grain populations, exponential shape (Tanaka, Res "
                       "Mechanica 18, 1986)",
        "relay": "a grid of 2000 relays, a discrete Preisach model (Mayergoyz, Mathematical "
                 "Models of Hysteresis, 1991), thresholds drawn from the same bands"},
    "thermal": {
        "conduction": "1-D heat equation along the wire, 18 finite volumes, clamps through a "
                      "contact conductance (Incropera, Fundamentals of Heat and Mass Transfer, "
                      "ch. 3, fins)",
        "lumped": "one volume, the model's own lumped balance (§thermal-model)"},
    "radiation": {
        "none": "no radiation",
        "grey": "grey-body radiation to the room, emissivity 0.05-0.3 (Stefan-Boltzmann)"},
    "convection": {
        "constant": "h constant, the model's (§convection)",
        "natural": "natural convection of a horizontal cylinder (Churchill & Chu, Int. J. Heat "
                   "Mass Transfer 18, 1975), scaled to h at 50 K",
        "gusts": "h fluctuating by 3-10 % (an Ornstein-Uhlenbeck process, 2-10 s), a lab with "
                 "moving air"},
    "thermocouple": {
        "two-pole": "sheath and junction, two first-order stages",
        "first-order": "one first-order stage (§sensors' model)",
        "ladder": "a three-stage RC ladder, the stages loading each other (a junction in a "
                  "coat, Doebelin, Measurement Systems, ch. 8)"},
    "resistivity": {
        "linear": "linear in the martensite fraction (§sma-material)",
        "tempco": "times 1 + a (T - 20 C), a of 2e-4-8e-4 1/K (NiTi's, data sheets)",
        "parallel": "the phases in parallel, 1/rho = xi/rho_M + (1 - xi)/rho_A"},
}
LIBRARY = ("thermocouple lag", "thermocouple bias", "latent heat", "convection change",
           "clamp heat loss", "training drift")
OUTSIDE = ("clamp slip", "gauge drift", "draught")
CAUSES = (CALIBRATION_ONLY, *LIBRARY, TWO_EFFECTS, OUTSIDE_LIBRARY)
QUANTA = (0.05, 0.1, 0.25)  # K: the thermocouple's resolution, by the amplifier


SCENARIO = independent.SCENARIO
SIGNALS = ["thermocouple.T_meas", "wire.strain"]  # the family's observed signals
# the SMA wire's operating regimes (`musclesim.diagnosis.REGIMES`) but "all", their reference
REGIMES = ["changing", "heating", "cooling", "hot", "transformation", "late"]


@dataclass(frozen=True)
class Family:
    """A family of bench forms as its calibration sees it: the blind benchmark's name for it
    (`bench`, also its folder and its key in scores.json), its `version`, the `scenario` its
    data sets name (the calibration is shipped under that name), its `forms` (subsystem ->
    form -> source), the single effects of the library it hides (`library`) and those outside
    it (`outside`), the observed `signals` and operating `regimes` the sets' features read,
    the modules besides the shared ones whose source makes its cases (`sources`, relative to
    `musclesim.benchmark`; the calibration's fingerprint), and how its cases are drawn
    (`plan`: count, seed, duration) and recorded (`record`: (case, scenarios folder, FMU
    folder) -> (time, columns, stated conditions)) for `duration` seconds by default."""

    bench: str
    version: int
    scenario: str
    forms: dict[str, dict[str, str]]
    library: tuple[str, ...]
    outside: tuple[str, ...]
    signals: list[str]
    regimes: list[str]
    sources: tuple[str, ...]
    plan: Callable[..., list[dict[str, Any]]]
    record: Callable[[tuple[dict[str, Any], Any, Any]], tuple[np.ndarray, dict, dict]]
    duration: float

    @property
    def causes(self) -> tuple[str, ...]:
        """The labels the sets are calibrated per, in order: calibration only, each single
        effect, two effects, outside the library."""
        return (CALIBRATION_ONLY, *self.library, TWO_EFFECTS, OUTSIDE_LIBRARY)


def forms(rng: np.random.Generator, table: dict[str, dict[str, str]] | None = None
          ) -> dict[str, str]:
    """One form per subsystem of `table` (default `FORMS`), drawn uniformly from `rng`."""
    return {sub: str(rng.choice(sorted(options))) for sub, options in (table or FORMS).items()}


def in_turn(causes: Sequence[str], count: int, rng: np.random.Generator) -> list[str]:
    """`count` labels of `causes` in equal shares (in turn), shuffled by `rng`."""
    out = [causes[i % len(causes)] for i in range(count)]
    rng.shuffle(out)
    return out


def hide(case: dict[str, Any], library: Sequence[str], outside: Sequence[str],
         hidden: Callable[[str, np.random.Generator, float], dict[str, Any]],
         rng: np.random.Generator) -> None:
    """Give family `case` the hidden change of its ``cause``, drawn from `rng` (in place):
    ``kind``, and ``effect`` or ``pair`` with their ``values`` (`hidden`(effect, rng,
    duration) of an effect of `library` or `outside`)."""
    cause, duration = case["cause"], case["duration"]
    if cause == CALIBRATION_ONLY:
        case["kind"] = "none"
    elif cause == TWO_EFFECTS:
        pair = [str(e) for e in rng.choice(library, size=2, replace=False)]
        values: dict[str, Any] = {}
        for e in pair:
            values.update(hidden(e, rng, duration))
        case.update(kind="pair", pair=pair, values=values)
    else:
        pool = outside if cause == OUTSIDE_LIBRARY else (cause,)
        effect = str(pool[int(rng.integers(len(pool)))])
        case.update(kind="outside" if cause == OUTSIDE_LIBRARY else "effect", effect=effect,
                    values=hidden(effect, rng, duration))


def _form_fields(form: dict[str, str], rng: np.random.Generator) -> dict[str, Any]:
    """The `Bench` fields of `form` with the parameters its forms draw from `rng`."""
    u = rng.uniform
    fields: dict[str, Any] = {
        "hysteresis": form["hysteresis"], "thermal": form["thermal"],
        "band_shift": u(-3.0, 3.0), "band_scale": u(0.9, 1.1),
        "convection": form["convection"], "tc_form": form["thermocouple"],
        "resistivity_law": form["resistivity"], "tc_quantum": float(rng.choice(QUANTA))}
    if form["radiation"] == "none":
        fields["emissivity"] = 0.0
    if form["convection"] == "gusts":
        fields.update(gust_level=u(0.03, 0.1), gust_time=u(2.0, 10.0))
    if form["resistivity"] == "tempco":
        fields["tempco"] = u(2e-4, 8e-4)
    return fields


def hidden(cause: str, rng: np.random.Generator, duration: float) -> dict[str, Any]:
    """{Bench field: value} of a `LIBRARY` or `OUTSIDE` cause at a magnitude drawn from `rng`."""
    u = rng.uniform
    if cause == "convection change":
        return {"h_exponent": u(0.25, 0.6)}
    if cause == "training drift":  # §drift: the loop moves over the first cycles, then settles
        return {"drift_shift": float(rng.choice([-1, 1])) * u(2.0, 6.0),
                "drift_amplitude": u(0.03, 0.08), "drift_time": u(15.0, 40.0)}
    return independent.hidden(cause, rng, duration)


def plan(count: int, seed: int, duration: float = DURATION) -> list[dict[str, Any]]:
    """`count` family cases drawn from `seed`, the causes of `CAUSES` in equal shares (in turn,
    then shuffled): dicts as `musclesim.benchmark.plan.plan` makes them, with ``cause`` (the
    label), ``forms`` and ``form_values`` (the forms' fields) besides."""
    rng = np.random.default_rng([seed, 19])  # a stream apart from the other plans'
    model_rng = np.random.default_rng([seed, 23])  # which cases run on our own model
    cases = []
    for i, cause in enumerate(in_turn(CAUSES, count, rng)):
        base = independent.conditions(rng)
        form = forms(rng)
        case: dict[str, Any] = {
            "case": f"case-f{i:03d}", "bench": BENCH, "cause": cause, "effect": None,
            "values": {}, "conditions": base, "duration": duration,
            "ambient_known": bool(rng.random() < independent.KNOWN_AMBIENT),
            "ambient_read": base["ambient"] + float(rng.uniform(-0.2, 0.2))}
        hide(case, LIBRARY, OUTSIDE, hidden, rng)
        if "clamp heat loss" in (case["effect"], *case.get("pair", ())):
            form["thermal"] = "conduction"
        case["forms"] = form
        case["form_values"] = _form_fields(form, rng)
        if model_rng.random() < MODEL_SHARE:
            case = _on_model(case, model_rng)
        cases.append(case)
    return cases


def _on_model(case: dict[str, Any], rng: np.random.Generator) -> dict[str, Any]:
    """`case` moved onto our own model (the own blind bench's tracking scenario), its cause
    kept, its hidden values drawn from `rng` (`MODEL_MAGNITUDES`, `own.OUTSIDE`)."""
    case = {k: v for k, v in case.items()
            if k in ("case", "cause", "kind", "pair", "effect", "duration")}
    case.update(bench="tracking", forms=dict.fromkeys(FORMS, MODEL), values={},
                latency_samples=int(rng.integers(0, 2)), seed=int(rng.integers(0, 2**31)))
    for effect in case.get("pair") or ([case["effect"]] if case["kind"] == "effect" else []):
        sign = -1.0 if effect in own.SIGNED and rng.random() < 0.5 else 1.0
        for inst, par, lo, hi in MODEL_MAGNITUDES[effect]:
            case["values"][f"{inst}.{par}"] = float(sign * rng.uniform(lo, hi))
    if case["kind"] == "outside":
        name = str(rng.choice(list(own.OUTSIDE)))
        case["effect"] = name
        if name == "clamp slip":  # (fraction of the run, strain lost) per slip
            case["slips"] = [[float(rng.uniform(0.1, 0.95)), float(rng.uniform(
                *own.OUTSIDE[name]))] for _ in range(int(rng.integers(2, 5)))]
        else:
            case["strain_drift"] = float(rng.choice([-1, 1]) * rng.uniform(*own.OUTSIDE[name]))
    return case


def bench_of(case: dict[str, Any]) -> Bench:
    """The `Bench` of family case `case`: conditions, the forms' fields, the hidden values."""
    fields = {**case["conditions"], **case["form_values"], **case["values"]}
    if "slips" in fields:
        fields["slips"] = tuple(tuple(s) for s in fields["slips"])
    return Bench(**fields)


def record(args: tuple[dict[str, Any], Any, Any]) -> tuple[np.ndarray, dict, dict]:
    """Run the bench of family case `case`: (time, {column: values}, {condition: value});
    `args` is (case, the scenarios' folder, the FMUs' folder), the last two for our own
    model's cases."""
    case, scenarios_dir, fmu_dir = args
    if case["bench"] == "tracking":
        scenario = bench_scenario(case, scenarios_dir)
        if case["duration"] != scenario.stop_time:
            scenario = replace(scenario, stop_time=case["duration"])
        time, cols = record_own(case, scenario, fmu_dir)
        return time, cols, {}
    out = run(bench_of(case), case["duration"])
    cols = dict(zip(independent.INPUTS + independent.OUTPUTS,
                    (out["u"], out["T_meas"], out["strain"])))
    stated = ({independent.AMBIENT: round(case["ambient_read"], 2)} if case["ambient_known"]
              else {})
    return out["time"], cols, stated


SMA = Family(bench=BENCH, version=VERSION, scenario=SCENARIO, forms=FORMS, library=LIBRARY,
             outside=OUTSIDE, signals=SIGNALS, regimes=REGIMES,
             sources=("family.py", "benches/sma.py", "benches/sma_kinetics.py"), plan=plan,
             record=record, duration=DURATION)
