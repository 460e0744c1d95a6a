"""The loads' FMUs (components/loads/slaves.py) against hand solutions: spring preload and slope,
a dead weight ringing on its link at the spring-mass period and feeling its inertia under a
sinusoidal lift, the coil's exact step response, the duty clamp, effects off = nominal exactly."""
import math

import numpy as np
import pytest

from musclesim.cosim import Signal
from musclesim.components.loads import loads
from component_runs import run_fmu

G = 9.80665


def test_bias_spring_preload_and_slope(fmu_dir):
    s = np.array([0.0, 1e-3, -5e-4, 2.2e-3])
    r = run_fmu(fmu_dir, "BiasSpring", {"flange.s": s}, params={"k": 490.0, "preload": 1.5})
    assert r["flange.f"][0] == 1.5
    np.testing.assert_allclose(r["flange.f"], 1.5 + 490.0 * s, rtol=1e-15, atol=0)
    default = run_fmu(fmu_dir, "BiasSpring", {"flange.s": s})["flange.f"]
    assert default[0] == loads.PRELOAD_125MPA
    np.testing.assert_allclose(np.diff(default) / np.diff(s), 490.0, rtol=1e-9)


def test_dead_weight_off_is_m_g_exactly(fmu_dir):
    s = 1e-3 * np.sin(np.linspace(0, 20, 200))
    nominal = run_fmu(fmu_dir, "DeadWeight", {"flange.s": s})["flange.f"]
    off = run_fmu(fmu_dir, "DeadWeight", {"flange.s": s}, params={"inertia": 0.0})["flange.f"]
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
    res = run_fmu(fmu_dir, "DeadWeight", {"flange.s": s}, dt=h, outputs=("flange.f", "lift"),
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
    half = run_fmu(fmu_dir, "DeadWeight", {"flange.s": s}, dt=h, outputs=("lift",),
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
        res = run_fmu(fmu_dir, "DeadWeight", {"flange.s": A * np.sin(w * t)}, dt=h,
                  params={"mass": m, "inertia": r, "k_link": k, "zeta": zeta})
        settled = res["flange.f"][t > 4.0] - m * G  # the transient decays as exp(-4.5 t / s)
        hand = r * k * A * abs((-m * w ** 2 + 1j * d * w) / (k - m * w ** 2 + 1j * d * w))
        assert (settled.max() - settled.min()) / 2 == pytest.approx(hand, rel=1e-3)


def test_coil_current_step_is_exact(fmu_dir):
    V, R, L, k_f, m_cal, h = 12.0, 24.0, 0.05, 2.0, 0.1, 4e-4
    n = 200
    # settled at duty 0 while initializing, then 0.5 from t = 0 on
    r = run_fmu(fmu_dir, "Electromagnet", {"duty": np.full(n + 1, 0.5), "flange.s": np.zeros(n + 1)},
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
    nominal = run_fmu(fmu_dir, "Electromagnet", ins, outputs=("flange.f", "i"))
    off = run_fmu(fmu_dir, "Electromagnet", ins, params={"nonlinearity": 0.0}, outputs=("flange.f", "i"))
    assert all(np.array_equal(nominal[k], off[k]) for k in nominal)
    assert nominal["i"][0] == 12.0 * 0.3 / 24.0
    on = run_fmu(fmu_dir, "Electromagnet", ins, params={"nonlinearity": 0.4}, outputs=("flange.f", "i"))
    assert np.array_equal(on["i"], nominal["i"])
    i = on["i"]
    np.testing.assert_allclose(on["flange.f"], 0.1 * G + 2.0 * i * (1 + 0.4 * i), rtol=1e-15)


def test_duty_outside_0_1_is_clamped_with_one_warning(fmu_dir):
    log = []
    duty = np.array([0.5, 1.7, 2.0, -0.3, 0.5])
    r = run_fmu(fmu_dir, "Electromagnet", {"duty": duty, "flange.s": np.zeros(5)}, log=log,
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


def test_dead_weight_inertia_in_the_wire_loop_is_stable(fmu_dir):
    """The 150 g weight ringing on its link under the wire's fast lift (sma-dead-weight, the whole
    mass moving): the tension swings by tenths of m g, smoothly from step to step (the explicit
    coupling with the wire's stress compliance does not chatter), and the lift trails the wire."""
    from conftest import SCENARIOS
    from musclesim.cosim import master, scenario

    s = scenario.load(SCENARIOS / "sma-dead-weight.toml", ["weight.inertia=1"], stop_time=2.0)
    res = master.Master(s, fmu_dir).run()
    assert res.error is None, res.error
    f, mg = res[Signal("weight", "flange.f")], 0.15 * G
    assert 0.1 * mg < f.max() - f.min() < mg  # it shows, and it stays a load
    assert np.max(np.abs(np.diff(f))) < 0.03 * mg  # omega h = 0.02: smooth, no step-to-step swing
    assert np.max(np.abs(res[Signal("weight", "lift")] - 0.1 * res[Signal("wire", "strain")])) > 1e-4


@pytest.mark.parametrize("name, params, inputs", [
    ("BiasSpring", {}, lambda k: {"flange_s": 1e-3 * math.sin(k / 7)}),
    ("DeadWeight", {"inertia": 0.7, "mass": 0.15}, lambda k: {"flange_s": 1e-3 * math.sin(k / 7)}),
    ("DeadWeight", {}, lambda k: {"flange_s": 1e-3 * math.sin(k / 7)}),
    ("Electromagnet", {"nonlinearity": 0.3},
     lambda k: {"duty": 0.5 + 0.7 * math.sin(k / 11), "flange_s": 0.0})])
def test_the_compiled_kernel_is_its_python_bit_for_bit(name, params, inputs):
    """Each load's compiled kernel gives the bits of its plain-Python source along a run (the
    dead weight ringing on its link, the magnet's duty swinging past its clamps)."""
    from conftest import in_process
    from kernel_paths import assert_paths_agree
    from musclesim.components.loads import slaves

    assert_paths_agree(in_process(getattr(slaves, name), name, **params), inputs, 4e-4, 600)
