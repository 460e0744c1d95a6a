"""The fused step (musclesim.cosim.fused): a scenario whose instances are all compiled kernels runs
in one compiled loop with the unfused master's bits, warnings and errors; multi-rate, Gauss-Seidel,
replayed inputs, a clamped input and a value that turns non-finite included."""
import importlib
import tomllib
from dataclasses import replace

import numpy as np
import pytest

from musclesim.components import CATALOGUE
from musclesim.cosim import Master, Signal, load_scenario
from musclesim.fmu.compiled import COMPILED
from musclesim.fmu.kernel import KernelSlave

from conftest import SCENARIOS
from test_hosts import assert_same  # names, times, data bit for bit, errors, warnings

pytestmark = pytest.mark.skipif(not COMPILED, reason="numba is not installed: nothing is fused")

RUNS = sorted(p for p in SCENARIOS.glob("*.toml") if "sweep" not in tomllib.loads(p.read_text()))
STEPS = 200


def slave_class(component):
    module, cls = CATALOGUE[component].split(":")
    return getattr(importlib.import_module(module), cls)


def compiled_kernel(component):
    cls = slave_class(component)
    return issubclass(cls, KernelSlave) and hasattr(cls.kernel.evaluate, "py_func")


def runs(s, fmu_dir, **kw):
    """(fused, unfused) Results of scenario `s`, and whether the first ran fused."""
    m = Master(s, fmu_dir, **kw)
    fused = m.run()
    return fused, Master(s, fmu_dir, fuse=False, **kw).run(), m.fused


@pytest.mark.parametrize("path", RUNS, ids=lambda p: p.stem)
def test_every_shipped_scenario_fuses_where_it_can_with_the_same_bits(fmu_dir, path):
    s = load_scenario(path)
    s = load_scenario(path, stop_time=min(s.stop_time, max(0.25, STEPS * s.step)))
    fused, unfused, ran_fused = runs(s, fmu_dir)
    assert ran_fused == all(compiled_kernel(i.component) for i in s.instances.values())
    assert_same(fused, unfused)


def crawler(stop_time=2.0, **changes):
    return replace(load_scenario(SCENARIOS / "crawler-ideal.toml", stop_time=stop_time), **changes)


def test_gauss_seidel_and_multi_rate_fuse_with_the_same_bits(fmu_dir):
    s = crawler(algorithm="gauss-seidel")
    inst = {**s.instances, "inputs": replace(s.instances["inputs"], every=3),
            "friction2": replace(s.instances["friction2"], every=7)}
    for case in (s, replace(s, instances=inst), replace(s, instances=inst, algorithm="jacobi")):
        fused, unfused, ran_fused = runs(case, fmu_dir)
        assert ran_fused and unfused.error is None
        assert_same(fused, unfused)


def test_replayed_inputs_fuse_with_the_same_bits(fmu_dir):
    s = crawler()
    s = replace(s, connections=tuple(c for c in s.connections if c[1] != Signal("body", "f_a")))
    f_a = 5.0 + 4.0 * np.sin(np.arange(s.n_steps + 1) * 0.01)
    fused, unfused, ran_fused = runs(s, fmu_dir, inputs={Signal("body", "f_a"): f_a})
    assert ran_fused
    assert_same(fused, unfused)


def test_a_value_that_turns_non_finite_stops_both_alike(fmu_dir):
    """A friction coefficient of 1e308 makes the force infinite: the same message, the same rows."""
    s = crawler()
    inst = {**s.instances, "friction1": replace(
        s.instances["friction1"], parameters={**s.instances["friction1"].parameters,
                                              "mu_k_high": 1e308, "mu_s_high": 1e308})}
    fused, unfused, ran_fused = runs(replace(s, instances=inst), fmu_dir)
    assert ran_fused and "became" in fused.error
    assert_same(fused, unfused)


def test_the_state_goes_back_into_the_slaves(fmu_dir):
    """After a fused run each slave holds the state, the clock and the inputs the loop reached, so
    an FMU state saved then is the unfused run's."""
    s = crawler(stop_time=0.5)
    states = []
    for fuse in (True, False):
        m = Master(s, fmu_dir, fuse=fuse)
        kept = {}
        original = m._instantiate

        def keep(tmp, m=m, kept=kept, original=original):
            original(tmp)
            kept.update({n: i.slave.slave for n, i in m.instances.items()})
        m._instantiate = keep
        m.run()
        states.append({n: (sl.kx.tobytes(), sl.time, sl.kernel_inputs()) for n, sl in kept.items()})
    assert states[0] == states[1]


def test_many_cases_in_one_pass_give_each_case_its_own_bits(fmu_dir):
    """run_cases: parameter sets of one scenario in one compiled call, each case's Results those
    of its own run, a failing case among them included; cases that cannot share a pass run one
    after the other (an FMU hosted by fmpy)."""
    from musclesim.cosim import ParamRef, run_cases, with_values

    s = crawler(stop_time=1.0)
    sets = [{ParamRef("body", "k"): k, ParamRef("friction1", "mu_s_low"): mu}
            for k, mu in ((200.0, 0.13), (150.0, 0.2), (260.0, 0.1))]
    sets.append({ParamRef("friction1", "mu_k_high"): 1e308, ParamRef("friction1", "mu_s_high"): 1e308})
    cases = [with_values(s, v) for v in sets]
    batch = run_cases([Master(c, fmu_dir) for c in cases])
    assert len(batch) == len(cases) and "became" in batch[-1].error
    for c, res in zip(cases, batch):
        assert_same(res, Master(c, fmu_dir, fuse=False).run())
    one_by_one = run_cases([Master(c, fmu_dir, host="fmpy") for c in cases[:2]])
    for a, b in zip(one_by_one, batch):
        assert_same(a, b)


def test_a_signal_stops_a_fused_run_between_two_chunks_with_its_rows(fmu_dir, monkeypatch):
    """A signal caught while a fused loop runs stops it at the end of its chunk of rows:
    `Interrupted` carries the rows so far, the unfused run's bits, and says when it stopped."""
    import signal

    from musclesim.cosim import Interrupted, interrupt, master

    monkeypatch.setattr(master, "FUSED_ROWS", 100)
    s = crawler(stop_time=1.0)
    full = Master(s, fmu_dir, fuse=False).run()

    def rows(time, data):
        interrupt.STATE["signum"] = signal.SIGINT  # as the handler records a signal

    monkeypatch.setattr(master, "FLUSH_SECONDS", 0.0)
    try:
        with pytest.raises(Interrupted) as stopped:
            Master(s, fmu_dir).run(on_rows=rows)
    finally:
        interrupt.STATE["signum"] = None
    res = stopped.value.results
    assert 100 < len(res.time) < len(full.time)
    assert res.data.tobytes() == full.data[:len(res.time)].tobytes()
    assert res.error == f"interrupted by SIGINT at t = {res.time[-1]:.6g} s"
