"""Loads of the SMA wire (SPEC 2.1, 2.4, 3.1): bias spring, dead weight, electromagnet.

Sign convention (the SmaWire FMU's): s [m] is the wire's contraction, positive when the wire
shortens and lifts or pulls its load; f [N] is the tension the load puts on the wire. Equations
and where every default comes from: components/loads/README.md.
"""
import math
from dataclasses import dataclass

from musclesim.components.checks import require

G = 9.80665  # m/s^2, standard gravity
AREA = math.pi * 127e-6 ** 2 / 4  # m^2, the 127 um main wire (SPEC 2.1), as SmaWire computes it
PRELOAD_125MPA = 125e6 * AREA  # N, the bias spring's baseline stress of about 125 MPa (SPEC 3.1)


def _require_finite(params, names):
    for name in names:
        if not math.isfinite(getattr(params, name)):
            raise ValueError(f"{name} must be a finite number (got {getattr(params, name)!r})")


@dataclass(frozen=True)
class SpringParams:
    """Preloaded bias spring (SPEC 3.1: 490 N/m, baseline stress about 125 MPa)."""

    k: float = 490.0  # N/m
    preload: float = PRELOAD_125MPA  # N, tension at s = 0

    def check(self):
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, non_negative=("k", "preload"))
        _require_finite(self, ("k", "preload"))


def spring_tension(s, p):
    """Tension [N] of the bias spring stretched by the wire's contraction s [m].

    Examples
    --------
    >>> spring_tension(0.001, SpringParams(k=490.0, preload=1.5))
    1.99
    """
    return p.preload + p.k * s


@dataclass(frozen=True)
class WeightParams:
    """Dead weight hanging from the wire; default: 125 MPa on the wire (SPEC 2.4, 3.1)."""

    mass: float = PRELOAD_125MPA / G  # kg
    g: float = G  # m/s^2
    inertia: float = 0.0  # effect: share of the weight's inertia the wire feels, 0 = off (m g)
                          # .. 1 = the whole weight (m (g + a))

    def check(self):
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("mass",), non_negative=("g",))
        _require_finite(self, ("mass", "g"))
        if not 0.0 <= self.inertia <= 1.0:
            raise ValueError(f"inertia must be within [0, 1] (0 = off, 1 = the whole weight; "
                             f"got {self.inertia!r})")


def acceleration(points):
    """Acceleration [m/s^2] from the last three (t, s) points: the second difference with the
    steps actually taken (the acceleration at the middle point, one step old); 0 with fewer points.

    Examples
    --------
    >>> acceleration([(0.0, 0.0), (0.5, 0.25), (1.5, 2.25)])  # s = t^2, uneven steps
    2.0
    """
    if len(points) < 3:
        return 0.0
    (t0, s0), (t1, s1), (t2, s2) = points[-3:]
    return 2.0 * ((s2 - s1) / (t2 - t1) - (s1 - s0) / (t1 - t0)) / (t2 - t0)


def weight_tension(a, p):
    """Tension [N] of the dead weight lifted with acceleration a [m/s^2] (a is ignored when the
    inertia effect is off)."""
    return p.mass * (p.g + p.inertia * a) if p.inertia else p.mass * p.g


@dataclass(frozen=True)
class MagnetParams:
    """Calibration weight plus an electromagnet driven by PWM (SPEC 2.1); coil values assumed."""

    m_cal: float = 0.1  # kg, the 100 g calibration weight (SPEC 2.1)
    g: float = G  # m/s^2
    V_supply: float = 12.0  # V, assumption
    R: float = 24.0  # Ohm, assumption
    L: float = 0.05  # H, assumption
    k_f: float = 2.0  # N/A, assumption: full duty adds 1.0 N (77..156 MPa on the wire)
    nonlinearity: float = 0.0  # 1/A, effect: 0 = off (force linear in the current)

    def check(self):
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("R", "L"), non_negative=("m_cal", "g", "V_supply", "k_f"))
        _require_finite(self, ("m_cal", "g", "V_supply", "R", "L", "k_f", "nonlinearity"))


def coil_steady(duty, p):
    """Steady coil current [A] of the PWM-averaged voltage V_supply duty."""
    return p.V_supply * duty / p.R


def coil_step(i, duty, dt, p):
    """Exact update of L di/dt = V_supply duty - R i over dt with the duty held.

    Examples
    --------
    >>> p = MagnetParams()
    >>> round(coil_step(0.0, 1.0, 1.0, p), 12)  # settled after 1 s (L/R = 2.1 ms)
    0.5
    """
    i_inf = coil_steady(duty, p)
    return i_inf + (i - i_inf) * math.exp(-dt * p.R / p.L)


def magnet_tension(i, p):
    """Tension [N]: the calibration weight plus the coil's pull k_f i (1 + nonlinearity i)."""
    return p.m_cal * p.g + p.k_f * i * (1.0 + p.nonlinearity * i)
