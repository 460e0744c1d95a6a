"""A scenario exported as one FMU (FMPy's container FMU, musclesim.export.container): it validates
clean, and FMPy's simulate_fmu runs it to our results bit for bit, every Jacobi scenario shipped
(the first 200 steps or 0.25 s)."""
import tomllib
import zipfile
from dataclasses import replace

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.validation import validate_fmu

from musclesim.cli import main
from musclesim.cosim import Master, Signal, forget_fmu_resource_paths, load_scenario
from musclesim.export import export_fmu
from musclesim.errors import UserError

from conftest import SCENARIOS

S = Signal.parse

STEPS, SECONDS = 200, 0.25
# Scenarios whose initial state closes a loop through initialization: the position control's
# electromagnet starts at the current its PID's first output asks for, which the load cell's
# reading of that magnet decides. Our master passes values in initialization mode and once more
# after it; FMPy's container runtime only in it, so its first step starts from the magnet's
# current before the PID spoke, and the run parts from ours from there (docs/user/export.md).
INIT_LOOP = {"sma-position-control"}


def _jacobi():
    out = []
    for path in sorted(SCENARIOS.glob("*.toml")):
        if "sweep" in tomllib.loads(path.read_text()):
            continue
        if load_scenario(path).algorithm == "jacobi":
            out.append(path)
    return out


@pytest.mark.parametrize("path", _jacobi(), ids=lambda p: p.stem)
def test_fmpy_runs_the_exported_scenario_to_our_bits(fmu_dir, tmp_path, path):
    s = load_scenario(path)
    s = load_scenario(path, stop_time=s.start_time + min(STEPS, round(SECONDS / s.step)) * s.step)
    fmu = export_fmu(s, fmu_dir, tmp_path / f"{s.name}.fmu")
    assert validate_fmu(str(fmu)) == []
    ours = Master(s, fmu_dir).run()
    assert ours.error is None
    theirs = simulate_fmu(str(fmu), start_time=s.start_time, stop_time=s.stop_time,
                          output_interval=s.step, output=list(map(str, ours.names)))
    forget_fmu_resource_paths()
    assert np.array_equal(theirs["time"], ours.time)
    differ = [c for c in ours.names if not np.array_equal(theirs[str(c)], ours[c])]
    if s.name in INIT_LOOP:  # listed for a reason that still holds
        assert S("loadcell.f_meas") in differ and theirs["loadcell.f_meas"][0] != \
            ours[S("loadcell.f_meas")][0]
    else:
        assert differ == []


@pytest.mark.parametrize("name, inner", [("crawler-ideal", 3), ("sma-temperature-tracking", 3),
                                         ("crawler-pneumatic", 2)])
def test_an_fmi3_container_of_fmi3_or_fmi2_fmus_runs_to_our_bits(fmu_dir, fmu3_dir, tmp_path, name,
                                                                inner):
    """``--fmi 3``: the same container as an FMI 3.0 FMU, around the FMI 3.0 FMUs or the FMI 2.0
    ones (FMPy's runtime takes either)."""
    s = load_scenario(SCENARIOS / f"{name}.toml")
    s = load_scenario(SCENARIOS / f"{name}.toml",
                      stop_time=s.start_time + min(STEPS, round(SECONDS / s.step)) * s.step)
    fmu = export_fmu(s, fmu3_dir if inner == 3 else fmu_dir, tmp_path / f"{name}.fmu", fmi=3)
    assert validate_fmu(str(fmu)) == []
    md = read_model_description(str(fmu))
    assert md.fmiVersion == "3.0" and md.modelVariables[0].causality == "independent"
    ours = Master(s, fmu_dir).run()
    theirs = simulate_fmu(str(fmu), start_time=s.start_time, stop_time=s.stop_time,
                          output_interval=s.step, output=list(map(str, ours.names)))
    forget_fmu_resource_paths()
    assert np.array_equal(theirs["time"], ours.time)
    assert [c for c in ours.names if not np.array_equal(theirs[str(c)], ours[c])] == []


def test_its_variables_are_the_scenarios_values_free_inputs_and_recorded_signals(fmu_dir,
                                                                                tmp_path):
    s = load_scenario(SCENARIOS / "crawler-ideal.toml", ["body.k=150"], stop_time=1.0)
    md = read_model_description(str(export_fmu(s, fmu_dir, tmp_path / "crawler.fmu")))
    by = {v.name: v for v in md.modelVariables}
    assert by["body.k"].causality == "parameter" and float(by["body.k"].start) == 150.0
    assert by["body.x_cm"].causality == "output" and by["body.x_cm"].unit == "m"
    assert by["body.x_cm"].displayUnit == "mm"
    assert "body.f_a" not in by  # connected: not the container's
    free = {v.name for v in md.modelVariables if v.causality == "input"}
    assert "body.flange_a.f" not in free and free  # fed by friction1; others are free inputs
    assert md.modelName == "crawler_ideal"  # an identifier, as OMSimulator requires
    ex = md.defaultExperiment
    assert (float(ex.startTime), float(ex.stopTime), float(ex.stepSize)) == (0.0, 1.0, 1e-3)
    with zipfile.ZipFile(tmp_path / "crawler.fmu") as zf:
        names = zf.namelist()
    assert "resources/CrawlerBody/modelDescription.xml" in names
    assert not any(n.endswith(".zip") for n in names)


def test_what_a_container_cannot_do_is_refused(fmu_dir, tmp_path):
    s = load_scenario(SCENARIOS / "crawler-ideal.toml")
    with pytest.raises(UserError, match="a Gauss-Seidel scenario would give other results"):
        export_fmu(replace(s, algorithm="gauss-seidel"), fmu_dir, tmp_path / "a.fmu")
    slow = {**s.instances, "inputs": replace(s.instances["inputs"], every=2)}
    with pytest.raises(UserError, match="instance 'inputs' steps every 2 points"):
        export_fmu(replace(s, instances=slow), fmu_dir, tmp_path / "b.fmu")
    with pytest.raises(UserError, match="must have a name ending in .fmu"):
        export_fmu(s, fmu_dir, tmp_path / "c.zip")
    with pytest.raises(UserError, match="FMI version 1: a container FMU is FMI 2.0 or 3.0"):
        export_fmu(s, fmu_dir, tmp_path / "d.fmu", fmi=1)
    assert not list(tmp_path.iterdir())  # nothing written


def test_cli_writes_one_fmu_or_an_archive_not_both(fmu_dir, tmp_path, capsys):
    cli = ["export", str(SCENARIOS / "crawler-ideal.toml"), "--fmus", str(fmu_dir),
           "--stop-time", "0.1"]
    assert main([*cli, "--fmu", str(tmp_path / "c.fmu")]) == 0
    assert "wrote" in capsys.readouterr().out and (tmp_path / "c.fmu").is_file()
    assert main([*cli, "--fmu", str(tmp_path / "c3.fmu"), "--fmi", "3"]) == 0
    assert read_model_description(str(tmp_path / "c3.fmu")).fmiVersion == "3.0"
    with pytest.raises(SystemExit) as stop:
        main([*cli, "--fmu", str(tmp_path / "d.fmu"), "--ssp", str(tmp_path / "d.ssp")])
    assert stop.value.code == 2 and "not allowed with argument" in capsys.readouterr().err


def _step_drifting(fmu, where, identifier, s, signal, lag):
    """Run the container FMU `fmu` (unpacked into `where`) through its binary `identifier` as a
    host whose clock lags the grid: every step `lag` (a fraction) shorter than the scenario's,
    then one last step to the stop time. Returns (the statuses of the steps, the values of
    `signal` after each full step)."""
    from ctypes import c_double, c_int, c_void_p

    from fmpy import extract
    from fmpy.fmi2 import FMU2Slave

    md = read_model_description(str(fmu))
    vr = next(v.valueReference for v in md.modelVariables if v.name == signal)
    slave = FMU2Slave(guid=md.guid, unzipDirectory=extract(str(fmu), str(where)),
                      modelIdentifier=identifier, instanceName="drift")
    slave.instantiate()
    slave.setupExperiment(startTime=s.start_time)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    do_step = slave.dll.fmi2DoStep  # the status, not fmpy's exception: both answers are seen
    do_step.argtypes, do_step.restype = [c_void_p, c_double, c_double, c_int], c_int
    statuses, values, t, h = [], [], s.start_time, s.step * (1 - lag)
    for _ in range(s.n_steps):
        statuses.append(do_step(slave.component, t, h, 1))
        t += h
        values.append(slave.getReal([vr])[0])
    statuses.append(do_step(slave.component, t, s.stop_time - t, 1))  # the drift
    if not any(statuses):
        slave.terminate()
    slave.freeInstance()
    forget_fmu_resource_paths()
    return statuses, values


def test_a_host_whose_clock_drifted_from_the_grid_runs_it_to_our_bits(fmu_dir, tmp_path):
    """A host that sums its steps reaches the stop time a little early and asks for one tiny last
    step (OMSimulator: "communicationStepSize=0.0000000000491... must be an even multiple of
    fixedStepSize=0.001"). The container takes its steps as the whole fixed steps they stand for,
    to our results bit for bit, and the tiny last one as done; FMPy's runtime alone refuses the
    first step that starts off its own time."""
    s = load_scenario(SCENARIOS / "crawler-ideal.toml", stop_time=0.2)
    fmu = export_fmu(s, fmu_dir, tmp_path / "crawler.fmu")
    with zipfile.ZipFile(fmu) as zf:
        if "binaries/linux64/container_fmu.runtime.so" not in zf.namelist():
            pytest.skip("no C compiler: the container has FMPy's runtime alone")
    ours = Master(s, fmu_dir).run()
    lag = 5e-11 / s.stop_time  # 5e-11 s behind at the stop time, as reported
    statuses, values = _step_drifting(fmu, tmp_path / "a", "container_fmu", s, "body.x_cm", lag)
    assert statuses == [0] * (s.n_steps + 1)
    assert np.array_equal(values, ours[S("body.x_cm")][1:])
    statuses, _ = _step_drifting(fmu, tmp_path / "b", "container_fmu.runtime", s, "body.x_cm",
                                 lag)
    assert statuses[0] == 0 and 3 in statuses[1:]  # fmi2Error from the second step on


def test_a_c_host_without_python_runs_it_to_our_bits(fmu_dir, tmp_path):
    """The container in the C host of tests/fmu/data/fmi2_host.c (no Python in its process, no
    PYTHON* variable): the runtime loads the FMUs inside, whose loaders start Python, and the
    blocks' positions are our master's bit for bit."""
    import os
    import shutil
    import subprocess
    from pathlib import Path

    import fmpy

    compiler = shutil.which("gcc") or shutil.which("cc")
    if compiler is None:
        pytest.skip("no C compiler (gcc or cc) to build the C host")
    s = load_scenario(SCENARIOS / "crawler-ideal.toml", stop_time=0.05)
    fmu = export_fmu(s, fmu_dir, tmp_path / "crawler.fmu")
    md = read_model_description(str(fmu))
    vr = next(v.valueReference for v in md.modelVariables if v.name == "body.flange_b.s")
    with zipfile.ZipFile(fmu) as zf:
        zf.extractall(tmp_path / "x")
    host = tmp_path / "fmi2_host"
    subprocess.run([compiler, f"-I{Path(fmpy.__file__).parent / 'c-code'}",
                    str(Path(__file__).parents[1] / "fmu" / "data" / "fmi2_host.c"),
                    "-o", str(host), "-ldl"], check=True)
    env = {k: v for k, v in os.environ.items()
           if not k.startswith("PYTHON") and k not in ("LD_PRELOAD", "LD_LIBRARY_PATH")}
    done = subprocess.run([str(host), str(tmp_path / "x/binaries/linux64/container_fmu.so"),
                           (tmp_path / "x/resources").as_uri(), md.guid, repr(s.step),
                           str(s.n_steps), str(vr)], capture_output=True, text=True, env=env,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    values = [float(line.split()[1]) for line in done.stdout.splitlines()]
    assert np.array_equal(values, Master(s, fmu_dir).run()[S("body.flange_b.s")][1:])
