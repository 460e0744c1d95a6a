"""The direct host (musclesim.cosim.direct) calls the slave code an FMU ships without fmpy and
pythonfmu's C layer: every shipped scenario gives the same bits on it as on fmpy, a failure reads
the same, and an FMU musclesim did not build runs beside ours on fmpy. Every shipped scenario's
results are also the bits stored in data/shipped_digests.json (a refactor changes no bit; a change
of physics rewrites that file on purpose: MUSCLESIM_WRITE_DIGESTS=1 pytest tests/cosim/test_hosts.py).
"""
import hashlib
import json
import os
import shutil
import tomllib
from pathlib import Path

import numpy as np
import pytest
from pythonfmu import FmuBuilder

from musclesim.cosim import Master, load_scenario
from musclesim.errors import UserError

from conftest import SCENARIOS

RUNS = sorted(p for p in SCENARIOS.glob("*.toml") if "sweep" not in tomllib.loads(p.read_text()))
STEPS = 200  # communication steps of each run (at least; 0.25 s where that is more)
DIGESTS = Path(__file__).parent / "data" / "shipped_digests.json"


def digest(results):
    """sha256 of a run's column names, times and data, bit for bit."""
    h = hashlib.sha256("\n".join(map(str, results.names)).encode())
    h.update(results.time.tobytes())
    h.update(results.data.tobytes())
    return h.hexdigest()


def stored_digest(name, value):
    """The digest stored for scenario `name` (or, with MUSCLESIM_WRITE_DIGESTS=1, `value` stored)."""
    table = json.loads(DIGESTS.read_text()) if DIGESTS.exists() else {}
    if os.environ.get("MUSCLESIM_WRITE_DIGESTS") == "1":
        table[name] = value
        DIGESTS.parent.mkdir(exist_ok=True)
        DIGESTS.write_text(json.dumps(dict(sorted(table.items())), indent=1) + "\n")
    return table.get(name)


def both(s, fmu_dir):
    """The scenario run on each host: (direct, fmpy) Results, and the direct run's hosts."""
    m = Master(s, fmu_dir)
    direct = m.run()
    return direct, Master(s, fmu_dir, host="fmpy").run(), m.hosts


def assert_same(a, b):
    assert a.names == b.names
    np.testing.assert_array_equal(a.time, b.time)
    assert a.data.tobytes() == b.data.tobytes()  # bit for bit, NaN and signed zeros included
    assert (a.error, a.warnings) == (b.error, b.warnings)


@pytest.mark.parametrize("path", RUNS, ids=lambda p: p.stem)
def test_every_shipped_scenario_gives_the_same_bits_on_both_hosts(fmu_dir, path):
    s = load_scenario(path)
    s = load_scenario(path, stop_time=min(s.stop_time, max(0.25, STEPS * s.step)))
    direct, fmpy, hosts = both(s, fmu_dir)
    assert direct.error is None
    assert set(hosts.values()) == {"direct"}
    assert_same(direct, fmpy)
    assert digest(direct) == stored_digest(path.stem, digest(direct))


def test_a_failing_instance_reads_the_same_on_both_hosts(fmu_dir):
    s = load_scenario(SCENARIOS / "crawler-ideal.toml", ["body.c=-1.3"], stop_time=0.1)
    direct, fmpy, _ = both(s, fmu_dir)
    assert direct.error.startswith("instance 'body' (CrawlerBody) failed during initialization "
                                   "at t = 0 s: ")
    assert "c must be non-negative" in direct.error
    assert_same(direct, fmpy)


def test_an_unknown_host_is_refused(fmu_dir):
    with pytest.raises(UserError, match="host 'c' is not one of direct, fmpy"):
        Master(load_scenario(SCENARIOS / "crawler-ideal.toml"), fmu_dir, host="c")


GAIN = '''
from pythonfmu import Fmi2Causality, Fmi2Slave, Fmi2Variability, Real


class Gain(Fmi2Slave):
    """y = k u, a plain pythonfmu FMU: not built by musclesim."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.k, self.u, self.y = 1.0, 0.0, 0.0
        self.register_variable(Real("k", causality=Fmi2Causality.parameter,
                                    variability=Fmi2Variability.tunable))
        self.register_variable(Real("u", causality=Fmi2Causality.input))
        self.register_variable(Real("y", causality=Fmi2Causality.output))

    def get_real(self, vrs):
        self.y = self.k * self.u
        return super().get_real(vrs)

    def do_step(self, t, h):
        return True
'''


def test_a_foreign_fmu_runs_on_fmpy_beside_ours_on_the_direct_host(fmu_dir, tmp_path):
    folder = shutil.copytree(fmu_dir, tmp_path / "fmus")  # BUILD.json lists ours, not the gain
    (tmp_path / "Gain.py").write_text(GAIN)
    FmuBuilder.build_FMU(tmp_path / "Gain.py", dest=folder)
    text = (SCENARIOS / "crawler-ideal.toml").read_text()
    wired = text.replace('["inputs.f_a", "body.f_a"]', '["inputs.f_a", "gain.u"], '
                         '["gain.y", "body.f_a"]') + '\n[instances.gain]\ncomponent = "Gain"\n'
    (tmp_path / "through-gain.toml").write_text(wired)
    mixed = load_scenario(tmp_path / "through-gain.toml", stop_time=1.0)
    direct, fmpy, hosts = both(mixed, folder)
    assert hosts == {"inputs": "direct", "body": "direct", "friction1": "direct",
                     "friction2": "direct", "gain": "fmpy"}
    assert_same(direct, fmpy)
    plain = Master(load_scenario(SCENARIOS / "crawler-ideal.toml", stop_time=1.0), fmu_dir).run()
    assert direct.data.tobytes() == plain.data.tobytes()  # a gain of 1 changes no bit
