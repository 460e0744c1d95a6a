"""SMA position control co-simulated against the monolithic model of the same equations
(components/sma/monolithic.py): from one initialized state, the fused co-simulation and the
monolithic loop give the same bits at every point."""
import numpy as np
import pytest

from musclesim.components.sma.monolithic import INSTANCES, RECORD, simulate_position
from musclesim.cosim import Master, Signal, scenario

from conftest import SCENARIOS

POSITION = SCENARIOS / "sma-position-control.toml"


def cosim_and_start(fmu_dir, overrides=(), stop_time=3.0):
    """(results of the co-simulated run, each instance's kernel arrays after initialization,
    the scenario)."""
    s = scenario.load(POSITION, overrides, stop_time)
    m = Master(s, fmu_dir)
    with m.session(None) as run:
        parts = m.kernels()
        run.error = m.steps(run)
    assert run.results is not None and run.results.error is None and m.fused
    assert sorted(parts) == sorted(INSTANCES)
    return run.results, parts, s


@pytest.mark.parametrize("overrides", [
    (), ("strain.profile=2", "loading.profile=3", "inverse.sigma_surface=125e6",
         "thermocouple.tau=0.05", "loadcell.noise_std=0.01")],
    ids=["SP-I-LP-I", "SP-II-LP-III-stress-ignored-lag-noise"])
def test_the_cosimulation_gives_the_monolithic_models_bits(fmu_dir, overrides):
    res, parts, s = cosim_and_start(fmu_dir, overrides)
    held = {name: tuple(a.copy() for a in arrays) for name, arrays in parts.items()}
    times, rows = simulate_position(parts, s.step, s.n_steps)
    np.testing.assert_array_equal(times, res.time)
    for j, name in enumerate(RECORD):
        np.testing.assert_array_equal(rows[:, j], res[Signal.parse(name)], err_msg=name)
    # the loop acted: heating, a moving strain and a load that follows its reference
    assert np.ptp(rows[:, RECORD.index("tpid.y")]) > 0.1
    assert np.ptp(rows[:, RECORD.index("wire.strain")]) > 0.0
    assert all(np.array_equal(a, b, equal_nan=True)
               for name in parts for a, b in zip(parts[name], held[name]))  # copied
