"""The FMUs' Linux binary for hosts without Python: a small C loader (fmi2_loader.c, for FMI 3.0
fmi3_loader.c, with loader_core.h) compiled at build time in front of pythonfmu's binary.

pythonfmu's Linux binary is not linked to libpython, so only a host that has Python in its
process can load it (FMPy, libcosimpy); a C or C++ host (OMSimulator's command line, the FMI
Compliance Checker) fails with ``undefined symbol: _Py_NoneStruct``. Adding libpython as a needed
library (patchelf) would let the binary load, but the interpreter it starts computes its prefix
from the host's executable and finds no standard library unless the user sets PYTHONHOME; the
loader instead starts the interpreter itself with the build interpreter's prefix as its home and
the build environment's site-packages on its path, and does nothing where the process already
has Python, so FMPy runs the FMUs exactly as before. It is compiled once per build with that
interpreter's facts written into a header, and installed into each FMU as
``binaries/linux64/<id>.so`` (FMI 3.0: ``binaries/x86_64-linux/<id>.so``), pythonfmu's binary
beside it as ``<id>.pythonfmu.so``.
"""
from __future__ import annotations

import functools
import json
import platform
import shutil
import site
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

SOURCES = {fmi: Path(__file__).with_name(f"fmi{fmi}_loader.c") for fmi in (2, 3)}
CORE = Path(__file__).with_name("loader_core.h")
REAL_SUFFIX = ".pythonfmu.so"  # pythonfmu's binary: binaries/<platform>/<id> + this
_PLATFORM = {2: "linux64", 3: "x86_64-linux"}  # the folder of an FMU's Linux binary


def _libpython() -> Path | None:
    """The shared libpython of this interpreter, or None for a static build."""
    if not sysconfig.get_config_var("Py_ENABLE_SHARED"):
        return None
    name = sysconfig.get_config_var("INSTSONAME") or sysconfig.get_config_var("LDLIBRARY")
    path = Path(sysconfig.get_config_var("LIBDIR") or "") / str(name)
    return path if path.is_file() else None


def _compiler() -> str | None:
    return shutil.which("gcc") or shutil.which("cc")


def _headers() -> list[Path]:
    """Folders holding Python.h and fmi2Functions.h, fmi3Functions.h (FMPy's copy of the FMI
    headers)."""
    import fmpy
    return [Path(sysconfig.get_paths()["include"]), Path(fmpy.__file__).parent / "c-code"]


def _compiler_missing() -> str | None:
    """What the loader needs beyond Python (Linux, a C compiler, the FMI headers), or None."""
    if not sys.platform.startswith("linux"):
        return "the loader for hosts without Python is built on Linux only"
    if _compiler() is None:
        return "no C compiler (gcc or cc) was found"
    missing = [h for h in ("fmi2Functions.h", "fmi3Functions.h")
               if not (_headers()[1] / h).is_file()]
    if missing:
        return f"{missing[0]} is not installed (FMPy's c-code folder)"
    return None


@functools.cache
def loader_unavailable(fmi: int = 2) -> str | None:
    """Why `musclesim build` cannot give its FMUs a binary that loads in a host without Python,
    as one sentence saying what follows, or None where it can.

    Parameters
    ----------
    fmi : int
        The FMI version built (2 or 3).

    Returns
    -------
    str or None
    """
    tail = "the FMUs will load only in hosts with Python in their process (FMPy, libcosimpy)"
    if fmi == 3 and platform.machine() not in ("x86_64", "AMD64"):
        return f"the FMI 3.0 loader forwards calls by x86-64 jumps: {tail}"
    missing = _compiler_missing()
    if missing:
        return f"{missing}: {tail}"
    if _libpython() is None:
        return (f"this Python ({sys.executable}) is not a shared build (sysconfig "
                f"Py_ENABLE_SHARED is 0, no libpython): {tail}")
    if not (_headers()[0] / "Python.h").is_file():
        return f"Python.h is not installed (this Python's development headers): {tail}"
    return None


def _config_header(grid_step: float | None, suffix: str) -> str:
    """loader_config.h: the suffix of the binary forwarded to and, for FMUs, this interpreter's
    libpython, home and the build environment's site folders, or the container's fixed step; as
    C literals (JSON's escapes are C's for these)."""
    if grid_step is not None:
        values: dict[str, str | float] = {"MUSCLESIM_GRID_STEP": float(grid_step)}
    else:
        home = sys.base_prefix if sys.base_exec_prefix == sys.base_prefix else \
            f"{sys.base_prefix}:{sys.base_exec_prefix}"
        base = {str(Path(p)) for p in site.getsitepackages([sys.base_prefix,
                                                            sys.base_exec_prefix])}
        extra = [p for p in site.getsitepackages() if str(Path(p)) not in base]
        script = ("import os, site\n"
                  f"for d in {extra!r}:\n"
                  "    if os.path.isdir(d):\n"
                  "        site.addsitedir(d)\n")
        values = {"MUSCLESIM_LIBPYTHON": str(_libpython()), "MUSCLESIM_PYTHONHOME": home,
                  "MUSCLESIM_SITE_SCRIPT": script}
    values["MUSCLESIM_REAL_SUFFIX"] = suffix
    return "".join(f"#define {k} {v!r}\n" if isinstance(v, float) else
                   f"#define {k} {json.dumps(v)}\n" for k, v in values.items())


def compile_loader(folder: Path, grid_step: float | None = None, suffix: str = REAL_SUFFIX,
                   fmi: int = 2) -> Path:
    """Compile the loader into `folder`; return the shared library's path.

    Parameters
    ----------
    folder : Path
        Where the header, and the library, are written.
    grid_step : float, optional
        None: the FMUs' loader, which starts this interpreter in a host without Python. A step:
        the loader in front of a container runtime with this fixed step, which puts a drifted
        host clock back on its grid and starts no Python.
    suffix : str
        The binary forwarded to is the loader's name without ``.so``, with this suffix.
    fmi : int
        The FMI version of the FMUs (2 or 3; a container's loader is FMI 2.0's).

    Raises
    ------
    RuntimeError
        If what the loader needs is missing (`loader_unavailable`), or the compiler fails (its
        output attached).
    """
    reason = _compiler_missing() if grid_step is not None else loader_unavailable(fmi)
    if reason:
        raise RuntimeError(reason)
    (folder / "loader_config.h").write_text(_config_header(grid_step, suffix))
    source = SOURCES[fmi]
    out = folder / source.with_suffix(".so").name
    includes = [f"-I{d}" for d in (folder, *_headers())]
    # no libpython at link time, nothing undefined: the binary loads in any process
    cmd = [str(_compiler()), "-shared", "-fPIC", "-O2", "-Wall", *includes, str(source),
           "-o", str(out), "-Wl,--no-undefined", "-ldl", "-lpthread", "-lm"]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode:
        raise RuntimeError(f"compiling {source.name} failed:\n{done.stderr}")
    return out


def install(fmu: Path, loader: Path, fmi: int = 2) -> None:
    """Put `loader` into the FMI `fmi` FMU archive `fmu` as its Linux binary, pythonfmu's beside
    it."""
    folder = f"binaries/{_PLATFORM[fmi]}/"
    with zipfile.ZipFile(fmu) as zf:
        items = [(i, zf.read(i)) for i in zf.infolist()]
    with zipfile.ZipFile(fmu, "w", zipfile.ZIP_DEFLATED) as zf:
        for item, data in items:
            if item.filename.startswith(folder) and item.filename.endswith(".so"):
                moved = zipfile.ZipInfo(item.filename.removesuffix(".so") + REAL_SUFFIX,
                                        item.date_time)
                moved.external_attr, moved.compress_type = item.external_attr, item.compress_type
                zf.writestr(moved, data)
                zf.write(loader, item.filename)
            else:
                zf.writestr(item, data)
