"""The blind benchmark's multiplier cases (§capstan-multiplier, §named-effects): drawn apart from
the other cases, each hidden effect recorded on the multiplier bench changes what the bench
measures."""
import numpy as np
import pytest

from musclesim.benchmark import blind
from musclesim.diagnosis import effects

from conftest import SCENARIOS


def test_multiplier_cases_are_drawn_from_their_own_stream():
    cases = blind.plan_multiplier(30, seed=2)
    assert cases == blind.plan_multiplier(30, seed=2)
    assert [c["case"] for c in cases[:2]] == ["case-m000", "case-m001"]
    assert {c["bench"] for c in cases} == {"multiplier"}
    drawn = {c["effect"] for c in cases if c["kind"] == "effect"}
    assert drawn == set(blind.BENCHES["multiplier"][3])
    assert 0 < sum(c["kind"] == "none" for c in cases) < 15
    for c in cases:
        for (inst, par, lo, hi) in blind.MAGNITUDES.get(c["effect"], []):
            assert lo <= abs(c["values"][f"{inst}.{par}"]) <= hi
    # every effect of the bench is in the library, on a component the bench has
    for name in blind.BENCHES["multiplier"][3]:
        assert effects.find(name).component in ("CapstanMultiplier", "DeadWeight")


@pytest.mark.parametrize("effect", ["capstan friction", "composition difference"])
def test_a_hidden_multiplier_effect_changes_the_recording(fmu_dir, effect):
    base = {"case": "c", "kind": "none", "bench": "multiplier", "effect": None, "values": {},
            "latency_samples": 0, "seed": 5}
    hidden = dict(base, kind="effect", effect=effect,
                  values={f"mult.{p}": v for (_, p, _, v) in blind.MAGNITUDES[effect]})
    t, nominal = blind.record(base, blind.bench_scenario(base, SCENARIOS), fmu_dir)
    _, changed = blind.record(hidden, blind.bench_scenario(hidden, SCENARIOS), fmu_dir)
    assert t[-1] == pytest.approx(blind.STOP_TIME["multiplier"])
    assert sorted(nominal) == ["laser.s_meas", "mult.u", "thermocouple.T_meas"]
    assert not np.allclose(nominal["laser.s_meas"], changed["laser.s_meas"], atol=2e-5)
