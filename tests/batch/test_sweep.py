"""Tests of musclesim.batch.sweep: grid parsing, sweep files, one result per case, resume, failures."""
import csv
import json
import math

import pytest

from musclesim import cli
from musclesim.batch import cases, sweep
from musclesim.cosim import load_scenario
from musclesim.errors import UserError

from conftest import SCENARIOS

IDEAL = SCENARIOS / "crawler-ideal.toml"
STOP = 0.2  # s: short cases, the sweep machinery is what is tested


@pytest.fixture(scope="module")
def scheduler():
    """Address of a two-worker local Dask cluster shared by the tests of this module."""
    from distributed import LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster:
        yield cluster.scheduler_address


def _rows(out):
    with (out / "sweep.csv").open(newline="") as f:
        return {r["case"]: r for r in csv.DictReader(f)}


@pytest.mark.parametrize("text, values", [
    ("inputs.f_f=0.01:1:3", (0.01, 0.505, 1.0)),
    ("inputs.phi=0:2pi:3", (0.0, round(math.pi, 11), round(2 * math.pi, 11))),
    ("body.m1=0.1, 0.2,0.1", (0.1, 0.2)),
    ("inputs.phi=-pi", (-round(math.pi, 11),)),
], ids=["range", "pi-range", "list-dedup", "single"])
def test_parse_axis(text, values):
    name, got = sweep.parse_axis(text)
    assert name == text.split("=")[0]
    assert got == pytest.approx(values, abs=1e-11)


@pytest.mark.parametrize("text", [
    "inputs.f_f", "f_f=1:2:3", "inputs.f_f=1:2", "inputs.f_f=1:2:1", "inputs.f_f=1:2:x",
    "inputs.f_f=a,b", "inputs.f_f=1,inf", "inputs.f_f=",
])
def test_parse_axis_refuses_bad_syntax(text):
    with pytest.raises(UserError, match="grid axis"):
        sweep.parse_axis(text)


def test_case_ids_do_not_depend_on_axis_order():
    a = sweep.grid_cases({"x.a": (1.0, 2.0), "y.b": (0.5,)})
    b = sweep.grid_cases({"y.b": (0.5,), "x.a": (2.0, 1.0)})
    assert sorted(cid for cid, _ in a) == sorted(cid for cid, _ in b)
    assert a[0][0] == "x.a=1,y.b=0.5"


def test_sweep_files_load():
    phase = sweep.load(SCENARIOS / "crawler-sweep-phase.toml")
    assert phase.scenario == IDEAL and list(phase.axes) == ["inputs.phi"]
    assert phase.axes["inputs.phi"][-1] == pytest.approx(2 * math.pi)
    assert phase.plot["kind"] == "line"
    freq = sweep.load(SCENARIOS / "crawler-sweep-frequency.toml",
                      ["inputs.f_u=0.5", "body.k=100,200"])
    assert freq.axes["inputs.f_u"] == (0.5,)  # --grid replaces the file's axis ...
    assert len(freq.axes["inputs.f_f"]) == 10 and "body.k" in freq.axes  # ... and adds its own
    assert freq.plot == {"kind": "heatmap", "x": "inputs.f_f", "y": "inputs.f_u",
                         "metrics": ["x1_final"]}
    load_scenario(freq.scenario)


def test_sweep_file_errors_name_the_file(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[sweep]\nscenario = "x.toml"\ngrid = ["inputs.phi=0:1"]\n')
    with pytest.raises(UserError, match=r"sweep file .*bad\.toml: grid axis"):
        sweep.load(bad)
    bad.write_text('[sweep]\nscenario = "x.toml"\ngird = []\n')
    with pytest.raises(UserError, match=r"bad\.toml must hold only"):
        sweep.load(bad)
    bad.write_text('[sweep]\nscenario = "x.toml"\n[sweep.plot]\nkind = "heatmap"\nx = "a.b"\n'
                   'metrics = []\n')
    with pytest.raises(UserError, match=r"bad\.toml: the plot needs"):
        sweep.load(bad)
    with pytest.raises(UserError, match="no grid axis"):
        sweep.load(IDEAL)


@pytest.mark.parametrize("axis, message", [
    ("nobody.m1=1,2", "no instance 'nobody'"),
    ("body.mass=1,2", "no variable 'mass'"),
], ids=["instance", "parameter"])
def test_unknown_axis_is_refused_before_running(fmu_dir, tmp_path, axis, message):
    with pytest.raises(UserError, match=message):
        sweep.run(IDEAL, [axis], tmp_path / "out", fmu_dir=fmu_dir)
    assert not (tmp_path / "out").exists()


def test_sweep_writes_one_result_per_case_on_a_local_cluster(fmu_dir, tmp_path):
    out = tmp_path / "out"
    summary = sweep.run(IDEAL, ["inputs.phi=0,pi"], out, fmu_dir=fmu_dir, workers=2,
                        stop_time=STOP)
    assert summary["failed"] == {}
    assert (summary["cases"], summary["ran"], summary["completed"]) == (2, 2, 2)
    rows = _rows(out)
    assert set(rows) == {"inputs.phi=0", "inputs.phi=3.14159265359"}
    for cid, row in rows.items():
        case = json.loads((out / "cases" / cid / "summary.json").read_text())
        assert case["completed"] and case["stop_time"] == STOP
        assert float(row["x1_final"]) == case["x1_final"]
    assert (out / "sweep.png").is_file()


def test_one_worker_runs_the_cases_in_this_process_as_a_cluster_would(fmu_dir, tmp_path,
                                                                       scheduler, monkeypatch):
    grid = ["inputs.phi=0,pi", "body.c=-1,1.3"]
    sweep.run(IDEAL, grid, tmp_path / "cluster", fmu_dir=fmu_dir, scheduler=scheduler,
              stop_time=STOP)
    monkeypatch.setattr(cases, "dask_client", None)  # no cluster may start
    here = sweep.run(IDEAL, grid, tmp_path / "here", fmu_dir=fmu_dir, workers=1, stop_time=STOP)
    assert (here["ran"], here["completed"], len(here["failed"])) == (4, 2, 2)
    assert _rows(tmp_path / "here") == _rows(tmp_path / "cluster")
    for cid in _rows(tmp_path / "here"):
        assert ((tmp_path / "here" / "cases" / cid / "results.csv").read_bytes() ==
                (tmp_path / "cluster" / "cases" / cid / "results.csv").read_bytes())


def test_resume_skips_finished_cases(fmu_dir, tmp_path, scheduler):
    out = tmp_path / "out"
    sweep.run(IDEAL, ["inputs.f_u=0.5,1"], out, fmu_dir=fmu_dir, scheduler=scheduler,
              stop_time=STOP)
    stamps = {p: p.stat().st_mtime_ns for p in out.glob("cases/*/summary.json")}
    assert len(stamps) == 2
    summary = sweep.run(IDEAL, ["inputs.f_u=0.5,1,0.25"], out, fmu_dir=fmu_dir,
                        scheduler=scheduler, stop_time=STOP)
    assert (summary["skipped"], summary["ran"], summary["completed"]) == (2, 1, 3)
    assert {p: p.stat().st_mtime_ns for p in stamps} == stamps
    assert len(_rows(out)) == 3
    with pytest.raises(UserError, match="other settings"):  # another stop time, same folder
        sweep.run(IDEAL, ["inputs.f_u=0.5"], out, fmu_dir=fmu_dir, scheduler=scheduler)


def test_failing_case_is_recorded_and_the_others_complete(fmu_dir, tmp_path, scheduler):
    out = tmp_path / "out"
    summary = sweep.run(IDEAL, ["body.c=-1,1.3"], out, fmu_dir=fmu_dir, scheduler=scheduler,
                        stop_time=STOP)
    assert list(summary["failed"]) == ["body.c=-1"]
    assert "c must be non-negative" in summary["failed"]["body.c=-1"]
    assert summary["completed"] == 1
    rows = _rows(out)
    assert rows["body.c=-1"]["completed"] == "False" and rows["body.c=-1"]["error"]
    assert rows["body.c=1.3"]["completed"] == "True"
    again = sweep.run(IDEAL, ["body.c=-1,1.3"], out, fmu_dir=fmu_dir, scheduler=scheduler,
                      stop_time=STOP)
    assert (again["skipped"], again["ran"], list(again["failed"])) == (1, 1, ["body.c=-1"])


def test_cli_sweep_file_with_grid_override(fmu_dir, tmp_path, scheduler, capsys):
    out = tmp_path / "out"
    status = cli.main(["sweep", str(SCENARIOS / "crawler-sweep-frequency.toml"),
                       "--grid", "inputs.f_f=0.5,1", "--grid", "inputs.f_u=0.5,1",
                       "--out", str(out), "--fmus", str(fmu_dir), "--scheduler", scheduler,
                       "--stop-time", str(STOP)])
    assert status == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["cases"] == 4 and summary["plot"] == str(out / "sweep.png")
    assert (out / "sweep.png").is_file()
