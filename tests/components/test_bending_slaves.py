"""The BendingActuator FMU (components/bending/slaves.py): its core stepped by hand, and its
errors."""

import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from musclesim.components.bending.slaves import BendingActuator

from conftest import in_process
from component_runs import make_bending



def test_fmu_refuses_bad_parameters_by_name():
    for name, value in (("thickness", -1e-4), ("pretension", -0.1), ("T_init", 0.0)):
        slave = in_process(BendingActuator, "act", **{name: value})
        with pytest.raises(ValueError, match=name):
            slave.setup()


def fmu_run(fmu_dir, tmp_path, name, inputs, outputs, dt, params=None):
    """Step the built FMU `name` through FMI with inputs[k] (a dict) held over step k; return the
    outputs at t_0 .. t_n as a list of rows."""
    md = read_model_description(str(fmu_dir / f"{name}.fmu"))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    slave = FMU2Slave(guid=md.guid, unzipDirectory=extract(fmu_dir / f"{name}.fmu", tmp_path),
                      modelIdentifier=md.coSimulation.modelIdentifier, instanceName=name)
    slave.instantiate()
    slave.setupExperiment(startTime=0.0)
    for key, value in (params or {}).items():
        slave.setReal([vr[key]], [value])
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    outs = [vr[o] for o in outputs]
    rows = [slave.getReal(outs)]
    for k, u in enumerate(inputs):
        slave.setReal([vr[i] for i in u], list(u.values()))
        slave.doStep(k * dt, dt)
        rows.append(slave.getReal(outs))
    slave.terminate()
    slave.freeInstance()
    return rows


def test_fmu_is_the_core_stepped_by_hand(fmu_dir, tmp_path):
    """The FMU adds nothing: the study's alternating pulses give the core's values bit for bit."""
    dt, n = 5e-4, 1200  # 0.6 s: each wire pulsed, cooling, pulsed again
    u = [(5.0 if k % 500 < 25 else 0.0, 5.0 if (k - 250) % 500 < 25 else 0.0) for k in range(n)]
    rows = fmu_run(fmu_dir, tmp_path, "BendingActuator",
                   [{"wireA.u": a, "wireB.u": b, "T_amb": 293.15} for a, b in u],
                   ["tip.s", "wireA.T", "wireB.f"], dt)
    core = make_bending()
    expected = [(core.deflection(0.017), core.T[0] + 273.15, core.tension[1])]
    for k in range(n):
        core.step(dt, u[k], 20.0, k * dt)
        expected.append((core.deflection(0.017), core.T[0] + 273.15, core.tension[1]))
    assert [tuple(r) for r in rows] == expected
    assert max(r[0] for r in rows) > 1e-5 and min(r[0] for r in rows) < -1e-5


@pytest.mark.parametrize("params", [{}, {"damping_ratio": 1.0}, {"damping_ratio": 1.5,
                                                                  "max_substep": 1e-4}],
                         ids=["nominal", "critical", "overdamped"])
def test_kernel_paths_agree(params):
    """The compiled kernel gives the bits of its plain-Python source along the study's alternating
    pulses (each wire heated, cooling, slack), with the mode under-, critically and over-damped."""
    from kernel_paths import assert_paths_agree

    def inputs(k):
        return {"wireA_u": 5.0 if k % 500 < 25 else 0.0,
                "wireB_u": 5.0 if (k - 250) % 500 < 25 else 0.0}
    assert_paths_agree(in_process(BendingActuator, "act", **params), inputs, 5e-4, 1200)
