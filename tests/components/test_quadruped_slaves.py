"""The QuadrupedBody and LegSequencer FMUs (components/quadruped/slaves.py): the cores stepped
by hand, their kernels compiled and as plain Python, and a NaN input refused."""
import math

from dataclasses import replace

import numpy as np
import pytest

from musclesim.components.quadruped import body, sequencer
from musclesim.components.quadruped.slaves import LegSequencer, QuadrupedBody
from musclesim.cosim import Master, Signal, load_scenario
from musclesim.fmu.compiled import COMPILED

from conftest import SCENARIOS, in_process
from kernel_paths import assert_paths_agree
from test_bending_slaves import fmu_run

DT = 5e-4  # s, the scenario's communication step


def legs(k):
    """The legs' deflections and rates before step k: 0.1 mm at 4 Hz, each leg 1 rad apart."""
    return {**{f"leg{i + 1}_s": 1e-4 * math.sin(2 * math.pi * 4 * k * DT + i) for i in range(4)},
            **{f"leg{i + 1}_v": 8e-4 * math.pi * math.cos(2 * math.pi * 4 * k * DT + i)
               for i in range(4)}}


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


def test_kernels_compiled_and_plain_give_the_same_bits():
    """Each kernel, compiled and as its plain-Python source (`.py_func`), over a short run (the
    body's feet sliding and sticking, every wire of the sequencer pulsed at least once)."""
    assert_paths_agree(in_process(QuadrupedBody, "body"), legs, DT, 300)
    assert_paths_agree(in_process(LegSequencer, "seq"), lambda k: None, DT, 500)


def test_the_body_step_compiled_and_plain_give_the_same_bits():
    """The body's sub-stepping (`step_core`, which the kernel's advance calls) compiled and as plain
    Python, over a run where the feet slide and stick."""
    step = body.step_core
    if getattr(step, "py_func", None) is None:
        pytest.skip("the core is not compiled here (numba absent or MUSCLESIM_COMPILE=0)")
    p = body.pack(body.QuadrupedParams())
    x, x_py = np.zeros(body.STATE), np.zeros(body.STATE)
    stuck = set()
    for k in range(400):
        u = np.array([legs(k)[f"leg{i}_{q}"] for i in range(1, 5) for q in "sv"])
        step(p, x, u, DT)
        step.py_func(p, x_py, u, DT)
        assert x.tobytes() == x_py.tobytes(), k
        stuck.add(x[body.FEET_V] == 0.0)
    assert stuck == {True, False}


def test_a_nan_leg_input_is_refused():
    slave = in_process(QuadrupedBody, "body")
    slave.enter_initialization_mode()
    slave.exit_initialization_mode()
    slave.leg2_v = float("nan")
    with pytest.raises(ValueError, match="input leg2.v is NaN at t = 0 s"):
        slave.do_step(0.0, DT)


@pytest.mark.skipif(not COMPILED, reason="numba is not installed: nothing is fused")
def test_body_and_sequencer_fuse_with_the_unfused_bits(fmu_dir):
    """quadruped-walk without its legs (not kernels: the walk itself is not fused), the body
    driven by replayed leg values: the master fuses the two kernels and gives the unfused bits,
    and a NaN leg value stops both alike."""
    walk = load_scenario(SCENARIOS / "quadruped-walk.toml", stop_time=0.25)
    s = replace(walk, instances={k: walk.instances[k] for k in ("sequencer", "body")},
                connections=(), metrics={}, plots=(),
                record=tuple(Signal(i, n) for i, n in (
                    ("body", "x"), ("body", "v"), ("body", "foot1.s"), ("body", "foot2.f"),
                    ("body", "foot3.stuck"), ("sequencer", "leg1.uA"), ("sequencer", "leg2.uB"))))
    k = np.arange(s.n_steps + 1)
    replayed = {Signal("body", f"leg{i}.{q}"): np.array([legs(j)[f"leg{i}_{q}"] for j in k])
                for i in range(1, 5) for q in "sv"}
    spoiled = {**replayed, Signal("body", "leg3.s"): np.where(k == 300, np.nan,
                                                              replayed[Signal("body", "leg3.s")])}
    runs = []
    for inputs in (replayed, spoiled):
        m = Master(s, fmu_dir, inputs=inputs)
        fused, unfused = m.run(), Master(s, fmu_dir, inputs=inputs, fuse=False).run()
        assert m.fused
        assert fused.names == unfused.names
        np.testing.assert_array_equal(fused.time, unfused.time)
        assert fused.data.tobytes() == unfused.data.tobytes()
        assert (fused.error, fused.warnings) == (unfused.error, unfused.warnings)
        runs.append(fused)
    assert runs[0].error is None and len(set(runs[0].data[:, 0])) > s.n_steps / 2  # it moved
    assert "input leg3.s is NaN" in runs[1].error
