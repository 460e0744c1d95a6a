"""Hosting FMUs in this process: fmpy's log callbacks, pythonfmu 0.7 workarounds, safe reading.

Process-wide concerns of loading FMUs with fmpy, kept apart from the master algorithm: one log
callback for the whole process, the fixes for pythonfmu 0.7's exit-time use-after-free and its
``sys.path`` entries, and reading untrusted archives: the model description read with a size cap
and without entity expansion, extraction entry by entry (no absolute path, no ``..``, no link,
a cap on the total size); and the temporary folders of runs killed before they could remove
their own (`remove_orphan_runs`).
"""
from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import atexit
import contextlib
import ctypes
import io
import os
import tempfile
import shutil
import stat
import sys
import zipfile
from pathlib import Path, PurePosixPath

from fmpy import read_model_description
from fmpy.fmi2 import (calloc, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE, free)
from fmpy.logging import addLoggerProxy

from musclesim.errors import UserError

# fmpy's native proxy formats an FMU's variadic log message (ctypes cannot) and hands it to one
# process-wide Python function. Registering a new function per run would leave the proxy pointing at
# a freed callback once that run ends, so one function lives as long as the process and routes each
# message to the running master named by the componentEnvironment in its callbacks.
LOG_SINKS: dict = {}  # componentEnvironment -> {instance name: wiring.Loaded}


def _route_log(env: Any, instance_name: bytes, status: int, category: Any, message: bytes) -> None:
    instances = LOG_SINKS.get(env)
    name = instance_name.decode("utf-8", "replace") if instance_name else ""
    if instances is not None and name in instances:
        instances[name].log.append((status, message.decode("utf-8", "replace").strip()))


_ROUTE_LOG = fmi2CallbackLoggerTYPE(_route_log)
_PROXY = fmi2CallbackFunctions()
_PROXY.logger = _ROUTE_LOG
addLoggerProxy(ctypes.byref(_PROXY))  # _PROXY.logger is now the native proxy


def callbacks(key: int) -> Any:
    """FMI callbacks whose log messages reach the master registered under `key`."""
    cb = fmi2CallbackFunctions()
    cb.logger = _PROXY.logger
    cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    cb.componentEnvironment = key
    return cb


def release_pythonfmu_libraries() -> None:
    """Reset the interpreter handle of every pythonfmu FMU library still loaded (Linux).

    pythonfmu 0.7.0's library resets its global interpreter handle from an ELF destructor that,
    at process exit, runs after the handle's own C++ destructor: a use-after-free that corrupts
    the heap now and then as the process ends. Resetting the handle earlier through the
    library's exported ``finalizePythonInterpreter`` (safe while Python runs: the handle owns
    nothing when the host started Python) makes both later resets no-ops. pythonfmu3's library
    (FMI 3.0, ``binaries/x86_64-linux``) has the same handle and export. Registered with atexit,
    so it covers the FMUs any library (fmpy, libcosim) loaded into this process.
    """
    try:
        maps = Path("/proc/self/maps").read_text().splitlines()
    except OSError:
        return
    paths = {line.split(None, 5)[5].removesuffix(" (deleted)") for line in maps
             if len(line.split(None, 5)) == 6 and ("/binaries/linux64/" in line
                                                    or "/binaries/x86_64-linux/" in line)}
    for path in paths:
        try:
            lib = ctypes.CDLL(path)  # already loaded: the loader matches the name, even if deleted
        except OSError:
            continue
        if hasattr(lib, "finalizePythonInterpreter"):
            lib.finalizePythonInterpreter()


atexit.register(release_pythonfmu_libraries)


def forget_fmu_resource_paths() -> None:
    """Drop the FMU resource folders pythonfmu puts at the front of ``sys.path``.

    Once an FMU's slave module is imported they serve no purpose, and left there they shadow
    this package with the copy each FMU ships, in this process and in the child processes that
    inherit ``sys.path`` (Dask workers).
    """
    sys.path[:] = [p for p in sys.path if not (Path(p) / "slavemodule.txt").is_file()]


MAX_DESCRIPTION = 16 * 2**20  # bytes of modelDescription.xml read at most (ours: ~30 kB)
MAX_EXTRACTED = 512 * 2**20  # bytes an FMU may unpack to (ours: ~0.2 MB each)
MAX_ENTRIES = 10_000  # files in one FMU


def _read_capped(zf: zipfile.ZipFile, name: str, cap: int, where: object) -> bytes:
    """The bytes of entry `name`, read in chunks and refused past `cap` (sizes can lie)."""
    with zf.open(name) as f:
        data = f.read(cap + 1)
    if len(data) > cap:
        raise UserError(f"{where}: {name} is larger than {cap // 2**20} MiB, refused")
    return data


_REUSE: dict[str, Any] = {"depth": 0, "folder": None, "descriptions": {}, "extracted": {}}


@contextlib.contextmanager
def reuse_fmus() -> Iterator[None]:
    """Within it, each FMU file is read and extracted once and reused by every run that follows
    (`read_fmu`, `extracted_fmu`), in one temporary folder removed when the outermost such block
    ends, however it ends. For work that runs a scenario many times in one process (a fit of the
    diagnosis: some twenty runs), where unpacking every FMU again for every run costs about a
    sixth of the time. An FMU file that changes (size or modification time) is read again."""
    if _REUSE["depth"] == 0:
        _REUSE["folder"] = Path(tempfile.mkdtemp(prefix=f"musclesim_run_{os.getpid()}_"))
    _REUSE["depth"] += 1
    try:
        yield
    finally:
        _REUSE["depth"] -= 1
        if _REUSE["depth"] == 0:
            shutil.rmtree(_REUSE["folder"], ignore_errors=True)
            _REUSE.update(folder=None, descriptions={}, extracted={})


def _key(path: str | Path) -> tuple[str, int, int]:
    stat_ = Path(path).stat()
    return str(Path(path).resolve()), stat_.st_size, stat_.st_mtime_ns


def extracted_fmu(path: str | Path) -> str | None:
    """The folder `reuse_fmus` extracted the FMU at `path` into (extracting it the first time),
    or None outside such a block."""
    if not _REUSE["depth"]:
        return None
    key = _key(path)
    if key not in _REUSE["extracted"]:
        folder = _REUSE["folder"] / str(len(_REUSE["extracted"]))
        _REUSE["extracted"][key] = extract_fmu(path, folder)
    return _REUSE["extracted"][key]


def read_fmu(path: str | Path) -> Any:
    """Read the model description of the FMU at `path` (once per file inside `reuse_fmus`)."""
    if _REUSE["depth"]:
        key = _key(path)
        if key not in _REUSE["descriptions"]:
            _REUSE["descriptions"][key] = _read_fmu(path)
        return _REUSE["descriptions"][key]
    return _read_fmu(path)


def _read_fmu(path: str | Path) -> Any:
    """Read an FMU's model description, refusing XML with a DTD (no entity expansion) and a
    description larger than `MAX_DESCRIPTION` before parsing it, and an archive whose entries
    `extract_fmu` would refuse (so that a command refuses it before any work)."""
    path = Path(path)
    try:
        with zipfile.ZipFile(path) as zf:
            _check_entries(zf, path)
            xml = _read_capped(zf, "modelDescription.xml", MAX_DESCRIPTION, path)
    except (OSError, KeyError, zipfile.BadZipFile, EOFError) as exc:
        raise UserError(f"{path} is not a readable FMU: {exc}") from None
    if b"<!DOCTYPE" in xml or b"<!ENTITY" in xml:
        raise UserError(f"{path}: modelDescription.xml declares a DTD or entities, refused")
    only = io.BytesIO()  # fmpy parses a zip: hand it one holding just the capped description
    with zipfile.ZipFile(only, "w") as zf:
        zf.writestr("modelDescription.xml", xml)
    try:
        md = read_model_description(only, validate=False)
    except Exception as exc:  # fmpy raises bare Exceptions for malformed descriptions
        raise UserError(f"{path}: cannot read modelDescription.xml: {exc}") from None
    if md.coSimulation is None:
        raise UserError(f"{path} is not a co-simulation FMU")
    return md


def _entry_problem(info: zipfile.ZipInfo) -> str | None:
    name = info.filename
    parts = PurePosixPath(name.replace("\\", "/")).parts
    if name.startswith(("/", "\\")) or (parts and ":" in parts[0]):
        return "has an absolute path"
    if ".." in parts:
        return "leaves the archive's folder ('..')"
    if stat.S_ISLNK(info.external_attr >> 16):
        return "is a link"
    return None


def _check_entries(zf: zipfile.ZipFile, path: str | Path) -> list[zipfile.ZipInfo]:
    """The archive's entries; raise naming the archive and the first entry that is refused."""
    infos = zf.infolist()
    if len(infos) > MAX_ENTRIES:
        raise UserError(f"FMU {path} holds {len(infos)} entries, more than {MAX_ENTRIES}")
    for info in infos:
        problem = _entry_problem(info)
        if problem:
            raise UserError(f"FMU {path}: entry {info.filename!r} {problem}, refused")
    return infos


def extract_fmu(path: str | Path, dest: str | Path) -> str:
    """Extract the FMU at `path` into the new folder `dest`, checking every entry first.

    Refuses, in one sentence naming the archive and the entry, an absolute path, a ``..``, a
    link, more than `MAX_ENTRIES` entries or more than `MAX_EXTRACTED` bytes unpacked (counted
    as they are written, not as the archive declares them). Returns `dest` as a string.
    """
    path, dest = Path(path), Path(dest)
    try:
        with zipfile.ZipFile(path) as zf:
            infos = _check_entries(zf, path)
            total = 0
            for info in infos:
                target = dest / info.filename
                if info.is_dir():
                    target.mkdir(parents=True, exist_ok=True)
                    continue
                target.parent.mkdir(parents=True, exist_ok=True)
                with zf.open(info) as src, open(target, "wb") as out:
                    while chunk := src.read(2**20):
                        total += len(chunk)
                        if total > MAX_EXTRACTED:
                            raise UserError(f"FMU {path}: entry {info.filename!r} takes the "
                                            f"archive past {MAX_EXTRACTED // 2**20} MiB "
                                            "unpacked, refused")
                        out.write(chunk)
    except (OSError, zipfile.BadZipFile, EOFError) as exc:
        shutil.rmtree(dest, ignore_errors=True)
        raise UserError(f"FMU {path} cannot be extracted: {exc}") from None
    except UserError:
        shutil.rmtree(dest, ignore_errors=True)
        raise
    return str(dest)


def remove_orphan_runs() -> None:
    """Remove the temporary folders of runs whose process is gone (killed with SIGKILL, which no
    ``finally`` survives): the next run cleans up after them."""
    for folder in Path(tempfile.gettempdir()).glob("musclesim_run_*_*"):
        pid = folder.name.split("_")[2]
        if not pid.isdigit():
            continue
        try:
            os.kill(int(pid), 0)
        except ProcessLookupError:
            shutil.rmtree(folder, ignore_errors=True)
        except OSError:  # alive, another user's
            continue
