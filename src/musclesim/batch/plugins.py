"""Dask worker plugins of the cluster `musclesim.batch.dask_client` starts or joins (imported
only with Dask's distributed itself, when a client starts)."""
from distributed.diagnostics.plugin import WorkerPlugin

from musclesim.cosim import reuse_fmus


class ReusedFmus(WorkerPlugin):
    """The worker unpacks each FMU once for its life (`musclesim.cosim.reuse_fmus` held open
    from its start to its close): the diagnosis's fits send every simulation as a task of its
    own, and unpacking the FMUs again for each would cost about a sixth of a run."""

    name = "musclesim-reused-fmus"

    def setup(self, worker):
        self._reuse = reuse_fmus()
        self._reuse.__enter__()

    def teardown(self, worker):
        self._reuse.__exit__(None, None, None)
