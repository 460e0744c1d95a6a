"""The independent benches' cases (musclesim.benchmark.plan): reproducible from the seed, bit for
bit, and their data sets load against the model."""
from pathlib import Path

import numpy as np
import pytest

from musclesim.benchmark import blind
from musclesim.benchmark import plan as independent_plan
from musclesim.cosim import ParamRef, Signal
from musclesim.diagnosis import load_dataset

ROOT = Path(__file__).resolve().parents[2]


def test_same_seed_same_data_bit_for_bit_and_the_plan_is_reproducible():
    cases = independent_plan.plan(12, 3, blind.DECOYS, duration=20.0)
    assert cases == independent_plan.plan(12, 3, blind.DECOYS, duration=20.0)
    assert {c["kind"] for c in cases} == {"effect", "decoy", "none", "outside"}
    case = next(c for c in cases if c["kind"] == "effect")
    t1, cols1, st1 = independent_plan.record(case)
    t2, cols2, st2 = independent_plan.record(case)
    assert np.array_equal(t1, t2) and st1 == st2
    assert all(np.array_equal(cols1[c], cols2[c]) for c in cols1)
    other = independent_plan.plan(12, 4, blind.DECOYS, duration=20.0)
    assert other != cases


def test_a_generated_data_set_loads_against_the_model(fmu_dir, tmp_path):
    case = next(c for c in independent_plan.plan(8, 2, blind.DECOYS, duration=12.0)
                if c["kind"] == "none")
    case["ambient_known"] = True
    blind.make_case(case, tmp_path, scenarios_dir=ROOT / "scenarios")
    ds = load_dataset(tmp_path / "cases" / case["case"], check_model=True, fmu_dir=fmu_dir)
    assert ds.inputs == (Signal("pid", "y"),)
    assert ds.outputs == (Signal("thermocouple", "T_meas"), Signal("wire", "strain"))
    assert ds.conditions == {ParamRef("wire", "T_amb"): pytest.approx(case["ambient_read"],
                                                                      abs=0.01)}
    assert ds.time[-1] == pytest.approx(12.0) and np.all(np.diff(ds.time) > 0)
    assert ds.units[Signal("thermocouple", "T_meas")] == "K"


def test_crawler_plan_is_reproducible_and_its_data_load_against_the_model(fmu_dir, tmp_path):
    cases = independent_plan.plan_crawler(12, 3)
    assert cases == independent_plan.plan_crawler(12, 3) != independent_plan.plan_crawler(12, 4)
    assert {c["kind"] for c in cases} == {"effect", "decoy", "none", "outside"}
    case = {**next(c for c in cases if c["kind"] == "none"), "duration": 2.0}
    t1, cols1, _ = independent_plan.record(case)
    t2, cols2, _ = independent_plan.record(case)
    assert all(np.array_equal(cols1[c], cols2[c]) for c in cols1)
    blind.make_case(case, tmp_path, scenarios_dir=ROOT / "scenarios")
    ds = load_dataset(tmp_path / "cases" / case["case"], check_model=True, fmu_dir=fmu_dir)
    assert ds.inputs == tuple(independent_plan.CRAWLER_INPUTS)
    assert ds.outputs == tuple(independent_plan.CRAWLER_OUTPUTS)
    assert ds.time[-1] == pytest.approx(2.0)
    for effect in independent_plan.CRAWLER_LIBRARY:  # each hidden effect is a library effect
        assert independent_plan.find_effect(effect).component in ("SoftActuator", "CrawlerBody",
                                                           "FrictionBlock")
