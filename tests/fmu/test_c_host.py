"""The FMUs in a host with no Python in its process (a small C program, tests/fmu/data/fmi2_host.c
and, for FMI 3.0, fmi3_host.c): the loader `musclesim build` puts in front of pythonfmu's binary
starts the build interpreter by itself, and the values are FMPy's; where it cannot be built,
`musclesim build` says so and makes the FMUs as before."""
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

DATA = Path(__file__).parent / "data"
STEP, STEPS = 1e-3, 50
PLATFORM = {2: "linux64", 3: "x86_64-linux"}  # where an FMU's Linux binary is


@pytest.fixture(scope="module", params=[2, 3], ids=["fmi2", "fmi3"])
def c_host(request, tmp_path_factory):
    """(FMI version, the C host for it), compiled (skips where no compiler is installed or the
    FMUs have no loader)."""
    fmi = request.param
    compiler = shutil.which("gcc") or shutil.which("cc")
    if compiler is None:
        pytest.skip("no C compiler (gcc or cc) to build the C host")
    if loader_unavailable(fmi):
        pytest.skip(loader_unavailable(fmi))
    exe = tmp_path_factory.mktemp("c_host") / f"fmi{fmi}_host"
    subprocess.run([compiler, "-O1", f"-I{Path(fmpy.__file__).parent / 'c-code'}",
                    str(DATA / f"fmi{fmi}_host.c"), "-o", str(exe), "-ldl"], check=True)
    return fmi, exe


@pytest.fixture
def fmus(c_host, request):
    """The folder of the FMUs of the C host's FMI version (the session's build)."""
    return request.getfixturevalue("fmu_dir" if c_host[0] == 2 else "fmu3_dir")


def _without_python_env():
    """This process's environment without anything that points a process at a Python."""
    return {k: v for k, v in os.environ.items()
            if not k.startswith("PYTHON") and k not in ("LD_PRELOAD", "LD_LIBRARY_PATH")}


def _run(c_host, fmu, where, binary, *assignments):
    """Run `fmu` (unpacked into `where`) in the C host `c_host` (FMI version, program) through
    `binary` (in the folder of its Linux binary); return the finished process."""
    fmi, exe = c_host
    with zipfile.ZipFile(fmu) as zf:
        zf.extractall(where)
    md = read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    # FMI 2.0 passes the resources as a URI, FMI 3.0 as a path ending in a separator
    resources = (where / "resources").as_uri() if fmi == 2 else f"{where / 'resources'}{os.sep}"
    return subprocess.run(
        [str(exe), str(where / "binaries" / PLATFORM[fmi] / binary),
         resources, md.guid, repr(STEP), str(STEPS),
         str(vr["flange_b.s"]), *(f"{vr[name]}={value!r}" for name, value in assignments)],
        capture_output=True, text=True, env=_without_python_env(), timeout=120)


def test_a_c_host_without_python_gets_fmpys_values(c_host, fmus, tmp_path):
    """CrawlerBody pushed apart by 1 N: the C host reads flange_b.s after every step, and FMPy's
    simulate_fmu reads the same values from the same FMU in this (Python) process."""
    fmu = fmus / "CrawlerBody.fmu"
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


def test_pythonfmus_own_binary_fails_there(c_host, fmus, tmp_path):
    """What the loader is for: pythonfmu's binary, not linked to libpython, does not load in a
    host without Python (the error OMSimulator reported)."""
    done = _run(c_host, fmus / "CrawlerBody.fmu", tmp_path / "fmu", "CrawlerBody" + REAL_SUFFIX)
    assert done.returncode != 0
    assert "undefined symbol" in done.stderr


@pytest.mark.parametrize("fmi, windows", [(2, "win64"), (3, "x86_64-windows")])
def test_the_loader_needs_no_libpython_to_load(request, tmp_path, fmi, windows):
    """The loader's binary names no libpython (so a process with another Python, or a static
    one, loads it), and pythonfmu's binary is kept beside it; Windows keeps pythonfmu's."""
    if loader_unavailable(fmi):
        pytest.skip(loader_unavailable(fmi))
    fmus = request.getfixturevalue("fmu_dir" if fmi == 2 else "fmu3_dir")
    linux = f"binaries/{PLATFORM[fmi]}/CrawlerBody"
    with zipfile.ZipFile(fmus / "CrawlerBody.fmu") as zf:
        names = set(zf.namelist())
        zf.extract(f"{linux}.so", tmp_path)
    assert {f"{linux}.so", linux + REAL_SUFFIX, f"binaries/{windows}/CrawlerBody.dll"} <= names
    data = (tmp_path / f"{linux}.so").read_bytes()
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


def test_other_platforms_say_why(monkeypatch):
    """Other systems than Linux, and FMI 3.0 on other processors than x86-64, keep pythonfmu's
    binary, and the sentence says so."""
    monkeypatch.setattr(loader.platform, "machine", lambda: "aarch64")
    loader_unavailable.cache_clear()
    try:
        assert "x86-64" in loader_unavailable(3)
        monkeypatch.setattr(loader.sys, "platform", "win32")
        loader_unavailable.cache_clear()
        assert "Linux only" in loader_unavailable(2)
    finally:
        loader_unavailable.cache_clear()


def test_musclesim_build_prints_the_sentence(monkeypatch, capsys, tmp_path):
    """`musclesim build` prints why, once, before building as before (the build itself stubbed:
    the sentence is the command's)."""
    import musclesim.cosim as cosim
    from musclesim.cli import main

    reason = "no C compiler (gcc or cc) was found: the FMUs will load only in hosts with Python " \
             "in their process (FMPy, libcosimpy)"
    monkeypatch.setattr(cosim, "loader_unavailable", lambda fmi: reason)
    monkeypatch.setattr(cosim, "build_all", lambda dest, fmi: [tmp_path / "A.fmu"])
    assert main(["build", "--fmus", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    assert err == f"musclesim: No C compiler{reason[len('no C compiler'):]}.\n"
    assert out == f"built {tmp_path / 'A.fmu'}\n"
