"""Loads of the SMA wire (§sma-bench, §loads): bias spring, dead weight, electromagnet.

Sign convention (the SmaWire FMU's): s [m] is the wire's contraction, positive when the wire
shortens and lifts or pulls its load; f [N] is the tension the load puts on the wire. Equations:
§loads (docs/model/loads-sensors.md). Each parameter is declared once, in its dataclass
(`musclesim.fmu.declare`), with its unit, description, source and diagnosis role: the FMUs, the
docs' tables and the diagnosis read it there.

The equations are written once, as `jit` functions on numbers (the ``*_core`` functions), which the
functions on the dataclasses below and the FMUs' kernels (`musclesim.components.loads.slaves`)
call (the link's transition matrix through `fixedorder`'s compiled exponential).
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from musclesim.components import fixedorder
from musclesim.components.checks import require
from musclesim.fmu import declare, jit

G = 9.80665  # m/s^2, standard gravity
AREA = math.pi * 127e-6 ** 2 / 4  # m^2, the 127 um main wire (§sma-bench), as SmaWire computes it
PRELOAD_125MPA = 125e6 * AREA  # N, the bias spring's baseline stress of about 125 MPa (§loads)


def _require_finite(params, names):
    for name in names:
        if not math.isfinite(getattr(params, name)):
            raise ValueError(f"{name} must be a finite number (got {getattr(params, name)!r})")


@dataclass(frozen=True)
class SpringParams:
    """Preloaded bias spring (§loads: 490 N/m, baseline stress about 125 MPa)."""

    k: float = declare(490.0, "N/m", "Spring stiffness (the study's spring of the pulse-heating "
                       "test, 2.8 lbf/in)", source="§multiplier-experiments")
    preload: float = declare(PRELOAD_125MPA, "N", "Tension at zero contraction: about 125 MPa on "
                             "the 127 um wire, that spring's preload",
                             source="§multiplier-experiments")

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, non_negative=("k", "preload"))
        _require_finite(self, ("k", "preload"))


def spring_tension(s: float, p: SpringParams) -> float:
    """Tension [N] of the bias spring `p` stretched by the wire's contraction `s` [m].

    Examples
    --------
    >>> spring_tension(0.001, SpringParams(k=490.0, preload=1.5))
    1.99
    """
    return float(spring_core(s, p.k, p.preload))


@jit
def spring_core(s: float, k: float, preload: float) -> float:
    """Tension [N] of a spring of stiffness `k` and `preload` at contraction `s` [m]."""
    return preload + k * s


@dataclass(frozen=True)
class WeightParams:
    """Dead weight hanging from the wire on a springy link; default: 125 MPa on the wire (§loads,
    3.1). Quasi-static (tension m g) unless its inertia is on (effect)."""

    mass: float = declare(PRELOAD_125MPA / G, "kg", "Mass of the weight: 125 MPa on the 127 um "
                          "wire, the middle of the study's 105 to 145 MPa (the multiplier "
                          "scenarios set the study's 150 g)", source="§loads")
    g: float = declare(G, "m/s2", "Gravitational acceleration (standard gravity)")
    inertia: float = declare(0.0, "1", "Effect, 0 = off (tension m g): the share r in (0, 1] of "
                             "the weight moving on its link, the dynamics of a hanging load at "
                             "high frequency", source="§position-control, §named-effects",
                             effect=(0.0, 1.0))
    k_link: float = declare(300.0, "N/m", "Stiffness of the link from the wire to the weight "
                            "(assumption, the study gives none: soft enough for a stable "
                            "coupling with the wire, stiff enough to act as a weight; 7.1 Hz "
                            "with 150 g)", source="§loads")
    zeta: float = declare(0.02, "1", "Damping ratio of the weight's motion on its link "
                          "(assumption: lightly damped, the ringing of 150 g decays by 1/e in "
                          "about 1.1 s)")

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("mass", "k_link"), non_negative=("g", "zeta"))
        _require_finite(self, ("mass", "g", "k_link", "zeta"))
        if not 0.0 <= self.inertia <= 1.0:
            raise ValueError(f"inertia must be within [0, 1] (0 = off, 1 = the whole weight; "
                             f"got {self.inertia!r})")


def link_omega(p: WeightParams) -> float:
    """Natural angular frequency [rad/s] of the weight `p` on its link (whatever share moves)."""
    return math.sqrt(p.k_link / p.mass)


def link_transition(dt: float, p: WeightParams) -> list[list[float]]:
    """2x2 matrix (rows of floats) advancing (y, dy/dt) of y'' = -w^2 y - 2 zeta w y' of the
    weight `p` exactly over `dt`: its matrix exponential, taken in a fixed order of operations (no
    BLAS, whose kernel is chosen per CPU: the same bits on every CPU)."""
    phi = np.empty((2, 2))
    link_transition_into(link_omega(p), p.zeta, float(dt), phi)
    return phi.tolist()


@jit
def link_transition_into(omega: float, zeta: float, dt: float, phi: np.ndarray) -> None:
    """`phi` (2x2) = `link_transition` over `dt` [s] of the link of angular frequency `omega`
    [rad/s] and damping ratio `zeta`."""
    A = np.empty((2, 2))
    A[0, 0], A[0, 1], A[1, 0], A[1, 1] = 0.0, 1.0, -omega * omega, -2.0 * zeta * omega
    integral = np.empty((2, 2))
    fixedorder.exp_and_integral_into(A, dt, phi, integral)


def weight_step(x: float, v: float, s: float, u: float, phi: Sequence[Sequence[float]], dt: float,
                p: WeightParams) -> tuple[float, float]:
    """Position `x` [m] and velocity `v` [m/s] of the moving share of the weight `p` after `dt`,
    with `phi` = link_transition(dt, p) and the wire's end moving as `s` + `u` t over the step
    (u: its slope extrapolated).

    The share r = inertia of the weight hangs on r k_link, so any share rings alike:
    m x'' = k_link (s - x) - d x', d = 2 zeta w m (the weight's motion damped, not the link: a
    damper in series with the wire's quasi-static compliance closes a loop of gain
    compliance x d / step). For s linear in t, y = x - s + d u / k_link obeys the free equation,
    which phi advances exactly.

    Examples
    --------
    >>> p = WeightParams(mass=0.1, inertia=1.0)
    >>> weight_step(0.002, 0.0, 0.002, 0.0, link_transition(0.01, p), 0.01, p)  # at rest
    (0.002, 0.0)
    """
    x1, v1 = weight_step_core(x, v, s, u, phi[0][0], phi[0][1], phi[1][0], phi[1][1], dt, p.zeta,
                              link_omega(p))
    return float(x1), float(v1)


@jit
def weight_step_core(x: float, v: float, s: float, u: float, phi00: float, phi01: float,
                     phi10: float, phi11: float, dt: float, zeta: float,
                     omega: float) -> tuple[float, float]:
    """`weight_step` of the position `x` [m], velocity `v` [m/s], wire end `s` [m] and its slope
    `u` [m/s] over `dt` [s], with the transition's elements `phi00`, `phi01`, `phi10`, `phi11`,
    the damping ratio `zeta` and the link's angular frequency `omega` [rad/s]; the product as
    `fixedorder.matvec` sums it."""
    lag = 2.0 * zeta * u / omega  # d u / k_link: how far it trails a steady lift
    a, b = x - s + lag, v - u
    y, w = phi00 * a + phi01 * b, phi10 * a + phi11 * b
    return y + s + u * dt - lag, w + u


def weight_tension(x: float, s: float, p: WeightParams) -> float:
    """Tension [N] of the weight `p` on the wire: m g plus the moving share's pull inertia k_link
    (`s` - `x`) (exactly m g with the inertia off)."""
    return float(weight_tension_core(x, s, p.mass, p.g, p.inertia, p.k_link))


@jit
def weight_tension_core(x: float, s: float, mass: float, g: float, inertia: float,
                        k_link: float) -> float:
    """`weight_tension` at the position `x` [m] and wire end `s` [m] of the weight's fields
    `mass` [kg], `g` [m/s2], `inertia` and `k_link` [N/m]."""
    return mass * g + inertia * k_link * (s - x)


def weight_lift(x: float, s: float, p: WeightParams) -> float:
    """Lift [m] of the weight `p`: the wire's end `s` less the link's stretch beyond its static
    one, (tension - m g) / k_link = inertia (s - `x`); s exactly with the inertia off."""
    return float(weight_lift_core(x, s, p.inertia))


@jit
def weight_lift_core(x: float, s: float, inertia: float) -> float:
    """`weight_lift` at the position `x` [m] and wire end `s` [m] of the moving share
    `inertia`."""
    return s + inertia * (x - s)


@dataclass(frozen=True)
class MagnetParams:
    """Calibration weight plus an electromagnet driven by PWM (§sma-bench); coil values assumed."""

    m_cal: float = declare(0.1, "kg", "Calibration weight (the study's 100 g)",
                           source="§sma-bench")
    g: float = declare(G, "m/s2", "Gravitational acceleration (standard gravity)")
    V_supply: float = declare(12.0, "V", "Supply voltage switched by the PWM (assumption: a "
                              "common supply for a small coil switched by a transistor from an "
                              "Arduino)")
    R: float = declare(24.0, "Ohm", "Coil resistance (assumption: 0.5 A, 6 W at full duty, a "
                       "small coil's rating)")
    L: float = declare(0.05, "H", "Coil inductance (assumption: L/R = 2.1 ms, a small "
                       "iron-cored coil, fast against the loading profiles' 1/17 Hz at most)",
                       source="§reference-profiles")
    k_f: float = declare(2.0, "N/A", "Force per coil current (assumption: the duty range spans "
                         "77..156 MPa on the wire, covering the study's 105..145 MPa, for "
                         "which k_f V_supply / R must reach 0.86 N)", source="§loads")
    nonlinearity: float = declare(0.0, "1/A", "Effect, 0 = off (linear): force k_f i (1 + "
                                  "nonlinearity i); negative: saturation, positive: a gain "
                                  "growing as the gap closes", source="§loads, §named-effects",
                                  effect=(-0.5, 0.5))

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("R", "L"), non_negative=("m_cal", "g", "V_supply", "k_f"))
        _require_finite(self, ("m_cal", "g", "V_supply", "R", "L", "k_f", "nonlinearity"))


def coil_steady(duty: float, p: MagnetParams) -> float:
    """Steady coil current [A] of the magnet `p` under the PWM-averaged voltage V_supply `duty`."""
    return float(coil_steady_core(duty, p.V_supply, p.R))


@jit
def coil_steady_core(duty: float, V_supply: float, R: float) -> float:
    """`coil_steady` at the `duty` of the supply `V_supply` [V] and the coil's resistance `R`
    [Ohm]."""
    return V_supply * duty / R


def coil_step(i: float, duty: float, dt: float, p: MagnetParams) -> float:
    """Exact update of the current `i` of the magnet `p`, L di/dt = V_supply `duty` - R i, over
    `dt` with the duty held.

    Examples
    --------
    >>> p = MagnetParams()
    >>> round(coil_step(0.0, 1.0, 1.0, p), 12)  # settled after 1 s (L/R = 2.1 ms)
    0.5
    """
    return float(coil_step_core(i, duty, dt, p.V_supply, p.R, p.L))


@jit
def coil_step_core(i: float, duty: float, dt: float, V_supply: float, R: float,
                   L: float) -> float:
    """`coil_step` of the current `i` [A] over `dt` [s] at the `duty`, of the supply `V_supply`
    [V], the coil's `R` [Ohm] and `L` [H]."""
    i_inf = coil_steady_core(duty, V_supply, R)
    return i_inf + (i - i_inf) * math.exp(-dt * R / L)


def magnet_tension(i: float, p: MagnetParams) -> float:
    """Tension [N] of the magnet `p` at coil current `i`: the calibration weight plus the coil's
    pull k_f i (1 + nonlinearity i)."""
    return float(magnet_tension_core(i, p.m_cal, p.g, p.k_f, p.nonlinearity))


@jit
def magnet_tension_core(i: float, m_cal: float, g: float, k_f: float,
                        nonlinearity: float) -> float:
    """`magnet_tension` at the coil current `i` [A] of the magnet's fields `m_cal` [kg], `g`
    [m/s2], `k_f` [N/A] and `nonlinearity` [1/A]."""
    return m_cal * g + k_f * i * (1.0 + nonlinearity * i)
