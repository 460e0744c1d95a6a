"""The quadruped (§quadruped) at the level of its cores: four bending-actuator legs pulsed by the
leg sequencer move the body only when the feet's friction depends on direction, and the way the
hooks point; the sequencer's pulses; the FMUs against their cores. About 0.5 s of wall time per
simulated second."""
import math

import pytest

from musclesim.components.bending import actuator, beam
from musclesim.components.quadruped import body, sequencer
from musclesim.components.sma.reference_wire import load_params

from test_bending import fmu_run

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


def test_sequencer_pulses_each_wire_at_its_phase():
    p = sequencer.SequencerParams()
    t = [k * 1e-4 for k in range(2500)]  # one 0.25 s period
    on = [[sum(sequencer.voltages(tk, p)[leg][w] > 0 for tk in t) * 1e-4 for w in (0, 1)]
          for leg in range(4)]
    for leg in range(4):
        assert on[leg] == [pytest.approx(0.0125, abs=2e-4)] * 2  # 12.5 ms per wire (§quadruped)
    first = [[next(tk for tk in t if sequencer.voltages(tk, p)[leg][w] > 0 or tk == t[-1])
              for w in (0, 1)] for leg in range(4)]
    assert first[0] == [0.0, pytest.approx(0.125)]  # wire B half a period after wire A
    assert first[1][0] == pytest.approx(0.125) and first[3][0] == 0.0  # trot
    with pytest.raises(ValueError, match="duty"):
        sequencer.SequencerParams(duty=1.0).check()


def test_fmus_are_the_cores_stepped_by_hand(fmu_dir, tmp_path):
    """QuadrupedBody and LegSequencer through FMI give their cores' values bit for bit."""
    dt, n = 5e-4, 400
    s = [[1e-4 * math.sin(2 * math.pi * 4 * k * dt + i) for i in range(4)] for k in range(n)]
    v = [[4e-4 * math.pi * math.cos(2 * math.pi * 4 * k * dt + i) for i in range(4)]
         for k in range(n)]
    inputs = [{**{f"leg{i + 1}.s": s[k][i] for i in range(4)},
               **{f"leg{i + 1}.v": v[k][i] for i in range(4)}} for k in range(n)]
    rows = fmu_run(fmu_dir, tmp_path, "QuadrupedBody", inputs, ["x", "foot1.s", "foot2.f"], dt)
    q = body.Quadruped(body.QuadrupedParams())
    expected = [(q.x, q.feet_x[0], q.forces[1])]
    for k in range(n):
        q.step(dt, s[k], v[k])
        expected.append((q.x, q.feet_x[0], q.forces[1]))
    assert [tuple(r) for r in rows] == expected
    assert len({r[0] for r in rows}) > n / 2  # the body moved

    names = [f"leg{i}.u{w}" for i in range(1, 5) for w in "AB"]
    rows = fmu_run(fmu_dir, tmp_path / "seq", "LegSequencer", [{}] * n, names, dt)
    p = sequencer.SequencerParams()
    assert [list(r) for r in rows] == [[u for leg in sequencer.voltages(k * dt, p) for u in leg]
                                       for k in range(n + 1)]
