"""Controller design shared by the linear analyses: PI gains by pole placement on a
first-order plant (`design_pi`), their margins and the sampled closed loop (`pi_margins`), and a PI
for a discrete plant by its loop crossover (`discrete_pi`)."""
from __future__ import annotations

import cmath
import math
from typing import Any, Callable

import control as ct
import numpy as np


def design_pi(plant: ct.StateSpace, omega_n: float, zeta: float) -> tuple[float, float]:
    """PI gains (Kp, Ki) placing the closed-loop poles of a first-order `plant` dx/dt = a x + b u
    at natural frequency `omega_n` [rad/s] and damping `zeta` (§temperature-control, §loads).

    With the error's integral as a second state, u = Kp e + Ki integral(e) closes the loop with
    the characteristic polynomial s^2 + (b Kp - a) s + b Ki = s^2 + 2 zeta omega_n s + omega_n^2:
    Kp = (2 zeta omega_n + a) / b, Ki = omega_n^2 / b. Written out rather than python-control's
    `place` on the augmented plant, which gives the same to rounding through LAPACK, whose last
    digits depend on the CPU's BLAS kernel.
    """
    a, b = float(plant.A[0, 0]), float(plant.B[0, 0])
    return (2.0 * zeta * omega_n + a) / b, omega_n * omega_n / b


def pi_margins(plant: ct.StateSpace, Kp: float, Ki: float, step: float) -> dict[str, Any]:
    """Gain margin (None: infinite), phase margin [deg] and gain crossover [rad/s] of the loop
    PI x plant (PI gains `Kp`, `Ki`; `plant` a python-control system), and the largest pole radius
    of its closed loop sampled at `step` (below 1: the controller running sampled keeps it
    stable)."""
    loop = ct.tf([Kp, Ki], [1, 0]) * ct.tf(plant)
    gm, pm, _, _, wc, _ = ct.stability_margins(loop)
    sampled = ct.feedback(ct.sample_system(loop, step, method="zoh"))
    return {"gain_margin": None if math.isinf(gm) else float(gm), "phase_margin_deg": float(pm),
            "crossover": float(wc), "sampled_pole_radius": float(np.abs(ct.poles(sampled)).max())}


def discrete_pi(plant: Callable[[complex], complex], crossover: float, zero_ratio: float,
                step: float) -> tuple[float, float]:
    """PI (Kp, Ki), u = Kp e + Ki sum(e) `step` (the PID FMU's form) for a discrete plant: the
    zero at `crossover` / `zero_ratio`, Kp so that the loop gain is 1 at `crossover` [rad/s].

    `plant` is a function of z; the arithmetic is Python's complex (numpy's vectorised complex
    product takes fused multiply-adds on CPUs that have them, and rounds differently)."""
    z = cmath.exp(1j * crossover * step)
    shape = (1.0 + step / zero_ratio * crossover / (z - 1.0)) * complex(plant(z))
    Kp = 1.0 / abs(shape)
    return Kp, Kp * crossover / zero_ratio
