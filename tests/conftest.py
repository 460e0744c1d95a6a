"""Shared fixtures: the FMUs are built once per test session into a temporary folder."""
import platform
from pathlib import Path

import pytest
from hypothesis import settings
from threadpoolctl import threadpool_limits

from musclesim.cosim.build import build_all

# the suite runs on two processes (pyproject's addopts), one per core: each one's BLAS on one
# thread, as `dask_client` does beside its workers (idle OpenBLAS threads spin on the other
# process's core; the tests' matrices are small)
threadpool_limits(1, user_api="blas")

# no wall-clock limit per example: a loaded CI machine made hypothesis's 200 ms deadline fail a
# correct test (speed is measured by the benchmarks, never asserted in a test)
settings.register_profile("musclesim", deadline=None)
settings.load_profile("musclesim")

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = ROOT / "scenarios"


@pytest.fixture(scope="session")
def fmu_dir(tmp_path_factory):
    """Folder holding freshly built FMUs of the whole catalogue (with BUILD.json)."""
    path = tmp_path_factory.mktemp("fmus")
    build_all(path)
    return path


@pytest.fixture(scope="session")
def fmu3_dir(tmp_path_factory):
    """Folder holding freshly built FMI 3.0 FMUs of the whole catalogue (`build_all(fmi=3)`)."""
    path = tmp_path_factory.mktemp("fmus3")
    build_all(path, fmi=3)
    return path


@pytest.fixture(scope="session")
def cluster_map():
    """`dask_map` over a local cluster of two worker processes, as `--workers 2` runs: the map of
    the tests that diagnose whole data sets or several cases (started once, when first asked)."""
    from musclesim.batch import dask_client, dask_map

    with dask_client(None, 2) as client:
        yield dask_map(client)


def in_process(cls, name, **params):
    """A slave of `cls` driven without FMI: instance `name`, `params` set, experiment set up."""
    slave = cls(instance_name=name)
    for key, value in params.items():
        setattr(slave, key, value)
    slave.setup_experiment(0.0)
    return slave


def schema_errors(name, document):
    """What makes `document` differ from musclesim/schemas/<name>.schema.json (the schema, shipped
    with the package and shown in the docs, checked first), one located sentence each."""
    import json
    from importlib.resources import files

    import jsonschema

    schema = json.loads((files("musclesim") / "schemas" / f"{name}.schema.json").read_text())
    jsonschema.Draft202012Validator.check_schema(schema)
    return [f"{'/'.join(map(str, e.absolute_path)) or '(top)'}: {e.message}"
            for e in jsonschema.Draft202012Validator(schema).iter_errors(document)]


def two_blas_kernels():
    """Two OpenBLAS kernels (OPENBLAS_CORETYPE) this CPU can run whose sums round differently,
    two processes given them standing for two CPUs: with FMA (Haswell) against without (Prescott),
    or, on a CPU without AVX2, two whose LAPACK exp differed (Sandybridge, Nehalem). Skips where
    OPENBLAS_CORETYPE names no kernel."""
    if platform.system() != "Linux" or platform.machine() != "x86_64":
        pytest.skip("OPENBLAS_CORETYPE names x86-64 kernels")
    flags = set()
    for line in Path("/proc/cpuinfo").read_text().splitlines():
        if line.startswith("flags"):
            flags = set(line.split(":", 1)[1].split())
            break
    if {"avx2", "fma"} <= flags:
        return "Haswell", "Prescott"
    if "avx" in flags:
        return "Sandybridge", "Nehalem"
    pytest.skip("no two differing OpenBLAS kernels known to run on this CPU")


@pytest.fixture
def passes(monkeypatch):
    """A list that records, for every many-cases call of the master (`musclesim.cosim.run_cases`),
    whether its cases ran in one compiled pass (`Fused.batchable`)."""
    from musclesim.cosim import fused

    seen = []
    batchable = fused.Fused.batchable
    monkeypatch.setattr(fused.Fused, "batchable",
                        staticmethod(lambda plans: seen.append(batchable(plans)) or seen[-1]))
    return seen
