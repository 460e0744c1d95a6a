"""The quadruped's body and feet (components/quadruped/body.py, §quadruped): isotropic feet go
nowhere, anisotropic feet forward, the hooks set the direction, and the direction-dependent
coefficients feed the crawler's friction."""
import math

import pytest

from musclesim.components.bending import actuator, beam
from musclesim.components.quadruped import body, sequencer
from musclesim.components.sma.reference_wire import load_params

DT = 5e-4  # s, the scenario's communication step
ISOTROPIC = {"mu_s_forward": 0.5, "mu_k_forward": 0.375, "mu_s_backward": 0.5,
             "mu_k_backward": 0.375}
REVERSED = {"mu_s_forward": 0.8, "mu_k_forward": 0.6, "mu_s_backward": 0.2,
            "mu_k_backward": 0.15}


def walk(feet=None, gait=None, stop_time=1.5):
    """Distance [m] the body covers over the last of the gait's 0.25 s periods (means over the
    last two periods: legs pushing together move it back and forth within a period) with four
    legs as scenarios/quadruped-walk.toml has them (the default actuator with 20 Ohm in series,
    not the 16.5 Ohm fitted to the lone actuator: see that file), and its range over the run.
    Legs and body exchange values at the start of each step (Jacobi, as in the scenario)."""
    layout = actuator.WireLayout(series_resistance=20.0)
    wire = actuator.wire_thermal(layout.length)
    surface = actuator.hysteresis_surface(load_params(),
                                          layout.pretension / (math.pi * 25e-6 ** 2))
    legs = [actuator.BendingActuator(beam.BeamParams(), layout, wire, surface) for _ in range(4)]
    q = body.Quadruped(body.QuadrupedParams(**(feet or {})))
    p = sequencer.SequencerParams(**(gait or {}))
    xs = []
    for k in range(round(stop_time / DT)):
        t = k * DT
        u = sequencer.voltages(t, p)
        q.step(DT, [leg.deflection(body.FOOT_HEIGHT) for leg in legs],
               [leg.velocity(body.FOOT_HEIGHT) for leg in legs])
        for leg, ui in zip(legs, u):
            leg.step(DT, ui, 20.0, t)
        xs.append(q.x)
    n = round(0.25 / DT)
    return (sum(xs[-n:]) - sum(xs[-2 * n:-n])) / n, max(xs) - min(xs)


IN_PHASE = {"phase1": 0.0, "phase2": 0.0, "phase3": 0.0, "phase4": 0.0}


@pytest.mark.parametrize("gait", [None, IN_PHASE], ids=["trot", "in-phase"])
def test_isotropic_feet_go_nowhere_anisotropic_feet_go_forward(gait):
    x_iso, swing = walk(ISOTROPIC, gait)
    x_fwd, _ = walk(None, gait)
    assert x_fwd > 1e-4  # about 0.6 mm/s, 0.15 mm per period
    assert abs(x_iso) < 0.01 * x_fwd  # what is left is the legs settling, of either sign
    if gait:  # all legs push the body together: it moves, and comes back
        assert swing > 1e-5


def test_the_hooks_set_the_direction():
    x_fwd, _ = walk()
    x_back, _ = walk(REVERSED)
    assert x_back < 0 < x_fwd
    assert abs(x_back) == pytest.approx(x_fwd, rel=0.2)


def test_direction_dependent_coefficients_feed_the_crawler_friction():
    p = body.QuadrupedParams(body_mass=1e3)  # a body that stays put
    N = body.normal_force(p)
    q = body.Quadruped(p)
    h = p.max_substep  # one sub-step: the forces as the legs start to push
    # a foot pushed backward below its grip holds; forward it slides at the easy kinetic value
    assert body.coefficients(0.0, -0.5 * p.mu_s_backward * N, p) == (p.mu_s_backward,
                                                                     p.mu_k_backward)
    q.step(h, [-0.5 * p.mu_s_backward * N / p.leg_stiffness] * 4, [0.0] * 4)
    assert all(q.stuck(i) for i in range(4))
    q = body.Quadruped(p)
    q.step(h, [5 * p.mu_s_forward * N / p.leg_stiffness] * 4, [0.0] * 4)
    assert all(f == pytest.approx(-p.mu_k_forward * N) for f in q.forces)
