"""musclesim.batch.cluster: the maps without a cluster (`dask_map` over a stand-in client), the
worker plugin called as a worker would, and two local clusters started at once."""
from pathlib import Path

from musclesim.batch import dask_client, dask_map, serial_map


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
