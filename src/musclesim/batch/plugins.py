"""Dask worker plugins of the cluster `musclesim.batch.dask_client` starts or joins (imported
only with Dask's distributed itself, when a client starts)."""
from __future__ import annotations

import shutil
import tempfile
from typing import Any

from distributed.diagnostics.plugin import WorkerPlugin

from musclesim.batch.shipped import FOLDERS, built_version, unpack
from musclesim.cosim import check_fresh, reuse_fmus
from musclesim.errors import UserError


class ReusedFmus(WorkerPlugin):
    """The worker unpacks each FMU once for its life (`musclesim.cosim.reuse_fmus` held open
    from its start to its close): the diagnosis's fits send every simulation as a task of its
    own, and unpacking the FMUs again for each would cost about a sixth of a run."""

    name = "musclesim-reused-fmus"

    def setup(self, worker: Any) -> None:
        """Open `reuse_fmus` on `worker` for its life."""
        self._reuse = reuse_fmus()
        self._reuse.__enter__()

    def teardown(self, worker: Any) -> None:
        """Close `reuse_fmus` as `worker` closes."""
        self._reuse.__exit__(None, None, None)


class ShippedFmus(WorkerPlugin):
    """A client's FMUs, as bytes ({file name: bytes}, `shipped.folder_files`), written once into
    a folder of the worker's own (in its local directory) where tasks find them under `key`
    (`shipped.FmuFolder`); removed when the plugin or the worker goes.

    The worker refuses FMUs that musclesim built from other sources than the ones it runs
    (`musclesim.cosim.check_fresh`): their slaves would import its own, different, modules.
    """

    def __init__(self, key: str, files: dict[str, bytes]) -> None:
        """The FMU folder's `files` ({name: bytes}), found on the workers under `key`."""
        self.key, self.files = key, files
        self.folder: str | None = None
        self.name = f"musclesim-fmus-{key}"

    def setup(self, worker: Any) -> None:
        """Write the files into a folder of `worker`'s own and check them fresh."""
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

    def teardown(self, worker: Any) -> None:
        """Remove the folder as the plugin or `worker` goes."""
        if FOLDERS.get(self.key) == self.folder:
            del FOLDERS[self.key]
        self._remove()

    def _remove(self) -> None:
        if self.folder is not None:
            shutil.rmtree(self.folder, ignore_errors=True)
            self.folder = None
