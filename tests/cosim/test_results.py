"""musclesim.cosim.results: the metric ops; results.csv is a plain CSV that the usual readers take
as it is (the FMI cross-check rules for result files: the names on line 1, time first, no comment
line); a run's files always belong to one run, a failed one too."""
import csv
import json
import math

import numpy as np
import pandas
import pytest
from fmpy.util import read_csv

from musclesim.cosim import Instance, Metric, Results, Scenario, Signal, compute_metrics, run_scenario
from musclesim.cosim.results import RunWriter, metric_unit

from conftest import SCENARIOS

S = Signal.parse


def _results(t, **signals):
    return Results(time=t, names=tuple(Signal("s", n) for n in signals),
                   data=np.column_stack(list(signals.values())))


def test_frequency_cycle_peak_to_peak_and_ratio_ops():
    t = np.arange(3001) * 1e-3  # 0..3 s
    y = np.sin(2 * math.pi * 2.0 * t)  # 2 Hz
    pulses = (np.mod(t, 0.5) < 0.1) * (1.0 + t)  # 0 or 1 + t: peak-to-peak 1.099 + its start
    res = _results(t, y=y, half=0.5 * y, pulses=pulses)
    y, half, pulses = S("s.y"), S("s.half"), S("s.pulses")
    out = compute_metrics(res, {
        "f": Metric(y, "frequency"),
        "ratio": Metric(y, "peak_to_peak", over=half),
        "cycles": Metric(pulses, "cycle_peak_to_peak", period=0.5, start=1.0),
        "flat": Metric(half, "frequency", start=2.9999),
        "no_ratio": Metric(y, "peak_to_peak", over=half, start=2.9999),  # one sample: ptp 0
    })
    assert out["f"] == pytest.approx(2.0, rel=1e-6)
    assert out["ratio"] == pytest.approx(2.0, rel=1e-12)
    # whole periods from 1.0 s: 1.0-1.5 ... 2.5-3.0 (4), the sample at 3.0 s starts a fifth
    assert out["cycles"] == pytest.approx(np.mean([2.099, 2.599, 3.099, 3.599]), rel=1e-9)
    assert math.isnan(out["flat"])  # no crossing in its window
    assert math.isnan(out["no_ratio"])  # over a signal whose op is 0


def test_a_metric_unit_follows_its_op():
    assert metric_unit("m", "rate") == "m/s" and metric_unit(None, "mean") == "1"
    assert metric_unit("K", "frequency") == "Hz" and metric_unit("m", "max", ratio=True) == "1"


def test_a_metric_of_a_controllers_error_is_in_its_measurements_unit(fmu_dir, tmp_path):
    """sma-bench-tracking: reference.y -> pid.u_s, thermocouple.T_meas [K] -> pid.u_m,
    pid.y -> wire.u (a voltage or a current, by the wire's drive_current: "1"). The PID's
    outputs are of unit "1" in its FMU; the wiring gives its error (``same_unit_as`` u_m) the
    kelvin of the measurement and the source the kelvin of the reference it feeds; its output
    and a strain stay "1"."""
    from musclesim.cosim import Master, load_scenario, signal_units

    s = load_scenario(SCENARIOS / "sma-bench-tracking.toml")
    m = Master(s, fmu_dir)
    units = signal_units(m)
    assert (units[S("pid.e")], units[S("pid.y")], units[S("reference.y")],
            units[S("thermocouple.T_meas")], units[S("wire.strain")]) == ("K", "1", "K", "K", "1")
    t = np.arange(3) * 20.0
    writer = RunWriter(tmp_path, s, m.columns, units, with_plot=False)
    writer.start()
    summary = writer.finish(Results(t, tuple(m.columns), np.ones((3, len(m.columns)))))
    assert summary["units"] == {"tracking_rms": "K", "strain_peak_to_peak": "1"}
    assert json.loads((tmp_path / "summary.json").read_text())["units"]["tracking_rms"] == "K"


def test_results_are_indexed_by_signal():
    res = _results(np.arange(3.0), y=np.array([1.0, 2.0, 3.0]), z=np.zeros(3))
    assert list(res[S("s.y")]) == [1.0, 2.0, 3.0]
    with pytest.raises(ValueError):
        res[S("s.w")]


def _tiny(tmp_path):
    return Scenario("tiny", tmp_path / "tiny.toml", {"a": Instance("a", "C")}, (), step=0.1,
                    stop_time=1.0, record=(S("a.y"),))


def test_a_failed_run_leaves_no_earlier_runs_results_csv(tmp_path):
    """The earlier run's results.csv and plot go as the new run starts; a run that fails after
    a row ends with its own partial results.csv (one row), never the earlier one's three."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "results.csv").write_text("time,a.y\n0,1\n0.1,2\n0.2,3\n")
    (out / "results.png").write_bytes(b"an earlier plot")
    (out / "summary.json").write_text('{"completed": true}\n')
    writer = RunWriter(out, _tiny(tmp_path), [S("a.y")], {S("a.y"): "m"}, with_plot=False)
    writer.start()
    assert sorted(p.name for p in out.iterdir()) == ["results.csv.part", "summary.json"]
    assert json.loads((out / "summary.json").read_text())["status"] == "running"
    time, data = np.array([0.0]), np.array([[5.0]])
    writer.rows(time, data)
    summary = writer.finish(Results(time, (S("a.y"),), data, error="instance 'a' failed"))
    assert sorted(p.name for p in out.iterdir()) == ["results.csv", "summary.json"]
    assert (out / "results.csv").read_text() == "time,a.y\n0,5\n"
    assert summary["completed"] is False and summary["error"] == "instance 'a' failed"
    assert json.loads((out / "summary.json").read_text())["run_id"] == summary["run_id"]


def test_a_layer_above_adds_summary_entries_but_never_over_the_runs_own(tmp_path):
    """`extra` entries (the predictions the cli gives) reach the final summary; one named like
    a metric or the run's state is refused."""
    time, data = np.array([0.0]), np.array([[5.0]])
    writer = RunWriter(tmp_path, _tiny(tmp_path), [S("a.y")], {S("a.y"): "m"}, with_plot=False)
    writer.start()
    writer.rows(time, data)
    summary = writer.finish(Results(time, (S("a.y"),), data), {"predictions": {"applies": False}})
    assert json.loads((tmp_path / "summary.json").read_text())["predictions"] == {
        "applies": False} == summary["predictions"]
    for key in ("status", "warnings"):
        with pytest.raises(ValueError, match=key):
            writer.finish(Results(time, (S("a.y"),), data), {key: 1})


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
