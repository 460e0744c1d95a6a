"""musclesim.batch.cluster: the maps without a cluster (`dask_map` over a stand-in client), the
worker plugins called as a worker would, and two local clusters started at once. A cluster that
shares no files with the client: test_cluster_without_shared_files.py."""
import contextlib
import json
import os
from pathlib import Path
from types import SimpleNamespace

import pytest

from musclesim.batch import (FmuFolder, cluster, cluster_map, dask_client, dask_map, in_process,
                            serial_map)
from musclesim.batch.shipped import folder_files
from musclesim.errors import UserError


class FakeClient:
    """What `dask_map` uses of a Dask client: map (futures) and gather (their results)."""

    def __init__(self):
        self.mapped = []

    def map(self, fn, items, pure=True):
        assert pure is False  # tasks are never taken from a cache
        self.mapped.append(list(items))
        return [fn(x) for x in items]

    def gather(self, futures):
        return list(futures)

    def scatter(self, obj, broadcast=False, hash=True):
        assert broadcast and not hash  # to every worker, a new key each time
        return ("sent", obj)


def test_dask_map_keeps_the_order_and_runs_every_item_on_the_cluster():
    """Nothing runs in the caller's process, so that the diagnosis's fits may call the map
    from several threads at once (``concurrent``), each simulation a task."""
    client = FakeClient()
    pmap = dask_map(client)
    assert pmap(lambda x: x * x, iter([3, 1, 2])) == [9, 1, 4]
    assert pmap(lambda x: -x, [5]) == [-5] and pmap(abs, []) == []
    assert client.mapped == [[3, 1, 2], [5]]  # no items, no tasks
    assert pmap.concurrent and not getattr(serial_map, "concurrent", False)
    assert pmap.share([1, 2]) == ("sent", [1, 2])


def test_a_worker_keeps_the_fmus_unpacked_for_its_life(fmu_dir):
    """The worker plugin holds `reuse_fmus` open from the worker's start to its close: an FMU
    is unpacked once for every task that runs it, and the folder goes with the worker."""
    from musclesim.batch.plugins import ReusedFmus
    from musclesim.cosim.host import extracted_fmu

    fmu = fmu_dir / "Thermocouple.fmu"
    assert extracted_fmu(fmu) is None  # outside, every run unpacks its own copy
    plugin = ReusedFmus()
    plugin.setup(worker=None)
    try:
        folder = extracted_fmu(fmu)
        assert folder is not None and extracted_fmu(fmu) == folder
    finally:
        plugin.teardown(worker=None)
    assert extracted_fmu(fmu) is None and not Path(folder).exists()


def test_the_fmus_a_job_needs_are_read_with_build_json(fmu_dir):
    files = folder_files(fmu_dir, ["Thermocouple", "PID", "Thermocouple", "NoSuchFmu"])
    assert sorted(files) == ["BUILD.json", "PID.fmu", "Thermocouple.fmu"]  # the master names
    assert files["PID.fmu"] == (fmu_dir / "PID.fmu").read_bytes()  # what is missing
    assert len(folder_files(fmu_dir)) == len(list(fmu_dir.glob("*.fmu"))) + 1


def test_a_worker_unpacks_the_fmus_it_is_sent_in_its_own_folder_and_removes_them(fmu_dir,
                                                                                 tmp_path):
    """Tasks name the worker's copy through the `FmuFolder` they carry; its text is no path."""
    from musclesim.batch.plugins import ShippedFmus

    files = folder_files(fmu_dir, ["Thermocouple"])
    worker = SimpleNamespace(address="tcp://worker:1", local_directory=str(tmp_path))
    plugin, folder = ShippedFmus("k1", files), FmuFolder("k1")
    plugin.setup(worker)
    try:
        there = Path(folder)
        assert there.parent == tmp_path and os.fspath(folder) == str(there)
        assert {p.name: p.read_bytes() for p in there.iterdir()} == files
        assert not Path(str(folder)).exists()
    finally:
        plugin.teardown(worker)
    assert list(tmp_path.iterdir()) == []
    with pytest.raises(UserError, match="not unpacked in this process"):
        os.fspath(folder)


def test_a_worker_refuses_fmus_built_from_other_sources_than_its_own(fmu_dir, tmp_path):
    """Their slaves would import the worker's own, other, modules: the worker says so."""
    from musclesim.batch.plugins import ShippedFmus

    files = folder_files(fmu_dir, ["Thermocouple"])
    stamp = json.loads(files["BUILD.json"])
    files["BUILD.json"] = json.dumps({**stamp, "sources": "0" * 64}).encode()
    worker = SimpleNamespace(address="tcp://worker:1", local_directory=str(tmp_path))
    with pytest.raises(UserError, match=r"^Dask worker tcp://worker:1 runs other musclesim "
                                        r"sources than the FMUs were built from \(musclesim "):
        ShippedFmus("k2", files).setup(worker)
    assert list(tmp_path.iterdir()) == []


def blas_threads():
    from threadpoolctl import threadpool_info

    return {i["filepath"]: i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"}


def test_two_local_clusters_at_once_start_quietly_and_this_process_blas_on_one_thread(recwarn):
    """Two commands at once on one machine (a sweep and a diagnosis, say) each start a local
    cluster: neither warns that the other holds its port. While a local cluster runs, this
    process's BLAS has one thread (idle ones would spin on the workers' cores), restored after."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(2, user_api="blas"):  # the suite's processes run one (conftest)
        before = blas_threads()
        with dask_client(None, 1) as a, dask_client(None, 1) as b:
            assert a.scheduler.address != b.scheduler.address
            assert set(blas_threads().values()) == {1}
        assert set(before.values()) == {2} and blas_threads() == before
    assert not [str(w.message) for w in recwarn if "already in use" in str(w.message)]


def test_serial_map():
    assert serial_map(lambda x: x + 1, (1, 2)) == [2, 3]


def test_one_worker_and_no_scheduler_work_in_this_process_else_on_a_cluster(monkeypatch):
    assert in_process(None, 1)
    assert not in_process(None, 2) and not in_process(None, None)
    assert not in_process("tcp://127.0.0.1:8786", 1)  # a scheduler's workers, whatever their number
    started = []
    monkeypatch.setattr(cluster, "dask_client", lambda *args: started.append(args) or
                        contextlib.nullcontext(FakeClient()))
    with cluster_map(None, 1) as pmap:
        assert pmap is serial_map
    with cluster_map(None, 2) as pmap:
        assert pmap(abs, [-1, 2]) == [1, 2] and pmap is not serial_map
    assert started == [(None, 2)]



def test_asyncios_unretrieved_task_errors_are_dropped_while_a_signal_stops_the_command():
    import logging
    import signal

    from musclesim.cosim import interrupt

    def record(text):
        return logging.LogRecord("asyncio", logging.ERROR, __file__, 1, text, None, None)
    noise = record("Task exception was never retrieved\nfuture: <Task finished ...>")
    other = record("something else went wrong")
    assert cluster._NOISE.filter(noise) and cluster._NOISE.filter(other)  # no signal: all shown
    interrupt.STATE["signum"] = signal.SIGINT
    try:
        assert not cluster._NOISE.filter(noise) and cluster._NOISE.filter(other)
    finally:
        interrupt.STATE["signum"] = None
