"""A family of crawler bench forms: the cases the diagnosis's sets on the pneumatic crawler are
calibrated and scored on.

The crawler's counterpart of `musclesim.benchmark.family` (read it first: the reasons, the causes
and how a case is drawn are the same). Each case draws every subsystem of the independent crawler
bench (`musclesim.benchmark.benches.crawler`, physics written apart from the library) from
several forms (`FORMS`, each with its source), its conditions and noise around the model's values
(`musclesim.benchmark.plan.crawler_conditions`), and one hidden cause (`CAUSES`, in equal
shares): nothing, one of the crawler library's effects the bench writes
(`musclesim.benchmark.plan.CRAWLER_LIBRARY`; supply-pressure drop and chamber leakage, friction
decay and bending on an incline are each other's look-alikes), two of them, or a change outside
the library (`OUTSIDE`: long sensor tubes, a change of surface part-way, a camera scale error).
A form's parameters are drawn with it: an ISO 6358 valve's critical ratio 0.2-0.5, a second-order
spool's damping 0.5-1, a polytropic exponent 1.1-1.3, a stiffening spring 5-30 % stiffer at 4 cm,
the camera's 30, 60 or 120 frames a second.

Our own model is one member (`MODEL_SHARE` of the cases, from a stream of their own): the
library's FMUs on the crawler-gait-incline scenario with the cause hidden in their parameters at
the own blind bench's magnitudes (`musclesim.benchmark.cases.MAGNITUDES`), the controllers'
duties replayed and the own bench's sensor noise. Its forms are all ``model``. A case whose cause
is outside the library stays on the bench: the own model has none of those changes.

>>> cases = plan(9, 1)
>>> sorted({c["cause"] for c in cases}) == sorted(CAUSES)
True
"""
from __future__ import annotations

import math
from dataclasses import replace
from typing import Any

import numpy as np

from musclesim.benchmark import cases as own
from musclesim.benchmark import plan as independent
from musclesim.benchmark.family import MODEL, Family, forms, hide, in_turn
from musclesim.benchmark.recording import bench_scenario
from musclesim.benchmark.recording import record as record_own
from musclesim.diagnosis import CALIBRATION_ONLY, OUTSIDE_LIBRARY, TWO_EFFECTS

VERSION = 1
BENCH = "crawler-family"
MODEL_SHARE = 0.125
SCENARIO = independent.CRAWLER_SCENARIO
DURATION = independent.CRAWLER_DURATION
OWN_BENCH = "crawler"  # the own blind bench's crawler (`musclesim.benchmark.cases.BENCHES`)
# subsystem -> form -> its source
FORMS: dict[str, dict[str, str]] = {
    "friction": {
        "lugre": "the LuGre model, bristles with Stribeck (Canudas de Wit et al., IEEE TAC 40, "
                 "1995)",
        "coulomb": "switching Coulomb with stiction (Karnopp, ASME J. Dyn. Syst. Meas. Control "
                   "107, 1985), the model's own form (§friction)",
        "dahl": "the Dahl model, presliding without Stribeck (Dahl, 1968; as in Canudas de Wit "
                "et al. 1995)"},
    "valve": {
        "nozzle": "isentropic nozzle flow, choked below the critical ratio "
                  "(Saint-Venant-Wantzel)",
        "orifice": "the incompressible orifice law, no choking",
        "iso6358": "ISO 6358's sonic conductance and critical ratio b (0.2-0.5), the model's "
                   "own form (§valves)"},
    "spool": {
        "first-order": "the spool follows the command with a first-order lag",
        "second-order": "a damped second-order spool (damping 0.5-1)",
        "dead-time": "the coil's build-up as a dead time, then a first-order lag"},
    "chamber": {
        "energy": "mass and energy balances with heat exchange to the wall",
        "isothermal": "isothermal air, p V = m R T_room",
        "polytropic": "a polytropic law, exponent 1.1-1.3"},
    "spring": {
        "linear": "the central actuator a linear spring (§two-mass)",
        "stiffening": "a hardening spring k d (1 + k3 d^2), 5-30 % stiffer at 4 cm (silicone "
                      "under large strain)"},
    "contact": {
        "logistic": "the share of silicone on the ground logistic in the pressure about a "
                    "threshold",
        "threshold": "the silicone on the ground once the pressure passes a threshold, reached "
                     "through a lag (the model reaches it at a constant rate, §contact)",
        "bulging": "the share growing linearly with the pressure as the silicone bulges"},
    "camera": {
        "interpolated": "video frames linearly interpolated onto the DAQ's clock",
        "held": "the last frame held until the next (zero-order hold)"},
}
FPS = (30.0, 60.0, 120.0)  # the camera's frames per second, drawn with either camera form
LIBRARY = independent.CRAWLER_LIBRARY
OUTSIDE = tuple(o for o in independent.CRAWLER_OUTSIDE if o != TWO_EFFECTS)
CAUSES = (CALIBRATION_ONLY, *LIBRARY, TWO_EFFECTS, OUTSIDE_LIBRARY)
SIGNALS = [str(s) for s in independent.CRAWLER_OUTPUTS]  # the observed signals
# the crawler's operating regimes (`musclesim.diagnosis.REGIMES`) its reports read, but "all"
REGIMES = ["late", "stress_extremes", "stick", "slip", "high_force", "load_changing",
           "pressure_changing", "pressurised"]


def form_fields(form: dict[str, str], rng: np.random.Generator) -> dict[str, Any]:
    """The `Crawler` fields of `form` with the parameters its forms draw from `rng`."""
    u = rng.uniform
    fields: dict[str, Any] = {
        "friction": form["friction"], "valve_law": form["valve"], "spool": form["spool"],
        "chamber": form["chamber"], "contact": form["contact"],
        "video_hold": form["camera"] == "held", "video_fps": float(rng.choice(FPS)),
        "k3": 0.0 if form["spring"] == "linear" else u(0.05, 0.3) / 0.04 ** 2}
    if form["valve"] == "iso6358":
        fields["valve_b"] = u(0.2, 0.5)
    if form["spool"] == "second-order":
        fields["spool_zeta"] = u(0.5, 1.0)
    if form["chamber"] == "polytropic":
        fields["polytropic_n"] = u(1.1, 1.3)
    return fields


def plan(count: int, seed: int, duration: float = DURATION) -> list[dict[str, Any]]:
    """`count` crawler family cases drawn from `seed`, the causes of `CAUSES` in equal shares (in
    turn, then shuffled): dicts with ``case`` (``case-k000``, ...), ``bench``, ``cause``,
    ``kind``, ``effect`` (or ``pair``), the hidden ``values``, ``conditions``, ``forms``,
    ``form_values`` and ``duration``; those moved onto our own model as the own blind bench's
    crawler cases are (bench "crawler")."""
    rng = np.random.default_rng([seed, 29])  # streams apart from the other plans'
    model_rng = np.random.default_rng([seed, 31])
    cases = []
    for i, cause in enumerate(in_turn(CAUSES, count, rng)):
        case: dict[str, Any] = {
            "case": f"case-k{i:03d}", "bench": BENCH, "cause": cause, "effect": None,
            "values": {}, "conditions": independent.crawler_conditions(rng),
            "duration": duration}
        hide(case, LIBRARY, OUTSIDE, independent.crawler_hidden, rng)
        form = forms(rng, FORMS)
        case["forms"] = form
        case["form_values"] = form_fields(form, rng)
        if model_rng.random() < MODEL_SHARE and case["kind"] != "outside":
            case = _on_model(case, model_rng)
        cases.append(case)
    return cases


def _on_model(case: dict[str, Any], rng: np.random.Generator) -> dict[str, Any]:
    """`case` moved onto our own model (the own blind bench's crawler), its cause kept, its
    hidden values drawn from `rng` at the own bench's magnitudes."""
    case = {k: v for k, v in case.items()
            if k in ("case", "cause", "kind", "pair", "effect", "duration")}
    case.update(bench=OWN_BENCH, forms=dict.fromkeys(FORMS, MODEL), values={},
                latency_samples=int(rng.integers(0, 2)), seed=int(rng.integers(0, 2**31)))
    for effect in case.get("pair") or ([case["effect"]] if case["kind"] == "effect" else []):
        case["values"].update(own.draw_values(effect, rng))
    return case


def bench_fields(case: dict[str, Any]) -> dict[str, Any]:
    """The `Crawler` fields of family case `case`: conditions, the forms' fields, the hidden
    values."""
    fields = {**case["conditions"], **case["form_values"], **case["values"]}
    if fields.get("surface_change") is not None:
        fields["surface_change"] = tuple(fields["surface_change"])
    return fields


def record(args: tuple[dict[str, Any], Any, Any]) -> tuple[np.ndarray, dict, dict]:
    """Run the bench of crawler family case `case`: (time, {column: values}, {}); `args` is
    (case, the scenarios' folder, the FMUs' folder), the last two for our own model's cases."""
    case, scenarios_dir, fmu_dir = args
    if case["bench"] == OWN_BENCH:
        scenario = bench_scenario(case, scenarios_dir)
        if not math.isclose(case["duration"], scenario.stop_time):
            scenario = replace(scenario, stop_time=case["duration"])
        time, cols = record_own(case, scenario, fmu_dir)
        return time, cols, {}
    return independent.record({"bench": "independent-crawler", "duration": case["duration"],
                               "conditions": bench_fields(case), "values": {}})


CRAWLER = Family(bench=BENCH, version=VERSION, scenario=SCENARIO, forms=FORMS, library=LIBRARY,
                 outside=OUTSIDE, signals=SIGNALS, regimes=REGIMES,
                 sources=("family_crawler.py", "benches/crawler.py", "benches/crawler_air.py"),
                 plan=plan, record=record, duration=DURATION)
