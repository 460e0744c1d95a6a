"""The FORC data file: one CSV row per grid value F(a, b; stress) of a Preisach hypersurface.

Format (UTF-8 text, '#' lines are comments)::

    # any comment lines
    stress_Pa,a_C,b_C,F
    105000000.0,30.0,30.0,0.0
    105000000.0,35.0,30.0,0.00012
    ...

One row for every grid pair a >= b (diagonal included, where F = 0) at every stress: 231 rows per
stress on the 21-point grid of §preisach. Stress in Pa, temperatures a (peak) and b (end of the
reversal) in degrees C, F the dimensionless strain increment of the first-order reversal curve.
Rows may come in any order; the temperature grid (uniform) and the stresses are read from the rows.
"""
from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

HEADER = ("stress_Pa", "a_C", "b_C", "F")
# physical bounds of each column: stress up to 10 GPa, temperatures from absolute zero to 1000 C,
# strain increments within +-100 % (the study's wire transforms by about 4 %, §forc-identification)
_RANGES = ((0.0, 1e10), (-273.15, 1000.0), (-273.15, 1000.0), (-1.0, 1.0))
_PREAMBLE = ("# musclesim FORC data set: F(a, b; stress) = strain increment of the first-order "
             "reversal curve heated from the lower saturation temperature to a, cooled to b "
             "(§preisach)",
             "# units: stress_Pa in Pa, a_C and b_C in degrees C, F dimensionless strain; "
             "one row per grid pair a >= b at every stress")


class TableError(ValueError):
    """Bad table entries; `entries` lists their (stress, a, b) positions in the table."""

    def __init__(self, message: str, entries: list[tuple[int, int, int]]) -> None:
        """The error's `message` and the `entries` at fault."""
        super().__init__(message)
        self.entries = entries


def write(path: str | Path, temps: Sequence[float] | np.ndarray,
          stresses: Sequence[float] | np.ndarray, table: np.ndarray,
          comments: Sequence[str] = ()) -> None:
    """Write to `path` the lower triangle (a >= b) of `table`[s, i, j] = F(`temps`[i],
    `temps`[j]; `stresses`[s]); `comments` (lines of text) follow the standard preamble as '#'
    lines."""
    with open(path, "w", newline="", encoding="utf-8") as fh:
        fh.write("\n".join([*_PREAMBLE, *(f"# {c}" for c in comments)]) + "\n")
        w = csv.writer(fh, lineterminator="\n")
        w.writerow(HEADER)
        for s, sigma in enumerate(stresses):
            for i, a in enumerate(temps):
                for j in range(i + 1):
                    w.writerow([repr(float(sigma)), repr(float(a)), repr(float(temps[j])),
                                repr(float(table[s, i, j]))])


def read(path: str | Path) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                    dict[tuple[int, int, int], int]]:
    """Read the FORC data file `path`.

    Returns
    -------
    temps, stresses, table, lines
        Grid temperatures [C], stresses [Pa], table[s, i, j] (NaN above the diagonal) and, for
        each (s, i, j), the line number it came from.

    Raises
    ------
    ValueError
        Naming the file and the line or grid entry at fault (not found, bad header, a row that is
        not four numbers, a row off the grid, a duplicate or a missing grid value).
    """
    rows = _rows(path)
    stresses = sorted({r[1] for r in rows})
    temps = sorted({r[2] for r in rows} | {r[3] for r in rows})
    table = np.full((len(stresses), len(temps), len(temps)), np.nan)
    lines: dict[tuple[int, int, int], int] = {}
    s_of, t_of = {v: k for k, v in enumerate(stresses)}, {v: k for k, v in enumerate(temps)}
    for line, sigma, a, b, value in rows:
        if b > a:
            raise ValueError(f"{path} line {line}: b = {b:g} C is above a = {a:g} C; "
                             "F is defined on the Preisach triangle a >= b only")
        key = (s_of[sigma], t_of[a], t_of[b])
        if key in lines:
            raise ValueError(f"{path} line {line}: duplicate of line {lines[key]} "
                             f"(stress {sigma:g} Pa, a = {a:g} C, b = {b:g} C)")
        lines[key] = line
        table[key] = value
    for s, sigma in enumerate(stresses):
        for i, a in enumerate(temps):
            for j in range(i + 1):
                if (s, i, j) not in lines:
                    raise ValueError(f"{path}: no row for stress {sigma:g} Pa, a = {a:g} C, "
                                     f"b = {temps[j]:g} C (every grid pair a >= b is needed)")
    return np.array(temps), np.array(stresses), table, lines


def _rows(path):
    """(line, stress, a, b, F) for every data row; the header must come first."""
    try:
        with open(path, newline="", encoding="utf-8") as fh:
            text = fh.read().splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot read the FORC data file ({exc})") from None
    rows, header_seen = [], False
    for line, fields in enumerate(csv.reader(text), start=1):
        if not fields or fields[0].lstrip().startswith("#"):
            continue
        if not header_seen:
            if tuple(f.strip() for f in fields) != HEADER:
                raise ValueError(f"{path} line {line}: expected the header "
                                 f"{','.join(HEADER)!r}, got {','.join(fields)!r}")
            header_seen = True
            continue
        rows.append((line, *_numbers(path, line, fields)))
    if not rows:
        raise ValueError(f"{path}: no data rows (expected the header {','.join(HEADER)!r} "
                         "then one row per grid value)")
    return rows


def _numbers(path, line, fields):
    """The four finite numbers of a data row; a bad one is named by its line and column."""
    if len(fields) != 4:
        raise ValueError(f"{path} line {line}: expected four numbers "
                         f"({','.join(HEADER)}), got {','.join(fields)!r}")
    values = []
    for name, text, (lo, hi) in zip(HEADER, fields, _RANGES):
        try:
            v = float(text)
        except ValueError:
            raise ValueError(f"{path} line {line}, column {name}: {text.strip()!r} is not a "
                             "number") from None
        if not math.isfinite(v):
            raise ValueError(f"{path} line {line}, column {name}: {text.strip()} is not a finite "
                             "number")
        if not lo <= v <= hi:
            raise ValueError(f"{path} line {line}, column {name}: {v:g} lies outside {lo:g} to "
                             f"{hi:g}, which no SMA wire's FORC data leaves")
        values.append(v)
    return values
