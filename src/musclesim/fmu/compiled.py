"""Compiled physics cores: `jit` compiles a core function with numba where numba is installed and
leaves it plain Python where it is not, so that an FMU still runs with only numpy and scipy.

A core written for `jit` is a function of floats and float64 arrays in numba's nopython subset
(no dataclasses, no closures, no Python objects): the same source runs compiled or as Python,
with the same operations in the same order. Neither path fuses multiply-adds or reorders sums
(numba compiles without ``fastmath``), so the two agree to the last bits wherever the C library's
``exp``, ``sin``... agree, and each is bit-identical run to run.

Set the environment variable ``MUSCLESIM_COMPILE=0`` before the first import to run every core as
plain Python (a debugger steps through it; the results agree to 1e-12 of each signal's range).

Compiled code is cached per user, never in the installed package: under ``$NUMBA_CACHE_DIR`` if
set, else ``$XDG_CACHE_HOME/musclesim/numba`` (``~/.cache/musclesim/numba``), in a folder named
by numba's version and a digest of the package's sources, so that an edited core (or one it calls
in another file, which numba's own cache check misses) is compiled anew and never read stale. A
folder not used for `UNUSED_DAYS` is removed. The first run of a new version pays the compile (seconds);
later runs load the machine code.
"""
from __future__ import annotations

import hashlib
import importlib.util
import os
import shutil
import time
from pathlib import Path
from typing import Any, Callable, TypeVar

__all__ = ["jit", "parallel_jit", "COMPILED", "CACHE", "range_over_cases"]

F = TypeVar("F", bound=Callable[..., Any])
UNUSED_DAYS = 7  # a cache folder (one per source version) not used for this long is removed


def _sources_digest() -> str:
    """Digest of every .py file of the package this module sits in and of its components (as
    installed, as an editable checkout lays them out, or as shipped in an FMU's resources): a
    change anywhere names a new cache folder."""
    roots = [Path(__file__).resolve().parents[1]]
    spec = importlib.util.find_spec("musclesim.components")
    roots += [Path(p).resolve() for p in (spec.submodule_search_locations or [])] if spec else []
    h = hashlib.sha256()
    for root in dict.fromkeys(roots):
        for path in sorted(root.rglob("*.py")):
            h.update(str(path.relative_to(root)).encode())
            h.update(path.read_bytes())
    return h.hexdigest()[:16]


def _cache_folder(numba: Any) -> Path | None:
    """This version's cache folder (created; those unused for `UNUSED_DAYS` removed), or None where the
    user set NUMBA_CACHE_DIR (numba then caches there) or no folder can be written."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return None
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "musclesim" / "numba"
    folder = base / f"{numba.__version__}-{_sources_digest()}"
    try:
        folder.mkdir(parents=True, exist_ok=True)
        os.utime(folder)  # the newest in use
        for p in base.iterdir():
            if p.is_dir() and time.time() - p.stat().st_mtime > UNUSED_DAYS * 86400:
                shutil.rmtree(p, ignore_errors=True)
    except OSError:  # a read-only home: compile in every process
        return None
    return folder


def _load_numba() -> Any:
    if os.environ.get("MUSCLESIM_COMPILE", "1").strip() == "0":
        return None
    try:
        import numba
    except ImportError:  # an FMU's own requirements are numpy and scipy only
        return None
    return numba


_NUMBA = _load_numba()
COMPILED = _NUMBA is not None  # the cores run compiled in this process
CACHE = _cache_folder(_NUMBA) if COMPILED else None  # where compiled code is kept
if CACHE is not None:
    _NUMBA.config.CACHE_DIR = str(CACHE)  # read when a function is decorated, below


def jit(fn: F) -> F:
    """`fn` compiled (numba's nopython mode, cached, releasing the GIL) where numba is installed,
    else `fn` itself."""
    if _NUMBA is None:
        return fn
    return _NUMBA.njit(cache=CACHE is not None or bool(os.environ.get("NUMBA_CACHE_DIR")),
                       nogil=True)(fn)


def parallel_jit(fn: F) -> F:
    """As `jit`, with `range_over_cases` run on threads (numba's ``prange``)."""
    if _NUMBA is None:
        return fn
    return _NUMBA.njit(cache=CACHE is not None or bool(os.environ.get("NUMBA_CACHE_DIR")),
                       nogil=True, parallel=True)(fn)


# the loop over independent cases in a `parallel_jit` function: threads where compiled
range_over_cases: Callable[[int], Any] = _NUMBA.prange if _NUMBA is not None else range
