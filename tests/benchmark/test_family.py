"""The family of SMA bench forms (musclesim.benchmark.family): balanced causes, every form
drawn and acting on the bench, causes that need a structure getting it."""
import numpy as np
import pytest

from musclesim.benchmark import family
from musclesim.benchmark.benches.sma import Bench, run


def test_the_causes_come_in_equal_shares_and_every_form_is_drawn():
    cases = family.plan(90, 3)
    causes = [c["cause"] for c in cases]
    assert {k: causes.count(k) for k in family.CAUSES} == dict.fromkeys(family.CAUSES, 10)
    for sub, options in family.FORMS.items():
        assert {c["forms"][sub] for c in cases} == {*options, family.MODEL}, sub
    on_model = [c for c in cases if c["bench"] == "tracking"]
    assert 0 < len(on_model) < 0.3 * len(cases)  # MODEL_SHARE, an eighth
    assert family.plan(90, 3) == cases  # a seed gives the same cases
    assert family.plan(90, 4) != cases


def test_each_case_is_labelled_by_its_hidden_change():
    for c in family.plan(45, 5):
        if c["cause"] == family.CALIBRATION_ONLY:
            assert c["kind"] == "none" and not c["values"]
        elif c["cause"] == family.TWO_EFFECTS:
            assert len(set(c["pair"])) == 2 and set(c["pair"]) <= set(family.LIBRARY)
        elif c["cause"] == family.OUTSIDE_LIBRARY:
            assert c["effect"] in family.OUTSIDE
            assert c["values"] or c.get("slips") or c.get("strain_drift")
        else:
            assert c["effect"] == c["cause"] in family.LIBRARY and c["values"]
        if c["bench"] == "tracking":  # our own model: the cause in its parameters
            effects = c.get("pair") or ([c["effect"]] if c["kind"] == "effect" else [])
            assert {k.split(".")[0] + "." + k.split(".")[1] for k in c["values"]} == {
                f"{i}.{p}" for e in effects for i, p, *_ in family.MODEL_MAGNITUDES[e]}
            continue
        if "clamp heat loss" in (c["effect"], *c.get("pair", ())):
            assert c["forms"]["thermal"] == "conduction"  # cold ends need a wire with length
        family.bench_of(c)  # every case makes a bench


def test_moving_cases_onto_the_model_leaves_the_others_as_drawn():
    cases = family.plan(60, 7)
    assert [c["cause"] for c in cases] == [c["cause"] for c in family.plan(60, 7)]
    bench = [c for c in cases if c["bench"] == family.BENCH]
    assert all(set(c["forms"].values()) != {family.MODEL} for c in bench)


@pytest.mark.parametrize("fields", [
    {"hysteresis": "exponential"}, {"hysteresis": "relay"}, {"thermal": "lumped"},
    {"resistivity_law": "tempco", "tempco": 5e-4}, {"resistivity_law": "parallel"},
    {"convection": "gusts", "gust_level": 0.1}, {"tc_form": "ladder"},
    {"tc_form": "first-order"}, {"h_exponent": 0.4},
    {"drift_shift": 4.0, "drift_amplitude": 0.05}], ids=str)
def test_every_form_and_new_cause_changes_what_the_bench_records(fields):
    base = {"tc_tau_sheath": 0.2, "tc_tau_junction": 0.05, "emissivity": 0.2}
    ref = run(Bench(**base), 12.0)
    out = run(Bench(**base, **fields), 12.0)
    change = max(np.max(np.abs(out["strain"] - ref["strain"])) / 1e-4,
                 np.max(np.abs(out["T_meas"] - ref["T_meas"])) / 0.1)
    assert change > 1, fields  # more than 1e-4 strain or 0.1 K somewhere
    assert np.all(np.isfinite(out["strain"])) and np.ptp(out["strain"]) > 0.005


def test_the_ladder_thermocouple_keeps_the_total_delay_of_its_stages():
    """Three loaded RC stages of tau/6 each: the step response's first moment (the mean
    delay) is 6 * tau/6 = tau, the same as the two-pole coat's tau_sheath + tau_junction."""
    from musclesim.benchmark.benches.sma import _Thermocouple
    dt, tau = 1e-3, 0.3
    delays = {}
    for form in ("ladder", "two-pole", "first-order"):
        tc = _Thermocouple(Bench(ambient=0.0, tc_form=form, tc_tau_sheath=0.2,
                                 tc_tau_junction=0.1), dt)
        y = []
        for _ in range(int(6 / dt)):
            tc.step(1.0, 1.0)
            y.append(tc.junction)
        delays[form] = float(np.sum(1 - np.array(y)) * dt)
    assert delays == pytest.approx(dict.fromkeys(delays, tau), rel=0.01)


def test_every_form_names_its_source():
    for sub, options in family.FORMS.items():
        assert len(options) >= 2, sub
        assert all(len(text) > 10 for text in options.values())
