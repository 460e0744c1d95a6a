"""The crawler's calibrated nuisances of the bench's form (issue 57): the central actuator's
hardening (body `k_hard`), the ground's Stribeck curve (friction `stribeck`), the valves'
subsonic index (actuator `m_sub`). Each against a hand-derived case; each default is today's
law to the bit; the crawler scenario's calibration table lists them with their bounds; the
kernels' compiled and plain-Python paths agree with them on."""
import math

import numpy as np
import pytest

from musclesim.components import declarations
from musclesim.components.crawler import body, friction
from musclesim.components.crawler.slaves import CrawlerBody, FrictionBlock
from musclesim.components.pneumatic import actuator as pa
from musclesim.cosim import load_scenario
from musclesim.diagnosis import effects

from conftest import SCENARIOS, in_process


def settle(p, F, steps=40000, dt=1e-3):
    """The body `p`'s kernel stepped `steps` times with the actuator force `F` held, no
    friction: its state after."""
    kp, kx, y = body.pack(p), body.initial_state(), np.zeros(10)
    u = np.array([F, 0.0, 0.0])
    for k in range(steps):
        body.advance(kp, kx, u, y, k * dt, dt)
    return kx[:4]


# -- the hardening ------------------------------------------------------------------------------
def test_hardening_settles_where_the_cubic_spring_balances_the_force():
    """Held F, no friction or gravity: the blocks settle at the stretch e with
    k e (1 + k_hard (e / 4 cm)^2) = F. With k = 200 N/m, k_hard = 0.25 and F = 10 N that is
    e = 4 cm by hand (200 * 0.04 * 1.25 = 10); the linear spring would give 5 cm."""
    p = body.BodyParams(k_hard=0.25, c=5.0, theta=0.0)
    x = settle(p, 10.0)
    assert x[2] - x[0] == pytest.approx(0.04, rel=1e-9)
    assert x[1] == pytest.approx(0.0, abs=1e-12) and x[3] == pytest.approx(0.0, abs=1e-12)
    assert settle(body.BodyParams(c=5.0), 10.0)[2] - settle(body.BodyParams(c=5.0), 10.0)[0] \
        == pytest.approx(0.05, rel=1e-9)
    softer = settle(body.BodyParams(k_hard=-0.1, c=5.0), 5.0)  # 200 e (1 - 0.1 (e/0.04)^2) = 5
    e = softer[2] - softer[0]
    assert e > 0.025 and 200.0 * e * (1 - 0.1 * (e / 0.04) ** 2) == pytest.approx(5.0, rel=1e-9)


def test_hardening_enters_the_non_friction_forces():
    """f_n1 = -k d (1 + k_hard (d / D)^2) - c (v1 - v2) - f_a - m1 g sin(theta), d = x1 - x2 (by
    hand at d = -3 cm, k_hard = 0.2: the spring's 6 N grows by 0.2 * 0.5625 = 11.25 %)."""
    p = body.BodyParams(k_hard=0.2, theta=0.1)
    x = [0.01, 0.05, 0.04, -0.02]
    f1, f2 = body.nonfriction_forces(x, 2.0, p)
    spring = 200.0 * -0.03 * (1 + 0.2 * 0.5625)
    slope = 9.81 * math.sin(0.1)
    assert f1 == pytest.approx(-spring - 1.3 * 0.07 - 2.0 - 0.2 * slope, rel=1e-12)
    assert f2 == pytest.approx(spring + 1.3 * 0.07 + 2.0 - 0.2 * slope, rel=1e-12)
    assert body.hardening(x, p) == pytest.approx(200.0 * 0.2 * 0.5625 * -0.03, rel=1e-12)
    # the force-dependent stiffness effect scales the hardening with k
    assert body.hardening(x, body.BodyParams(k_hard=0.2, k_slope=0.01), 10.0) == pytest.approx(
        1.1 * body.hardening(x, p), rel=1e-12)


def test_hardening_off_is_the_linear_body_to_the_bit():
    """k_hard = 0 (the default): advance is the hold step of the linear plant with f_a itself,
    and the forces are the linear spring's, bit for bit."""
    p = body.BodyParams(theta=0.13)
    assert p.k_hard == 0.0 and body.hardening([0.01, 0, -0.02, 0], p) == 0.0
    kp, kx, y = body.pack(p), body.initial_state(), np.zeros(10)
    Ad, Bd = body.discretise(p, 1e-3)
    x = np.zeros(4)
    rng = np.random.default_rng(5)
    for k, (f_a, f1, f2) in enumerate(rng.uniform(-5, 5, (300, 3))):
        u = np.array([f_a, f1, f2])
        body.advance(kp, kx, u, y, k * 1e-3, 1e-3)
        x = body.step_state(x, u, Ad, Bd)
        assert kx[:4].tobytes() == x.tobytes()
        f_spring = p.k * (x[0] - x[2]) + p.c * (x[1] - x[3])
        assert body.nonfriction_forces(x, f_a, p)[0] == -f_spring - f_a - p.m1 * kp[body.SLOPE]


# -- the Stribeck curve -------------------------------------------------------------------------
def test_the_stribeck_curve_by_hand():
    """Sliding at v: mu = mu_k + stribeck (mu_s - mu_k) exp(-(v / v_stribeck)^2). Low contact
    (0.13, 0.0975) at v = -v_stribeck = -2 mm/s on N = 1.9 N: f = +(0.0975 + 0.0325 / e) 1.9 at
    amplitude 1, +(0.0975 - 0.5 * 0.0325 / e) 1.9 at -0.5 (friction strengthening with speed)."""
    p = friction.FrictionParams(stribeck=1.0, v_stribeck=2e-3)
    kp, y = friction.pack(p), np.zeros(4)
    friction.evaluate(kp, np.array([0.0, 0.0]), np.array([-2e-3, 0.3, 1.9, 0.0, 0.0]), 0.0, y)
    assert y[0] == pytest.approx((0.0975 + 0.0325 / math.e) * 1.9, rel=1e-12)
    # fast: the kinetic coefficient; within the stick band: holding, as without the curve
    friction.evaluate(kp, np.array([0.0, 0.0]), np.array([0.05, 0.3, 1.9, 0.0, 0.0]), 0.0, y)
    assert y[0] == pytest.approx(-0.0975 * 1.9 * (1 + (0.0325 / 0.0975) * math.exp(-625)),
                                 rel=1e-12)
    friction.evaluate(kp, np.array([0.0, 0.0]), np.array([5e-4, 0.2, 1.9, 0.0, 0.0]), 0.0, y)
    assert y[0] == -0.2 and y[2] == 1.0
    # breaking away from rest: the curve at v = 0 is the static coefficient
    friction.evaluate(kp, np.array([0.0, 0.0]), np.array([0.0, 0.3, 1.9, 0.0, 0.0]), 0.0, y)
    assert y[0] == pytest.approx(-0.13 * 1.9, rel=1e-12)
    weaker = friction.pack(friction.FrictionParams(stribeck=-0.5, v_stribeck=2e-3))
    friction.evaluate(weaker, np.array([0.0, 0.0]), np.array([-2e-3, 0.3, 1.9, 0.0, 0.0]), 0.0, y)
    assert y[0] == pytest.approx((0.0975 - 0.5 * 0.0325 / math.e) * 1.9, rel=1e-12)


@pytest.mark.parametrize("theta", [0.0, 0.13])
def test_stribeck_off_is_the_karnopp_law_to_the_bit(theta):
    p = friction.FrictionParams()
    assert p.stribeck == 0.0
    kp, y = friction.pack(p), np.zeros(4)
    rng = np.random.default_rng(7)
    for v, f_n, u in rng.uniform([-5e-3, -3.0, 0.0], [5e-3, 3.0, 1.0], (300, 3)):
        u = float(u > 0.5)
        friction.evaluate(kp, np.array([u, 0.0]), np.array([v, f_n, 1.9, u, theta]), 0.0, y)
        mu_s, mu_k = friction.coefficients(u, p)
        assert y[0] == friction.friction_force(v, f_n, 1.9, mu_s, mu_k, p.v_s)
        assert friction.kinetic(v, p, mu_s, mu_k) == mu_k


# -- the subsonic index -------------------------------------------------------------------------
def test_the_subsonic_index_by_hand():
    """ISO 6358-1: q = C p_up rho_0 (1 - x^2)^m, x = (r - b) / (1 - b). At p_up = 200 kPa, r =
    0.75, b = 0.3: q_choked = 1.185e-4 kg/s, 1 - x^2 = 1 - (0.45 / 0.7)^2 = 0.58673469..."""
    C, b = 5e-10, 0.3
    y = 1 - (0.45 / 0.7) ** 2
    for m in (0.35, 0.5, 0.8, 1.0):
        assert pa.mass_flow(200e3, 150e3, C, b, m=m) == pytest.approx(1.185e-4 * y ** m,
                                                                       rel=1e-12)
    assert pa.mass_flow(200e3, 150e3, C, b, m=1.0) == pytest.approx(6.952806e-5, rel=1e-6)
    # choked and at equal pressures the index changes nothing
    for m in (0.35, 0.8):
        assert pa.mass_flow(200e3, 50e3, C, b, m=m) == pa.mass_flow(200e3, 50e3, C, b)
        assert pa.mass_flow(200e3, 200e3, C, b, m=m) == 0.0
        assert pa.signed_flow(150e3, 200e3, C, b, m=m) == -pa.mass_flow(200e3, 150e3, C, b, m=m)


def run_actuator(params, duties):
    """Pressures of an actuator `params` driven by `duties` at 1 ms, its kernel's path."""
    kp = pa.pack(params)
    x, y = pa.start_state(kp), np.zeros(4)
    out = []
    for k, duty in enumerate(duties):
        pa.advance(kp, x, np.array([duty, 0.0, 0.0]), y, k * 1e-3, 1e-3)
        out.append(x[pa.PRESSURE])
    return np.array(out)


def test_the_subsonic_index_shapes_the_filling():
    """m_sub 0.5 (the default) is the ellipse, math.sqrt's to the bit; a smaller index keeps the
    flow higher near equal pressures, so the chamber fills faster towards the supply."""
    C, b = 5e-10, 0.3
    for p_down in np.linspace(0.31, 0.999, 50) * 200e3:
        x = (p_down / 200e3 - b) / (1 - b)
        assert pa.mass_flow(200e3, p_down, C, b) == C * 200e3 * pa.RHO_0 * math.sqrt(1 - x * x)
    duties = np.r_[np.full(400, 1.0), np.full(100, 0.0), np.full(300, -1.0)]
    nominal = run_actuator(pa.ActuatorParams(), duties)
    assert run_actuator(pa.ActuatorParams(m_sub=0.5), duties).tobytes() == nominal.tobytes()
    low = run_actuator(pa.ActuatorParams(m_sub=0.35), duties)
    assert np.all(low[:400] >= nominal[:400]) and low[399] > nominal[399] + 1e3
    assert low.max() <= 40e3 and low[-1] < low[499]  # bounded by the supply, exhausted after
    with pytest.raises(ValueError, match="m_sub"):
        pa.ActuatorParams(m_sub=0.0).check()


# -- the calibration table and the kernels' paths ------------------------------------------------
NUISANCES = {("CrawlerBody", "k_hard"): (-0.1, 0.3, False),
             ("FrictionBlock", "stribeck"): (-0.5, 1.0, False),
             ("SoftActuator", "m_sub"): (0.5, 1.6, True)}


def test_the_crawler_calibration_lists_the_nuisances_with_their_bounds():
    """The gait scenarios' instances (the independent bench's cases are diagnosed on
    crawler-gait-incline) calibrate each nuisance within its documented bounds around its
    nominal value: the default, which the FMU declares."""
    s = load_scenario(SCENARIOS / "crawler-gait-incline.toml")
    table = {}
    for inst, spec in s.instances.items():
        for c in effects.calibration_of(spec.component):
            nominal = spec.parameters.get(c.name, declarations(spec.component)[c.name].default)
            table[spec.component, inst, c.name] = c.bounds(float(nominal))
    expected = {("CrawlerBody", "body", "k_hard"): (-0.1, 0.3),
                ("FrictionBlock", "friction1", "stribeck"): (-0.5, 1.0),
                ("FrictionBlock", "friction2", "stribeck"): (-0.5, 1.0)}
    for inst in ("act1", "actc", "act2"):
        expected["SoftActuator", inst, "m_sub"] = (0.25, 0.8)
    for key, bounds in expected.items():
        assert table[key] == pytest.approx(bounds, rel=1e-12), key
        # strictly around the nominal value, where each acts to first order (a local fit from
        # there moves it)
        nominal = declarations(key[0])[key[2]].default
        assert bounds[0] < nominal < bounds[1]
    assert table["CrawlerBody", "body", "k"] == pytest.approx((140.0, 260.0))  # still there
    for (component, name), (lower, upper, relative) in NUISANCES.items():
        c = {c.name: c for c in effects.calibration_of(component)}[name]
        assert (c.lower, c.upper, c.relative) == (lower, upper, relative)
        assert "bench form" in c.reference and c.why
        d = declarations(component)[name]
        assert d.causality == "parameter" and d.effect is None and d.unit in ("1", "m/s")


def test_the_kernels_agree_compiled_and_as_python_with_the_nuisances_on():
    from kernel_paths import assert_paths_agree

    rng = np.random.default_rng(11)
    forces = rng.uniform(-6, 6, (400, 3))
    assert_paths_agree(in_process(CrawlerBody, "body", k_hard=0.2, theta=0.13),
                       lambda k: {"f_a": forces[k, 0], "flange_a_f": forces[k, 1],
                                  "flange_b_f": forces[k, 2]}, 1e-3, 400)
    flows = rng.uniform([-4e-3, -3.0, 0.0], [4e-3, 3.0, 1.0], (400, 3))
    assert_paths_agree(in_process(FrictionBlock, "friction", stribeck=0.7),
                       lambda k: {"flange_v": flows[k, 0], "flange_f_n": flows[k, 1],
                                  "flange_N": 1.9, "u": float(flows[k, 2] > 0.5)}, 1e-3, 400)
