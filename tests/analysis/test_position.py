"""musclesim.analysis.position: SMA position control (issue 5, §position-control): short runs of
each kind of the study's matrix and the tables' computation. (The stress loop's design:
tests/analysis/test_linear_sma_load.py.)"""
import math

import numpy as np
import pytest

from musclesim.analysis import position as table
from musclesim.batch import run_case, write_case
from musclesim.cosim import Master, Signal, load_scenario
from musclesim.errors import UserError

from conftest import SCENARIOS

POSITION = SCENARIOS / "sma-position-control.toml"


def run(fmu_dir, sets, stop_time=3.0):
    s = load_scenario(POSITION, sets, stop_time)
    res = Master(s, fmu_dir).run()
    assert res.error is None, res.error
    return res


@pytest.mark.parametrize("kind", ["constant-stress", "stress-aware", "stress-ignored"])
def test_each_kind_of_the_matrix_runs_and_tracks(fmu_dir, kind):
    res = run(fmu_dir, table.cases()[kind][0][3])  # the first cell of its table
    settled = res.time >= 0.5  # after the stress loop's start from the weight alone
    stress_error = (res[Signal("wire", "stress")][settled]
                    - res[Signal("loading", "sigma_ref")][settled])
    assert np.max(np.abs(stress_error)) < 1e6  # Pa: the stress loop holds within 1 MPa
    temperature_error = res[Signal("thermocouple", "T_meas")] - res[Signal("inverse", "T_ref")]
    assert np.sqrt(np.mean(temperature_error[settled] ** 2)) < 2.0  # K
    # the wire moves
    assert np.max(res[Signal("wire", "strain")]) > 0.5 * np.max(res[Signal("strain", "eps_ref")])


def test_the_tables_strain_is_the_lasers_contraction_over_the_wires_length(fmu_dir):
    s = load_scenario(POSITION, (), 2.0)
    length = table.wire_length(s, fmu_dir)
    assert length == 58.42e-3  # the SmaWire's own (§thermal-model)
    res = Master(s, fmu_dir).run()
    laser_strain = res[Signal("laser", "s_meas")] / length  # laser effects off
    assert np.max(res[Signal("wire", "strain")]) > 0.004
    np.testing.assert_allclose(laser_strain, res[Signal("wire", "strain")], rtol=0, atol=1e-12)
    longer = load_scenario(POSITION, ["wire.length=0.2"], 2.0)
    assert table.wire_length(longer, fmu_dir) == 0.2


def test_stress_ignored_inverse_does_not_follow_the_stress(fmu_dir):
    sets = ["strain.profile=1.0", "loading.profile=1.0"]
    aware = run(fmu_dir, sets, 2.0)
    ignored = run(fmu_dir, sets + ["inverse.sigma_surface=125e6"], 2.0)
    T_ref = Signal("inverse", "T_ref")
    assert not np.array_equal(aware[T_ref], ignored[T_ref])


def test_table_of_a_fixed_small_run(tmp_path):
    t = np.linspace(0.0, 1.0, 5)
    ref = np.array([0.0, 0.01, 0.02, 0.03, 0.04])
    laser = (ref + np.array([0.0, 0.001, -0.001, 0.002, 0.0])) * 0.1  # s = strain x 0.1 m
    csv = tmp_path / "results.csv"
    np.savetxt(csv, np.column_stack([t, ref, laser]), delimiter=",",
               header="time,strain.eps_ref,laser.s_meas", comments="")
    time, col = table.read_case(csv, ("strain.eps_ref", "laser.s_meas"))
    np.testing.assert_array_equal(time, t)
    np.testing.assert_array_equal(col["laser.s_meas"], laser)
    rmse, percent = table.strain_error(col, 0.1)
    assert rmse == pytest.approx(math.sqrt((1 + 1 + 4) / 5) * 1e-3)
    assert percent == pytest.approx(100 * rmse / 0.04)
    cells = {("SP I", "105 MPa"): (1e-3, 2.0), ("SP I", "115 MPa"): (3e-3, 4.0),
             ("SP II", "105 MPa"): None, ("SP II", "115 MPa"): (2e-3, 6.0)}
    stats = table.write_table(tmp_path, "t", ["SP I", "SP II"], ["105 MPa", "115 MPa"], cells)
    assert stats["cells"] == 3 and stats["rmse"][0] == pytest.approx(2e-3)
    assert stats["percent"] == pytest.approx((4.0, math.sqrt(8 / 3)))
    md = (tmp_path / "t.md").read_text()
    assert "| SP II | - | 2.000 (6.00 %) |" in md and "over 3 of 4 cells" in md
    rows = (tmp_path / "t.csv").read_text().splitlines()
    assert len(rows) == 1 + 4 + 2 and rows[-2] == f"mean,,{2e-3!r},{4.0!r},"
    assert rows[1] == f"SP I,105 MPa,{1e-3!r},{2.0!r},done" and rows[3] == "SP II,105 MPa,,,not run"
    table.write_table(tmp_path, "empty", ["SP I"], ["105 MPa"], {("SP I", "105 MPa"): None})
    assert "No cell finished yet (0 of 1)." in (tmp_path / "empty.md").read_text()


def test_the_matrix_is_the_studys():
    c = table.cases()
    assert [len(c[k]) for k in ("constant-stress", "stress-aware", "stress-ignored")] == \
        [20, 24, 30]
    assert all("strain.profile=4.0" in sets for *_, sets in c["stress-ignored"])


def test_a_case_without_the_tables_columns_is_named(tmp_path):
    csv = tmp_path / "results.csv"
    csv.write_text("time,strain.eps_ref\n0,0\n")
    with pytest.raises(UserError, match=r"results.csv has no column laser.s_meas"):
        table.read_case(csv, ("strain.eps_ref", "laser.s_meas"))


def test_tables_are_written_from_the_finished_cases(tmp_path, fmu_dir):
    out = tmp_path / "matrix"
    first, second, third = table.cases()["stress-ignored"][:3]
    s = load_scenario(POSITION, (), 0.4)
    for r, c, cid, sets in (first, second):
        summary = write_case(out / "cases" / cid, run_case(s, fmu_dir, sets))
        assert summary["completed"] is True
    # a case that fails (no SP IX) is reported as failed, not as a case still to run
    summary = write_case(out / "cases" / third[2],
                         run_case(s, fmu_dir, [*third[3], "strain.profile=9.0"]))
    assert summary["completed"] is False
    report = table.sma_position(out, POSITION, fmu_dir, 0.4, only=["stress-ignored"], run=False)
    _, col = table.read_case(out / "cases" / first[2] / "results.csv")
    rmse = np.sqrt(np.mean((col["strain.eps_ref"] - col["laser.s_meas"] / 58.42e-3) ** 2))
    md = (out / "stress-ignored.md").read_text()
    assert f"| {first[0]} | {rmse * 1e3:.3f} (" in md and "over 2 of 30 cells" in md
    assert f"| {third[0]} | " in md and "| failed |" in md and "1 failed" in md
    assert report["stress-ignored"]["rmse"][0] > 0
    assert list(report["stress-ignored"]["failed"]) == [third[2]]
    assert "profile must be one of 1..4" in report["stress-ignored"]["failed"][third[2]]
    assert all((out / "cases" / cid / "figure.png").stat().st_size > 10_000
               for _, _, cid, _ in (first, second))
    assert not (out / "constant-stress.md").exists()
    # the folder keeps the cases of one stop time: a table of other runs is refused
    with pytest.raises(UserError, match="other settings \\(stop_time\\)"):
        table.sma_position(out, POSITION, fmu_dir, 0.8, only=["stress-ignored"], run=False)


def test_the_tables_of_cases_run_here_equal_the_tables_read_back_from_their_files(
        tmp_path, fmu_dir, monkeypatch):
    out = tmp_path / "matrix"
    matrix = table.cases()
    monkeypatch.setattr(table, "cases", lambda: {"constant-stress": matrix["constant-stress"][:3]})
    read_case, reads = table.read_case, []
    monkeypatch.setattr(table, "read_case", lambda *a: reads.append(a) or read_case(*a))
    fresh = table.sma_position(out, POSITION, fmu_dir, 0.2, workers=1, only=["constant-stress"])
    assert reads == []  # the cells and figures came from the results in memory
    figures = {p: p.read_bytes() for p in out.glob("cases/*/figure.png")}
    tables = {p: p.read_bytes() for p in out.glob("constant-stress.*")}
    assert len(figures) == 3 and fresh["constant-stress"]["cells"] == 3
    read = table.sma_position(out, POSITION, fmu_dir, 0.2, only=["constant-stress"], run=False)
    assert read == fresh and len(reads) == 3
    assert {p: p.read_bytes() for p in out.glob("constant-stress.*")} == tables
    assert {p: p.read_bytes() for p in out.glob("cases/*/figure.png")} == figures
