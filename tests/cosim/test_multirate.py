"""Multi-rate stepping (docs/user/scenarios.md, the master algorithm): an instance declared with
``every = m`` steps only at every m-th communication point, m steps at once; between its points
the values read from it are held and its inputs are not taken; the SSP export carries it as the
Open Simulation Platform's step size hint, which libcosim turns into the same decimation.
"""
import math
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest

from musclesim.cosim import Signal, scenario
from musclesim.cosim.master import Master
from musclesim.errors import UserError
from musclesim.export import ssp

from export.test_ssp import run_libcosim  # tests/export/test_ssp.py

S = Signal.parse

STEP, N, M = 0.01, 10, 3  # 10 steps, the source every 3rd point: its last step is 1 step long
SINE = 'kind = 1.0, amplitude = 2.0, frequency = 0.7, offset = 0.5'


def write(tmp_path, text, name="multirate.toml"):
    path = tmp_path / name
    path.write_text(text)
    return scenario.load(path)


def source_only(tmp_path, every, algorithm):
    return write(tmp_path, f'step = {STEP}\nstop_time = {N * STEP}\nalgorithm = "{algorithm}"\n'
                 f'record = ["src.y"]\n[instances.src]\ncomponent = "SignalSource"\n'
                 f'every = {every}\nparameters = {{ {SINE} }}\n')


@pytest.mark.parametrize("algorithm", ["jacobi", "gauss-seidel"])
def test_an_instance_is_read_at_its_own_points_and_held_between(fmu_dir, tmp_path, algorithm):
    """Rows 0, 3, 6, 9 hold the source's value at their time, the rows between the value of the
    point before; the last step (9 -> 10) is shortened to end at the stop time, where it is read."""
    slow = Master(source_only(tmp_path, M, algorithm), fmu_dir).run()
    fast = Master(source_only(tmp_path, 1, algorithm), fmu_dir).run()
    assert slow.error is None and fast.error is None
    y, exact = slow[S("src.y")], 0.5 + 2.0 * np.sin(2 * math.pi * 0.7 * fast.time)
    own = [0, 3, 6, 9, 10]
    np.testing.assert_allclose(y[own], exact[own], rtol=0, atol=1e-14)
    np.testing.assert_allclose(fast[S("src.y")], exact, rtol=0, atol=1e-14)
    held = [k - k % M for k in range(N + 1)]
    held[N] = N
    assert list(y) == list(y[held])
    assert len(set(y)) == len(own)  # the source moves: nothing else is held by accident


def body_driven(tmp_path, every_body, every_force=5, n=400, name="driven.toml"):
    """The crawler body's two blocks on its spring and damper (friction inputs left at 0), pushed
    apart by a sine force from a source stepping every 5th point; the body every `every_body`."""
    return write(tmp_path, f'step = 0.001\nstop_time = {n * 0.001}\nalgorithm = "jacobi"\n'
                 'connections = [["force.y", "body.f_a"]]\n'
                 'record = ["body.flange_a.s", "body.flange_b.s", "body.flange_b.v", "force.y"]\n'
                 f'[instances.force]\ncomponent = "SignalSource"\nevery = {every_force}\n'
                 f'parameters = {{ kind = 1.0, amplitude = 3.0, frequency = 2.0 }}\n'
                 f'[instances.body]\ncomponent = "CrawlerBody"\nevery = {every_body}\n', name)


def test_stepping_at_once_equals_stepping_point_by_point_where_the_inputs_are_held(fmu_dir,
                                                                                 tmp_path):
    """The body integrates its linear dynamics exactly over a step with its inputs held
    (§ideal-actuation's zero-order hold), and its force is held over the source's 5 points anyway:
    stepped 5 points at once it lands where 5 single steps land, to rounding. Stepped 10 at once it
    no longer takes the force of every source point: it differs."""
    single = Master(body_driven(tmp_path, 1), fmu_dir).run()
    five = Master(body_driven(tmp_path, 5), fmu_dir).run()
    ten = Master(body_driven(tmp_path, 10), fmu_dir).run()
    assert single.error is None and five.error is None and ten.error is None
    own = np.arange(0, 401, 5)
    for sig in ("body.flange_a.s", "body.flange_b.s", "body.flange_b.v"):
        scale = np.abs(single[S(sig)]).max()
        assert scale > 1e-4
        np.testing.assert_allclose(five[S(sig)][own], single[S(sig)][own], rtol=0, atol=1e-12 * scale)
        between = np.setdiff1d(np.arange(401), own)
        assert np.all(five[S(sig)][between] == five[S(sig)][between - between % 5])
        assert np.abs(ten[S(sig)][::10] - single[S(sig)][::10]).max() > 1e-3 * scale


@pytest.mark.parametrize("every", ["0", "-2", "2.5", "true", '"3"'])
def test_every_must_be_a_whole_number_of_steps(tmp_path, every):
    text = f'step = 0.01\nstop_time = 0.1\n[instances.src]\ncomponent = "SignalSource"\n' \
           f'every = {every}\n'
    with pytest.raises(UserError, match="instance 'src': every = .* must be a whole number of "
                                        "communication steps from 1 to 1,000,000"):
        write(tmp_path, text)


def test_ssp_carries_the_rate_and_libcosim_steps_it_the_same(fmu_dir, tmp_path):
    """The archive gives the source its own step (5 ms on the 1 ms base step) in the OSP
    annotation; libcosim decimates it the same way: the body's positions match ours (Jacobi, no
    feedthrough into them) to 1e-12 of their range, where the source at every point would move
    them by 1e-4 of it."""
    s = body_driven(tmp_path, 1, n=200)
    path = ssp.export(s, fmu_dir, tmp_path / "driven.ssp")
    with zipfile.ZipFile(path) as zf:
        root = ET.fromstring(zf.read("SystemStructure.ssd"))
    hints = {c.get("name"): [h.get("value") for h in c.iter(f"{{{ssp.NS['osp']}}}StepSizeHint")]
             for c in root.iter(f"{{{ssp.NS['ssd']}}}Component")}
    assert hints == {"force": [repr(5 * 0.001)], "body": []}
    from fmpy.ssp.ssd import validate_tree
    from lxml import etree
    with zipfile.ZipFile(path) as zf:  # the annotation keeps the archive valid SSP 1.0
        validate_tree(etree.fromstring(zf.read("SystemStructure.ssd")),
                      "SystemStructureDescription.xsd")
    signals = ["body.flange_a.s", "body.flange_b.s"]
    _, theirs = run_libcosim(path, signals, s.n_steps, s.step)
    ours = Master(s, fmu_dir).run()
    every_point = Master(body_driven(tmp_path, 1, every_force=1, n=200, name="fine.toml"),
                         fmu_dir).run()
    for sig in signals:
        scale = np.abs(ours[S(sig)]).max()
        np.testing.assert_allclose(theirs[sig], ours[S(sig)], rtol=0, atol=1e-12 * scale)
        assert np.abs(every_point[S(sig)] - ours[S(sig)]).max() > 1e-4 * scale
