"""Stick-slip friction of a crawler block (§friction, Karnopp style) with switchable coefficients.

The indicator u in [0, 1] selects low (casing on the ground, 0) or high (inflated silicone, 1)
friction. With a switching time t_switch > 0 the contact state s follows u at a finite rate instead
of jumping (a candidate unmodelled effect; §crawler-hardware says switching takes up to 0.4 s). Two
more effects, off by default, lower the high (silicone) coefficients only: bending of the soft
actuator under shear on an incline, and contamination of the silicone over time (§gait,
§named-effects). The anchoring slip, the distance a block slides while its contact is high, is
accumulated here too.

The FMU's kernel (`KERNEL`, compiled where numba is installed: `musclesim.fmu.compiled`) runs the
same functions on arrays: parameters `pack`, state x = [s, slip], inputs u = [v, f_n, N, u,
theta], outputs y = [f, contact, stuck, slip].
"""
from __future__ import annotations

import math
from dataclasses import astuple, dataclass

import numpy as np

from musclesim.components.checks import require
from musclesim.fmu import Calibration, Kernel, declare, jit


@dataclass(frozen=True)
class FrictionParams:
    """Friction coefficients and numerics (defaults: §friction). Each parameter is declared once
    here (`declare`): the FMU, the docs' tables and the diagnosis's catalogues read it."""

    # the high coefficients are the effect "anchoring slip": off, they are the study's
    mu_s_high: float = declare(1.0, "1", "Static coefficient, high friction: the inflated "
                               "silicone (the study's slip angle on HDPE)", source="§friction",
                               effect=(0.2, 1.0))
    mu_k_high: float = declare(0.75, "1", "Kinetic coefficient, high friction: 0.75 mu_s_high, "
                               "the study's ratio", source="§friction", effect=(0.15, 0.75))
    # not the high ones: on a constant incline the effect "actuator bending on an incline" scales
    # them by a constant
    mu_s_low: float = declare(0.13, "1", "Static coefficient, low friction: the ABS casing (the "
                              "study's slip angle on HDPE)", source="§friction",
                              calibrate=Calibration(0.7, 1.3, True, "the ground's static "
                                                    "friction on the casing"))
    mu_k_low: float = declare(0.0975, "1", "Kinetic coefficient, low friction: 0.75 mu_s_low, "
                              "the study's ratio", source="§friction",
                              calibrate=Calibration(0.7, 1.3, True,
                                                    "the ground's kinetic friction"))
    v_s: float = declare(1e-3, "m/s", "Stick velocity band (the study's)", source="§friction")
    # effects, off by default (diagnosis candidates)
    t_switch: float = declare(0.0, "s", "Effect, 0 = off: low/high friction transition time "
                              "(the study switches at once; the robot takes up to 0.4 s)",
                              source="§crawler-hardware", effect=(0.0, 0.4))
    bending: float = declare(0.0, "1/rad", "Effect, 0 = off: high coefficients scaled by "
                             "max(0, 1 - bending |theta|): the soft actuator bends under shear on "
                             "an incline", source="§friction, §gait", effect=(0.0, 4.0))
    mu_decay: float = declare(0.0, "1/s", "Effect, 0 = off: high coefficients scaled by "
                              "exp(-mu_decay t): particles collect on the silicone and lower its "
                              "friction over time", source="§gait", effect=(0.0, 0.02))
    # a nuisance of the friction law's form, calibrated (stribeck 0 = the study's Karnopp law)
    stribeck: float = declare(0.0, "1", "Stribeck amplitude, 0 = off: while sliding, the kinetic "
                              "coefficient is mu_k + stribeck (mu_s - mu_k) exp(-(v / "
                              "v_stribeck)^2); 1 is LuGre's curve, the static coefficient fading "
                              "into the kinetic one as the block speeds up; below 0 friction "
                              "strengthens with speed",
                              source="§friction, bench form (LuGre's Stribeck curve: Canudas de "
                              "Wit et al., IEEE TAC 40, 1995)",
                              calibrate=Calibration(-0.5, 1.0, False, "the ground's Stribeck "
                                                    "curve: real friction falls from static to "
                                                    "kinetic over mm/s, not at once"))
    v_stribeck: float = declare(2e-3, "m/s", "Stribeck velocity of the curve `stribeck` scales "
                                "(a few mm/s, the order of LuGre's; no effect while stribeck is "
                                "0, so not calibrated: from there its sensitivity is nil)",
                                source="§friction, bench form (Canudas de Wit et al. 1995)")

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("v_s", "v_stribeck"),
                non_negative=("mu_s_high", "mu_k_high", "mu_s_low", "mu_k_low", "t_switch",
                              "bending", "mu_decay"))


def high_scale(theta: float, t: float, p: FrictionParams) -> float:
    """Factor on the high coefficients of `p` from bending on the incline `theta` [rad] and decay
    at time `t` [s].

    Exactly 1.0 with both effects off.

    Examples
    --------
    >>> high_scale(0.5, 10.0, FrictionParams())
    1.0
    >>> high_scale(-0.5, 0.0, FrictionParams(bending=1.0))
    0.5
    """
    return _high_scale(theta, t, p.bending, p.mu_decay)


@jit
def _high_scale(theta, t, bending, mu_decay):
    return max(0.0, 1.0 - bending * abs(theta)) * math.exp(-mu_decay * t)


def coefficients(s: float, p: FrictionParams, scale: float = 1.0) -> tuple[float, float]:
    """Static and kinetic coefficients of `p` at contact state `s` (0 = low, 1 = high
    friction), with the high coefficients multiplied by `scale` (see `high_scale`); the low ones
    are unaffected."""
    return coefficients_core(s, p.mu_s_high, p.mu_k_high, p.mu_s_low, p.mu_k_low, scale)


@jit
def coefficients_core(s: float, mu_s_high: float, mu_k_high: float, mu_s_low: float,
                      mu_k_low: float, scale: float) -> tuple[float, float]:
    """`coefficients` at contact state `s` of the coefficients `mu_s_high`, `mu_k_high`,
    `mu_s_low`, `mu_k_low`, the high ones times `scale`."""
    mu_s_high, mu_k_high = scale * mu_s_high, scale * mu_k_high
    return mu_s_low + s * (mu_s_high - mu_s_low), mu_k_low + s * (mu_k_high - mu_k_low)


def kinetic(v: float, p: FrictionParams, mu_s: float, mu_k: float) -> float:
    """The kinetic coefficient of `p` at velocity `v` [m/s] between the static `mu_s` and the
    kinetic `mu_k` (`stribeck_core`): mu_k itself with stribeck = 0.

    Examples
    --------
    >>> kinetic(0.01, FrictionParams(), 1.0, 0.75)
    0.75
    >>> round(kinetic(-2e-3, FrictionParams(stribeck=1.0), 1.0, 0.75), 12)  # 0.75 + 0.25/e
    0.841969860293
    """
    return stribeck_core(v, mu_s, mu_k, p.stribeck, p.v_stribeck)


@jit
def stribeck_core(v: float, mu_s: float, mu_k: float, amplitude: float,
                  v_stribeck: float) -> float:
    """The sliding coefficient at velocity `v` [m/s] of the Stribeck curve mu_k + `amplitude`
    (`mu_s` - `mu_k`) exp(-(v / `v_stribeck`)^2) (the LuGre model's at amplitude 1; Canudas de
    Wit et al. 1995); `mu_k` itself at amplitude 0."""
    if amplitude == 0.0:
        return mu_k
    r = v / v_stribeck
    return mu_k + amplitude * (mu_s - mu_k) * math.exp(-r * r)


@jit
def friction_force(v: float, f_n: float, normal: float, mu_s: float, mu_k: float,
                   v_s: float) -> float:
    """Friction force on a block (§friction).

    Parameters
    ----------
    v : float
        Block velocity along the surface [m/s].
    f_n : float
        Net non-friction force along the surface [N].
    normal : float
        Normal force [N].
    mu_s, mu_k : float
        Static and kinetic coefficients.
    v_s : float
        Velocity band below which the block counts as at rest [m/s].

    Returns
    -------
    float
        Friction force [N]: kinetic against the motion, or holding (-f_n) while stuck, or kinetic
        against f_n when f_n breaks away from rest.

    Examples
    --------
    >>> friction_force(0.0, 0.5, 1.0, 1.0, 0.75, 1e-3)
    -0.5
    >>> friction_force(0.0, 2.0, 1.0, 1.0, 0.75, 1e-3)
    -0.75
    >>> friction_force(-0.1, 2.0, 1.0, 1.0, 0.75, 1e-3)
    0.75
    """
    if abs(v) > v_s:
        return -math.copysign(mu_k * normal, v)
    if abs(f_n) <= mu_s * normal:
        return -f_n
    return -math.copysign(mu_k * normal, f_n)


@jit
def advance_contact(s: float, u: float, dt: float, t_switch: float) -> float:
    """Contact state `s` after `dt` [s]: jumps to the indicator `u` when `t_switch` == 0, else
    ramps towards u at 1/t_switch."""
    if t_switch <= 0.0:
        return u
    rate = dt / t_switch
    return min(u, s + rate) if u > s else max(u, s - rate)


@jit
def accumulate_slip(slip: float, v: float, contact: float, dt: float, v_s: float) -> float:
    """Anchoring `slip` after a step of `dt`: grows by |v| dt while the `contact` is high (>= 0.5)
    and the block slides (|`v`| > `v_s`); v and contact are the values at the start of the step.

    Examples
    --------
    >>> accumulate_slip(0.0, -0.01, 1.0, 0.1, 1e-3)
    0.001
    >>> accumulate_slip(0.0, -0.01, 0.0, 0.1, 1e-3)
    0.0
    """
    if contact >= 0.5 and abs(v) > v_s:
        return slip + abs(v) * dt
    return slip


def pack(p: FrictionParams) -> np.ndarray:
    """The kernel's parameters: `p`'s fields in their declared order (mu_s_high, mu_k_high,
    mu_s_low, mu_k_low, v_s, t_switch, bending, mu_decay, stribeck, v_stribeck)."""
    return np.array(astuple(p), dtype=float)


@jit
def evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """Kernel outputs `y` = [f, contact, stuck, slip] at state `x` = [s, slip], inputs `u` = [v,
    f_n, N, u, theta] and time `t` [s] (parameters `p` from `pack`)."""
    contact = u[3] if p[5] <= 0 else x[0]
    mu_s, mu_k = coefficients_core(contact, p[0], p[1], p[2], p[3], _high_scale(u[4], t, p[6], p[7]))
    if p[8] != 0.0:  # the Stribeck curve (the branch keeps stribeck = 0 to the bit)
        mu_k = stribeck_core(u[0], mu_s, mu_k, p[8], p[9])
    y[0] = friction_force(u[0], u[1], u[2], mu_s, mu_k, p[4])
    y[1] = contact
    y[2] = 1.0 if abs(u[0]) <= p[4] and abs(u[1]) <= mu_s * u[2] else 0.0
    y[3] = x[1]


@jit
def advance(p: np.ndarray, x: np.ndarray, u: np.ndarray, y: np.ndarray, t: float,
            dt: float) -> None:
    """Kernel step of the state `x` over [`t`, `t` + `dt`] [s] (parameters `p`, inputs `u`): the
    slip from the velocity and the contact (outputs `y`) at the step's start, the contact state
    towards the indicator."""
    x[1] = accumulate_slip(x[1], u[0], y[1], dt, p[4])
    x[0] = advance_contact(x[0], u[3], dt, p[5])


KERNEL = Kernel(evaluate, advance, inputs=("flange.v", "flange.f_n", "flange.N", "u", "theta"),
                outputs=("flange.f", "contact", "stuck", "slip"))
