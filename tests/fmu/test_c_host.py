"""The FMUs in a host with no Python in its process (a small C program, tests/fmu/data/fmi2_host.c):
the loader `musclesim build` puts in front of pythonfmu's binary starts the build interpreter by
itself, and the values are FMPy's; where it cannot be built, `musclesim build` says so and makes
the FMUs as before."""
import os
import shutil
import subprocess
import sysconfig
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu

import fmpy
from musclesim.cosim import build_all, host, loader
from musclesim.cosim.loader import REAL_SUFFIX, loader_unavailable

HOST_SOURCE = Path(__file__).parent / "data" / "fmi2_host.c"
STEP, STEPS = 1e-3, 50


@pytest.fixture(scope="module")
def c_host(tmp_path_factory):
    """The C host, compiled (skips where no compiler is installed or the FMUs have no loader)."""
    compiler = shutil.which("gcc") or shutil.which("cc")
    if compiler is None:
        pytest.skip("no C compiler (gcc or cc) to build the C host")
    if loader_unavailable(2):
        pytest.skip(loader_unavailable(2))
    exe = tmp_path_factory.mktemp("c_host") / "fmi2_host"
    subprocess.run([compiler, "-O1", f"-I{Path(fmpy.__file__).parent / 'c-code'}",
                    str(HOST_SOURCE), "-o", str(exe), "-ldl"], check=True)
    return exe


def _without_python_env():
    """This process's environment without anything that points a process at a Python."""
    return {k: v for k, v in os.environ.items()
            if not k.startswith("PYTHON") and k not in ("LD_PRELOAD", "LD_LIBRARY_PATH")}


def _run(c_host, fmu, where, binary, *assignments):
    """Run `fmu` (unpacked into `where`) in the C host through `binary` (under binaries/linux64);
    return the finished process."""
    with zipfile.ZipFile(fmu) as zf:
        zf.extractall(where)
    md = read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    return subprocess.run(
        [str(c_host), str(where / "binaries" / "linux64" / binary),
         (where / "resources").as_uri(), md.guid, repr(STEP), str(STEPS),
         str(vr["flange_b.s"]), *(f"{vr[name]}={value!r}" for name, value in assignments)],
        capture_output=True, text=True, env=_without_python_env(), timeout=120)


def test_a_c_host_without_python_gets_fmpys_values(c_host, fmu_dir, tmp_path):
    """CrawlerBody pushed apart by 1 N: the C host reads flange_b.s after every step, and FMPy's
    simulate_fmu reads the same values from the same FMU in this (Python) process."""
    fmu = fmu_dir / "CrawlerBody.fmu"
    done = _run(c_host, fmu, tmp_path / "fmu", "CrawlerBody.so", ("f_a", 1.0), ("k", 150.0))
    assert done.returncode == 0, done.stderr  # loaded, ran, and ended without a crash at exit
    assert "Could not find" not in done.stderr  # the interpreter found its standard library
    rows = np.array([[float(x) for x in line.split()] for line in done.stdout.splitlines()])
    assert rows.shape == (STEPS, 2)

    fmpys = simulate_fmu(str(fmu), stop_time=STEPS * STEP, output_interval=STEP,
                         start_values={"f_a": 1.0, "k": 150.0}, output=["flange_b.s"])
    host.forget_fmu_resource_paths()
    assert np.max(np.abs(fmpys["flange_b.s"][1:STEPS + 1] - rows[:, 1])) <= 1e-12
    assert np.max(np.abs(rows[:, 1])) > 1e-4  # it moved


def test_pythonfmus_own_binary_fails_there(c_host, fmu_dir, tmp_path):
    """What the loader is for: pythonfmu's binary, not linked to libpython, does not load in a
    host without Python (the error OMSimulator reported)."""
    done = _run(c_host, fmu_dir / "CrawlerBody.fmu", tmp_path / "fmu",
                "CrawlerBody" + REAL_SUFFIX)
    assert done.returncode != 0
    assert "undefined symbol" in done.stderr


def test_the_loader_needs_no_libpython_to_load(fmu_dir, tmp_path):
    """The loader's binary names no libpython (so a process with another Python, or a static
    one, loads it), and pythonfmu's binary is kept beside it."""
    with zipfile.ZipFile(fmu_dir / "CrawlerBody.fmu") as zf:
        names = set(zf.namelist())
        zf.extract("binaries/linux64/CrawlerBody.so", tmp_path)
    assert {"binaries/linux64/CrawlerBody.so", "binaries/linux64/CrawlerBody" + REAL_SUFFIX,
            "binaries/win64/CrawlerBody.dll"} <= names
    data = (tmp_path / "binaries/linux64/CrawlerBody.so").read_bytes()
    assert b"_Py_NoneStruct" not in data and b"libpython" in data  # loaded by path, not needed


def test_without_a_shared_python_the_build_says_so_and_goes_on(monkeypatch, tmp_path):
    """A static interpreter: one sentence saying where the FMUs will load, and pythonfmu's binary
    as today."""
    monkeypatch.setattr(sysconfig, "get_config_var",
                        lambda name, real=sysconfig.get_config_var:
                        0 if name == "Py_ENABLE_SHARED" else real(name))
    loader_unavailable.cache_clear()
    try:
        reason = loader_unavailable(2)
        built = build_all(tmp_path, names=["SignalSource"])
    finally:
        loader_unavailable.cache_clear()
    assert reason is not None and "not a shared build" in reason
    assert "will load only in hosts with Python in their process" in reason
    assert reason.count(". ") == 0  # one sentence
    with zipfile.ZipFile(built[0]) as zf:
        assert not [n for n in zf.namelist() if n.endswith(REAL_SUFFIX)]


def test_fmi3_and_other_platforms_say_why(monkeypatch):
    """FMI 3.0 FMUs and other systems than Linux keep pythonfmu's binary, and the sentence says
    so."""
    assert "FMI 3.0" in loader_unavailable(3)
    monkeypatch.setattr(loader.sys, "platform", "win32")
    loader_unavailable.cache_clear()
    try:
        assert "Linux only" in loader_unavailable(2)
    finally:
        loader_unavailable.cache_clear()
