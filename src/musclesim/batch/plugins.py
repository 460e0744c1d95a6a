"""Dask worker plugins of the cluster `musclesim.batch.dask_client` starts or joins (imported
only with Dask's distributed itself, when a client starts)."""
import shutil
import tempfile

from distributed.diagnostics.plugin import WorkerPlugin

from musclesim.batch.shipped import FOLDERS, built_version, unpack
from musclesim.cosim import check_fresh, reuse_fmus
from musclesim.errors import UserError


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


class ShippedFmus(WorkerPlugin):
    """A client's FMUs, as bytes ({file name: bytes}, `shipped.folder_files`), written once into
    a folder of the worker's own (in its local directory) where tasks find them under `key`
    (`shipped.FmuFolder`); removed when the plugin or the worker goes.

    The worker refuses FMUs that musclesim built from other sources than the ones it runs
    (`musclesim.cosim.check_fresh`): their slaves would import its own, different, modules.
    """

    def __init__(self, key, files):
        self.key, self.files, self.folder = key, files, None
        self.name = f"musclesim-fmus-{key}"

    def setup(self, worker):
        where = getattr(worker, "address", "this worker")
        try:
            self.folder = tempfile.mkdtemp(prefix="musclesim-fmus-",
                                           dir=getattr(worker, "local_directory", None))
            unpack(self.files, self.folder)
        except OSError as exc:
            self._remove()
            raise UserError(f"Dask worker {where} cannot write the FMUs it was sent: "
                            f"{exc.strerror or exc}") from None
        try:
            check_fresh(self.folder)
        except UserError:
            self._remove()
            raise UserError(f"Dask worker {where} runs other musclesim sources than the FMUs "
                            f"were built from (musclesim {built_version(self.files)}); install "
                            "the client's musclesim, the same version and sources, on every "
                            "worker") from None
        FOLDERS[self.key] = self.folder

    def teardown(self, worker):
        if FOLDERS.get(self.key) == self.folder:
            del FOLDERS[self.key]
        self._remove()

    def _remove(self):
        if self.folder is not None:
            shutil.rmtree(self.folder, ignore_errors=True)
            self.folder = None
