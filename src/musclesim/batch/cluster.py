"""The one place for Dask: the client (a local cluster or a running scheduler) and the maps.

A map is ``pmap(fn, items) -> [fn(item) for item in items]`` (results in the items' order): the
diagnosis fits its candidates with the one it is given, `serial_map` by default, `cluster_map`'s
on the command line (in this process for one worker: `in_process`); sweeps and tables submit
their cases on `dask_client` (`cases.run_cases`).
The workers need none of the client's files: `ship_fmus` sends them the FMUs as bytes, a task
takes its scenario as an object, and its results come back to the client.
"""
from __future__ import annotations

import contextlib
import hashlib
import logging
import os
import signal
import threading
import uuid
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from typing import Any

from musclesim.batch.shipped import FOLDERS, FmuFolder, folder_files
from musclesim.cosim import interrupt_requested
from musclesim.errors import UserError


# A local cluster's bookkeeping for a dashboard it does not serve, slowed down: the statistical
# profiler samples every task's stack every 10 ms, and the system monitor and the event loop's
# tick wake every process often, each time taking the GIL from a simulation in Python. The
# command's process (scheduler and client) and the workers share the machine's cores.
QUIET = {"distributed.worker.profile.enabled": False,
         "distributed.admin.system-monitor.interval": "5s",
         "distributed.admin.tick.interval": "500ms"}


class _StoppingNoise(logging.Filter):
    """Drops asyncio's "Task exception was never retrieved" while a signal stops the command: a
    local cluster's scheduler (in this process) leaves one when the stopping client releases the
    keys of a scatter it is still replicating. The command's one line says what happened."""

    def filter(self, record: logging.LogRecord) -> bool:
        return interrupt_requested() is None or not record.getMessage().startswith(
            "Task exception was never retrieved")


_NOISE = _StoppingNoise()


@contextlib.contextmanager
def dask_client(scheduler: str | None = None, workers: int | None = None,
                tasks: int | None = None) -> Iterator[Any]:
    """A Dask client on `scheduler`, else on a LocalCluster of `workers` processes (default: the
    cores, at most `tasks`), closed on exit. Sweeps and the diagnosis's fits run on it.

    Raises
    ------
    UserError
        When the local cluster cannot start or the scheduler cannot be reached.
    """
    import dask
    from distributed import Client, LocalCluster
    from threadpoolctl import threadpool_limits

    from musclesim.batch.plugins import ReusedFmus
    from musclesim.cosim import forget_fmu_resource_paths

    forget_fmu_resource_paths()  # workers inherit sys.path: no FMU's copy of musclesim in it
    logging.getLogger("asyncio").addFilter(_NOISE)  # once: a filter is added only once
    cluster = None
    try:
        if scheduler is None:
            # one thread per worker process, since the Python FMUs hold the GIL; the cluster's
            # log noise (heartbeats cut at shutdown) stays quiet, as task errors are recorded;
            # no dashboard, and the scheduler's HTTP server on a free port, not on 8787 (which
            # a second command's cluster found taken, with a warning)
            n = workers or os.cpu_count() or 1
            with _workers_ignore_sigint(), dask.config.set(QUIET):
                cluster = LocalCluster(n_workers=max(1, min(n, tasks or n)), threads_per_worker=1,
                                       processes=True, dashboard_address=None,
                                       scheduler_kwargs={"dashboard_address": ":0"},
                                       silence_logs=logging.CRITICAL)
        client = Client(scheduler or cluster)
        client.register_plugin(ReusedFmus())
    except (OSError, TimeoutError) as exc:
        if cluster is not None:
            cluster.close()
        raise UserError(f"cannot start or reach the Dask scheduler {scheduler or ''}: "
                        f"{exc}") from None
    # beside a local cluster, this process's BLAS on one thread: it steers the workers' runs
    # and, between them, solves small least-squares steps (a Jacobian of ten columns), which
    # threads do not speed up, while OpenBLAS's idle threads spin on the cores the workers need
    # (the workers get one thread from Dask's nanny). Measured on 2 cores, the diagnosis of an
    # independent-bench case: this process's CPU 11.5 s -> 2.9 s, wall 57 -> 49 s, the report
    # the same to the bit
    try:
        with threadpool_limits(1, user_api="blas") if cluster is not None else (
                contextlib.nullcontext()):
            yield client
    finally:
        try:
            _withdraw_fmus(client)
        finally:
            client.close()
        if cluster is not None:
            cluster.close()


# a client's id (`Client.id`, unique to it) -> {digest of the files: (plugin name, FmuFolder)}
# of the FMUs shipped on it, withdrawn from its workers as `dask_client` closes it
_SHIPPED: dict[str, dict[str, tuple[str, Any]]] = {}


def ship_fmus(client: Any, fmu_dir: str | Path, components: Iterable[str] | None = None
              ) -> FmuFolder:
    """Send the FMUs of `components` (default: all) in `fmu_dir`, with its BUILD.json, to every
    worker of `client` (and to every worker that joins later), and return the `FmuFolder` that
    tasks carry in the folder's place: each worker writes the files once into a folder of its
    own, which the folder names there (in this process: `fmu_dir`).

    The FMUs are checked fresh here (`musclesim.cosim.check_fresh`), and each worker checks that
    it runs the musclesim they were built from (else the direct host could not take them, and
    their slaves would import its other modules). The same files shipped again on the same
    client are not sent again; `dask_client` withdraws them from the workers as it closes.

    Raises
    ------
    UserError
        When the FMUs are stale or unreadable, or a worker cannot take them.
    """
    from musclesim.batch.plugins import ShippedFmus
    from musclesim.cosim import check_fresh

    check_fresh(fmu_dir)
    files = folder_files(fmu_dir, components)
    digest = hashlib.sha256()
    for name, data in sorted(files.items()):
        digest.update(hashlib.sha256(name.encode()).digest() + hashlib.sha256(data).digest())
    shipped = _SHIPPED.setdefault(client.id, {})
    if digest.hexdigest() not in shipped:
        plugin = ShippedFmus(uuid.uuid4().hex, files)
        try:
            client.register_plugin(plugin)
        except BaseException:  # not left for the workers that took them, nor for later ones
            _unregister(client, plugin.name)
            raise
        FOLDERS[plugin.key] = str(Path(fmu_dir).resolve())
        shipped[digest.hexdigest()] = (plugin.name, FmuFolder(plugin.key))
    return shipped[digest.hexdigest()][1]


def _withdraw_fmus(client: Any) -> None:
    """Remove the FMUs shipped on `client` from its workers (each deletes its copy)."""
    for name, folder in _SHIPPED.pop(client.id, {}).values():
        FOLDERS.pop(folder.key, None)
        _unregister(client, name)


def _unregister(client: Any, name: str) -> None:
    try:
        client.unregister_worker_plugin(name)
    except Exception:  # a scheduler gone, or the plugin never registered: nothing to remove
        pass


@contextlib.contextmanager
def _workers_ignore_sigint() -> Iterator[None]:
    """Start worker processes with SIGINT ignored (a disposition they inherit, and under which
    Python installs no KeyboardInterrupt): Ctrl-C reaches the whole process group, and only this
    process should act on it, by closing the cluster, rather than every worker dying with a
    traceback."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


class DaskMap:
    """`pmap` over a Dask client (`dask_map`): ``pmap(fn, items)`` returns the tasks' results in
    order; `concurrent`, `width`, `share` and `ship_fmus` as `dask_map` says."""

    concurrent = True  # callable from several threads at once

    def __init__(self, client: Any) -> None:
        """The map over the Dask `client`."""
        self.client = client

    def __call__(self, fn: Callable[[Any], Any], items: Iterable[Any]) -> list[Any]:
        """`fn` of each of the `items`, each a task on the cluster, in order."""
        items = list(items)
        return self.client.gather(self.client.map(fn, items, pure=False)) if items else []

    def width(self) -> int:
        """How many tasks the cluster runs at once (its workers' threads)."""
        return max(1, sum(self.client.nthreads().values()))

    def share(self, obj: Any) -> Any:
        """Send `obj` to every worker once; return what items carry in its place."""
        return self.client.scatter(obj, broadcast=True, hash=False)

    def ship_fmus(self, fmu_dir: str | Path, components: Iterable[str] | None = None
                  ) -> FmuFolder:
        """`ship_fmus` of `fmu_dir` (the FMUs of `components`) on this client."""
        return ship_fmus(self.client, fmu_dir, components)


def in_process(scheduler: str | None, workers: int | None) -> bool:
    """Whether work asked of `scheduler` and `workers` (the command line's ``--scheduler`` and
    ``--workers``) runs in this process: one worker and no scheduler. No cluster starts, no
    worker imports musclesim and loads its compiled code again (seconds each), and a case's
    simulations still run in one compiled pass."""
    return scheduler is None and workers == 1


@contextlib.contextmanager
def cluster_map(scheduler: str | None = None, workers: int | None = None
                ) -> Iterator[Callable[[Callable[[Any], Any], Iterable[Any]], list[Any]]]:
    """The map work runs on: `serial_map` where it runs `in_process`, else `dask_map` on
    `dask_client` (`scheduler`, `workers`), closed on exit."""
    if in_process(scheduler, workers):
        yield serial_map
        return
    with dask_client(scheduler, workers) as client:
        yield dask_map(client)


def dask_map(client: Any) -> DaskMap:
    """`pmap` over the Dask `client`: ``pmap(fn, items)`` returns the tasks' results in order. Every
    item is a task on the cluster, none runs here, so that the map may be called from several
    threads at once (``pmap.concurrent``: the diagnosis's fits steer their simulations so).
    ``pmap.share(obj)`` sends `obj` to every worker once and returns what items carry in its
    place (a fit's unit and its data, rather than in each of its hundred tasks);
    ``pmap.width()`` is how many tasks the cluster runs at once (its workers' threads);
    ``pmap.ship_fmus(fmu_dir, components)`` is `ship_fmus` on this client: what tasks carry in
    place of an FMU folder."""
    return DaskMap(client)


def serial_map(fn: Callable[[Any], Any], items: Iterable[Any]) -> list[Any]:
    """`pmap` one item after the other, in this process: ``[fn(x) for x in items]``, `fn` of
    each of the `items`.

    Examples
    --------
    >>> serial_map(abs, [-1, 2.5])
    [1, 2.5]
    """
    return [fn(x) for x in items]
