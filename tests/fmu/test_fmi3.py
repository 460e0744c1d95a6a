"""FMI 3.0 FMUs (`musclesim build --fmi 3`): the same slaves behind `musclesim.fmu.fmi3.Fmi3Face`.
Every one passes FMPy's FMI 3.0 validation with its variables as the FMI 2.0 one declares them,
every shipped scenario runs on them to the FMI 2.0 bits, and a saved state restores in a fresh
instance."""
import time
import tomllib

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave
from fmpy.validation import validate_fmu

from musclesim.components import CATALOGUE
from musclesim.cosim import Master, build_all, load_scenario
from musclesim.errors import UserError

from conftest import SCENARIOS

RUNS = sorted(p for p in SCENARIOS.glob("*.toml") if "sweep" not in tomllib.loads(p.read_text()))
STEPS = 200  # communication steps of each run (at least; 0.25 s where that is more)


@pytest.mark.parametrize("name", CATALOGUE)
def test_fmi3_fmu_validates_and_declares_what_the_fmi2_one_does(fmu_dir, fmu3_dir, name):
    assert validate_fmu(str(fmu3_dir / f"{name}.fmu")) == []
    md2, md3 = (read_model_description(str(d / f"{name}.fmu")) for d in (fmu_dir, fmu3_dir))
    assert md3.fmiVersion == "3.0" and md3.defaultExperiment.stopTime == \
        md2.defaultExperiment.stopTime
    cs = md3.coSimulation
    assert not cs.needsExecutionTool and cs.canSerializeFMUstate
    assert cs.canHandleVariableCommunicationStepSize
    time, *variables = md3.modelVariables
    assert (time.name, time.causality, time.valueReference) == ("time", "independent", 0)
    fields = ("name", "causality", "variability", "initial", "start", "unit", "displayUnit",
              "description")
    assert [[str(getattr(v, f)) for f in fields] for v in variables] == \
        [[str(getattr(v, f)) for f in fields] for v in md2.modelVariables]
    assert [v.valueReference for v in variables] == \
        [v.valueReference + 1 for v in md2.modelVariables]
    assert [(o.variable.name, sorted(d.name for d in o.dependencies)) for o in md3.outputs] == \
        [(o.variable.name, sorted(d.name for d in o.dependencies)) for o in md2.outputs]


@pytest.mark.parametrize("path", RUNS, ids=lambda p: p.stem)
def test_every_shipped_scenario_runs_on_fmi3_fmus_to_the_fmi2_bits(fmu_dir, fmu3_dir, path):
    s = load_scenario(path)
    s = load_scenario(path, stop_time=min(s.stop_time, max(0.25, STEPS * s.step)))
    fmi2, fmi3 = Master(s, fmu_dir, host="fmpy").run(), Master(s, fmu3_dir).run()
    assert fmi2.error is None
    assert fmi3.names == fmi2.names
    np.testing.assert_array_equal(fmi3.time, fmi2.time)
    assert fmi3.data.tobytes() == fmi2.data.tobytes()
    assert (fmi3.error, fmi3.warnings) == (fmi2.error, fmi2.warnings)


@pytest.mark.benchmark
@pytest.mark.parametrize("path", RUNS, ids=lambda p: p.stem)
def test_every_shipped_scenario_under_a_minute_runs_whole_on_fmi3_fmus_to_the_fmi2_bits(
        fmu_dir, fmu3_dir, path):
    """The whole run, not its first steps: slow (minutes in all), so a benchmark, run on demand:
    ``python -m pytest -m benchmark -n 0 tests/fmu/test_fmi3.py``. A scenario whose FMI 2.0 run
    takes a minute or more on the fmpy host is skipped, saying how long it took."""
    s = load_scenario(path)
    started = time.perf_counter()
    fmi2 = Master(s, fmu_dir, host="fmpy").run()
    took = time.perf_counter() - started
    if took >= 60:
        pytest.skip(f"{path.stem}: {took:.0f} s on FMI 2.0 FMUs, over a minute")
    fmi3 = Master(s, fmu3_dir).run()
    assert fmi2.error is None and fmi3.names == fmi2.names
    np.testing.assert_array_equal(fmi3.time, fmi2.time)
    assert fmi3.data.tobytes() == fmi2.data.tobytes()
    assert (fmi3.error, fmi3.warnings) == (fmi2.error, fmi2.warnings)


def test_a_warning_logged_during_a_step_reaches_the_run_as_on_fmi2(fmu_dir, fmu3_dir, tmp_path):
    """A wire loaded far beyond its hysteresis data warns once, mid-step: the FMI 3.0 FMU passes
    the message on as the FMI 2.0 one does (pythonfmu3's C layer crashed the process on a
    pythonfmu message before)."""
    path = tmp_path / "loaded.toml"
    path.write_text('step = 0.001\nstop_time = 0.01\nrecord = ["wire.stress"]\n'
                    '[instances.wire]\ncomponent = "SmaWire"\n'
                    'parameters = { "flange.f" = 100.0 }\n')
    fmi2, fmi3 = (Master(load_scenario(path), d, host="fmpy").run() for d in (fmu_dir, fmu3_dir))
    assert len(fmi2.warnings) == 1 and "clamped" in fmi2.warnings[0]
    assert fmi3.warnings == fmi2.warnings and fmi3.data.tobytes() == fmi2.data.tobytes()


def test_a_failure_on_fmi3_names_the_instance_and_the_parameter(fmu3_dir):
    s = load_scenario(SCENARIOS / "crawler-ideal.toml", ["body.c=-1.3"], stop_time=0.1)
    res = Master(s, fmu3_dir).run()
    assert res.error.startswith("instance 'body' (CrawlerBody) failed during initialization at "
                                "t = 0 s: ") and "c must be non-negative" in res.error


def test_a_saved_fmi3_state_restores_in_a_fresh_instance_to_the_same_bits(fmu3_dir, tmp_path):
    path = fmu3_dir / "FrictionBlock.fmu"
    md = read_model_description(str(path))
    vr = {v.name: v.valueReference for v in md.modelVariables}

    def instance(folder, name):
        slave = FMU3Slave(guid=md.guid, unzipDirectory=extract(path, tmp_path / folder),
                          modelIdentifier="FrictionBlock", instanceName=name)
        slave.instantiate()
        slave.setFloat64([vr["t_switch"]], [0.05])  # the contact moves: state worth saving
        slave.enterInitializationMode(startTime=0.0)
        slave.exitInitializationMode()
        return slave

    def steps(slave, t):
        out = []
        for k in range(5):
            slave.setFloat64([vr["u"], vr["flange.v"], vr["flange.N"]], [1.0, 0.01, 2.0])
            slave.doStep(t + k * 1e-3, 1e-3)
            out.append(slave.getFloat64([vr["contact"], vr["slip"], vr["flange.f"]]))
        return out

    one = instance("one", "one")
    steps(one, 0.0)
    saved = one.getFMUState()
    data = one.serializeFMUState(saved)
    first = steps(one, 5e-3)
    two = instance("two", "two")
    two.setFMUState(two.deserializeFMUState(data))
    assert steps(two, 5e-3) == first and first[0] != first[-1]
    for slave in (one, two):
        slave.terminate()
        slave.freeInstance()


def test_only_fmi_2_and_3_are_built(tmp_path):
    with pytest.raises(UserError, match="FMI version 4"):
        build_all(tmp_path, ["PID"], fmi=4)
