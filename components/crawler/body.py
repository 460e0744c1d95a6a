"""Crawler body: the two-mass, spring, damper plant of §two-mass and its zero-order-hold
discretisation.

State x = [x1, v1, x2, v2] (positions are variations from rest, climbing is positive x);
input u = [f_a, f1, f2] (actuator force pushing the blocks apart, friction on block 1 and 2).
The same `state_space` serves the FMU, the monolithic reference simulation and the linear analysis.

The FMU's kernel (`KERNEL`, compiled where numba is installed: `musclesim.fmu.compiled`):
parameters `pack`; state [x1, v1, x2, v2, the step and the held force the hold matrices were
made for, Ad (16 values), Bd (16)]; inputs u = [f_a, f1, f2]; outputs y = [s1, v1, f_n1, N1, s2,
v2, f_n2, N2, x_cm, incline].
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import astuple, dataclass

import numpy as np

from musclesim.components import fixedorder
from musclesim.components.checks import require
from musclesim.fmu import Calibration, Kernel, declare, jit

G = 9.81  # m/s^2


@dataclass(frozen=True)
class BodyParams:
    """Crawler body parameters (defaults: §ideal-actuation, flat ground). Each parameter is
    declared once here (`declare`): the FMU, the docs' tables and the diagnosis's catalogues read
    it."""

    m1: float = declare(0.2, "kg", "Mass of the rear block 1 (the study's simulation; on the "
                        "hardware an extremal actuator, its casing, its steel plate and half the "
                        "central actuator make 0.19 kg)",
                        source="§ideal-actuation, §crawler-hardware")
    m2: float = declare(0.2, "kg", "Mass of the front block 2 (as block 1)",
                        source="§ideal-actuation, §crawler-hardware")
    k: float = declare(200.0, "N/m", "Stiffness of the central actuator, from its tensile test; "
                       "the real one is nonlinear and depends on the pressure (see k_slope)",
                       source="§ideal-actuation", calibrate=Calibration(
                           0.7, 1.3, True, "the soft actuator's stiffness"))
    c: float = declare(1.3, "N.s/m", "Damping of the central actuator (the study's simulation "
                       "value; it gives no separate measurement)", source="§ideal-actuation",
                       calibrate=Calibration(0.5, 2.0, True, "the soft actuator's damping"))
    theta: float = declare(0.0, "rad", "Incline of the ground, climbing positive, within "
                           "(-pi/2, pi/2) (flat; the incline scenario sets 7.5 deg, 0.1309 rad)",
                           source="§two-mass")
    # effects, off by default (diagnosis candidates)
    k_slope: float = declare(0.0, "1", "Effect, 0 = off: relative stiffness change per newton of "
                             "actuator force [1/N]: the real stiffness is nonlinear and pressure "
                             "dependent", source="§two-mass, §named-effects",
                             effect=(-0.04, 0.04))
    c_ground: float = declare(0.0, "N.s/m", "Effect, 0 = off: viscous drag of the ground on "
                              "each block", source="§named-effects", effect=(0.0, 5.0))
    # a nuisance of the spring's form, calibrated (0 = the study's linear spring)
    k_hard: float = declare(0.0, "1", "Hardening of the central actuator: its spring force is "
                            "k d (1 + k_hard (d / 4 cm)^2) at the deflection d = x1 - x2, "
                            "k_hard the share it is stiffer at 4 cm, about its stroke at the "
                            "gait's pressure (a silicone tube stiffens as it stretches); the "
                            "cubic part is taken at the step's start and held over it",
                            source="§two-mass, bench form (a hardening spring)",
                            calibrate=Calibration(-0.1, 0.3, False, "the soft actuator's "
                                                  "stiffening with its deflection: the tensile "
                                                  "test's line is a secant"))

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its physical range."""
        require(self, positive=("m1", "m2"), non_negative=("k", "c", "c_ground"))
        if not math.isfinite(self.k_hard):
            raise ValueError(f"k_hard must be a finite number (got {self.k_hard!r})")
        if not abs(self.theta) < math.pi / 2:
            raise ValueError(f"theta must lie in (-pi/2, pi/2) rad (got {self.theta!r})")


def stiffness(p: BodyParams, f_a: float = 0.0) -> float:
    """Actuator stiffness of the body `p` at actuator force `f_a`: k (1 + k_slope f_a), never
    below zero."""
    return _stiffness(pack(p), f_a)


# the kernel's parameters (`pack`): the fields, then constants derived from them
M1, M2, K, C, THETA, K_SLOPE, C_GROUND, K_HARD, N1, N2, SLOPE = range(11)
D_HARD = 0.04  # m: the deflection at which k_hard is the spring's stiffening


def pack(p: BodyParams) -> np.ndarray:
    """The kernel's parameters: `p`'s fields in their declared order (m1, m2, k, c, theta,
    k_slope, c_ground, k_hard), then the normal forces N1, N2 and g sin(theta)."""
    return np.array([*astuple(p), *normal_forces(p), G * math.sin(p.theta)], dtype=float)


@jit
def _stiffness(p, f_a):
    return max(0.0, p[K] * (1.0 + p[K_SLOPE] * f_a))


def hardening(x: Sequence[float] | np.ndarray, p: BodyParams, f_a: float = 0.0) -> float:
    """The cubic part k k_hard (d / D_HARD)^2 d [N] of the central actuator's spring force of
    the body `p` in state `x` (d = x1 - x2), k at actuator force `f_a` (`stiffness`); exactly 0.0
    with k_hard = 0.

    Examples
    --------
    >>> hardening([0.0, 0.0, -0.04, 0.0], BodyParams(k_hard=0.1))  # 0.1 * 200 N/m * 4 cm
    0.8
    """
    return hardening_core(np.asarray(x, dtype=float), pack(p), f_a)


@jit
def hardening_core(x: np.ndarray, p: np.ndarray, f_a: float) -> float:
    """`hardening` of the state `x` at actuator force `f_a` [N], the packed parameters `p`: the
    linear spring's extra force, which acts as the actuator force does (pushing the blocks apart
    when negative)."""
    if p[K_HARD] == 0.0:
        return 0.0
    d = x[0] - x[2]
    r = d / D_HARD
    return _stiffness(p, f_a) * p[K_HARD] * r * r * d


def state_space(p: BodyParams, f_a: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Continuous plant of §two-mass of the body `p`: return (A, B) with B's columns for f_a,
    f1, f2.

    With the effects on, k is the stiffness at actuator force `f_a` and each block also feels
    the ground's viscous drag -c_ground v_i.
    """
    A, B = _state_space(pack(p), f_a)
    return A, B[:, :3]


@jit
def _state_space(p, f_a):
    """(A, B) of `state_space`, B with the gravity column as its fourth."""
    m1, m2, k, c, cg = p[M1], p[M2], _stiffness(p, f_a), p[C], p[C_GROUND]
    A, B = np.zeros((4, 4)), np.zeros((4, 4))  # element by element: quicker to compile
    A[0, 1] = A[2, 3] = 1.0
    A[1, 0], A[1, 1], A[1, 2], A[1, 3] = -k / m1, -(c + cg) / m1, k / m1, c / m1
    A[3, 0], A[3, 1], A[3, 2], A[3, 3] = k / m2, c / m2, -k / m2, -(c + cg) / m2
    B[1, 0], B[1, 1], B[1, 3] = -1 / m1, 1 / m1, -p[SLOPE]
    B[3, 0], B[3, 2], B[3, 3] = 1 / m2, 1 / m2, -p[SLOPE]
    return A, B


def discretise(p: BodyParams, Ts: float, f_a: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Zero-order-hold discretisation of the body `p` at step `Ts`, gravity included as a
    constant fourth input.

    Returns (Ad, Bd) with x[k+1] = Ad x[k] + Bd [f_a, f1, f2, 1]; `f_a` sets the stiffness when
    k_slope is on. The pair scipy's cont2discrete (the routine behind python-control's
    ``StateSpace.sample(Ts, 'zoh')``) gives, computed in a fixed order of operations
    (`fixedorder.zoh`): through BLAS its last digits would depend on the CPU (§two-mass).
    """
    Ad, Bd = np.empty((4, 4)), np.empty((4, 4))
    discretise_into(pack(p), Ts, f_a, Ad, Bd)
    return Ad, Bd


@jit
def discretise_into(p: np.ndarray, Ts: float, f_a: float, Ad: np.ndarray, Bd: np.ndarray
                    ) -> None:
    """`discretise` of the packed parameters `p` (`pack`) at step `Ts` [s] and actuator force
    `f_a` [N] into `Ad` and `Bd` (4 x 4 each)."""
    A, B = _state_space(p, f_a)
    fixedorder.zoh_into(A, B, Ts, Ad, Bd)


def nonfriction_forces(x: Sequence[float] | np.ndarray, f_a: float, p: BodyParams) -> tuple[float, float]:
    """Net non-friction force along the surface on each block of the body `p` in state `x` under
    actuator force `f_a` (spring, damper, actuator, gravity, and the ground's viscous drag when
    that effect is on)."""
    return nonfriction_core(np.asarray(x, dtype=float), f_a, pack(p))


@jit
def nonfriction_core(x: np.ndarray, f_a: float, p: np.ndarray) -> tuple[float, float]:
    """`nonfriction_forces` of the state `x` under actuator force `f_a` [N], the packed
    parameters `p` (`pack`)."""
    f_spring = _stiffness(p, f_a) * (x[0] - x[2]) + p[C] * (x[1] - x[3])
    if p[K_HARD] != 0.0:  # the spring's hardening (the branch keeps k_hard = 0 to the bit)
        f_spring += hardening_core(x, p, f_a)
    slope = p[SLOPE]
    return (-f_spring - f_a - p[M1] * slope - p[C_GROUND] * x[1],
            f_spring + f_a - p[M2] * slope - p[C_GROUND] * x[3])


def normal_forces(p: BodyParams) -> tuple[float, float]:
    """Normal force of each block of the body `p` on the ground, N_i = m_i g cos(theta)
    (§friction)."""
    return p.m1 * G * math.cos(p.theta), p.m2 * G * math.cos(p.theta)


def centre_of_mass(x: Sequence[float] | np.ndarray, p: BodyParams) -> float:
    """Position of the centre of mass (m1 x1 + m2 x2) / (m1 + m2) of the body `p` in state `x`."""
    return _centre_of_mass(np.asarray(x, dtype=float), pack(p))


@jit
def _centre_of_mass(x, p):
    return (p[M1] * x[0] + p[M2] * x[2]) / (p[M1] + p[M2])


def step_state(x: Sequence[float] | np.ndarray, u: Sequence[float], Ad: np.ndarray,
               Bd: np.ndarray) -> np.ndarray:
    """One zero-order-hold step of the state `x` under the inputs `u` (f_a, f1, f2): x[k+1] =
    `Ad` x[k] + `Bd` [f_a, f1, f2, 1], written out rather than
    through BLAS, whose kernel is chosen per CPU and rounds differently (a stick-slip run would
    differ from CPU to CPU). Each row sums the positions' terms, then the velocities', then
    f_a's, the frictions' and gravity's: mirroring the blocks (x1 <-> -x2, v1 <-> -v2,
    f1 <-> -f2) leaves these sums alone, so with equal masses a mirrored run is bit for bit the
    mirror image (`fixedorder.zoh` keeps Ad and Bd mirror-symmetric too)."""
    out = np.array(x, dtype=float)
    step_state_into(out, u[0], u[1], u[2], np.asarray(Ad, dtype=float), np.asarray(Bd, dtype=float))
    return out


@jit
def step_state_into(x: np.ndarray, f_a: float, f1: float, f2: float, Ad: np.ndarray,
                    Bd: np.ndarray) -> None:
    """`step_state` in place on the array `x`, the inputs `f_a`, `f1`, `f2` [N] held, with the
    hold matrices `Ad` and `Bd`."""
    x0, x1, x2, x3 = x[0], x[1], x[2], x[3]
    for i in range(4):
        a, b = Ad[i], Bd[i]
        x[i] = (((a[0] * x0 + a[2] * x2) + (a[1] * x1 + a[3] * x3))
                + ((b[0] * f_a + (b[1] * f1 + b[2] * f2)) + b[3]))


def initial_state() -> np.ndarray:
    """The kernel's state at rest (§ideal-actuation), its hold matrices not yet made."""
    x = np.zeros(38)
    x[4] = math.nan
    return x


@jit
def evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """Kernel outputs `y` = [s1, v1, f_n1, N1, s2, v2, f_n2, N2, x_cm, incline] at state `x` and
    inputs `u` = [f_a, f1, f2], parameters `p` (`pack`; the time `t` does not matter)."""
    f_n1, f_n2 = nonfriction_core(x, u[0], p)
    y[0], y[1], y[2], y[3] = x[0], x[1], f_n1, p[N1]
    y[4], y[5], y[6], y[7] = x[2], x[3], f_n2, p[N2]
    y[8], y[9] = _centre_of_mass(x, p), p[THETA]


@jit
def advance(p: np.ndarray, x: np.ndarray, u: np.ndarray, y: np.ndarray, t: float,
            dt: float) -> None:
    """Kernel step of the state `x` over [`t`, `t` + `dt`] [s] with the inputs `u` held
    (parameters `p`; the outputs `y` are not needed): the hold matrices for this step (made anew
    when the step changes beyond rounding, as an integer clock's steps do, or, with a
    force-dependent stiffness, the actuator force), then `step_state`; the spring's hardening
    (k_hard) enters as a force beside the actuator's, taken at the step's start and held."""
    f_held = u[0] if p[K_SLOPE] != 0.0 else 0.0
    Ad, Bd = x[6:22].reshape((4, 4)), x[22:38].reshape((4, 4))
    if math.isnan(x[4]) or abs(dt - x[4]) > 1e-9 * max(abs(dt), abs(x[4])) or f_held != x[5]:
        discretise_into(p, dt, f_held, Ad, Bd)
        x[4], x[5] = dt, f_held
    f_a = u[0]
    if p[K_HARD] != 0.0:
        f_a += hardening_core(x, p, u[0])
    step_state_into(x[:4], f_a, u[1], u[2], Ad, Bd)


KERNEL = Kernel(evaluate, advance, inputs=("f_a", "flange_a.f", "flange_b.f"),
                outputs=("flange_a.s", "flange_a.v", "flange_a.f_n", "flange_a.N", "flange_b.s",
                         "flange_b.v", "flange_b.f_n", "flange_b.N", "x_cm", "incline"))
