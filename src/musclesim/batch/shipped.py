"""FMU folders sent to Dask workers as bytes, for clusters that share no files with the client.

The client reads the FMUs a job needs and the folder's BUILD.json (`folder_files`); a worker
plugin (`musclesim.batch.plugins.ShippedFmus`, registered by `musclesim.batch.ship_fmus`) writes
them once per worker into a folder of the worker's own (`unpack`). Tasks carry an `FmuFolder` in
place of the client's folder: a path (``os.PathLike``) that names, in each process, the folder that
process reads those FMUs from: on a worker its own copy, in the client the client's folder. With
BUILD.json beside them, the master's direct host (`musclesim.cosim.Master`) recognises the FMUs on
a worker that runs the same musclesim, as it does on the client.
"""
from __future__ import annotations

import json
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

from musclesim.errors import UserError

BUILD = "BUILD.json"
FOLDERS: dict[str, str] = {}  # key of an `FmuFolder` -> the folder this process reads its FMUs from


@dataclass(frozen=True)
class FmuFolder:
    """An FMU folder shipped to a cluster's workers, under `key`: a path to whatever folder holds
    its FMUs in the process at hand (``Path(folder)``, ``os.fspath(folder)``).

    Its text (``str``) is not a path, so that a folder taken as text in one process and read in
    another fails, rather than naming the client's files on a worker.
    """

    key: str

    def __fspath__(self) -> str:
        folder = FOLDERS.get(self.key)
        if folder is None:
            raise UserError(f"the FMUs sent to the Dask workers as {self.key} are not unpacked in "
                            "this process; run the work again (a worker may have restarted)")
        return folder


def folder_files(fmu_dir: str | Path, components: Iterable[str] | None = None
                 ) -> dict[str, bytes]:
    """{file name: bytes} of the FMUs of `components` (default: every FMU) in `fmu_dir`, and of
    the folder's BUILD.json when it has one. An FMU that is not there is left out: the master
    names it when it looks for it.

    Raises
    ------
    UserError
        When a file cannot be read.
    """
    fmu_dir = Path(fmu_dir)
    names = ([f"{c}.fmu" for c in sorted(set(components))] if components is not None
             else sorted(p.name for p in fmu_dir.glob("*.fmu")))
    files = {}
    for name in [*names, BUILD]:
        path = fmu_dir / name
        try:
            if path.is_file():
                files[name] = path.read_bytes()
        except OSError as exc:
            raise UserError(f"cannot read {path} to send it to the Dask workers: "
                            f"{exc.strerror or exc}") from None
    return files


def unpack(files: Mapping[str, bytes], folder: str | Path) -> None:
    """Write `files` ({file name: bytes}, `folder_files`) into the existing `folder`."""
    for name, data in files.items():
        if Path(name).name != name or name in ("", ".", ".."):  # a name, never a path
            raise UserError(f"refused to unpack {name!r}: not a plain file name")
        (Path(folder) / name).write_bytes(data)


def built_version(files: Mapping[str, bytes]) -> str | None:
    """The musclesim version BUILD.json among `files` says the FMUs were built with, or None."""
    try:
        return str(json.loads(files[BUILD]).get("musclesim"))
    except (KeyError, ValueError, AttributeError):
        return None

