"""A sweep and a diagnosis on a Dask cluster whose workers share no files with the client.

A scheduler and two workers run as processes of their own (``dask scheduler``, ``dask worker``),
each in its own folder: its working directory, HOME, TMPDIR and Dask's local directory. Every
worker records what files it touches (`worker_audit`, Python's audit events). The client's FMU
folder, scenario and data set lie in a folder that no worker is told of; the results must equal a
run in this process bit for bit, no worker may open anything in the client's folder or write
anywhere but in its own, and the runs must take the direct host there (no worker loads an FMU's
binary library).
"""
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from musclesim import cli
from musclesim.batch import dask_client, run_case, ship_fmus
from musclesim.benchmark import blind
from musclesim.cosim import Master, Signal, load_scenario, run_scenario
from musclesim.diagnosis import diagnose, load_dataset

from conftest import SCENARIOS, schema_errors

S = Signal.parse

AUDIT = Path(__file__).with_name("worker_audit.py")
GRID = "inputs.phi=0,1.5,3"
CASES = ("inputs.phi=0", "inputs.phi=1.5", "inputs.phi=3")
STOP = "1"  # s of crawler-ideal: the cluster, not the physics, is what is tested


def _own_env(folder, **extra):
    """Environment of a process whose HOME and TMPDIR are in its own `folder`."""
    for sub in ("home", "tmp"):
        (folder / sub).mkdir(parents=True, exist_ok=True)
    return {**os.environ, "HOME": str(folder / "home"), "TMPDIR": str(folder / "tmp"),
            "PYTHONDONTWRITEBYTECODE": "1", **extra}


def _wait(ready, what, procs, timeout=60):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if ready():
            return
        dead = [p for p in procs if p.poll() is not None]
        if dead:
            pytest.fail(f"{what}: a cluster process ended ({dead[0].args})")
        time.sleep(0.1)
    pytest.fail(f"{what} did not happen within {timeout} s")


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    """(scheduler address, [each worker's own folder]): `dask scheduler` and two `dask worker`
    processes of one thread, with no nanny, each in its own folder."""
    from distributed import Client

    root = tmp_path_factory.mktemp("cluster")
    dask = [sys.executable, "-m", "dask"]
    procs, logs, folders = [], [], [root / "worker0", root / "worker1"]
    sched = root / "scheduler"
    try:
        procs.append(subprocess.Popen(
            [*dask, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
             "--scheduler-file", str(sched / "scheduler.json")],
            cwd=sched, env=_own_env(sched),
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        _wait(lambda: (sched / "scheduler.json").is_file(), "the scheduler's address", procs)
        address = json.loads((sched / "scheduler.json").read_text())["address"]
        for i, folder in enumerate(folders):
            env = _own_env(folder, MUSCLESIM_TEST_AUDIT=str(folder / "audit.jsonl"))
            logs.append((folder / "stderr.txt").open("w"))
            procs.append(subprocess.Popen(
                [*dask, "worker", address, "--nthreads", "1", "--no-nanny", "--no-dashboard",
                 "--name", f"w{i}", "--local-directory", str(folder / "local"), "--preload",
                 str(AUDIT)],
                cwd=folder, env=env, stdout=subprocess.DEVNULL, stderr=logs[-1]))
        with Client(address, timeout=60) as client:
            client.wait_for_workers(2, timeout=60)
        yield address, folders
    finally:
        # the workers first, and gone before the scheduler: a worker whose scheduler went
        # away with it tries to reach it again for tens of seconds
        for group in (procs[1:], procs[:1]):
            for p in group:
                p.terminate()
            for p in group:
                try:
                    p.wait(timeout=20)
                except subprocess.TimeoutExpired:
                    p.kill()
        for log in logs:
            log.close()


@pytest.fixture
def client_dir(tmp_path, fmu_dir):
    """The client's folder: its FMUs (a copy of the session's), a scenario and a data set."""
    folder = tmp_path / "client"
    shutil.copytree(fmu_dir, folder / "fmus")
    shutil.copy(SCENARIOS / "crawler-ideal.toml", folder / "crawler-ideal.toml")
    _data_set(folder / "bench", fmu_dir)
    return folder


def _data_set(folder, fmu_dir):
    """20 s of the stress bench (its scenario in the data set's folder) with the thermocouple
    reading 3 K high, a little noise: calibration alone explains it, after a few fits."""
    folder.mkdir()
    (folder / "bench.toml").write_text(
        (SCENARIOS / "sma-bench-stress.toml").read_text()
        .replace("stop_time = 60.0", "stop_time = 20.0").replace("from = 10.0", "from = 5.0"))
    res = Master(load_scenario(folder / "bench.toml", ["thermocouple.bias=3.0"]), fmu_dir).run()
    noise = np.random.default_rng(3).standard_normal((2, len(res.time)))
    np.savetxt(folder / "data.csv", np.column_stack([
        res.time, res[S("wire.u")], res[S("wire.flange.f")],
        res[S("thermocouple.T_meas")] + 0.05 * noise[0], res[S("wire.strain")] + 1e-5 * noise[1]]),
        delimiter=",", comments="", fmt="%.17g",
        header="time,wire.u,wire.flange.f,thermocouple.T_meas,wire.strain")
    (folder / "manifest.toml").write_text(
        'scenario = "bench.toml"\ninputs = ["wire.u", "wire.flange.f"]\n'
        'outputs = ["thermocouple.T_meas", "wire.strain"]\n'
        '[units]\n"thermocouple.T_meas" = "K"\n[split]\nheld_out_fraction = 0.3\n')


def _tree(folder):
    """{path: (size, mtime)} of every file under `folder`."""
    return {p: (p.stat().st_size, p.stat().st_mtime_ns) for p in folder.rglob("*") if p.is_file()}


def _audit(folder):
    lines = (folder / "audit.jsonl").read_text().splitlines()
    return [json.loads(line) for line in lines]


def _under(path, folder):
    return Path(os.path.realpath(path)).is_relative_to(os.path.realpath(folder))


def check_isolation(folders, client):
    """No worker touched the client's folder, wrote outside its own or loaded an FMU binary."""
    for folder in folders:
        events = _audit(folder)
        assert events, f"{folder}: the audit recorded nothing"
        assert not [e for e in events if e["kind"] == "error"]
        touched = sorted({e["path"] for e in events if _under(e["path"], client)})
        assert touched == [], f"worker {folder.name} touched the client's files"
        outside = sorted({e["path"] for e in events if e["kind"] == "write"
                          and e["path"] != os.devnull and not _under(e["path"], folder)})
        assert outside == [], f"worker {folder.name} wrote outside its own folder"
        fmus = {e["path"] for e in events if e["path"].endswith(".fmu")}
        assert fmus and all(_under(p, folder) for p in fmus)  # every FMU it read: its own copy
        binaries = [e["path"] for e in events if e["kind"] == "dlopen" and "binaries" in e["path"]]
        assert binaries == [], "an FMU ran on fmpy's host, not the direct one"


def test_a_sweep_on_workers_that_see_none_of_the_clients_files(cluster, client_dir, tmp_path,
                                                                capsys):
    address, folders = cluster
    scenario, fmus, out = client_dir / "crawler-ideal.toml", client_dir / "fmus", client_dir / "out"
    before = _tree(client_dir)
    status = cli.main(["sweep", str(scenario), "--grid", GRID, "--stop-time", STOP,
                       "--out", str(out), "--fmus", str(fmus), "--scheduler", address])
    summary = json.loads(capsys.readouterr().out)
    assert status == 0 and summary["failed"] == {} and summary["completed"] == len(CASES)
    after = _tree(client_dir)
    assert {p: after[p] for p in before} == before  # the FMUs and the scenario untouched
    assert all(p.is_relative_to(out) for p in set(after) - set(before))
    for cid in CASES:  # the same bits as a run in this process
        local = tmp_path / "local" / cid
        run_scenario(scenario, local, fmus, [cid], float(STOP), with_plot=False)
        case = out / "cases" / cid
        assert (case / "results.csv").read_bytes() == (local / "results.csv").read_bytes()
        mine, theirs = (json.loads((d / "summary.json").read_text()) for d in (local, case))
        assert mine.pop("run_id") != theirs.pop("run_id") and mine == theirs
    check_isolation(folders, client_dir)


def test_the_workers_runs_take_the_direct_host(cluster, client_dir):
    """A case sent as a task names no file of the client's: the scenario goes as an object,
    the FMUs as bytes (BUILD.json with them); the worker runs its copies on the direct host."""
    address, folders = cluster
    s = load_scenario(client_dir / "crawler-ideal.toml", (), float(STOP))
    with dask_client(address) as client:
        fmus = ship_fmus(client, client_dir / "fmus", {"CrawlerBody", "FrictionBlock",
                                                       "FrictionSwitchingInputs"})
        assert os.fspath(fmus) == str((client_dir / "fmus").resolve())  # here, the client's
        assert ship_fmus(client, client_dir / "fmus", {"CrawlerBody", "FrictionBlock",
                                                       "FrictionSwitchingInputs"}) == fmus
        outcome = client.submit(run_case, s, fmus, ["inputs.phi=3"], pure=False).result()
        there = client.run(os.fspath, fmus)  # each worker's own copy
    local = run_case(s, client_dir / "fmus", ["inputs.phi=3"])
    assert outcome.error is None and set(outcome.hosts.values()) == {"direct"}
    assert outcome.hosts == local.hosts
    np.testing.assert_array_equal(outcome.results.data, local.results.data)
    assert len(there) == len(folders)
    for folder in folders:
        assert sum(_under(path, folder) for path in there.values()) == 1
    assert not any(Path(p).exists() for p in there.values())  # withdrawn as the client closed
    check_isolation(folders, client_dir)


def test_a_diagnosis_on_workers_that_see_none_of_the_clients_files(cluster, client_dir,
                                                                   tmp_path, capsys):
    address, folders = cluster
    data, fmus, out = client_dir / "bench", client_dir / "fmus", client_dir / "diag"
    before = _tree(client_dir)
    status = cli.main(["diagnose", str(data), "--out", str(out), "--fmus", str(fmus),
                       "--scheduler", address])
    assert status == 0 and capsys.readouterr().out.startswith("verdict: recalibration")
    after = _tree(client_dir)
    assert {p: after[p] for p in before} == before
    assert all(p.is_relative_to(out) for p in set(after) - set(before))
    here = diagnose(load_dataset(data, check_model=True, fmu_dir=fmus), fmus).to_json()  # here
    assert json.loads((out / "report.json").read_text()) == json.loads(json.dumps(here,
                                                                                  default=float))
    check_isolation(folders, client_dir)


def test_a_blind_benchmark_on_workers_that_see_none_of_the_clients_files(cluster, client_dir,
                                                                         tmp_path, capsys):
    """`benchmark-diagnosis --scheduler`: the workers record, diagnose and score each case from
    data and shipped FMUs; the data sets, reports and scores are written by the client (the
    recording the same bits as one made here; a diagnosis on such a cluster equals one here,
    `test_a_diagnosis_on_workers_that_see_none_of_the_clients_files`)."""
    address, folders = cluster
    scenarios, fmus, out = client_dir / "scenarios", client_dir / "fmus", client_dir / "blind"
    shutil.copytree(SCENARIOS, scenarios)
    before = _tree(client_dir)
    assert cli.main(["benchmark-diagnosis", "--bench", "independent", "--cases", "1", "--seed",
                     "102", "--duration", "20", "--fmus", str(fmus), "--scenarios",
                     str(scenarios), "--out", str(out), "--scheduler", address]) == 0
    capsys.readouterr()
    after = _tree(client_dir)
    assert {p: after[p] for p in before} == before
    assert all(p.is_relative_to(out) for p in set(after) - set(before))
    case = json.loads((out / "independent" / "key.json").read_text())["cases"][0]
    here = blind.make_case(case, tmp_path, fmus, scenarios)
    there = out / "independent" / "cases" / case["case"]
    assert (there / "data.csv").read_bytes() == (here / "data.csv").read_bytes()
    report = json.loads((there / "report.json").read_text())
    assert schema_errors("report", report) == [] and report["verdict"] != "error"
    assert json.loads((out / "scores.json").read_text())["independent"]["cases"] == 1
    check_isolation(folders, client_dir)
