"""The SoftActuator FMU (components/pneumatic/slaves.py): it fills and empties within its
sources, its contact at the extremes."""
import numpy as np
from fmpy import simulate_fmu


def test_soft_actuator_fmu_fills_and_empties_within_its_sources(fmu_dir):
    fmu = str(fmu_dir / "SoftActuator.fmu")
    r = simulate_fmu(fmu, stop_time=1.0, output_interval=1e-3, start_values={"duty": 1.0})
    assert np.all(np.diff(r["p"]) >= 0) and r["p"].max() <= 40e3 and r["p"][-1] > 39e3
    np.testing.assert_allclose(r["f_a"], 9.62e-4 * r["p"], rtol=1e-15)
    assert np.all(r["m_flow"] >= 0) and r["m_flow"][1] > 0
    r = simulate_fmu(fmu, stop_time=0.5, output_interval=1e-3, start_values={"duty": -1.0})
    assert np.all(np.diff(r["p"]) <= 0) and r["p"].min() >= -20e3 and r["p"][-1] < -10e3
    clamped = simulate_fmu(fmu, stop_time=0.1, output_interval=1e-3, start_values={"duty": 2.0})
    full = simulate_fmu(fmu, stop_time=0.1, output_interval=1e-3, start_values={"duty": 1.0})
    assert np.array_equal(clamped["p"], full["p"])


def test_soft_actuator_fmu_extremal_contact(fmu_dir):
    r = simulate_fmu(str(fmu_dir / "SoftActuator.fmu"), stop_time=0.6, output_interval=1e-3,
                     start_values={"duty": 1.0, "central": 0.0, "V0": 1.41e-5})
    assert r["u"][0] == 0.0 and r["u"][-1] == 1.0
