"""Hosting FMUs in this process: fmpy's log callbacks, pythonfmu 0.7 workarounds, safe reading.

Process-wide concerns of loading FMUs with fmpy, kept apart from the master algorithm: one log
callback for the whole process, the fixes for pythonfmu 0.7's exit-time use-after-free and its
``sys.path`` entries, and reading model descriptions without entity expansion.
"""
import atexit
import ctypes
import sys
import zipfile
from pathlib import Path

from fmpy import read_model_description
from fmpy.fmi2 import (calloc, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE, free)
from fmpy.logging import addLoggerProxy

from musclesim.errors import UserError

# fmpy's native proxy formats an FMU's variadic log message (ctypes cannot) and hands it to one
# process-wide Python function. Registering a new function per run would leave the proxy pointing at
# a freed callback once that run ends, so one function lives as long as the process and routes each
# message to the running master named by the componentEnvironment in its callbacks.
LOG_SINKS = {}  # componentEnvironment -> {instance name: _Instance}


def _route_log(env, instance_name, status, category, message):
    instances = LOG_SINKS.get(env)
    name = instance_name.decode("utf-8", "replace") if instance_name else ""
    if instances is not None and name in instances:
        instances[name].log.append((status, message.decode("utf-8", "replace").strip()))


_ROUTE_LOG = fmi2CallbackLoggerTYPE(_route_log)
_PROXY = fmi2CallbackFunctions()
_PROXY.logger = _ROUTE_LOG
addLoggerProxy(ctypes.byref(_PROXY))  # _PROXY.logger is now the native proxy


def callbacks(key):
    """FMI callbacks whose log messages reach the master registered under `key`."""
    cb = fmi2CallbackFunctions()
    cb.logger = _PROXY.logger
    cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
    cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
    cb.componentEnvironment = key
    return cb


def release_pythonfmu_libraries():
    """Reset the interpreter handle of every pythonfmu FMU library still loaded (Linux).

    pythonfmu 0.7.0's library resets its global interpreter handle from an ELF destructor that,
    at process exit, runs after the handle's own C++ destructor: a use-after-free that corrupts
    the heap now and then as the process ends. Resetting the handle earlier through the
    library's exported ``finalizePythonInterpreter`` (safe while Python runs: the handle owns
    nothing when the host started Python) makes both later resets no-ops. Registered with atexit,
    so it covers the FMUs any library (fmpy, libcosim) loaded into this process.
    """
    try:
        maps = Path("/proc/self/maps").read_text().splitlines()
    except OSError:
        return
    paths = {line.split(None, 5)[5].removesuffix(" (deleted)") for line in maps
             if len(line.split(None, 5)) == 6 and "/binaries/linux64/" in line}
    for path in paths:
        try:
            lib = ctypes.CDLL(path)  # already loaded: the loader matches the name, even if deleted
        except OSError:
            continue
        if hasattr(lib, "finalizePythonInterpreter"):
            lib.finalizePythonInterpreter()


atexit.register(release_pythonfmu_libraries)


def forget_fmu_resource_paths():
    """Drop the FMU resource folders pythonfmu puts at the front of ``sys.path``.

    Once an FMU's slave module is imported they serve no purpose, and left there they shadow
    this package with the copy each FMU ships, in this process and in the child processes that
    inherit ``sys.path`` (Dask workers).
    """
    sys.path[:] = [p for p in sys.path if not (Path(p) / "slavemodule.txt").is_file()]


def read_fmu(path):
    """Read an FMU's model description, refusing XML with a DTD (no entity expansion)."""
    path = Path(path)
    try:
        with zipfile.ZipFile(path) as zf:
            xml = zf.read("modelDescription.xml")
    except (OSError, KeyError, zipfile.BadZipFile) as exc:
        raise UserError(f"{path} is not a readable FMU: {exc}") from None
    if b"<!DOCTYPE" in xml or b"<!ENTITY" in xml:
        raise UserError(f"{path}: modelDescription.xml declares a DTD or entities, refused")
    try:
        md = read_model_description(str(path), validate=False)
    except Exception as exc:  # fmpy raises bare Exceptions for malformed descriptions
        raise UserError(f"{path}: cannot read modelDescription.xml: {exc}") from None
    if md.coSimulation is None:
        raise UserError(f"{path} is not a co-simulation FMU")
    return md
