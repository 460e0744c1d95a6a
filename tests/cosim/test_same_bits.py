"""The same bits on every CPU: no result depends on the BLAS kernel OpenBLAS picks for the CPU.

numpy's and scipy's OpenBLAS choose their kernels per CPU, and the kernels round differently
(Haswell's use fused multiply-adds, older ones do not); in a stick-slip run a last digit decides
a stick or a slip a step earlier and grows from there. OPENBLAS_CORETYPE forces a kernel, so two
processes given two kernels stand for two CPUs: their recorded rows must be equal bit for bit.
"""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import SCENARIOS, two_blas_kernels

# stick-slip runs: the ideal crawler, the pneumatic one walking (PIDs, sensors, sequencer), and
# a wire lifting a weight that rings on its link
RUNS = [("crawler-ideal.toml", 5.0, []),
        ("crawler-gait-forward.toml", 3.0, []),
        ("sma-dead-weight.toml", 0.5, ["weight.inertia=1.0"])]

CHILD = """
import json, sys
import numpy as np
from threadpoolctl import threadpool_info
from musclesim.cosim import Master, load_scenario

fmu_dir, out, runs = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
for k, (path, stop_time, overrides) in enumerate(runs):
    res = Master(load_scenario(path, overrides, stop_time=stop_time), fmu_dir).run()
    assert res.error is None, res.error
    np.save(f"{out}/{k}.npy", np.column_stack([res.time, res.data]))
print(json.dumps(sorted({i["architecture"] for i in threadpool_info()
                         if i["internal_api"] == "openblas"})))
"""


def _run(fmu_dir, out, kernel):
    out.mkdir()
    runs = [(str(SCENARIOS / name), stop, overrides) for name, stop, overrides in RUNS]
    env = {**os.environ, "OPENBLAS_CORETYPE": kernel}
    done = subprocess.run([sys.executable, "-c", CHILD, str(fmu_dir), str(out), json.dumps(runs)],
                          env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.splitlines()[-1])


def test_stick_slip_rows_are_the_same_bits_under_two_blas_kernels(fmu_dir, tmp_path):
    first, second = two_blas_kernels()
    kernels = (_run(fmu_dir, tmp_path / first, first), _run(fmu_dir, tmp_path / second, second))
    if not all(kernels) or kernels[0] == kernels[1]:
        pytest.skip(f"numpy's BLAS is no OpenBLAS that OPENBLAS_CORETYPE steers ({kernels})")
    differ = []
    for k, (name, _, _) in enumerate(RUNS):
        a, b = (np.load(tmp_path / kernel / f"{k}.npy") for kernel in (first, second))
        assert a.shape == b.shape and a.shape[0] > 100
        rows = np.flatnonzero(np.any(a.view(np.uint64) != b.view(np.uint64), axis=1))
        if len(rows):
            differ.append(f"{name}: {len(rows)} of {len(a)} rows differ between the {first} and "
                          f"{second} kernels, the first at t = {a[rows[0], 0]} s")
    assert not differ, "\n".join(differ)
