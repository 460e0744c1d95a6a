"""Loads of the SMA bench (SPEC 2.1, 2.4, 3.1) and the load-cell and laser sensors, through their
FMUs against hand solutions: spring preload and slope, a dead weight's inertia under a sinusoidal
lift, the coil's exact step response, the duty clamp, effects off = nominal exactly."""
import math
from types import SimpleNamespace

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from musclesim import fmuhost
from musclesim.components.loads import loads

G = 9.80665
AREA = 1.2667686977437442e-08  # m^2, SmaWire's cross-section pi (127 um)^2 / 4


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
    fmuhost.LOG_SINKS[key] = {name: SimpleNamespace(log=log if log is not None else [])}
    try:
        slave.instantiate(callbacks=fmuhost.callbacks(key), loggingOn=True)
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
        del fmuhost.LOG_SINKS[key]
    return dict(zip(outputs, np.array(rows).T))


def test_defaults_are_125_mpa_and_the_100_g_weight():
    assert loads.AREA == AREA
    assert loads.SpringParams().preload / AREA == pytest.approx(125e6, rel=1e-15)
    assert loads.WeightParams().mass * G / AREA == pytest.approx(125e6, rel=1e-15)
    p = loads.MagnetParams()
    lo, hi = loads.magnet_tension(0.0, p), loads.magnet_tension(loads.coil_steady(1.0, p), p)
    assert lo / AREA < 105e6 and hi / AREA > 145e6  # the duty range covers SPEC 2.4's stresses


def test_bias_spring_preload_and_slope(fmu_dir):
    s = np.array([0.0, 1e-3, -5e-4, 2.2e-3])
    r = run(fmu_dir, "BiasSpring", {"flange.s": s}, params={"k": 490.0, "preload": 1.5})
    assert r["flange.f"][0] == 1.5
    np.testing.assert_allclose(r["flange.f"], 1.5 + 490.0 * s, rtol=1e-15, atol=0)
    default = run(fmu_dir, "BiasSpring", {"flange.s": s})["flange.f"]
    assert default[0] == loads.PRELOAD_125MPA
    np.testing.assert_allclose(np.diff(default) / np.diff(s), 490.0, rtol=1e-9)


def test_dead_weight_off_is_m_g_exactly(fmu_dir):
    s = 1e-3 * np.sin(np.linspace(0, 20, 200))
    nominal = run(fmu_dir, "DeadWeight", {"flange.s": s})["flange.f"]
    off = run(fmu_dir, "DeadWeight", {"flange.s": s}, params={"inertia": 0.0})["flange.f"]
    assert np.array_equal(nominal, off)
    assert np.all(nominal == loads.WeightParams().mass * G)


def test_dead_weight_inertia_under_a_sinusoidal_lift(fmu_dir):
    """s = A sin(w t) sampled every h: the second difference is the acceleration one step old,
    -A w^2 sinc^2(w h / 2) sin(w t_(k-1)); the tension's oscillating part has amplitude m w^2 A
    within the one-step lag."""
    m, A, f, h = 0.15, 2e-3, 5.0, 1e-3
    w = 2 * math.pi * f
    t = np.arange(1001) * h
    s = A * np.sin(w * t)
    r = run(fmu_dir, "DeadWeight", {"flange.s": s}, dt=h, params={"mass": m, "inertia": 1.0})
    tension = r["flange.f"]
    assert np.all(tension[:2] == m * G)  # fewer than three points: no acceleration yet
    sinc2 = (math.sin(w * h / 2) / (w * h / 2)) ** 2
    hand = m * (G - A * w ** 2 * sinc2 * np.sin(w * t[1:-1]))
    # to the round-off of a second difference: ~eps A / h^2 m = 7e-14 N per unit of cancellation
    np.testing.assert_allclose(tension[2:], hand, rtol=0, atol=1e-10)
    # against the true inertia m (g + s''(t_k)): off by at most the one-step lag
    true = m * (G - A * w ** 2 * np.sin(w * t[2:]))
    assert np.max(np.abs(tension[2:] - true)) <= m * A * w ** 2 * (w * h + (1 - sinc2)) * 1.001
    amplitude = (tension[2:].max() - tension[2:].min()) / 2
    assert amplitude == pytest.approx(m * w ** 2 * A, rel=1e-3)


def test_dead_weight_acceleration_with_uneven_steps():
    # s = t^2 / 2 + t: acceleration 1 whatever the steps
    pts = [(t, t * t / 2 + t) for t in (0.0, 0.003, 0.004)]
    assert loads.acceleration(pts) == pytest.approx(1.0, rel=1e-9)
    assert loads.acceleration(pts[:2]) == 0.0


def test_coil_current_step_is_exact(fmu_dir):
    V, R, L, k_f, m_cal, h = 12.0, 24.0, 0.05, 2.0, 0.1, 4e-4
    n = 200
    # settled at duty 0 while initializing, then 0.5 from t = 0 on
    r = run(fmu_dir, "Electromagnet", {"duty": np.full(n + 1, 0.5), "flange.s": np.zeros(n + 1)},
            dt=h, outputs=("flange.f", "i"), init={"duty": 0.0})
    t = np.arange(n + 1) * h
    i = V * 0.5 / R * (1 - np.exp(-t * R / L))
    np.testing.assert_allclose(r["i"], i, rtol=0, atol=1e-12)
    np.testing.assert_allclose(r["flange.f"], m_cal * G + k_f * i, rtol=0, atol=1e-12)
    assert r["i"][0] == 0.0 and r["flange.f"][0] == m_cal * G  # no direct feedthrough of duty


def test_coil_starts_settled_and_nonlinearity_off_is_nominal(fmu_dir):
    n = 50
    duty = 0.3 + 0.2 * np.sin(np.arange(n) / 5)
    ins = {"duty": duty, "flange.s": np.zeros(n)}
    nominal = run(fmu_dir, "Electromagnet", ins, outputs=("flange.f", "i"))
    off = run(fmu_dir, "Electromagnet", ins, params={"nonlinearity": 0.0}, outputs=("flange.f", "i"))
    assert all(np.array_equal(nominal[k], off[k]) for k in nominal)
    assert nominal["i"][0] == 12.0 * 0.3 / 24.0
    on = run(fmu_dir, "Electromagnet", ins, params={"nonlinearity": 0.4}, outputs=("flange.f", "i"))
    assert np.array_equal(on["i"], nominal["i"])
    i = on["i"]
    np.testing.assert_allclose(on["flange.f"], 0.1 * G + 2.0 * i * (1 + 0.4 * i), rtol=1e-15)


def test_duty_outside_0_1_is_clamped_with_one_warning(fmu_dir):
    log = []
    duty = np.array([0.5, 1.7, 2.0, -0.3, 0.5])
    r = run(fmu_dir, "Electromagnet", {"duty": duty, "flange.s": np.zeros(5)}, log=log,
            outputs=("i",))
    clamped = np.clip(duty, 0, 1)
    p = loads.MagnetParams()
    i = [loads.coil_steady(clamped[0], p)]
    for k in range(4):
        i.append(loads.coil_step(i[-1], clamped[k], 1e-3, p))
    np.testing.assert_allclose(r["i"], i, rtol=0, atol=1e-15)
    assert len(log) == 1, log
    status, message = log[0]
    assert status == 1 and "duty 1.7" in message and "clamped to 1" in message  # fmi2Warning


@pytest.mark.parametrize("params, match", [
    ({"R": 0.0}, "R must be positive"), ({"L": -1.0}, "L must be positive"),
    ({"k_f": -2.0}, "k_f must be non-negative"), ({"nonlinearity": math.inf}, "nonlinearity"),
])
def test_bad_magnet_parameters_name_themselves(params, match):
    with pytest.raises(ValueError, match=match):
        loads.MagnetParams(**params).check()


def test_bad_weight_and_spring_parameters_name_themselves():
    with pytest.raises(ValueError, match=r"inertia must be within \[0, 1\]"):
        loads.WeightParams(inertia=1.5).check()
    with pytest.raises(ValueError, match="mass must be positive"):
        loads.WeightParams(mass=0.0).check()
    with pytest.raises(ValueError, match="k must be non-negative"):
        loads.SpringParams(k=-1.0).check()


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
