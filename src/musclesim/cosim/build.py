"""`musclesim build`: package every component of the catalogue as an FMI 2.0 co-simulation FMU
(pythonfmu), or with ``--fmi 3`` as an FMI 3.0 one (pythonfmu3, the same slave behind
`musclesim.fmu.fmi3.Fmi3Face`).

Each FMU is self-contained: its resources hold the slave, the physics cores with the data files
they read, the FMU base (`musclesim.fmu`, under the `musclesim` package name with an empty
package __init__) and pythonfmu's Python files, so it runs where only Python, numpy and scipy are
installed. On Linux an FMU's binary is a small loader in front of pythonfmu's
(`musclesim.cosim.loader`), so that hosts without Python load it too. BUILD.json beside them
records a digest of the sources the FMUs came from (the loader's among them), so that the runner
can tell when they are stale.
"""
from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import functools
import hashlib
import importlib
import json
import shutil
import tempfile
from pathlib import Path

import pythonfmu
from pythonfmu import FmuBuilder
from pythonfmu3 import FmuBuilder as Fmu3Builder

import musclesim
import musclesim.fmu
from musclesim.components import CATALOGUE
from musclesim.cosim import loader
from musclesim.errors import UserError


# pythonfmu 0.7.0 finds the slave class by executing this script in the module's namespace once per
# instantiation, and then releases a reference to that namespace it never owned; the second
# instance of the same FMU in one process then crashes. Each execution therefore adds the
# reference that is taken away, one that nothing else releases (the module's first import adds one
# spare: the namespace lives as long as the process). A reference held by a Python object instead
# (a list in the namespace) is released again when the interpreter clears the module at exit:
# the namespace is then freed while it is being cleared, and the process crashed now and then
# as it ended.
# Where musclesim is not installed, the package comes from the first musclesim FMU's resources; a
# host that deletes that folder (fmpy's simulate_fmu does) would leave a second FMU importing from
# nowhere, so a package whose folder is gone is forgotten and imported again from this FMU.
_STUB = '''"""FMU entry point of {name}."""
import ctypes
import os
import sys

ctypes.pythonapi.Py_IncRef(ctypes.py_object(globals()))
if not all(os.path.isdir(p) for p in getattr(sys.modules.get("musclesim"), "__path__", [])):
    for _name in [n for n in sys.modules if n == "musclesim" or n.startswith("musclesim.")]:
        del sys.modules[_name]

from {module} import {cls} as _Slave


class {name}(_Slave):
    pass
'''


# FMI 3.0: the same slave behind `musclesim.fmu.fmi3.Fmi3Face` (pythonfmu3's builder finds the class
# whose bases name Fmi3Slave in the script)
_STUB3 = _STUB.replace("class {name}(_Slave):\n    pass\n", """from pythonfmu3 import Fmi3Slave
from musclesim.fmu.fmi3 import Fmi3Face
class {name}(Fmi3Face, Fmi3Slave):
    inner_class = _Slave
""")
assert _STUB3 != _STUB

# the FMU state can be saved, restored and serialized (the options' names per FMI version); the
# step may vary (pythonfmu3 0.3.4 writes false unless told)
_OPTIONS = {2: {"canGetAndSetFMUstate": True, "canSerializeFMUstate": True},
            3: {"canGetAndSetFMUState": True, "canSerializeFMUState": True,
                "canHandleVariableCommunicationStepSize": True}}

# what every FMU ships from components/: the code, and the data files the cores read at run time
# (wire parameter sets, FORC data sets and their index) — not reference results such as CSVs of
# scenario outputs
_SHIPPED = ("*.py", "*/params/*.toml", "*/data/*.toml", "*/data/*.csv")


def _component_sources() -> dict[Path, Path]:
    """The files shipped in every FMU: {relative path in resources: source path}."""
    import musclesim.components as comps

    root = Path(comps.__file__).parent
    fmu_base = Path(musclesim.fmu.__file__).parent
    files = {Path("musclesim/fmu") / src.name: src for src in sorted(fmu_base.glob("*.py"))}
    found = {src for pattern in _SHIPPED for src in root.rglob(pattern)}
    for src in sorted(found):
        files[Path("musclesim/components") / src.relative_to(root)] = src
    return files


def source_digest() -> str:
    """SHA-256 over the sources an FMU is built from (names and contents, and its entry point)."""
    h = hashlib.sha256(musclesim.__version__.encode() + _STUB.encode() + _STUB3.encode()
                       + b"".join(p.read_bytes() for p in (*loader.SOURCES.values(),
                                                           loader.CORE)))
    for rel, src in _component_sources().items():
        h.update(str(rel).encode())
        h.update(src.read_bytes())
    return h.hexdigest()


def build_all(dest: str | Path = "fmus", names: Iterable[str] | None = None, fmi: int = 2
              ) -> list[Any]:
    """Build the FMUs of `names` (default: the whole catalogue) into `dest`, as FMI `fmi` (2 or 3)
    co-simulation FMUs; return their paths.

    Raises
    ------
    UserError
        For another FMI version, or naming a component whose module fails to import.

    Notes
    -----
    Where `loader.loader_unavailable` gives a reason (a static Python, no compiler, not Linux),
    the FMUs keep pythonfmu's binary, which loads only where the host has Python in its process.
    """
    if fmi not in (2, 3):
        raise UserError(f"FMI version {fmi!r}: musclesim builds FMI 2.0 or 3.0 FMUs (2 or 3)")
    builder = FmuBuilder if fmi == 2 else Fmu3Builder
    dest = Path(dest)
    dest.mkdir(parents=True, exist_ok=True)
    built = []
    with tempfile.TemporaryDirectory(prefix="musclesim_build_") as tmp:
        stage = Path(tmp) / "stage"
        for rel, src in _component_sources().items():
            (stage / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(src, stage / rel)
        (stage / "musclesim" / "__init__.py").write_text('"""musclesim FMU runtime."""\n')
        shipped = [stage / "musclesim"]
        binary = None if loader.loader_unavailable(fmi) else \
            loader.compile_loader(Path(tmp), fmi=fmi)
        if fmi == 3:  # the FMI 2.0 base the slaves derive from, as pythonfmu ships it in its FMUs
            (stage / "pythonfmu").mkdir()
            for src in Path(pythonfmu.__file__).parent.glob("*.py"):
                shutil.copy2(src, stage / "pythonfmu" / src.name)
            shipped.append(stage / "pythonfmu")
        for name in names or CATALOGUE:
            module, cls = CATALOGUE[name].split(":")
            _check_imports(name, module)
            # pythonfmu loads the deepest Fmi2Slave subclass of a one-class script: a stub per FMU
            # the script's module name, unique per FMI version: FMUs of both in one process
            script = Path(tmp) / f"musclesim_fmu{'' if fmi == 2 else '3'}_{name}.py"
            script.write_text((_STUB if fmi == 2 else _STUB3).format(name=name, module=module,
                                                                     cls=cls))
            fmu = builder.build_FMU(
                script, dest=dest, project_files=shipped,
                # no external-tool flag: PyFMI refuses an FMU that sets it, and the FMU carries
                # its code; what it needs installed (Python, numpy, scipy) the docs say
                needsExecutionTool=False, **_OPTIONS[fmi])
            if binary is not None:
                loader.install(Path(fmu), binary, fmi)
            built.append(fmu)
    sources, fmus = source_digest(), dict[str, str]()
    if names:  # a partial build keeps the digests of the FMUs built before from the same sources
        old = _stamp(dest)
        fmus = old.get("fmus", {}) if old.get("sources") == sources else {}
    fmus.update({Path(b).name: _file_digest(b) for b in built})
    (dest / "BUILD.json").write_text(json.dumps(
        {"musclesim": musclesim.__version__, "sources": sources, "fmus": fmus}, indent=2) + "\n")
    return built


def _check_imports(name: str, module: str) -> None:
    """Refuse to build component `name` when its slave's `module` fails to import, in one
    sentence naming the component and the cause (not a traceback from the builder)."""
    try:
        importlib.import_module(module)
    except Exception as exc:  # whatever the module raises as it is imported
        cause = " ".join(str(exc).split()) or "no message"
        raise UserError(f"component {name} cannot be built: its module {module} fails to import "
                        f"({type(exc).__name__}: {cause})") from None


def _file_digest(path: str | Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


@functools.cache
def _installed_digest() -> str:
    """`source_digest` computed once: what `built_here` compares against for every run."""
    return source_digest()


@functools.cache
def _cached_file_digest(path: str, size: int, mtime_ns: int) -> str:
    return _file_digest(path)


def _stamp(fmu_dir: str | Path) -> dict[str, Any]:
    """BUILD.json's content as a dict ({} when absent or unreadable)."""
    try:
        stamp = json.loads((Path(fmu_dir) / "BUILD.json").read_text())
    except (OSError, ValueError):
        return {}
    return stamp if isinstance(stamp, dict) else {}


def built_here(fmu_path: str | Path) -> bool:
    """Whether `musclesim build` made the FMU at `fmu_path` from the sources this process runs:
    BUILD.json beside it lists it with its digest and those sources' digest (what
    `check_fresh` checks, as a yes or no; digests of the sources computed once per process, the
    code that runs being the code imported, and of each FMU file once per version of it)."""
    path = Path(fmu_path)
    stamp = _stamp(path.parent)
    listed = stamp.get("fmus", {}).get(path.name) if isinstance(stamp.get("fmus"), dict) else None
    if listed is None or stamp.get("sources") != _installed_digest():
        return False
    try:
        stat = path.stat()
    except OSError:
        return False
    return _cached_file_digest(str(path.resolve()), stat.st_size, stat.st_mtime_ns) == listed


def check_fresh(fmu_dir: str | Path) -> None:
    """Refuse the FMUs in `fmu_dir` that `musclesim build` made from other sources than the
    installed ones.

    In the runner's process the FMUs' slaves import the installed musclesim modules, so a stale
    FMU would run code that differs from the one it ships; rebuilding keeps the two the same.
    An FMU that BUILD.json lists but whose file is not the one built (replaced or edited) is
    refused the same way; an FMU it does not list is foreign and left to the master's checks.
    """
    if not (Path(fmu_dir) / "BUILD.json").is_file():
        return  # foreign or missing FMUs: the master reports what is missing
    stamp = _stamp(fmu_dir)
    if stamp.get("sources") != source_digest() or not isinstance(stamp.get("fmus"), dict):
        raise UserError(f"the FMUs in {fmu_dir} were built from other sources than this musclesim; "
                        "run `musclesim build` to rebuild them")
    for name, digest in sorted(stamp["fmus"].items()):
        path = Path(fmu_dir) / Path(str(name)).name  # a name, never a path out of the folder
        if path.is_file() and _file_digest(path) != digest:
            raise UserError(f"{path} is not the FMU `musclesim build` made (its digest differs "
                            "from BUILD.json's); run `musclesim build` to rebuild it")
