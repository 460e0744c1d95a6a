"""The QuadrupedBody and LegSequencer FMUs (components/quadruped/slaves.py): the cores stepped
by hand."""
import math

from musclesim.components.quadruped import body, sequencer

from test_bending_slaves import fmu_run


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
