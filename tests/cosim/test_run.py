"""musclesim.cosim.run: a scenario from file to folder, the same rows as the master's run, written
as it goes; a run refused before it starts leaves the earlier run's files as they were."""
import json

import numpy as np
import pytest

from musclesim.cosim import Master, load_scenario, run_scenario
from musclesim.errors import UserError

from conftest import SCENARIOS


def test_the_folder_holds_the_masters_run(fmu_dir, tmp_path):
    summary, res = run_scenario(SCENARIOS / "crawler-ideal.toml", tmp_path / "out", fmu_dir,
                                overrides=["body.k=150"], stop_time=0.2, with_plot=False)
    direct = Master(load_scenario(SCENARIOS / "crawler-ideal.toml", ["body.k=150"], 0.2),
                    fmu_dir).run()
    assert np.array_equal(res.data, direct.data) and res.names == direct.names
    rows = np.loadtxt(tmp_path / "out" / "results.csv", delimiter=",", skiprows=1)
    assert np.array_equal(rows[:, 1:], res.data) and np.array_equal(rows[:, 0], res.time)
    assert summary["completed"] and summary["parameters"]["body"]["k"] == 150.0
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["results.csv", "summary.json"]


def test_a_run_refused_before_it_starts_leaves_the_earlier_run_whole(fmu_dir, tmp_path):
    out = tmp_path / "out"
    first, _ = run_scenario(SCENARIOS / "crawler-ideal.toml", out, fmu_dir, stop_time=0.1,
                            with_plot=False)
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    with pytest.raises(UserError, match="no instance 'ghost'"):
        run_scenario(SCENARIOS / "crawler-ideal.toml", out, fmu_dir, ["ghost.k=1"],
                     stop_time=0.1, with_plot=False)
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert json.loads(before["summary.json"])["run_id"] == first["run_id"]
