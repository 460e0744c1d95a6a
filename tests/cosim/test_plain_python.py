"""The cores run as plain Python where numba is not installed (an FMU's own requirements are
numpy and scipy): every shipped scenario gives, in a process where numba cannot be imported, the
compiled run's values to 1e-12 of each signal's range."""
import subprocess
import sys
import textwrap
import tomllib

import numpy as np
import pytest

from musclesim.cosim import Master, load_scenario
from musclesim.fmu.compiled import COMPILED

from conftest import SCENARIOS

RUNS = sorted(p for p in SCENARIOS.glob("*.toml") if "sweep" not in tomllib.loads(p.read_text()))
STEPS = 200


def short(path):
    s = load_scenario(path)
    return min(s.stop_time, max(0.25, STEPS * s.step))


@pytest.mark.skipif(not COMPILED, reason="numba is not installed: there is no compiled run")
def test_every_shipped_scenario_agrees_without_the_compiler(fmu_dir, tmp_path):
    script = textwrap.dedent(f"""
        import sys
        sys.modules["numba"] = None  # as if numba were not installed: import numba fails
        import numpy as np
        from musclesim.fmu.compiled import COMPILED
        from musclesim.cosim import Master, load_scenario
        assert not COMPILED
        out = {{}}
        for i, (path, stop) in enumerate({[(str(p), short(p)) for p in RUNS]!r}):
            res = Master(load_scenario(path, stop_time=stop), {str(fmu_dir)!r}).run()
            out[f"{{i}}"] = res.data
            out[f"{{i}}_error"] = np.array(res.error or "")
        np.savez({str(tmp_path / "plain.npz")!r}, **out)
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    plain = np.load(tmp_path / "plain.npz")
    for i, path in enumerate(RUNS):
        res = Master(load_scenario(path, stop_time=short(path)), fmu_dir).run()
        assert str(plain[f"{i}_error"]) == (res.error or ""), path.stem
        assert plain[str(i)].shape == res.data.shape, path.stem
        span = np.ptp(res.data, axis=0) if len(res.data) else np.zeros(res.data.shape[1])
        off = np.abs(plain[str(i)] - res.data).max(axis=0, initial=0.0)
        bad = [f"{c}: {d:.3g} of a range {r:.3g}" for c, d, r in zip(res.names, off, span)
               if not d <= 1e-12 * r]
        assert not bad, f"{path.stem}: {'; '.join(bad)}"
