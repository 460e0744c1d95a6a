"""Crawler body: the two-mass, spring, damper plant of SPEC 1.2 and its zero-order-hold discretisation.

State x = [x1, v1, x2, v2] (positions are variations from rest, climbing is positive x);
input u = [f_a, f1, f2] (actuator force pushing the blocks apart, friction on block 1 and 2).
The same `state_space` serves the FMU, the monolithic reference simulation and the linear analysis.
"""
import math
from dataclasses import dataclass

import numpy as np
from scipy.signal import cont2discrete

G = 9.81  # m/s^2


@dataclass(frozen=True)
class BodyParams:
    """Crawler body parameters (defaults: SPEC 1.4, flat ground)."""

    m1: float = 0.2  # kg, rear block (SPEC 1.4)
    m2: float = 0.2  # kg, front block (SPEC 1.4)
    k: float = 200.0  # N/m, central actuator stiffness from its tensile test (SPEC 1.4)
    c: float = 1.3  # N s/m, central actuator damping (SPEC 1.4)
    theta: float = 0.0  # rad, incline of the ground, climbing positive (SPEC 1.2)

    def check(self):
        """Raise ValueError naming the first parameter outside its physical range."""
        for name in ("m1", "m2"):
            if not getattr(self, name) > 0:
                raise ValueError(f"{name} must be positive (got {getattr(self, name)!r})")
        for name in ("k", "c"):
            if not getattr(self, name) >= 0:
                raise ValueError(f"{name} must be non-negative (got {getattr(self, name)!r})")
        if not abs(self.theta) < math.pi / 2:
            raise ValueError(f"theta must lie in (-pi/2, pi/2) rad (got {self.theta!r})")


def state_space(p):
    """Continuous plant of SPEC 1.2: return (A, B) with B's columns for f_a, f1, f2."""
    m1, m2, k, c = p.m1, p.m2, p.k, p.c
    A = np.array([[0.0, 1.0, 0.0, 0.0],
                  [-k / m1, -c / m1, k / m1, c / m1],
                  [0.0, 0.0, 0.0, 1.0],
                  [k / m2, c / m2, -k / m2, -c / m2]])
    B = np.array([[0.0, 0.0, 0.0],
                  [-1 / m1, 1 / m1, 0.0],
                  [0.0, 0.0, 0.0],
                  [1 / m2, 0.0, 1 / m2]])
    return A, B


def discretise(p, Ts):
    """Zero-order-hold discretisation at step Ts, gravity included as a constant fourth input.

    Returns (Ad, Bd) with x[k+1] = Ad x[k] + Bd [f_a, f1, f2, 1]. Uses scipy's cont2discrete, the
    routine python-control's ``StateSpace.sample(Ts, 'zoh')`` calls.
    """
    A, B = state_space(p)
    gravity = np.array([0.0, -G * math.sin(p.theta), 0.0, -G * math.sin(p.theta)])
    Ad, Bd, *_ = cont2discrete((A, np.column_stack([B, gravity]), np.eye(4), np.zeros((4, 4))),
                               Ts, method="zoh")
    return Ad, Bd


def nonfriction_forces(x, f_a, p):
    """Net non-friction force along the surface on each block (spring, damper, actuator, gravity)."""
    f_spring = p.k * (x[0] - x[2]) + p.c * (x[1] - x[3])
    slope = G * math.sin(p.theta)
    return -f_spring - f_a - p.m1 * slope, f_spring + f_a - p.m2 * slope


def normal_forces(p):
    """Normal force of each block on the ground, N_i = m_i g cos(theta) (SPEC 1.3)."""
    return p.m1 * G * math.cos(p.theta), p.m2 * G * math.cos(p.theta)


def centre_of_mass(x, p):
    """Position of the centre of mass (m1 x1 + m2 x2) / (m1 + m2)."""
    return (p.m1 * x[0] + p.m2 * x[2]) / (p.m1 + p.m2)


def step_state(x, u, Ad, Bd):
    """One zero-order-hold step: x[k+1] = Ad x[k] + Bd [f_a, f1, f2, 1]."""
    return Ad @ x + Bd @ np.array([u[0], u[1], u[2], 1.0])
