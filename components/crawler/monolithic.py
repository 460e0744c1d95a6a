"""Monolithic reference simulation of the ideal-actuation crawler (§ideal-actuation) in plain numpy.

It steps the same physics cores as the FMUs in one loop, with no co-simulation in between; the
co-simulated scenario must agree with it (tests/cosim/test_crawler_cosim.py) and the benchmark uses
it as the speed reference. Time is accumulated step by step exactly as the master does, so that
square waves switch on the same sample in both.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from musclesim.components.crawler import body, friction, inputs


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
    Ad, Bd = body.discretise(body_p, step)
    normal = body.normal_forces(body_p)
    x = np.zeros(4)
    t = 0.0
    f_a, u1, u2 = inputs.signals(t, inputs_p)
    contact = [u1, u2]
    times = np.empty(n + 1)
    states = np.empty((n + 1, 4))
    for k in range(n + 1):
        times[k], states[k] = t, x
        if k == n:
            break
        f_n = body.nonfriction_forces(x, f_a, body_p)
        forces = []
        for i, (p, u) in enumerate(zip(friction_p, (u1, u2))):
            s = u if p.t_switch <= 0 else contact[i]
            mu_s, mu_k = friction.coefficients(s, p)
            forces.append(friction.friction_force(x[1 + 2 * i], f_n[i], normal[i], mu_s, mu_k, p.v_s))
            contact[i] = friction.advance_contact(contact[i], u, step, p.t_switch)
        t_next = (k + 1) * step  # t0 + k h, as the master counts its points
        f_next, u1, u2 = inputs.signals(t_next, inputs_p)
        f_held = f_next if actuator_lead else f_a
        if body_p.k_slope:  # the stiffness follows the actuator force held over the step
            Ad, Bd = body.discretise(body_p, step, f_held)
        x = body.step_state(x, (f_held, *forces), Ad, Bd)
        t, f_a = t_next, f_next
    return times, states


def write_reference(path: str | Path, stop_time: float = 5.0, every: int = 10) -> None:
    """Write to `path` the reference result CSV kept next to the components (time, x1, v1, x2,
    v2): the run to `stop_time` [s], one row of `every`."""
    times, states = simulate_ideal(stop_time=stop_time)
    np.savetxt(path, np.column_stack([times, states])[::every], delimiter=",", fmt="%.17g",
               header="time,x1,v1,x2,v2", comments="")
