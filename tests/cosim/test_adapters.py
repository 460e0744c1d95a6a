"""musclesim.cosim.adapters: an FMU called through fmpy (FMI 2.0 and 3.0) the way the master calls
it, with Real, Integer and Boolean values moved as floats; the same numbers as the direct host.

A relay (BangBang: input T, Boolean parameter initially_on, Real output y, Boolean output on)
driven through a cold and a hot spell: hand-derived, it switches on below T_on and off above
T_off."""
import numpy as np
import pytest

from musclesim.cosim import direct
from musclesim.cosim.adapters import KINDS, Fmpy3Slave, FmpySlave
from musclesim.cosim.host import callbacks, extract_fmu, read_fmu

T_ON, T_OFF = 290.0, 300.0
TEMPERATURES = [295.0, 285.0, 295.0, 305.0, 295.0]  # inside, cold, inside, hot, inside
ON = [0.0, 1.0, 1.0, 0.0, 0.0]  # the relay's state after each temperature: hysteresis


def drive(slave, md):
    """Set the thresholds, then read (y, on) after each temperature, through the master's calls."""
    vr = {v.name: v.valueReference for v in md.modelVariables}
    kind = {v.name: KINDS[v.type] for v in md.modelVariables if v.type in KINDS}
    names = ["T_on", "T_off", "initially_on"]
    slave.setup_experiment(0.0, 1.0)
    slave.set_real([vr[n] for n in names], [T_ON, T_OFF, 0.0], [kind[n] for n in names])
    out, values = np.zeros(2), np.zeros(1)
    get = slave.reader([vr["y"], vr["on"]], out, [kind["y"], kind["on"]])
    put = slave.writer([vr["T"]], np.array([0]), values, [kind["T"]])
    step = slave.stepper()
    values[0] = TEMPERATURES[0]
    slave.enter_initialization_mode()
    put()
    slave.exit_initialization_mode()
    rows = []
    for k, temperature in enumerate(TEMPERATURES):
        values[0] = temperature
        put()
        step(0.1 * k, 0.1)
        get()
        rows.append(out.copy())
    slave.terminate()
    return np.array(rows)


def test_nothing_to_read_or_write_gives_no_call(fmu_dir, tmp_path):
    path = fmu_dir / "BangBang.fmu"
    md = read_fmu(path)
    slave = FmpySlave(md, extract_fmu(path, tmp_path / "x"), "relay", callbacks(0))
    assert slave.reader([], np.zeros(0)) is None
    assert slave.writer([], np.zeros(0, dtype=np.intp), np.zeros(0)) is None
    slave.terminate()


def test_the_fmi2_adapter_moves_real_and_boolean_values_as_the_direct_host_does(fmu_dir,
                                                                               tmp_path):
    path = fmu_dir / "BangBang.fmu"
    md = read_fmu(path)
    assert {KINDS[v.type] for v in md.modelVariables if v.name in ("on", "initially_on")} \
        == {"Boolean"}
    fmpy_rows = drive(FmpySlave(md, extract_fmu(path, tmp_path / "a"), "relay", callbacks(0)),
                      md)
    assert list(fmpy_rows[:, 1]) == ON
    cls = direct.slave_class(path, md.coSimulation.modelIdentifier)
    direct_rows = drive(direct.DirectSlave(cls, "relay", []), md)
    assert np.array_equal(fmpy_rows, direct_rows)


def test_the_fmi3_adapter_gives_the_same_numbers(fmu_dir, fmu3_dir, tmp_path):
    md2, md3 = read_fmu(fmu_dir / "BangBang.fmu"), read_fmu(fmu3_dir / "BangBang.fmu")
    assert md3.fmiVersion.startswith("3")
    log = []
    rows3 = drive(Fmpy3Slave(md3, extract_fmu(fmu3_dir / "BangBang.fmu", tmp_path / "c"),
                             "relay", log), md3)
    rows2 = drive(FmpySlave(md2, extract_fmu(fmu_dir / "BangBang.fmu", tmp_path / "d"), "relay",
                            callbacks(0)), md2)
    assert list(rows3[:, 1]) == ON and np.array_equal(rows3, rows2)


@pytest.mark.parametrize("fmi_type, kind", [("Real", "Real"), ("Float64", "Real"),
                                            ("Integer", "Integer"), ("Int32", "Integer"),
                                            ("Boolean", "Boolean")])
def test_kinds_name_fmi2_and_fmi3_types_by_their_fmi2_name(fmi_type, kind):
    assert KINDS[fmi_type] == kind
