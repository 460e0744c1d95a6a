"""The Preisach hypersurface (components/sma/surface.py, §preisach): its interpolation, the checks
of its table and grid, and the FORC data file."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from musclesim.components.sma.analytic import sma_like_surface, uniform
from musclesim.components.sma.preisach import GRID_TEMPS, STRESSES, Hypersurface

C = 2e-5  # 1/C^2, density of the uniform surface: F(130, 30) = 0.1
# uniform density scaled by stress, five levels: F linear in stress is then exact
UNIFORM_5 = Hypersurface.from_function(lambda a, b, s: uniform(C)(a, b, s) * s / 125e6)
SMA = sma_like_surface()


def test_interpolation_bilinear_in_cells_linear_in_stress():
    h = UNIFORM_5
    corners = [h.F(a, b, 115e6) for a, b in ((80, 50), (85, 50), (80, 55), (85, 55))]
    assert h.F(82.5, 52.5, 115e6) == pytest.approx(sum(corners) / 4)
    assert h.F(82.5, 52.5, 110e6) == pytest.approx(
        (h.F(82.5, 52.5, 105e6) + h.F(82.5, 52.5, 115e6)) / 2)
    assert h.F(77.3, 77.3, 130e6) == 0.0 and h.F(60.0, 70.0, 130e6) == 0.0
    # diagonal half cells are linear and continuous with their neighbours
    assert h.F(72.5, 70.0, 125e6) == pytest.approx(h.F(75.0, 70.0, 125e6) / 2)


def _table_with(i, j, value, s=0):
    table = np.array(SMA.table)
    table[s, i, j] = value
    return table


@pytest.mark.parametrize("table, match", [
    pytest.param(_table_with(10, 4, -1.0), r"^F\(a = 80 C, b = 50 C; stress 1\.05e\+08 Pa\) = "
                 r"-1\.0 is negative$", id="negative"),
    pytest.param(_table_with(10, 4, 0.0, s=2), r"F must not decrease in a: F\(a = 80 C, b = 50 C; "
                 r"stress 1\.25e\+08 Pa\) = 0\.0 is below F\(a = 75 C, b = 50 C",
                 id="decreasing-in-a"),
    pytest.param(_table_with(10, 4, 1.0), r"F must not increase in b: F\(a = 80 C, b = 45 C.* is "
                 r"below F\(a = 80 C, b = 50 C; stress 1\.05e\+08 Pa\) = 1\.0$", id="bump"),
    pytest.param(_table_with(7, 7, 1e-3), r"a = 65 C, b = 65 C.*diagonal", id="diagonal"),
    pytest.param(_table_with(3, 1, math.nan), r"a = 45 C, b = 35 C.*not finite", id="nan"),
    pytest.param(np.zeros((5, 21, 20)), r"shape \(5, 21, 21\)", id="shape"),
])
def test_invalid_tables_name_the_entry(table, match):
    with pytest.raises(ValueError, match=match):
        Hypersurface(GRID_TEMPS, STRESSES, table)


@settings(max_examples=200)
@given(st.integers(0, 4), st.integers(0, 20), st.integers(0, 20),
       st.sampled_from([-1.0, -1e-11, 0.0, 1e-11, 1e-3, 0.05, 1.0, math.nan, math.inf]))
def test_vectorised_table_check_agrees_with_the_entry_by_entry_check(s, i, j, value):
    from musclesim.components.sma.surface import _check_table, _table_is_valid

    table = _table_with(max(i, j), min(i, j), value, s=s)
    try:
        _check_table(np.array(GRID_TEMPS), np.array(STRESSES), table)
    except ValueError:
        assert not _table_is_valid(table)
    else:
        assert _table_is_valid(table)


def test_grid_is_checked():
    with pytest.raises(ValueError, match="uniform"):
        Hypersurface([30, 40, 45], [1e8], np.zeros((1, 3, 3)))
    with pytest.raises(ValueError, match="increasing"):
        Hypersurface([30, 40, 50], [2e8, 1e8], np.zeros((2, 3, 3)))


def test_file_round_trip(tmp_path):
    path = tmp_path / "forc.csv"
    SMA.save(path)
    back = Hypersurface.load(path)
    assert np.array_equal(back.table, SMA.table)
    assert np.array_equal(back.temps, SMA.temps) and np.array_equal(back.stresses, SMA.stresses)
    assert path.read_text().count("\n") == 2 + 1 + 5 * 231


def _edit(path, line, text):
    lines = path.read_text().splitlines()
    lines[line - 1] = text
    path.write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("line, text, match", [
    pytest.param(3, "stress,a,b,F", "line 3: expected the header", id="header"),
    pytest.param(10, "105000000.0,60.0,x,0.1", "line 10, column b_C: 'x' is not a number",
                 id="not-a-number"),
    pytest.param(10, "105000000.0,60.0,0.1", "line 10: expected four numbers", id="three-fields"),
    pytest.param(10, "105000000.0,60.0,70.0,0.1", "line 10: b = 70 C is above a = 60 C",
                 id="outside-triangle"),
    pytest.param(10, "105000000.0,30.0,30.0,0.0", "line 10: duplicate of line 4", id="duplicate"),
    pytest.param(10, "105000000.0,45.0,30.0,inf", "line 10, column F: inf is not a finite number",
                 id="infinite"),
    pytest.param(10, "105000000.0,45.0,30.0,nan", "line 10, column F: nan is not a finite number",
                 id="nan"),
    pytest.param(10, "105000000.0,nan,30.0,0.1", "line 10, column a_C: nan is not a finite number",
                 id="nan-temperature"),
    pytest.param(40, "105000000.0,70.0,30.0,-0.5", r"line 40: F\(a = 70 C, b = 30 C; stress "
                 r"1\.05e\+08 Pa\) = -0\.5 is negative", id="negative"),
    pytest.param(40, "105000000.0,70.0,30.0,0.01", r"lines 40 and 49: F must not decrease in a: "
                 r"F\(a = 75 C, b = 30 C.* is below F\(a = 70 C, b = 30 C; stress 1\.05e\+08 Pa\) "
                 r"= 0\.01$", id="non-monotonic"),
])
def test_bad_file_gives_one_error_naming_file_and_line(tmp_path, line, text, match):
    path = tmp_path / "forc.csv"
    SMA.save(path)
    _edit(path, line, text)
    with pytest.raises(ValueError, match=f"forc.csv {match}"):
        Hypersurface.load(path)


def test_missing_row_and_missing_file(tmp_path):
    path = tmp_path / "forc.csv"
    SMA.save(path)
    lines = path.read_text().splitlines()
    path.write_text("\n".join(lines[:50] + lines[51:]) + "\n")
    with pytest.raises(ValueError, match=r"forc.csv: no row for stress 1\.05e\+08 Pa"):
        Hypersurface.load(path)
    with pytest.raises(ValueError, match="nope.csv: cannot read"):
        Hypersurface.load(tmp_path / "nope.csv")
