"""The FORC data file (components/sma/forcfile.py): a written table reads back bit for bit, rows in
any order; every bad file is refused naming its line or grid entry."""
import numpy as np
import pytest

from musclesim.components.sma import forcfile

TEMPS = [30.0, 80.0, 130.0]
STRESSES = [105e6, 145e6]


def _table():
    table = np.full((2, 3, 3), np.nan)
    for s in range(2):
        for i in range(3):
            for j in range(i + 1):
                table[s, i, j] = 0.001 * (s + 1) * (TEMPS[i] - TEMPS[j]) / 100 + 1e-17 * i
    return table


def test_write_then_read_is_the_table_bit_for_bit(tmp_path):
    path = tmp_path / "set.csv"
    forcfile.write(path, TEMPS, STRESSES, _table(), comments=["made by hand"])
    text = path.read_text().splitlines()
    assert text[0].startswith("# musclesim FORC data set") and "# made by hand" in text
    assert sum(1 for line in text if not line.startswith("#")) == 1 + 2 * 6  # header, a >= b rows
    temps, stresses, table, lines = forcfile.read(path)
    assert temps.tolist() == TEMPS and stresses.tolist() == STRESSES
    assert np.array_equal(table, _table(), equal_nan=True)
    assert len(lines) == 12 and lines[(0, 0, 0)] == text.index("105000000.0,30.0,30.0,0.0") + 1


def test_rows_in_any_order_read_the_same(tmp_path):
    path = tmp_path / "set.csv"
    forcfile.write(path, TEMPS, STRESSES, _table())
    head, *rows = [ln for ln in path.read_text().splitlines() if not ln.startswith("#")]
    (tmp_path / "shuffled.csv").write_text("\n".join([head, *reversed(rows)]) + "\n")
    assert np.array_equal(forcfile.read(tmp_path / "shuffled.csv")[2], _table(), equal_nan=True)


@pytest.mark.parametrize("rows, match", [
    (["a,b,c,d"], "line 1: expected the header"),
    ([",".join(forcfile.HEADER)], "no data rows"),
    ([",".join(forcfile.HEADER), "1e8,30,30"], "line 2: expected four numbers"),
    ([",".join(forcfile.HEADER), "1e8,30,x,0"], "line 2, column b_C: 'x' is not a number"),
    ([",".join(forcfile.HEADER), "1e8,30,30,nan"], "column F: nan is not a finite"),
    ([",".join(forcfile.HEADER), "1e8,30,30,2"], "column F: 2 lies outside"),
    ([",".join(forcfile.HEADER), "1e8,30,40,0"], "line 2: b = 40 C is above a = 30 C"),
    ([",".join(forcfile.HEADER), "1e8,30,30,0", "1e8,30,30,0"], "line 3: duplicate of line 2"),
    ([",".join(forcfile.HEADER), "1e8,30,30,0", "1e8,40,40,0"], "no row for stress 1e\\+08 Pa, "
                                                                "a = 40 C, b = 30 C"),
], ids=["header", "empty", "short", "text", "nan", "range", "above", "duplicate", "missing"])
def test_a_bad_file_is_refused_naming_the_line(tmp_path, rows, match):
    path = tmp_path / "bad.csv"
    path.write_text("\n".join(rows) + "\n")
    with pytest.raises(ValueError, match=match):
        forcfile.read(path)
    with pytest.raises(ValueError, match="cannot read the FORC data file"):
        forcfile.read(tmp_path / "none.csv")
