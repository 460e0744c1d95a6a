"""Friction function of §friction (components/crawler/friction.py) against hand-derived cases,
the contact switching, the anchoring slip and the effects on the high coefficients (bending on
an incline, decay over time)."""
import math

import numpy as np
import pytest

from musclesim.components.crawler import body
from musclesim.components.crawler.friction import (FrictionParams, accumulate_slip,
                                                   advance_contact, coefficients, friction_force,
                                                   high_scale)
from musclesim.components.crawler.slaves import FrictionBlock

from component_runs import set_reals, started

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
    # normal force 1 N, mu_s = 1.0, mu_k = 0.75 (§friction high friction)
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
    """A block at rest on an incline holds while tan(theta) <= mu_s (§friction slip angles)."""
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
    assert steps == pytest.approx(400, abs=1)  # 0.4 s at 1 ms steps (§crawler-hardware)
    assert advance_contact(0.3, 0.0, 0.1, 0.4) == pytest.approx(0.05)
    assert advance_contact(0.05, 0.0, 0.1, 0.4) == 0.0


def test_slip_accumulates_only_while_high_and_sliding():
    dt = 1e-3
    assert accumulate_slip(0.5, -0.02, 1.0, dt, V_S) == 0.5 + 0.02 * dt  # high, sliding back
    assert accumulate_slip(0.5, 0.02, 0.5, dt, V_S) == 0.5 + 0.02 * dt  # contact counts high at 0.5
    assert accumulate_slip(0.5, 0.02, 0.49, dt, V_S) == 0.5  # low: the casing slides freely
    assert accumulate_slip(0.5, 0.9 * V_S, 1.0, dt, V_S) == 0.5  # inside the stick band


def test_bending_and_decay_scale_only_the_high_coefficients():
    p = FrictionParams(bending=2.0, mu_decay=0.1)
    theta, t = math.radians(7.5), 3.0
    scale = (1 - 2.0 * theta) * math.exp(-0.1 * t)
    assert high_scale(theta, t, p) == pytest.approx(scale, rel=1e-15)
    assert high_scale(-theta, t, p) == high_scale(theta, t, p)  # grows with the slope either way
    assert high_scale(1.0, 0.0, p) == 0.0  # no negative friction on a steep slope
    assert coefficients(1.0, p, scale) == pytest.approx((1.0 * scale, 0.75 * scale), rel=1e-15)
    assert coefficients(0.0, p, scale) == (0.13, 0.0975)  # the casing is unaffected
    # halfway through a switch the high part of the blend is scaled
    assert coefficients(0.5, p, scale)[0] == pytest.approx(0.13 + 0.5 * (scale - 0.13), rel=1e-15)


@pytest.mark.parametrize("theta", [0.0, 0.13])
def test_effects_off_are_nominal_bit_for_bit(theta):
    """Defaults: the scale is exactly 1, so the coefficients and forces equal the nominal ones."""
    p = FrictionParams()
    for s, t in zip([0.0, 0.3, 1.0, 0.7], [0.0, 1.7, 59.999, 1e6]):
        scale = high_scale(theta, t, p)
        assert scale == 1.0 and coefficients(s, p, scale) == coefficients(s, p)
    block, vr = started(FrictionBlock)
    rng = np.random.default_rng(3)
    for k, (v, f_n, u) in enumerate(rng.uniform([-2e-3, -3.0, 0.0], [2e-3, 3.0, 1.0], (200, 3))):
        u = float(u > 0.5)
        set_reals(block, vr, {"flange.v": v, "flange.f_n": f_n, "flange.N": 1.9, "u": u, "theta": theta})
        mu_s, mu_k = coefficients(u, p)
        assert block.get_real([vr["flange.f"]])[0] == friction_force(v, f_n, 1.9, mu_s, mu_k, p.v_s)
        block.do_step(1e-3 * k, 1e-3)
