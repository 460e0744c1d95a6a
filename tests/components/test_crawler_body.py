"""Crawler body plant (components/crawler/body.py, §two-mass): matrices, zero-order hold,
momentum and gravity invariants."""
import math

import control as ct
import numpy as np
import pytest

from musclesim.components.crawler import body

UNEQUAL = body.BodyParams(m1=0.3, m2=0.2, k=150.0, c=0.9)


def test_state_space_is_spec_matrices():
    m1, m2, k, c = UNEQUAL.m1, UNEQUAL.m2, UNEQUAL.k, UNEQUAL.c
    A, B = body.state_space(UNEQUAL)
    np.testing.assert_array_equal(A, [[0, 1, 0, 0], [-k / m1, -c / m1, k / m1, c / m1],
                                      [0, 0, 0, 1], [k / m2, c / m2, -k / m2, -c / m2]])
    np.testing.assert_array_equal(B, [[0, 0, 0], [-1 / m1, 1 / m1, 0], [0, 0, 0], [1 / m2, 0, 1 / m2]])


def test_zoh_is_python_control_sample():
    A, B = body.state_space(UNEQUAL)
    sysd = ct.ss(A, B, np.eye(4), np.zeros((4, 3))).sample(1e-3, method="zoh")
    Ad, Bd = body.discretise(UNEQUAL, 1e-3)
    np.testing.assert_allclose(Ad, sysd.A, rtol=0, atol=1e-14)
    np.testing.assert_allclose(Bd[:, :3], sysd.B, rtol=0, atol=1e-14)


@pytest.mark.parametrize("h", [1e-3, 4e-4, 0.05])
def test_zoh_of_equal_masses_is_the_hand_solution(h):
    """Equal masses m, no ground drag: the centre of mass is a free mass ([[1, h], [0, 1]]) and the
    stretch r = x2 - x1 a damped oscillator, m r'' = -2 k r - 2 c r' + 2 f_a (§two-mass), so with
    w0^2 = 2 k / m, sigma = c / m, wd^2 = w0^2 - sigma^2 the hold matrices follow by hand: the free
    response e^(-sigma h) [[cos + sigma/wd sin, sin/wd], [-w0^2/wd sin, cos - sigma/wd sin]] and
    f_a's step response r = 2/(m w0^2) (1 - e^(-sigma h) (cos + sigma/wd sin)),
    r' = 2/m e^(-sigma h) sin/wd (the argument wd h)."""
    p = body.BodyParams()  # m1 = m2 = 0.2 kg, k = 200 N/m, c = 1.3 N s/m
    m, k, c = p.m1, p.k, p.c
    w0sq, sigma = 2 * k / m, c / m
    wd = math.sqrt(w0sq - sigma ** 2)
    e, cos, sin = math.exp(-sigma * h), math.cos(wd * h), math.sin(wd * h)
    free = e * np.array([[cos + sigma / wd * sin, sin / wd],
                         [-w0sq / wd * sin, cos - sigma / wd * sin]])
    # modal coordinates (x_cm, v_cm, r, r') = T x and back
    T = np.array([[0.5, 0, 0.5, 0], [0, 0.5, 0, 0.5], [-1, 0, 1, 0], [0, -1, 0, 1]])
    T_inv = np.array([[1, 0, -0.5, 0], [0, 1, 0, -0.5], [1, 0, 0.5, 0], [0, 1, 0, 0.5]])
    modal = np.zeros((4, 4))
    modal[:2, :2], modal[2:, 2:] = [[1.0, h], [0.0, 1.0]], free
    f_a_column = T_inv @ [0.0, 0.0, 2 / (m * w0sq) * (1 - e * (cos + sigma / wd * sin)),
                          2 / m * e * sin / wd]
    Ad, Bd = body.discretise(p, h)
    scale = np.array([[1.0], [w0sq ** 0.5], [1.0], [w0sq ** 0.5]])  # velocities ~ w0 positions
    np.testing.assert_allclose(Ad / scale, T_inv @ modal @ T / scale, rtol=0, atol=1e-14)
    np.testing.assert_allclose(Bd[:, 0], f_a_column, rtol=0, atol=1e-14 * np.abs(Bd[:, 0]).max())


@pytest.mark.parametrize("p", [body.BodyParams(), body.BodyParams(k_slope=0.02, c_ground=0.4)])
def test_mirrored_blocks_step_to_the_mirror_image_bit_for_bit(p):
    """Equal masses: swapping the blocks (x1 <-> -x2, v1 <-> -v2, f1 <-> -f2, f_a kept) steps to
    the mirror image exactly, not just to rounding, so a mirrored stick-slip run stays the
    mirror image (the gait's forward and backward runs, tests/cosim/test_gait_scenarios.py)."""
    rng = np.random.default_rng(5)
    for h, f_a in ((1e-3, 0.0), (4e-4, 7.3), (0.05, 2.0)):
        Ad, Bd = body.discretise(p, h, f_a)
        for _ in range(200):
            x, (f1, f2) = rng.standard_normal(4), rng.standard_normal(2)
            step = body.step_state(x, (f_a, f1, f2), Ad, Bd)
            mirrored = body.step_state(-x[[2, 3, 0, 1]], (f_a, -f2, -f1), Ad, Bd)
            assert np.array_equal(mirrored, -step[[2, 3, 0, 1]])


def test_actuator_alone_cannot_move_centre_of_mass():
    """Without friction, internal forces leave the centre of mass where it is (momentum)."""
    Ad, Bd = body.discretise(UNEQUAL, 1e-3)
    rng = np.random.default_rng(1)
    x = np.zeros(4)
    for f_a in rng.uniform(0.0, 20.0, 5000):
        x = body.step_state(x, (f_a, 0.0, 0.0), Ad, Bd)
        assert abs(body.centre_of_mass(x, UNEQUAL)) < 1e-12
    assert abs(x[0] - x[2]) > 1e-3  # the blocks did move relative to each other


def test_free_slide_on_incline_is_exact_parabola():
    """No friction, no actuation on an incline: x_cm = -g sin(theta) t^2 / 2 (ZOH is exact)."""
    p = body.BodyParams(theta=math.radians(10.0))
    Ad, Bd = body.discretise(p, 1e-3)
    x = np.zeros(4)
    for _ in range(1000):
        x = body.step_state(x, (0.0, 0.0, 0.0), Ad, Bd)
    assert body.centre_of_mass(x, p) == pytest.approx(-0.5 * body.G * math.sin(p.theta), rel=1e-9)


def test_nonfriction_forces_balance_without_gravity():
    f1, f2 = body.nonfriction_forces([0.01, 0.2, -0.01, 0.1], 3.0, UNEQUAL)
    assert f1 + f2 == pytest.approx(0.0, abs=1e-12)  # spring, damper and actuator are internal


@pytest.mark.parametrize("field, value", [("m1", 0.0), ("m2", -1.0), ("k", -1.0), ("c", -0.1),
                                          ("theta", 2.0)])
def test_parameter_check_names_the_parameter(field, value):
    with pytest.raises(ValueError, match=field):
        body.BodyParams(**{field: value}).check()


def test_ground_drag_decays_the_centre_of_mass_velocity_exponentially():
    """Equal masses, no friction: v_cm(t) = v0 exp(-c_ground t / m) (hand solution)."""
    p = body.BodyParams(c_ground=0.5)
    Ad, Bd = body.discretise(p, 1e-3)
    x = np.array([0.0, 0.1, 0.0, 0.1])
    for _ in range(1000):
        x = body.step_state(x, (0.0, 0.0, 0.0), Ad, Bd)
    assert (x[1] + x[3]) / 2 == pytest.approx(0.1 * math.exp(-0.5 * 1.0 / 0.2), rel=1e-9)


def test_force_dependent_stiffness_sets_the_static_stretch():
    """Held f_a = F without friction or gravity: the blocks settle F / k(F) apart."""
    p = body.BodyParams(k_slope=0.02, c=5.0)
    F = 10.0
    Ad, Bd = body.discretise(p, 1e-3, F)
    x = np.zeros(4)
    for _ in range(20000):
        x = body.step_state(x, (F, 0.0, 0.0), Ad, Bd)
    assert x[2] - x[0] == pytest.approx(F / (p.k * (1 + 0.02 * F)), rel=1e-9)
    assert body.stiffness(body.BodyParams(k_slope=-1.0), 5.0) == 0.0  # never negative


def test_effects_off_leave_the_nominal_plant():
    A0, B0 = body.state_space(body.BodyParams())
    A1, B1 = body.state_space(body.BodyParams(k_slope=0.0, c_ground=0.0), f_a=15.0)
    assert np.array_equal(A0, A1) and np.array_equal(B0, B1)
