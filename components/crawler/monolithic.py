"""Monolithic reference simulation of the ideal-actuation crawler (§ideal-actuation).

It steps the same physics cores as the FMUs in one loop, with no co-simulation in between,
compiled where numba is installed (`musclesim.fmu.compiled`); the co-simulated scenario must agree
with it (tests/cosim/test_crawler_cosim.py) and the benchmark uses it as the limit of speed. Time
is accumulated step by step exactly as the master does, so that square waves switch on the same
sample in both.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from musclesim.components.crawler import body, friction, inputs
from musclesim.fmu import jit


def simulate_ideal(body_p: body.BodyParams = body.BodyParams(),
                   friction_p: tuple[friction.FrictionParams, ...] = (
                       friction.FrictionParams(),) * 2,
                   inputs_p: inputs.InputParams = inputs.InputParams(), step: float = 1e-3,
                   stop_time: float = 60.0,
                   actuator_lead: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Simulate §ideal-actuation and return (time, x) with x[:, :] = [x1, v1, x2, v2] at every step.

    Parameters
    ----------
    body_p, friction_p, inputs_p
        Parameters of the body, of the two friction blocks and of the input signals.
    step, stop_time : float
        Sampling period and duration [s].
    actuator_lead : bool
        Apply f_a at the end of each step to the body (what a Gauss-Seidel master does when the
        signal source is stepped before the body); the friction still sees f_a at the start.
    """
    n = int(round(stop_time / step))
    times, states = np.empty(n + 1), np.empty((n + 1, 4))
    _simulate(body.pack(body_p), np.stack([friction.pack(p) for p in friction_p]),
              inputs.pack(inputs_p), step, n, actuator_lead, times, states)
    return times, states


@jit
def _simulate(pb, pf, pi, step, n, actuator_lead, times, states):
    """`simulate_ideal` on the packed parameters of the body `pb`, the blocks `pf` (a row each)
    and the inputs `pi`, into `times` and `states`."""
    Ad, Bd = np.empty((4, 4)), np.empty((4, 4))
    body.discretise_into(pb, step, 0.0, Ad, Bd)
    x = np.zeros(4)
    t = 0.0
    f_a, u1, u2 = inputs.signals_core(t, pi)
    contact = np.array([u1, u2])
    forces = np.zeros(2)
    for k in range(n + 1):
        times[k], states[k] = t, x
        if k == n:
            break
        f_n = body.nonfriction_core(x, f_a, pb)
        for i in range(2):
            p, u = pf[i], u1 if i == 0 else u2
            s = u if p[5] <= 0 else contact[i]  # t_switch off: the contact follows u at once
            mu_s, mu_k = friction.coefficients_core(s, p[0], p[1], p[2], p[3], 1.0)
            if p[8] != 0.0:  # the Stribeck curve, as the FMU's
                mu_k = friction.stribeck_core(x[1 + 2 * i], mu_s, mu_k, p[8], p[9])
            forces[i] = friction.friction_force(x[1 + 2 * i], f_n[i], pb[body.N1 + i], mu_s,
                                                mu_k, p[4])
            contact[i] = friction.advance_contact(contact[i], u, step, p[5])
        t_next = (k + 1) * step  # t0 + k h, as the master counts its points
        f_next, u1, u2 = inputs.signals_core(t_next, pi)
        f_held = f_next if actuator_lead else f_a
        if pb[body.K_SLOPE]:  # the stiffness follows the actuator force held over the step
            body.discretise_into(pb, step, f_held, Ad, Bd)
        if pb[body.K_HARD]:  # the spring's hardening, held over the step like the FMU's
            f_held += body.hardening_core(x, pb, f_held)
        body.step_state_into(x, f_held, forces[0], forces[1], Ad, Bd)
        t, f_a = t_next, f_next


def write_reference(path: str | Path, stop_time: float = 5.0, every: int = 10) -> None:
    """Write to `path` the reference result CSV kept next to the components (time, x1, v1, x2,
    v2): the run to `stop_time` [s], one row of `every`."""
    times, states = simulate_ideal(stop_time=stop_time)
    np.savetxt(path, np.column_stack([times, states])[::every], delimiter=",", fmt="%.17g",
               header="time,x1,v1,x2,v2", comments="")
