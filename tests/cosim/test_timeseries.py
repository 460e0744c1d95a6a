"""musclesim.cosim.timeseries: a results.csv-format file read, every problem located by line and
column, a column name checked as a signal."""
import numpy as np

from musclesim.cosim import read_time_series


def read(tmp_path, text):
    path = tmp_path / "data.csv"
    path.write_text(text)
    problems = []
    return read_time_series(path, problems, where="data.csv"), problems


def test_a_good_file_gives_header_time_and_data(tmp_path):
    (header, time, data), problems = read(tmp_path, "# a comment\ntime,a.y,b.flange.s\n"
                                                    "0,1,2\n0.5,3,4\n")
    assert problems == [] and header == ["time", "a.y", "b.flange.s"]
    assert np.array_equal(time, [0.0, 0.5]) and np.array_equal(data, [[1.0, 2.0], [3.0, 4.0]])


def test_every_problem_is_located(tmp_path):
    result, problems = read(tmp_path, "t,y,a.y,a.y\n0,1,2,3\n0,x,2,3\n1,2,3\n")
    header, time, data = result
    assert time is None and data is None
    assert "data.csv line 1: the first column must be 'time' (got 't')" in problems
    assert "data.csv line 1, column 2: 'y' is not of the form instance.variable" in problems
    assert "data.csv line 1, column 4: 'a.y' appears twice" in problems
    assert "data.csv line 4: 3 fields where the header has 4" in problems
    assert "data.csv line 3, column 'y': 'x' is not a number" in problems


def test_time_must_increase_and_an_empty_file_is_named(tmp_path):
    _, problems = read(tmp_path, "time,a.y\n0,1\n0,2\n-1,3\n")
    assert any("time repeats (0.0 then 0.0 s)" in p for p in problems)
    assert any("time decreases (0.0 then -1.0 s)" in p for p in problems)
    assert read(tmp_path, "")[0] is None and read(tmp_path, "")[1] == ["data.csv is empty"]
