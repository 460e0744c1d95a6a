"""Downstream restarts (musclesim.diagnosis.simulate): a run whose values differ from a kept run's
only in instances that feed no other fitted instance simulates those alone, the upstream
outputs replayed, and gives the same bits as the whole run."""
import pickle
from dataclasses import replace

import numpy as np

from musclesim.cosim import reuse_fmus
from musclesim.cosim import ParamRef, Signal
from musclesim.diagnosis import dataset
from musclesim.diagnosis import simulate as sim
from musclesim.diagnosis.problem import Problem
from musclesim.diagnosis.stats import TRAIN

from conftest import SCENARIOS


def _same(a, b):
    for run_a, run_b in zip(a, b, strict=True):
        assert run_a.keys() == run_b.keys()
        for column in run_a:
            assert np.array_equal(run_a[column], run_b[column], equal_nan=True), column


def test_a_sensors_values_rerun_the_sensor_alone_to_the_same_bits(fmu_dir, monkeypatch):
    """The independent tracking bench (Jacobi): with the wire's h and the thermocouple's lag
    fitted, the thermocouple feeds no other fitted instance; a second value of its lag, the wire's
    h unchanged, runs the thermocouple alone, the wire's temperature replayed; both parts of the
    data, and every row, as the whole model gives them."""
    ds = dataset.load(SCENARIOS / "data" / "sma-independent-thermocouple-lag")
    unit = Problem(ds, fmu_dir).unit("model")
    assert unit.runs[0].scenario.algorithm == "jacobi"
    ran = []
    master = sim.Master

    def counting(s, *args, **kwargs):
        ran.append(tuple(sorted(s.instances)))
        return master(s, *args, **kwargs)

    monkeypatch.setattr(sim, "Master", counting)
    first = {ParamRef("wire", "h"): 110.0, ParamRef("thermocouple", "tau"): 0.2}
    second = {ParamRef("wire", "h"): 110.0, ParamRef("thermocouple", "tau"): 0.5}
    with reuse_fmus():
        for part in (TRAIN, None):
            ran.clear()
            sim.simulate(unit, first, fmu_dir, part)
            restarted = sim.simulate(unit, second, fmu_dir, part)
            assert ran[1] == ("thermocouple",) and len(ran[0]) > 1
            _same(restarted, sim.simulate(replace(unit), second, fmu_dir, part))
            assert len(ran[2]) == len(ran[0])  # the copy kept no run: it ran whole
        assert unit.restarts and not pickle.loads(pickle.dumps(unit)).restarts  # nor a worker's
        # h changed: the kept run does not apply, the whole model runs again
        ran.clear()
        moved = sim.simulate(unit, {**second, ParamRef("wire", "h"): 120.0}, fmu_dir)
        assert len(ran[0]) > 1
        strain = Signal("wire", "strain")
        assert not np.array_equal(moved[0][strain], restarted[0][strain])


def test_no_restart_where_the_master_is_gauss_seidel_or_nothing_is_upstream(fmu_dir):
    ds = dataset.load(SCENARIOS / "data" / "sma-independent-thermocouple-lag")
    run = Problem(ds, fmu_dir).unit("model").runs[0]
    s, _ = run.stepped(run.scenario)  # the constant load replayed already (`Run.stepped`)
    assert set(s.instances) == {"wire", "thermocouple"}
    values = {ParamRef("wire", "h"): 110.0, ParamRef("thermocouple", "tau"): 0.2}
    _, kept, cut = sim._downstream(s, values)
    assert kept == {"thermocouple"} and [k.dst for k in cut] == [Signal("thermocouple", "T")]
    assert sim._downstream(replace(s, algorithm="gauss-seidel"), values) is None
    # the wire feeds the sensor
    assert sim._downstream(s, {ParamRef("wire", "h"): 110.0}) is None
    assert sim._downstream(s, {}) is None


def test_many_values_simulated_together_give_each_its_own_runs(fmu_dir):
    """simulate_many (the cases of a run in one pass where they fuse) gives each parameter set
    simulate's runs to the bit, and a failed set its failure, not the others'."""
    ds = dataset.load(SCENARIOS / "data" / "sma-independent-thermocouple-lag")
    unit = Problem(ds, fmu_dir).unit("model")
    tau = ParamRef("thermocouple", "tau")
    sets = [{tau: 0.05}, {tau: 0.4}, {tau: -1.0}]  # a negative lag fails the sensor's check
    with reuse_fmus():
        many = sim.simulate_many(unit, sets, fmu_dir, TRAIN)
        assert [m.failed for m in many] == [False, False, True]
        for values, got in zip(sets[:2], many):
            _same(got.runs, sim.simulate(replace(unit), values, fmu_dir, TRAIN))  # no restarts kept
