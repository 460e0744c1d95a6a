"""The one place for Dask: the client (a local cluster or a running scheduler) and the maps.

A map is ``pmap(fn, items) -> [fn(item) for item in items]`` (results in the items' order): the
diagnosis fits its candidates with the one it is given, `serial_map` by default, `dask_map`'s on
the command line; sweeps and tables submit their cases on `dask_client` (`cases.run_cases`).
"""
import contextlib
import logging
import os
import signal
import threading

from musclesim.errors import UserError


# A local cluster's bookkeeping for a dashboard it does not serve, slowed down: the statistical
# profiler samples every task's stack every 10 ms, and the system monitor and the event loop's
# tick wake every process often, each time taking the GIL from a simulation in Python. The
# command's process (scheduler and client) and the workers share the machine's cores.
QUIET = {"distributed.worker.profile.enabled": False,
         "distributed.admin.system-monitor.interval": "5s",
         "distributed.admin.tick.interval": "500ms"}


@contextlib.contextmanager
def dask_client(scheduler=None, workers=None, tasks=None):
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
        client.close()
        if cluster is not None:
            cluster.close()


@contextlib.contextmanager
def _workers_ignore_sigint():
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


def dask_map(client):
    """`pmap` over a Dask client: ``pmap(fn, items)`` returns the tasks' results in order. Every
    item is a task on the cluster, none runs here, so that the map may be called from several
    threads at once (``pmap.concurrent``: the diagnosis's fits steer their simulations so).
    ``pmap.share(obj)`` sends `obj` to every worker once and returns what items carry in its
    place (a fit's unit and its data, rather than in each of its hundred tasks);
    ``pmap.width()`` is how many tasks the cluster runs at once (its workers' threads)."""
    def pmap(fn, items):
        items = list(items)
        return client.gather(client.map(fn, items, pure=False)) if items else []
    pmap.concurrent = True
    pmap.width = lambda: max(1, sum(client.nthreads().values()))  # tasks it runs at once
    pmap.share = lambda obj: client.scatter(obj, broadcast=True, hash=False)
    return pmap


def serial_map(fn, items):
    """`pmap` one item after the other, in this process: ``[fn(x) for x in items]``.

    Examples
    --------
    >>> serial_map(abs, [-1, 2.5])
    [1, 2.5]
    """
    return [fn(x) for x in items]
