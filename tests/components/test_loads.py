"""Loads of the SMA bench (§sma-bench, §position-control, §capstan-multiplier) and the load-cell and
laser sensors, through their FMUs against hand solutions: spring preload and slope, a dead weight
ringing on its link at the spring-mass period and feeling its inertia under a sinusoidal lift, the
coil's exact step response, the duty clamp, effects off = nominal exactly."""
import math
from types import SimpleNamespace

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from musclesim.cosim import host
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


def test_defaults_are_125_mpa_and_the_100_g_weight():
    assert loads.AREA == AREA
    assert loads.SpringParams().preload / AREA == pytest.approx(125e6, rel=1e-15)
    assert loads.WeightParams().mass * G / AREA == pytest.approx(125e6, rel=1e-15)
    p = loads.MagnetParams()
    lo, hi = loads.magnet_tension(0.0, p), loads.magnet_tension(loads.coil_steady(1.0, p), p)
    assert lo / AREA < 105e6 and hi / AREA > 145e6  # covers §position-control's stresses


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


def test_dead_weight_rings_at_the_spring_mass_period(fmu_dir):
    """The wire's end steps up by A and holds: the weight rings about A with the damped period
    2 pi / (w sqrt(1 - zeta^2)), w = sqrt(k_link / m), whatever share r of it moves (that share
    hangs on r k_link), its amplitude falling by exp(-2 pi zeta / sqrt(1 - zeta^2)) a period; the
    tension is m g + k_link (A - lift)."""
    m, r, k, zeta, A, h = 0.15, 0.8, 300.0, 0.05, 1e-3, 4e-4
    t = np.arange(5001) * h
    s = np.where(t > 0, A, 0.0)
    res = run(fmu_dir, "DeadWeight", {"flange.s": s}, dt=h, outputs=("flange.f", "lift"),
              params={"mass": m, "inertia": r, "k_link": k, "zeta": zeta})
    np.testing.assert_allclose(res["flange.f"], m * G + k * (s - res["lift"]), rtol=0, atol=1e-12)
    y = res["lift"][2:] - A  # free from the second step on (the first extrapolates the jump)
    tt = t[2:]
    up = np.flatnonzero((y[:-1] < 0) & (y[1:] >= 0))
    crossings = tt[up] - y[up] * h / (y[up + 1] - y[up])
    w = math.sqrt(k / m)
    period = 2 * math.pi / (w * math.sqrt(1 - zeta ** 2))
    assert np.diff(crossings) == pytest.approx(period, rel=1e-4)
    peaks = [y[(tt >= c) & (tt < c + period)].max() for c in crossings[:-1]]
    ratio = math.exp(-2 * math.pi * zeta / math.sqrt(1 - zeta ** 2))
    np.testing.assert_allclose(np.array(peaks[1:]) / peaks[:-1], ratio, rtol=2e-3)
    half = run(fmu_dir, "DeadWeight", {"flange.s": s}, dt=h, outputs=("lift",),
               params={"mass": m, "inertia": r / 2, "k_link": k, "zeta": zeta})["lift"]
    np.testing.assert_allclose(half[2:] - A, y / 2, rtol=0, atol=1e-15)  # linear in the share


def test_dead_weight_under_a_sinusoidal_lift_feels_its_inertia(fmu_dir):
    """s = A sin(w t): once settled, the tension's oscillating part is r k_link (s - x) with
    (S - X) / S = (-m w^2 + i d w) / (k_link - m w^2 + i d w): the inertia r m a of the moving
    share following the wire (r m w^2 A) and its motion's drag (r d w A), raised near the link's
    resonance; linear in the share r."""
    m, k, zeta, A, f, h = 0.15, 300.0, 0.1, 1e-3, 2.0, 4e-4
    w = 2 * math.pi * f
    d = 2 * zeta * math.sqrt(k * m)
    t = np.arange(15001) * h
    for r in (0.3, 1.0):
        res = run(fmu_dir, "DeadWeight", {"flange.s": A * np.sin(w * t)}, dt=h,
                  params={"mass": m, "inertia": r, "k_link": k, "zeta": zeta})
        settled = res["flange.f"][t > 4.0] - m * G  # the transient decays as exp(-4.5 t / s)
        hand = r * k * A * abs((-m * w ** 2 + 1j * d * w) / (k - m * w ** 2 + 1j * d * w))
        assert (settled.max() - settled.min()) / 2 == pytest.approx(hand, rel=1e-3)


def test_dead_weight_in_a_steady_lift_trails_by_its_damping():
    # riding along at the particular solution x = s - d U / k_link, v = U, for any steps: the
    # tension is m g + r d U (the damped motion's drag), nothing else
    p = loads.WeightParams(mass=0.15, inertia=0.5, k_link=300.0, zeta=0.1)
    U = 0.05
    lag = 2 * p.zeta * math.sqrt(p.k_link * p.mass) * U / p.k_link
    x, v, s = -lag, U, 0.0
    for dt in (4e-4, 1e-3, 2.5e-4, 3e-2):
        x, v = loads.weight_step(x, v, s, U, loads.link_transition(dt, p), dt, p)
        s += U * dt
        assert x == pytest.approx(s - lag, abs=1e-15) and v == pytest.approx(U, rel=1e-12)
    assert loads.weight_tension(x, s, p) == pytest.approx(p.mass * G + 0.5 * p.k_link * lag,
                                                          rel=1e-9)
    assert loads.weight_lift(x, s, p) == pytest.approx(s - 0.5 * lag, rel=1e-9)


@pytest.mark.parametrize("zeta", [0.0, 0.02, 1.0, 3.0])
def test_link_transition_is_the_damped_oscillators_hand_solution(zeta):
    """exp of [[0, 1], [-w^2, -2 zeta w]] dt by hand: e^(-zeta w t) times cos/sin (under-damped),
    1 + zeta w t (critical) or cosh/sinh (over-damped) terms (§loads); the fixed-order series
    that replaces scipy's expm gives it to rounding."""
    p = loads.WeightParams(mass=0.15, inertia=1.0, k_link=300.0, zeta=zeta)
    w = loads.link_omega(p)
    sigma = zeta * w
    for dt in (4e-4, 1e-3, 3e-2, 0.1):
        if zeta < 1:
            wd = w * math.sqrt(1 - zeta ** 2)
            c, s = math.cos(wd * dt), math.sin(wd * dt) / wd
        elif zeta == 1:
            c, s = 1.0, dt
        else:
            q = w * math.sqrt(zeta ** 2 - 1)
            c, s = math.cosh(q * dt), math.sinh(q * dt) / q
        hand = math.exp(-sigma * dt) * np.array([[c + sigma * s, s], [-w * w * s, c - sigma * s]])
        scale = np.abs(hand).max(axis=1, keepdims=True)  # per row: y and dy/dt differ by ~w
        np.testing.assert_allclose(np.array(loads.link_transition(dt, p)) / scale, hand / scale,
                                   rtol=0, atol=1e-14, err_msg=f"dt = {dt}")


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


def test_dead_weight_inertia_in_the_wire_loop_is_stable(fmu_dir):
    """The 150 g weight ringing on its link under the wire's fast lift (sma-dead-weight, the whole
    mass moving): the tension swings by tenths of m g, smoothly from step to step (the explicit
    coupling with the wire's stress compliance does not chatter), and the lift trails the wire."""
    from conftest import SCENARIOS
    from musclesim.cosim import master, scenario

    s = scenario.load(SCENARIOS / "sma-dead-weight.toml", ["weight.inertia=1"], stop_time=2.0)
    res = master.Master(s, fmu_dir).run()
    assert res.error is None, res.error
    f, mg = res["weight.flange.f"], 0.15 * G
    assert 0.1 * mg < f.max() - f.min() < mg  # it shows, and it stays a load
    assert np.max(np.abs(np.diff(f))) < 0.03 * mg  # omega h = 0.02: smooth, no step-to-step swing
    assert np.max(np.abs(res["weight.lift"] - 0.1 * res["wire.strain"])) > 1e-4
