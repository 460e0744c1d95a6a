"""The long-duration drift test (§drift), shortened: the core runner against the
co-simulated test, no drift = identical loops, settling drift = later tests closer, and the CLI."""
import numpy as np
import pytest

from musclesim.cli import main
from musclesim.components.sma.drift import DriftParams
from musclesim.cosim import Master, Signal, load_scenario
from musclesim.hysteresis import DriftProtocol, drift_test

from conftest import SCENARIOS

SHORT = DriftProtocol(rounds=4, cycles=2, samples_per_cycle=40, compare=(1, 2, 4))


def test_without_drift_every_test_repeats_its_loop_exactly():
    out = drift_test(SHORT, DriftParams())
    assert all(r == {"1-2": 0.0, "2-4": 0.0} for r in out["rmse"].values())
    loop = out["loops"][125e6][1]
    assert 0.035 < np.ptp(loop) < 0.045  # the major loop at 125 MPa spans about 4 %
    # a full 30-130-30 C cycle sweeps xi 1 -> 0 -> 1: one counted cycle per temperature cycle
    assert out["cycles"] == pytest.approx(4 * 5 * 2, rel=0.01)


def test_a_settling_drift_changes_early_loops_more_than_late_ones():
    params = DriftParams(amplitude_change=0.1, shift=5.0, cycles_to_settle=5.0)
    out = drift_test(SHORT, params)
    for r in out["rmse"].values():
        assert r["1-2"] > 2 * r["2-4"] > 0


def test_the_core_runner_is_the_co_simulated_test(fmu_dir):
    # the scenario's first two cycles (closed-loop temperature at 200 Hz) against the runner with
    # the same temperature samples imposed: they differ by the loop's 0.05 K tracking error
    s = load_scenario(SCENARIOS / "sma-drift.toml", stop_time=40.0)
    res = Master(s, fmu_dir).run()
    assert res.error is None, res.error
    wire = s.instances["wire"].parameters
    params = DriftParams(wire["drift_amplitude"], wire["drift_shift"], wire["drift_settle_cycles"])
    out = drift_test(DriftProtocol(stresses=(125e6,), rounds=1, cycles=2, samples_per_cycle=4000,
                                   compare=(1, 1)), params)
    # the same average of 2 cycles
    cosim = res[Signal("wire", "strain")][1:].reshape(2, 4000).mean(axis=0)
    assert np.sqrt(np.mean((cosim - out["loops"][125e6][1]) ** 2)) < 3e-4
    assert np.ptp(cosim) > 0.035


def test_cli_prints_the_rmse_per_stress(capsys):
    assert main(["drift", str(SCENARIOS / "sma-drift.toml"), "--rounds", "3", "--cycles", "2",
                 "--samples-per-cycle", "20", "--compare", "1", "3"]) == 0
    out = capsys.readouterr().out
    assert "tests     1-3" in out and out.count(" MPa ") == 5


def test_cli_refuses_tests_beyond_the_rounds_in_one_sentence(capsys):
    assert main(["drift", "--rounds", "3", "--compare", "1", "13"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == ("musclesim: the compared tests [1, 13] must be at least two test numbers "
                   "within 1..3 (the rounds run)")
