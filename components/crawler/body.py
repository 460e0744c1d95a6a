"""Crawler body: the two-mass, spring, damper plant of §two-mass and its zero-order-hold
discretisation.

State x = [x1, v1, x2, v2] (positions are variations from rest, climbing is positive x);
input u = [f_a, f1, f2] (actuator force pushing the blocks apart, friction on block 1 and 2).
The same `state_space` serves the FMU, the monolithic reference simulation and the linear analysis.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from musclesim.components import fixedorder
from musclesim.components.checks import require
from musclesim.fmu import Calibration, declare

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

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its physical range."""
        require(self, positive=("m1", "m2"), non_negative=("k", "c", "c_ground"))
        if not abs(self.theta) < math.pi / 2:
            raise ValueError(f"theta must lie in (-pi/2, pi/2) rad (got {self.theta!r})")


def stiffness(p: BodyParams, f_a: float = 0.0) -> float:
    """Actuator stiffness of the body `p` at actuator force `f_a`: k (1 + k_slope f_a), never
    below zero."""
    return max(0.0, p.k * (1.0 + p.k_slope * f_a))


def state_space(p: BodyParams, f_a: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Continuous plant of §two-mass of the body `p`: return (A, B) with B's columns for f_a,
    f1, f2.

    With the effects on, k is the stiffness at actuator force `f_a` and each block also feels
    the ground's viscous drag -c_ground v_i.
    """
    m1, m2, k, c, cg = p.m1, p.m2, stiffness(p, f_a), p.c, p.c_ground
    A = np.array([[0.0, 1.0, 0.0, 0.0],
                  [-k / m1, -(c + cg) / m1, k / m1, c / m1],
                  [0.0, 0.0, 0.0, 1.0],
                  [k / m2, c / m2, -k / m2, -(c + cg) / m2]])
    B = np.array([[0.0, 0.0, 0.0],
                  [-1 / m1, 1 / m1, 0.0],
                  [0.0, 0.0, 0.0],
                  [1 / m2, 0.0, 1 / m2]])
    return A, B


def discretise(p: BodyParams, Ts: float, f_a: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Zero-order-hold discretisation of the body `p` at step `Ts`, gravity included as a
    constant fourth input.

    Returns (Ad, Bd) with x[k+1] = Ad x[k] + Bd [f_a, f1, f2, 1]; `f_a` sets the stiffness when
    k_slope is on. The pair scipy's cont2discrete (the routine behind python-control's
    ``StateSpace.sample(Ts, 'zoh')``) gives, computed in a fixed order of operations
    (`fixedorder.zoh`): through BLAS its last digits would depend on the CPU (§two-mass).
    """
    A, B = state_space(p, f_a)
    gravity = np.array([0.0, -G * math.sin(p.theta), 0.0, -G * math.sin(p.theta)])
    Ad, Bd = fixedorder.zoh(A.tolist(), np.column_stack([B, gravity]).tolist(), Ts)
    return np.array(Ad), np.array(Bd)


def nonfriction_forces(x: Sequence[float] | np.ndarray, f_a: float, p: BodyParams) -> tuple[float, float]:
    """Net non-friction force along the surface on each block of the body `p` in state `x` under
    actuator force `f_a` (spring, damper, actuator, gravity, and the ground's viscous drag when
    that effect is on)."""
    f_spring = stiffness(p, f_a) * (x[0] - x[2]) + p.c * (x[1] - x[3])
    slope = G * math.sin(p.theta)
    return (-f_spring - f_a - p.m1 * slope - p.c_ground * x[1],
            f_spring + f_a - p.m2 * slope - p.c_ground * x[3])


def normal_forces(p: BodyParams) -> tuple[float, float]:
    """Normal force of each block of the body `p` on the ground, N_i = m_i g cos(theta)
    (§friction)."""
    return p.m1 * G * math.cos(p.theta), p.m2 * G * math.cos(p.theta)


def centre_of_mass(x: Sequence[float] | np.ndarray, p: BodyParams) -> float:
    """Position of the centre of mass (m1 x1 + m2 x2) / (m1 + m2) of the body `p` in state `x`."""
    return (p.m1 * x[0] + p.m2 * x[2]) / (p.m1 + p.m2)


def step_state(x: Sequence[float] | np.ndarray, u: Sequence[float], Ad: np.ndarray,
               Bd: np.ndarray) -> np.ndarray:
    """One zero-order-hold step of the state `x` under the inputs `u` (f_a, f1, f2): x[k+1] =
    `Ad` x[k] + `Bd` [f_a, f1, f2, 1], written out rather than
    through BLAS, whose kernel is chosen per CPU and rounds differently (a stick-slip run would
    differ from CPU to CPU). Each row sums the positions' terms, then the velocities', then
    f_a's, the frictions' and gravity's: mirroring the blocks (x1 <-> -x2, v1 <-> -v2,
    f1 <-> -f2) leaves these sums alone, so with equal masses a mirrored run is bit for bit the
    mirror image (`fixedorder.zoh` keeps Ad and Bd mirror-symmetric too)."""
    x0, x1, x2, x3 = x.tolist() if isinstance(x, np.ndarray) else x
    f_a, f1, f2 = u
    return np.array([((a0 * x0 + a2 * x2) + (a1 * x1 + a3 * x3))
                     + ((b0 * f_a + (b1 * f1 + b2 * f2)) + b3)
                     for (a0, a1, a2, a3), (b0, b1, b2, b3) in zip(Ad.tolist(), Bd.tolist())])
