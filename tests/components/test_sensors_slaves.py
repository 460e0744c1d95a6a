"""The sensors' FMUs (components/sensors/slaves.py) against hand solutions: perfect by default,
the load cell's lag, bias and quantisation, the laser's seeded noise, the thermocouple lagging a
step, the pressure sensor passing its reading."""

import numpy as np
import pytest
from fmpy import simulate_fmu

from component_runs import run_fmu


def test_sensors_are_perfect_by_default(fmu_dir):
    f = 1.5 + 0.3 * np.sin(np.arange(100) / 7)
    assert np.array_equal(run_fmu(fmu_dir, "LoadCell", {"f": f}, outputs=("f_meas",))["f_meas"], f)
    s = 1e-3 * np.sin(np.arange(100) / 7)
    assert np.array_equal(run_fmu(fmu_dir, "LaserSensor", {"s": s}, outputs=("s_meas",))["s_meas"], s)


def test_load_cell_lag_bias_and_quantisation(fmu_dir):
    n, h, tau = 300, 1e-3, 0.02
    f, init = np.full(n + 1, 2.0), {"f": 1.0}  # settled at 1 N, then 2 N from t = 0 on
    r = run_fmu(fmu_dir, "LoadCell", {"f": f}, dt=h, params={"tau": tau, "bias": 0.01},
            outputs=("f_meas",), init=init)
    t = np.arange(n + 1) * h
    np.testing.assert_allclose(r["f_meas"], 2.0 - np.exp(-t / tau) + 0.01, rtol=0, atol=1e-12)
    q = run_fmu(fmu_dir, "LoadCell", {"f": f}, dt=h, params={"tau": tau, "quantum": 0.05},
            outputs=("f_meas",), init=init)["f_meas"]
    np.testing.assert_allclose(q, 0.05 * np.round((2.0 - np.exp(-t / tau)) / 0.05), atol=1e-12)


def test_laser_noise_is_seeded_with_the_asked_spread(fmu_dir):
    s = np.full(4000, 1e-3)
    a = run_fmu(fmu_dir, "LaserSensor", {"s": s}, params={"noise_std": 2e-6, "seed": 5.0},
            outputs=("s_meas",))["s_meas"]
    b = run_fmu(fmu_dir, "LaserSensor", {"s": s}, params={"noise_std": 2e-6, "seed": 5.0},
            outputs=("s_meas",))["s_meas"]
    assert np.array_equal(a, b)
    assert np.std(a - s) == pytest.approx(2e-6, rel=0.05) and abs(np.mean(a - s)) < 1e-7


def test_thermocouple_fmu_lags_a_step(fmu_dir):
    r = simulate_fmu(str(fmu_dir / "Thermocouple.fmu"), stop_time=0.2, output_interval=1e-3,
                     start_values={"tau": 0.05, "T": 350.0, "bias": -1.0},
                     output=["T_meas"])
    # the junction starts at the wire's temperature and the input is constant: reading = T + bias
    np.testing.assert_allclose(r["T_meas"], 349.0, rtol=0, atol=1e-9)
    r = simulate_fmu(str(fmu_dir / "Thermocouple.fmu"), stop_time=0.1, output_interval=1e-3,
                     start_values={"T": 373.15, "gain": 1.005}, output=["T_meas"])
    np.testing.assert_allclose(r["T_meas"], 373.65, rtol=0, atol=1e-9)  # 0.5 % of 100 C


def test_pressure_sensor_fmu_passes_the_reading(fmu_dir):
    r = simulate_fmu(str(fmu_dir / "PressureSensor.fmu"), stop_time=0.05, output_interval=1e-3,
                     start_values={"p": 12e3}, output=["p_meas"])
    assert np.all(r["p_meas"] == 12e3)
    r = simulate_fmu(str(fmu_dir / "PressureSensor.fmu"), stop_time=0.05, output_interval=1e-3,
                     start_values={"p": 12e3, "bias": 150.0, "quantum": 100.0}, output=["p_meas"])
    assert np.all(r["p_meas"] == 12.2e3)
