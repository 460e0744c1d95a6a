"""musclesim.cosim.direct: a musclesim FMU's slave class loaded once per process from its own
resources (read from the archive, nothing unpacked), called as pythonfmu's C layer calls it; an
exception in the slave is logged as its repr and raised as fmpy raises a failed call."""
import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

from musclesim.cosim import direct
from musclesim.cosim.host import read_fmu


def test_the_class_is_loaded_once_for_every_copy_of_an_fmu(fmu_dir, tmp_path):
    path = fmu_dir / "SignalSource.fmu"
    md = read_fmu(path)
    copy = tmp_path / "copy.fmu"
    copy.write_bytes(path.read_bytes())
    one = direct.slave_class(path, md.coSimulation.modelIdentifier)
    two = direct.slave_class(copy, md.coSimulation.modelIdentifier)
    assert one is two and one.__name__ == md.coSimulation.modelIdentifier
    assert not list(tmp_path.glob("*/")) and sorted(tmp_path.iterdir()) == [copy]  # unpacked: none


def test_a_failing_call_is_logged_and_raised_as_fmpy_raises_it(fmu_dir, tmp_path):
    path = fmu_dir / "CrawlerBody.fmu"
    md = read_fmu(path)
    log = []
    slave = direct.DirectSlave(direct.slave_class(path, md.coSimulation.modelIdentifier),
                               "body", log)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    slave.setup_experiment(0.0, 1.0)
    slave.set_real([vr["m1"]], [-0.2])  # a mass below zero: refused as initialization ends
    slave.enter_initialization_mode()
    with pytest.raises(FMICallException):
        slave.exit_initialization_mode()
    assert log and log[-1][0] == direct.ERROR and "m1" in log[-1][1]
    assert slave.reader([], np.zeros(0)) is None and slave.writer([], None, None) is None
