"""The sensors' FMUs (components/sensors/slaves.py) against hand solutions: perfect by default,
the load cell's lag, bias and quantisation, the laser's seeded noise, the thermocouple lagging a
step, the pressure sensor passing its reading."""
from types import SimpleNamespace

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Slave

from musclesim.cosim import host


def run(fmu_dir, name, inputs, dt=1e-3, params=None, outputs=("flange.f",), log=None, init=None):
    """Run FMU `name` with inputs {name: values per point t_0..t_n} (value k set at t_k, held
    over step k; `init` {name: value} overrides the values set while initializing); returns
    {output: array at t_0..t_n}, the FMU's log in `log`."""
    path = fmu_dir / f"{name}.fmu"
    md = read_model_description(str(path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    n = len(next(iter(inputs.values())))
    slave = FMU2Slave(guid=md.guid, unzipDirectory=extract(path), instanceName=name,
                      modelIdentifier=md.coSimulation.modelIdentifier)
    key = id(slave)
    host.LOG_SINKS[key] = {name: SimpleNamespace(log=log if log is not None else [])}
    try:
        slave.instantiate(callbacks=host.callbacks(key), loggingOn=True)
        slave.setupExperiment(startTime=0.0)
        for par, value in (params or {}).items():
            slave.setReal([vr[par]], [value])
        ins, outs = [vr[k] for k in inputs], [vr[k] for k in outputs]
        slave.enterInitializationMode()
        start = {k: v[0] for k, v in inputs.items()} | (init or {})
        slave.setReal(ins, [float(v) for v in start.values()])
        slave.exitInitializationMode()
        rows = []
        for k in range(n):
            slave.setReal(ins, [float(v[k]) for v in inputs.values()])
            rows.append(slave.getReal(outs))
            if k < n - 1:
                slave.doStep(k * dt, dt)
        slave.terminate()
        slave.freeInstance()
    finally:
        del host.LOG_SINKS[key]
    return dict(zip(outputs, np.array(rows).T))


def test_sensors_are_perfect_by_default(fmu_dir):
    f = 1.5 + 0.3 * np.sin(np.arange(100) / 7)
    assert np.array_equal(run(fmu_dir, "LoadCell", {"f": f}, outputs=("f_meas",))["f_meas"], f)
    s = 1e-3 * np.sin(np.arange(100) / 7)
    assert np.array_equal(run(fmu_dir, "LaserSensor", {"s": s}, outputs=("s_meas",))["s_meas"], s)


def test_load_cell_lag_bias_and_quantisation(fmu_dir):
    n, h, tau = 300, 1e-3, 0.02
    f, init = np.full(n + 1, 2.0), {"f": 1.0}  # settled at 1 N, then 2 N from t = 0 on
    r = run(fmu_dir, "LoadCell", {"f": f}, dt=h, params={"tau": tau, "bias": 0.01},
            outputs=("f_meas",), init=init)
    t = np.arange(n + 1) * h
    np.testing.assert_allclose(r["f_meas"], 2.0 - np.exp(-t / tau) + 0.01, rtol=0, atol=1e-12)
    q = run(fmu_dir, "LoadCell", {"f": f}, dt=h, params={"tau": tau, "quantum": 0.05},
            outputs=("f_meas",), init=init)["f_meas"]
    np.testing.assert_allclose(q, 0.05 * np.round((2.0 - np.exp(-t / tau)) / 0.05), atol=1e-12)


def test_laser_noise_is_seeded_with_the_asked_spread(fmu_dir):
    s = np.full(4000, 1e-3)
    a = run(fmu_dir, "LaserSensor", {"s": s}, params={"noise_std": 2e-6, "seed": 5.0},
            outputs=("s_meas",))["s_meas"]
    b = run(fmu_dir, "LaserSensor", {"s": s}, params={"noise_std": 2e-6, "seed": 5.0},
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
