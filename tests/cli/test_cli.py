"""The command line on good and bad input: one clear sentence for every mistake, kept results."""
import json
import shutil

import pytest

from musclesim import cli
from musclesim.cosim import Signal

from conftest import SCENARIOS

IDEAL = SCENARIOS / "crawler-ideal.toml"


def run(capsys, *argv):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_run_writes_results_summary_and_plot_reproducibly(fmu_dir, tmp_path, capsys):
    for out in ("a", "b"):
        code, text, err = run(capsys, "run", IDEAL, "--out", tmp_path / out, "--fmus", fmu_dir,
                              "--stop-time", "2", "--set", "inputs.phi=1.0")
        assert code == 0, err
    assert "mean_speed" in text and str(tmp_path / "b" / "results.png") in text
    assert text.splitlines()[0].endswith("(with --set inputs.phi=1.0)")  # the run, not the file
    summary = json.loads((tmp_path / "a" / "summary.json").read_text())
    for key in ("x1_final", "x2_final", "x_cm_final", "mean_speed"):
        assert isinstance(summary[key], float)
    assert summary["units"]["mean_speed"] == "m/s" and summary["completed"] is True
    assert summary["parameters"]["inputs"]["phi"] == 1.0
    a, b = ((tmp_path / d / "results.csv").read_bytes() for d in "ab")
    assert a == b  # reruns are bit-identical, the whole file
    run_ids = [json.loads((tmp_path / d / "summary.json").read_text())["run_id"] for d in "ab"]
    assert run_ids[0] != run_ids[1]  # the run's id lives in its summary only
    lines = a.decode().splitlines()
    header = lines[0].split(",")  # a plain CSV: the header on line 1
    assert header[0] == "time" and "body.flange_a.s" in header and len(lines) == 2002
    assert sorted(p.name for p in (tmp_path / "a").iterdir()) == [
        "results.csv", "results.png", "summary.json"]
    assert (tmp_path / "a" / "results.png").stat().st_size > 10_000


def write(tmp_path, text, name="bad.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def ideal_with(tmp_path, old, new):
    text = IDEAL.read_text()
    assert old in text
    return write(tmp_path, text.replace(old, new))


CASES = {
    "missing-file": (lambda p: p / "nope.toml", [], "does not exist"),
    "malformed-toml": (lambda p: write(p, "step = [1,"), [], "not valid TOML"),
    "unknown-component": (lambda p: ideal_with(p, 'component = "CrawlerBody"', 'component = '
                                                                               '"Crawler"'),
                          [], "component 'Crawler' has no FMU"),
    "unknown-instance": (lambda p: ideal_with(p, '["inputs.f_a", "body.f_a"]', '["input.f_a", '
                                                                               '"body.f_a"]'),
                         [], "no instance 'input'"),
    "unknown-variable": (lambda p: ideal_with(p, '"body.x_cm", op', '"body.xcm", op'),
                         [], "has no variable 'xcm'"),
    "incompatible-units": (lambda p: ideal_with(p, '["inputs.f_a", "body.f_a"]',
                                                '["inputs.f_a", "friction1.flange.v"]'),
                           [], "incompatible units 'N' and 'm/s'"),
    "output-to-output": (lambda p: ideal_with(p, '["inputs.f_a", "body.f_a"]', '["inputs.f_a", '
                                                                               '"body.x_cm"]'),
                         [], "body.x_cm is an output, not an input"),
    "non-positive-step": (lambda p: ideal_with(p, "step = 1e-3", "step = -1e-3"), [], "step must be positive"),
    "unknown-parameter": (lambda p: IDEAL, ["--set", "body.mass=1"], "has no variable 'mass'"),
    "unknown-set-instance": (lambda p: IDEAL, ["--set", "robot.m1=1"], "no instance 'robot'"),
    "non-numeric-set": (lambda p: IDEAL, ["--set", "body.m1=heavy"], "'heavy' is not a number"),
    "set-a-connected-input": (lambda p: IDEAL, ["--set", "body.f_a=1"],
                              "body.f_a is an input connected from inputs.f_a"),
    "set-an-output": (lambda p: IDEAL, ["--set", "body.x_cm=1"],
                      "body.x_cm is an output, not a parameter or an input"),
    "algebraic-loop": (lambda p: ideal_with(p, '["inputs.f_a", "body.f_a"]', '["friction1.flange.f", "body.f_a"]'),
                       [], "algebraic loop: outputs of body, friction1"),
}


def test_a_tracking_error_is_printed_in_its_measurements_unit(fmu_dir, tmp_path, capsys):
    """sma-bench-tracking's tracking_rms, the rms of the PID's error (unit "1" in its FMU), is of
    the thermocouple's kelvin its wiring feeds the PID (its window starts at 10 s)."""
    code, text, err = run(capsys, "run", SCENARIOS / "sma-bench-tracking.toml", "--out",
                          tmp_path, "--fmus", fmu_dir, "--stop-time", "10.5")
    assert code == 0, err
    printed = [line for line in text.splitlines() if line.startswith("tracking_rms = ")]
    assert len(printed) == 1 and printed[0].endswith(" K")
    assert json.loads((tmp_path / "summary.json").read_text())["units"]["tracking_rms"] == "K"


@pytest.mark.parametrize("case", CASES)
def test_bad_input_is_one_sentence(case, fmu_dir, tmp_path, capsys):
    make, extra, expected = CASES[case]
    code, out, err = run(capsys, "run", make(tmp_path), "--out", tmp_path / "out",
                         "--fmus", fmu_dir, *extra)
    assert code == 2
    assert expected in err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1


def test_problems_are_collected_not_first_only(fmu_dir, tmp_path, capsys):
    path = ideal_with(tmp_path, '["inputs.u1", "friction1.u"]', '["inputs.u9", "friction1.w"]')
    code, _, err = run(capsys, "run", path, "--out", tmp_path / "o", "--fmus", fmu_dir)
    assert code == 2 and "'u9'" in err and "'w'" in err


def test_fmu_error_during_initialization_names_instance_and_cause(fmu_dir, tmp_path, capsys):
    code, _, err = run(capsys, "run", IDEAL, "--out", tmp_path / "o", "--fmus", fmu_dir,
                       "--set", "body.c=-1.3")
    assert code == 1
    assert "instance 'body' (CrawlerBody) failed during initialization at t = 0 s" in err
    assert "c must be non-negative (got -1.3)" in err


def test_failure_mid_run_keeps_results_up_to_then(fmu_dir, tmp_path, capsys):
    # f_a = 1.7e308 + 1e308 sin(2 pi t) overflows once sin(2 pi t) > 0.0977, at t = 0.0156 s
    code, _, err = run(capsys, "run", IDEAL, "--out", tmp_path / "o", "--fmus", fmu_dir,
                       "--set", "inputs.f_mean=1.7e308", "--set", "inputs.f_amp=1e308")
    assert code == 1
    assert "signal inputs.f_a became inf at t = 0.016 s" in err
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["completed"] is False and summary["end_time"] == pytest.approx(0.016)
    rows = (tmp_path / "o" / "results.csv").read_text().splitlines()
    assert len(rows) == 1 + 17 and rows[-1].split(",")[0] == repr(summary["end_time"])


def test_stale_fmus_are_refused(fmu_dir, tmp_path, capsys):
    stale = tmp_path / "fmus"
    shutil.copytree(fmu_dir, stale)
    (stale / "BUILD.json").write_text('{"sources": "old"}')
    code, _, err = run(capsys, "run", IDEAL, "--out", tmp_path / "o", "--fmus", stale)
    assert code == 2 and "musclesim build" in err


def test_build_command_writes_every_fmu(tmp_path, capsys):
    from musclesim.components import CATALOGUE

    code, out, _ = run(capsys, "build", "--fmus", tmp_path)
    assert code == 0
    assert sorted(p.stem for p in tmp_path.glob("*.fmu")) == sorted(CATALOGUE)
    assert (tmp_path / "BUILD.json").is_file() and "built" in out


def test_the_build_command_runs_the_cores_as_plain_python_and_writes_the_same_fmus(fmu_dir,
                                                                                   tmp_path):
    """`musclesim build` in a process of its own compiles nothing, and every model description
    it writes (the start values come from running each slave's setup and outputs) is that of the
    session's build, whose cores ran compiled."""
    import os
    import re
    import subprocess
    import sys
    import zipfile

    script = ("import sys; from musclesim import cli; code = cli.main(sys.argv[1:]); "
              "from musclesim.fmu import COMPILED; print('compiled:', COMPILED); sys.exit(code)")
    env = {k: v for k, v in os.environ.items() if k != "MUSCLESIM_COMPILE"}
    done = subprocess.run([sys.executable, "-c", script, "build", "--fmus", str(tmp_path)],
                          env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[-1] == "compiled: False"

    def description(fmu):
        with zipfile.ZipFile(fmu) as zf:
            text = zf.read("modelDescription.xml").decode()
        return re.sub(r'(generationDateAndTime|guid)="[^"]*"', "", text)
    built = sorted(tmp_path.glob("*.fmu"))
    assert [f.name for f in built] == sorted(f.name for f in fmu_dir.glob("*.fmu"))
    for fmu in built:
        assert description(fmu) == description(fmu_dir / fmu.name), fmu.name


def test_parameters_file_is_read_and_inline_values_win(fmu_dir, tmp_path, capsys):
    (tmp_path / "body.toml").write_text("m1 = 0.3\nk = 150.0\n")
    path = ideal_with(tmp_path,
                      "parameters = { m1 = 0.2, m2 = 0.2, k = 200.0, c = 1.3, theta = 0.0 }",
                      'parameters_file = "body.toml"\nparameters = { m2 = 0.25 }')
    code, _, err = run(capsys, "run", path, "--out", tmp_path / "o", "--fmus", fmu_dir,
                       "--stop-time", "0.01")
    assert code == 0, err
    params = json.loads((tmp_path / "o" / "summary.json").read_text())["parameters"]["body"]
    assert params == {"m1": 0.3, "k": 150.0, "m2": 0.25}
    (tmp_path / "body.toml").write_text("m1 = 'heavy'\n")
    code, _, err = run(capsys, "run", path, "--out", tmp_path / "o", "--fmus", fmu_dir)
    assert code == 2 and "sets m1 to something that is not a finite number" in err
    assert "heavy" not in err  # a value read from a file is never repeated


def test_metric_window_scale_and_per_period(fmu_dir, tmp_path, capsys):
    import numpy as np

    metrics = ('[metrics]\nlate = { signal = "body.x_cm", op = "rms", from = 1.5 }\n'
               'middle = { signal = "body.x_cm", op = "max", from = 0.5, to = 1.0 }\n'
               'per_stride = { signal = "body.x_cm", op = "per_period", period = 3.0, '
               'from = 0.5, scale = -1.0 }')
    path = ideal_with(tmp_path, "[metrics]", metrics)
    code, _, err = run(capsys, "run", path, "--out", tmp_path / "o", "--fmus", fmu_dir,
                       "--stop-time", "2")
    assert code == 0, err
    data = np.genfromtxt(tmp_path / "o" / "results.csv", delimiter=",", names=True,
                         deletechars="")
    t, x = data["time"], data["body.x_cm"]
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    # a window's edge takes the sample on it, which the accumulated time misses by ~1e-13 s
    tol = 1e-9
    assert summary["late"] == pytest.approx(float(np.sqrt(np.mean(x[t >= 1.5 - tol] ** 2))),
                                            rel=1e-12)
    middle = (t >= 0.5 - tol) & (t <= 1.0 + tol)
    assert middle.sum() == 501
    assert summary["middle"] == pytest.approx(x[middle].max(), rel=1e-12)
    window = t >= 0.5 - tol
    rate = (x[window][-1] - x[window][0]) / (t[window][-1] - t[window][0])
    assert summary["per_stride"] == pytest.approx(-3.0 * rate, rel=1e-12)
    assert summary["units"]["per_stride"] == "m"


def test_per_period_metric_needs_a_period(fmu_dir, tmp_path, capsys):
    path = ideal_with(tmp_path, "[metrics]",
                      '[metrics]\nstride = { signal = "body.x_cm", op = "per_period" }')
    code, _, err = run(capsys, "run", path, "--out", tmp_path / "o", "--fmus", fmu_dir)
    assert code == 2 and "per_period with period = a positive time" in err


def test_a_scenario_extends_another(fmu_dir, tmp_path, capsys):
    from musclesim.cosim import scenario

    shutil.copy(IDEAL, tmp_path / "base.toml")
    (tmp_path / "variant.toml").write_text(
        'extends = "base.toml"\nname = "variant"\nstop_time = 2.0\nrecord = ["body.flange_a.N"]\n'
        '[instances.body]\nparameters = { theta = 0.1 }\n'
        '[metrics]\nx1_final = { signal = "body.flange_a.s", op = "max" }\n')
    s = scenario.load(tmp_path / "variant.toml")
    assert (s.name, s.stop_time) == ("variant", 2.0)
    # tables merge key by key: the other parameters and metrics stay
    assert s.instances["body"].parameters == {"m1": 0.2, "m2": 0.2, "k": 200.0, "c": 1.3,
                                              "theta": 0.1}
    assert s.metrics["x1_final"].op == "max" and "mean_speed" in s.metrics
    assert s.record[-2:] == (Signal("friction2", "flange.f"),  # lists are added to
                             Signal("body", "flange_a.N"))
    (tmp_path / "base.toml").write_text('extends = "variant.toml"\n')
    code, _, err = run(capsys, "run", tmp_path / "variant.toml", "--out", tmp_path / "o",
                       "--fmus", fmu_dir)
    assert code == 2 and "extends itself through" in err


def test_version(capsys):
    import musclesim

    with pytest.raises(SystemExit) as exc:
        cli.main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out == f"musclesim {musclesim.__version__}\n"
