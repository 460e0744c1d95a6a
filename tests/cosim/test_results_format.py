"""results.csv is a plain CSV that the usual readers take as it is (the FMI cross-check rules for
result files: the names on line 1, time first, no comment line)."""
import csv
import json

import numpy as np
import pandas
import pytest
from fmpy.util import read_csv

from musclesim.cosim import run_scenario

from conftest import SCENARIOS


@pytest.fixture(scope="module")
def run(fmu_dir, tmp_path_factory):
    """A short crawler-ideal run: its folder and its results as the runner returned them."""
    out = tmp_path_factory.mktemp("run")
    summary, results = run_scenario(SCENARIOS / "crawler-ideal.toml", out, fmu_dir,
                                    stop_time=0.05, with_plot=False)
    return out, summary, results


def test_the_header_is_line_one_with_time_first(run):
    out, summary, results = run
    lines = (out / "results.csv").read_text().splitlines()
    assert lines[0] == ",".join(["time", *map(str, results.names)])
    assert "." in str(results.names[0])  # <instance>.<variable>
    assert len(lines) == 1 + len(results.time) and not any(ln.startswith("#") for ln in lines)
    assert json.loads((out / "summary.json").read_text())["run_id"] == summary["run_id"]


def test_pandas_reads_names_and_values(run):
    out, _, results = run
    frame = pandas.read_csv(out / "results.csv")
    assert list(frame.columns) == ["time", *map(str, results.names)]
    np.testing.assert_array_equal(frame["time"].to_numpy(), results.time)
    for name in results.names:
        np.testing.assert_array_equal(frame[str(name)].to_numpy(), results[name])


def test_numpy_reads_names_and_values(run):
    out, _, results = run
    data = np.genfromtxt(out / "results.csv", delimiter=",", names=True, deletechars="")
    assert data.dtype.names == ("time", *map(str, results.names))
    np.testing.assert_array_equal(data["time"], results.time)
    for name in results.names:
        np.testing.assert_array_equal(data[str(name)], results[name])


def test_the_csv_module_reads_names_and_values(run):
    out, _, results = run
    with open(out / "results.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["time", *map(str, results.names)]
    np.testing.assert_array_equal([float(r["time"]) for r in rows], results.time)
    for name in results.names:
        np.testing.assert_array_equal([float(r[str(name)]) for r in rows], results[name])


def test_fmpy_reads_it_as_a_cross_check_result(run):
    out, _, results = run
    traj = read_csv(out / "results.csv")
    assert traj.dtype.names == ("time", *map(str, results.names))
    np.testing.assert_array_equal(traj["time"], results.time)
    for name in results.names:
        np.testing.assert_array_equal(traj[str(name)], results[name])
