"""Controller design shared by the linear analyses: PI gains by pole placement on a
first-order plant (`design_pi`), their margins and the sampled closed loop (`pi_margins`), and a PI
for a discrete plant by its loop crossover (`discrete_pi`)."""
import math

import control as ct
import numpy as np


def design_pi(plant, omega_n, zeta):
    """PI gains placing the closed-loop poles of a first-order plant at omega_n, zeta.

    The plant is augmented with the integral of the error and the state feedback comes from
    python-control's `place`; u = Kp e + Ki integral(e) gives the same closed-loop poles.
    """
    a, b = plant.A[0, 0], plant.B[0, 0]
    A = np.array([[a, 0.0], [-1.0, 0.0]])
    B = np.array([[b], [0.0]])
    wd = omega_n * math.sqrt(1 - zeta ** 2)
    K = ct.place(A, B, [complex(-zeta * omega_n, wd), complex(-zeta * omega_n, -wd)])
    return float(K[0, 0]), float(-K[0, 1])


def pi_margins(plant, Kp, Ki, step):
    """Gain margin (None: infinite), phase margin [deg] and gain crossover [rad/s] of the loop
    PI x plant, and the largest pole radius of its closed loop sampled at `step` (below 1: the
    controller running sampled keeps it stable)."""
    loop = ct.tf([Kp, Ki], [1, 0]) * ct.tf(plant)
    gm, pm, _, _, wc, _ = ct.stability_margins(loop)
    sampled = ct.feedback(ct.sample_system(loop, step, method="zoh"))
    return {"gain_margin": None if math.isinf(gm) else float(gm), "phase_margin_deg": float(pm),
            "crossover": float(wc), "sampled_pole_radius": float(np.abs(ct.poles(sampled)).max())}


def discrete_pi(plant, crossover, zero_ratio, step):
    """PI u = Kp e + Ki sum(e) step (the PID FMU's form) for a discrete plant: the zero at
    crossover / zero_ratio, Kp so that the loop gain is 1 at `crossover` [rad/s]."""
    z = np.exp(1j * crossover * step)
    shape = (1.0 + step / zero_ratio * crossover / (z - 1.0)) * complex(plant(z))
    Kp = 1.0 / float(abs(shape))
    return Kp, Kp * crossover / zero_ratio
