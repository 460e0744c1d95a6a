"""Friction function of SPEC 1.3 against hand-derived cases, and the contact switching."""
import math

import pytest

from musclesim.components.crawler import body
from musclesim.components.crawler.friction import (FrictionParams, advance_contact, coefficients,
                                                    friction_force)

HIGH = FrictionParams()
V_S = HIGH.v_s


@pytest.mark.parametrize("v, f_n, expected", [
    pytest.param(0.0, 0.5, -0.5, id="stuck-holds-push"),
    pytest.param(0.0, -0.9, 0.9, id="stuck-holds-pull"),
    pytest.param(5e-4, 0.9, -0.9, id="stuck-inside-velocity-band"),
    pytest.param(0.0, 1.5, -0.75, id="slipping-from-rest-forward"),
    pytest.param(0.0, -1.5, 0.75, id="slipping-from-rest-backward"),
    pytest.param(0.01, -5.0, -0.75, id="kinetic-against-motion-not-force"),
    pytest.param(-0.01, 0.0, 0.75, id="kinetic-backward"),
])
def test_friction_cases(v, f_n, expected):
    # normal force 1 N, mu_s = 1.0, mu_k = 0.75 (SPEC 1.3 high friction)
    assert friction_force(v, f_n, 1.0, 1.0, 0.75, V_S) == pytest.approx(expected, abs=1e-15)


def test_breakaway_threshold_is_static_coefficient():
    N = 0.2 * body.G
    mu_s, mu_k = coefficients(0.0, HIGH)  # low friction: casing on the ground
    assert friction_force(0.0, mu_s * N, N, mu_s, mu_k, V_S) == -mu_s * N
    assert friction_force(0.0, mu_s * N * (1 + 1e-9), N, mu_s, mu_k, V_S) == pytest.approx(-mu_k * N)


@pytest.mark.parametrize("theta_deg, contact, holds", [
    pytest.param(7.0, 0.0, True, id="casing-holds-below-7.5deg"),
    pytest.param(8.0, 0.0, False, id="casing-slides-above-7.5deg"),
    pytest.param(30.0, 1.0, True, id="silicone-holds-at-30deg"),
    pytest.param(46.0, 1.0, False, id="silicone-slides-above-45deg"),
])
def test_incline_hold_or_slide(theta_deg, contact, holds):
    """A block at rest on an incline holds while tan(theta) <= mu_s (SPEC 1.3 slip angles)."""
    p = body.BodyParams(theta=math.radians(theta_deg), k=0.0, c=0.0)
    f_n1, _ = body.nonfriction_forces([0.0, 0.0, 0.0, 0.0], 0.0, p)
    N1, _ = body.normal_forces(p)
    mu_s, mu_k = coefficients(contact, HIGH)
    f = friction_force(0.0, f_n1, N1, mu_s, mu_k, V_S)
    if holds:
        assert f + f_n1 == pytest.approx(0.0, abs=1e-15)  # net force zero: the block stays
    else:
        assert f == pytest.approx(mu_k * N1) and f + f_n1 < 0  # slides down the slope


def test_coefficients_switch_between_low_and_high():
    assert coefficients(0.0, HIGH) == (0.13, 0.0975)
    assert coefficients(1.0, HIGH) == (1.0, 0.75)


def test_contact_jumps_without_switching_time_and_ramps_with_it():
    assert advance_contact(0.0, 1.0, 1e-3, 0.0) == 1.0
    s, steps = 0.0, 0
    while s < 1.0:
        s = advance_contact(s, 1.0, 1e-3, 0.4)
        steps += 1
    assert steps == pytest.approx(400, abs=1)  # 0.4 s at 1 ms steps (SPEC 1.1)
    assert advance_contact(0.3, 0.0, 0.1, 0.4) == pytest.approx(0.05)
    assert advance_contact(0.05, 0.0, 0.1, 0.4) == 0.0
