"""Loads of the SMA bench (components/loads/loads.py; §sma-bench, §position-control,
§capstan-multiplier) against hand solutions: the defaults' stresses, a weight riding a steady
lift, the link's exact transition, parameter errors."""
import math

import numpy as np
import pytest

from musclesim.components.loads import loads

G = 9.80665
AREA = 1.2667686977437442e-08  # m^2, SmaWire's cross-section pi (127 um)^2 / 4


def test_defaults_are_125_mpa_and_the_100_g_weight():
    assert loads.AREA == AREA
    assert loads.SpringParams().preload / AREA == pytest.approx(125e6, rel=1e-15)
    assert loads.WeightParams().mass * G / AREA == pytest.approx(125e6, rel=1e-15)
    p = loads.MagnetParams()
    lo, hi = loads.magnet_tension(0.0, p), loads.magnet_tension(loads.coil_steady(1.0, p), p)
    assert lo / AREA < 105e6 and hi / AREA > 145e6  # covers §position-control's stresses


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
