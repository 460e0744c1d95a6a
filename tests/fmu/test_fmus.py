"""Every FMU of the catalogue: clean fmpy validation, documented SI variables, real FMU state
(restored in place and, serialized, in a fresh instance), what other tools need to import it,
and self-containment (runs in a virtual environment with only numpy, scipy and fmpy)."""
import gc
import inspect
import json
import subprocess
import sys
import textwrap

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from fmpy.validation import validate_fmu

from musclesim.cosim import host
from musclesim.components import CATALOGUE
from musclesim.fmu import UNITS

# parameter values that give each component internal state worth saving
STATEFUL = {
    "FrictionBlock": {"t_switch": 0.05},
    "GaitSequencer": {"t_protrusion": 0.002, "t_stance": 0.006},  # 8 ms strides: phases change
    "PID": {"Ki": 2.0, "Kd": 0.1, "Tf": 0.01},
    "GainScheduledPID": {"Ki[1]": 2.0, "Kd[1]": 0.1, "Tf": 0.01},
    "Thermocouple": {"tau": 0.01, "noise_std": 0.5, "seed": 3.0},  # the generator is state too
    "LoadCell": {"tau": 0.01},
    "LaserSensor": {"tau": 0.01, "noise_std": 1e-5, "seed": 2.0},
    "PressureSensor": {"tau": 0.01},
    "DeadWeight": {"inertia": 1.0},  # the positions of the last steps
    "Electromagnet": {"nonlinearity": 0.5},  # the coil current
    # valve delays pend across steps; a small cross-section keeps the random +-1 m flange
    # positions a small volume change
    "SoftActuator": {"s_a": 1e-6, "t_open_delay": 3e-3, "t_close_delay": 2e-3,
                     "C_leak": 1e-10},
    "SignalSource": {"kind": 1.0, "amplitude": 1.0, "frequency": 5.0},
    "ForcReference": {"period": 0.01},  # run 2 (5 K above T_low) spans the test steps
    # hot in the transformation, so the hysteresis memory moves; latent heat and drift state too
    "SmaWire": {"T_init": 350.0, "latent_heat": 20e3, "drift_shift": 3.0, "drift_amplitude": -0.1},
    # wires in their transformation, so the hysteresis memories and the first mode move
    "BendingActuator": {"T_init": 340.0},
    "LegSequencer": {"frequency": 100.0, "duty": 0.5},  # 5 ms pulses: outputs change in the test
    "CapstanMultiplier": {"T_init": 350.0, "composition_shift": 2.0},  # every segment's memory
    # thresholds 0.2 K apart around the 355 K input: the random inputs switch the relay
    "BangBang": {"T_on": 354.9, "T_off": 355.1},
}
# outputs that may repeat over five steps with one input: square waves, a memoryless spring, an
# inverse whose random strain references are clamped to the data set's range, a relay that settles
# at once under one held input
MEMORYLESS = {"FrictionSwitchingInputs", "BiasSpring", "PreisachInverse", "BangBang"}
# added to the random inputs in [-1, 1] so that they stay physical: K, N (~116 MPa on the wire), Pa
INPUT_OFFSETS = {"SmaWire": {"T_amb": 293.15, "flange.f": 1.47},
                 "BendingActuator": {"T_amb": 293.15, "wireA.u": 3.0, "wireB.u": 3.0},
                 "CapstanMultiplier": {"T_amb": 293.15, "flange.f": 1.47},
                 "BangBang": {"T": 355.0},
                 "PreisachInverse": {"sigma_ref": 125e6}}


@pytest.mark.parametrize("name", CATALOGUE)
def test_fmu_validates_without_problems(fmu_dir, name):
    assert validate_fmu(str(fmu_dir / f"{name}.fmu")) == []


@pytest.mark.parametrize("name", CATALOGUE)
def test_variables_have_descriptions_and_si_units(fmu_dir, name):
    md = read_model_description(str(fmu_dir / f"{name}.fmu"))
    assert md.description and md.coSimulation.canGetAndSetFMUstate
    for v in md.modelVariables:
        assert v.description, v.name
        assert (v.unit or "1") in UNITS, v.name
    outputs = {u.variable.name for u in md.outputs}
    assert outputs == {u.variable.name for u in md.initialUnknowns}
    assert outputs == {v.name for v in md.modelVariables if v.causality == "output"}


@pytest.mark.parametrize("name", CATALOGUE)
def test_other_tools_can_import_and_run_it_as_it_is(fmu_dir, name):
    """No external-tool flag (PyFMI refuses an FMU that sets it), a serializable state, a
    default experiment from 0 to the stop time of the component's study experiment in whole
    steps, and display units (C, MPa or kPa, mm) on the SI units users read in another."""
    md = read_model_description(str(fmu_dir / f"{name}.fmu"))
    cs, ex = md.coSimulation, md.defaultExperiment
    assert not cs.needsExecutionTool and cs.canSerializeFMUstate
    assert float(ex.startTime) == 0.0 and float(ex.stopTime) > 0 and float(ex.stepSize) > 0
    n = float(ex.stopTime) / float(ex.stepSize)
    assert abs(n - round(n)) < 1e-6 * n
    # display units where users read another unit: 293.15 K shows as 20 degC, 1 m as 1000 mm
    shown = {u.name: {d.name: (d.factor, d.offset) for d in u.displayUnits}
             for u in md.unitDefinitions}
    for v in md.modelVariables:
        expected = {"K": {"degC"}, "Pa": {"MPa", "kPa"}, "m": {"mm"}}.get(v.unit, {None})
        assert v.displayUnit in expected, v.name
        if v.displayUnit:
            factor, offset = shown[v.unit][v.displayUnit]
            assert {"degC": factor * 293.15 + offset, "MPa": factor * 1e6,
                    "kPa": factor * 1e3, "mm": factor * 1.0}[v.displayUnit] == pytest.approx(
                {"degC": 20.0, "MPa": 1.0, "kPa": 1.0, "mm": 1000.0}[v.displayUnit])


def _open(fmu_dir, name, tmp_path, instance=None):
    md = read_model_description(str(fmu_dir / f"{name}.fmu"))
    slave = FMU2Slave(guid=md.guid, unzipDirectory=extract(fmu_dir / f"{name}.fmu", tmp_path),
                      modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName=instance or name)
    slave.instantiate()
    slave.setupExperiment(startTime=0.0)
    variables = {v.name: v.valueReference for v in md.modelVariables}
    for par, value in STATEFUL.get(name, {}).items():
        slave.setReal([variables[par]], [value])
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    inputs = [v.valueReference for v in md.modelVariables if v.causality == "input"]
    outputs = [v.valueReference for v in md.modelVariables if v.causality == "output"]
    offsets = INPUT_OFFSETS.get(name, {})
    offset = np.array([offsets.get(v.name, 0.0) for v in md.modelVariables if v.causality == "input"])
    return slave, inputs, outputs, offset


@pytest.mark.parametrize("name", CATALOGUE)
def test_state_save_step_restore_redo_is_bit_identical(fmu_dir, name, tmp_path):
    slave, inputs, outputs, offset = _open(fmu_dir, name, tmp_path)
    rng = np.random.default_rng(7)
    t, h = 0.0, 1e-3

    def step(u):
        nonlocal t
        if inputs:
            slave.setReal(inputs, list(u + offset))
        slave.doStep(t, h)
        t += h
        return slave.getReal(outputs)

    for _ in range(20):  # build up internal state
        step(rng.uniform(-1, 1, len(inputs)) + (0.5 if name == "FrictionBlock" else 0))
    u_next = rng.uniform(-1, 1, len(inputs))
    saved, t_saved = slave.getFMUstate(), t
    first = [step(u_next) for _ in range(5)]
    step(rng.uniform(-1, 1, len(inputs)))  # wander off
    slave.setFMUstate(saved)
    t = t_saved
    again = [step(u_next) for _ in range(5)]
    slave.setFMUstate(saved)  # a saved state can be restored more than once
    t = t_saved
    third = [step(u_next) for _ in range(5)]
    assert first == again == third
    assert first[0] != first[-1] or name in MEMORYLESS  # the steps did something
    # serialized to bytes and restored in a fresh instance (another extraction, as another
    # process would), it steps on to the same bits
    data = slave.serializeFMUstate(saved)
    slave.freeFMUstate(saved)
    slave.terminate()
    slave.freeInstance()
    slave, *_ = _open(fmu_dir, name, tmp_path / "fresh", instance=f"{name}_restored")
    slave.setFMUstate(slave.deSerializeFMUstate(data))
    t = t_saved
    assert [step(u_next) for _ in range(5)] == first
    slave.terminate()
    slave.freeInstance()


def test_instances_leave_the_slave_namespace_with_every_reference_its_holders_release(fmu_dir,
                                                                                     tmp_path):
    """pythonfmu 0.7.0 releases, per instance, a reference to the slave module's namespace that it
    never took; the FMU's entry point gives one back. The count must stay at least what the
    objects holding the namespace will release when the interpreter clears the module at exit:
    below it, the namespace was freed while being cleared (the suite's process crashed as it
    ended, now and then)."""
    for k in range(3):
        slave = _open(fmu_dir, "SignalSource", tmp_path / str(k))[0]
        slave.terminate()
        slave.freeInstance()
    namespace = sys.modules["musclesim_fmu_SignalSource"].__dict__
    held = sum(sum(x is namespace for x in r) if isinstance(r, list) else 1
               for r in gc.get_referrers(namespace))
    assert held >= 1  # the module itself
    assert sys.getrefcount(namespace) - 2 >= held  # less this frame's name and the call's argument


def test_fmu_runs_in_a_venv_without_musclesim(fmu_dir, fmu3_dir, tmp_path):
    """An FMU needs only Python, numpy and scipy (fmpy is the host here), not this project;
    SmaWire finds its data files (wire parameters, FORC data sets) inside the FMU."""
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    py = venv / "bin" / "python"
    subprocess.run([str(py), "-m", "pip", "install", "-q", "numpy", "scipy", "fmpy"], check=True)
    # the process ends with the same exit-time workaround for pythonfmu 0.7 as musclesim's own
    release = inspect.getsource(host.release_pythonfmu_libraries)

    def run(body):
        script = textwrap.dedent("""
            import ctypes, importlib.util, json
            from pathlib import Path
            from fmpy import simulate_fmu
            assert importlib.util.find_spec("musclesim") is None
            assert importlib.util.find_spec("pythonfmu") is None
            assert importlib.util.find_spec("pythonfmu3") is None
        """) + textwrap.dedent(body) + textwrap.dedent(release) + "release_pythonfmu_libraries()\n"
        out = subprocess.run([str(py), "-c", script], capture_output=True, text=True, cwd=tmp_path)
        assert out.returncode == 0, out.stderr
        return json.loads(out.stdout.strip().splitlines()[-1])

    x1, x2, x_cm = run(f"""
        r = simulate_fmu({str(fmu_dir / 'CrawlerBody.fmu')!r}, stop_time=0.5, output_interval=1e-3,
                         start_values={{"f_a": 2.0}}, output=["flange_a.s", "flange_b.s", "x_cm"])
        print(json.dumps([float(r["flange_a.s"][-1]), float(r["flange_b.s"][-1]),
                          float(r["x_cm"][-1])]))
    """)
    assert x1 < 0 < x2 and abs(x_cm) < 1e-12  # pushed apart, centre of mass fixed
    # its FMI 3.0 build too, which ships pythonfmu3's and pythonfmu's Python files: the same bits
    assert run(f"""
        r = simulate_fmu({str(fmu3_dir / 'CrawlerBody.fmu')!r}, stop_time=0.5, output_interval=1e-3,
                         start_values={{"f_a": 2.0}}, output=["flange_a.s", "flange_b.s", "x_cm"])
        print(json.dumps([float(r[c][-1]) for c in ("flange_a.s", "flange_b.s", "x_cm")]))
    """) == [x1, x2, x_cm]
    # in the same process: simulate_fmu deleted CrawlerBody's folder, whose copy of musclesim the
    # process imported; SmaWire must bring its own
    wires = run(f"""
        simulate_fmu({str(fmu_dir / 'CrawlerBody.fmu')!r}, stop_time=0.01, output_interval=1e-3)
        wire = [simulate_fmu({str(fmu_dir / 'SmaWire.fmu')!r}, stop_time=0.4, output_interval=4e-4,
                             start_values={{"u": 2.0, "hysteresis": k}}, output=["T", "strain"])
                for k in (0.0, 1.0)]  # the reference wire's parameter file; a FORC data set
        print(json.dumps([[float(w["T"][-1]), float(w["strain"][-1])] for w in wire]))
    """)
    for T_wire, strain in wires:
        assert T_wire > 373.15 and strain > 0.03  # heated past the transformation: contracted
    # the bending actuator reads the 127 um wire's hysteresis file from its own resources
    tip = run(f"""
        simulate_fmu({str(fmu_dir / 'CrawlerBody.fmu')!r}, stop_time=0.01, output_interval=1e-3)
        r = simulate_fmu({str(fmu_dir / 'BendingActuator.fmu')!r}, stop_time=0.5,
                         output_interval=5e-4, start_values={{"wireA.u": 1.5}}, output=["tip.s"])
        print(json.dumps(float(r["tip.s"][-1])))
    """)
    assert tip > 1e-6  # wire A warmed into its transformation: bent toward A
