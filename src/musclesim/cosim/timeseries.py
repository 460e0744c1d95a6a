"""Reading time-series CSV files in the format of results.csv, with every problem located.

The format: a header ``time,<instance>.<variable>,...`` and one row per sample of comma-separated
numbers; time increases strictly and every value is finite and at most `MAX_MAGNITUDE` in size.
Lines starting with ``#`` before the header are comments, skipped (a run's results.csv has none:
its header is its first line).
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from musclesim.cosim.address import Signal

MAX_MAGNITUDE = 1e12  # SI values beyond this are a unit or file error, not a bench's quantity


def read_time_series(path: str | Path, problems: list[str], where: str | None = None
                     ) -> tuple[list[str], np.ndarray | None, np.ndarray | None] | None:
    """(header, time, data) of the results.csv-format file at `path`, or None when it is
    unusable.

    Every problem found is appended to `problems` as a sentence naming `where` (default: the
    file name), the line and the column; per-row problems are counted per column, not repeated.
    """
    where = where or Path(path).name
    try:
        with open(path, newline="", encoding="utf-8-sig") as f:
            reader = csv.reader(f)
            header = next(reader, None)
            while header and header[0].startswith("#"):
                header = next(reader, None)
            if header is None:
                problems.append(f"{where} is empty")
                return None
            header = [h.strip() for h in header]
            before = len(problems)
            _check_header(header, where, problems)
            rows: list[tuple[int, list[float]]] = []
            bad_fields: dict[str, list[tuple[int, int]]] = {}
            bad_values: dict[int, list[tuple[int, str]]] = {}
            n = len(header)
            for row in reader:
                line = reader.line_num
                if not row or all(not x.strip() for x in row):
                    continue
                if len(row) != n:
                    bad_fields.setdefault("count", []).append((line, len(row)))
                    continue
                values = []
                for j, text in enumerate(row):
                    try:
                        values.append(float(text))
                    except ValueError:
                        bad_values.setdefault(j, []).append((line, text.strip()))
                        values.append(math.nan)
                rows.append((line, values))
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        problems.append(f"{where} cannot be read: {exc}")
        return None
    for line, count in bad_fields.get("count", [])[:1]:
        k = len(bad_fields["count"])
        problems.append(f"{where} line {line}: {count} fields where the header has {n}"
                        + (f" ({k} such lines)" if k > 1 else ""))
    for j, hits in bad_values.items():
        line, text = hits[0]
        problems.append(f"{where} line {line}, column {header[j]!r}: {text!r} is not a number"
                        + (f" ({len(hits)} such values in the column)" if len(hits) > 1 else ""))
    if not rows:
        problems.append(f"{where} has no data rows")
        return None
    lines = np.array([r[0] for r in rows])
    array = np.array([r[1] for r in rows], dtype=float)
    not_number = {j for j in bad_values}
    for j, name in enumerate(header):
        bad = ~np.isfinite(array[:, j])
        if j in not_number:
            bad &= ~np.isin(lines, [ln for ln, _ in bad_values[j]])
        if bad.any():
            first = int(np.argmax(bad))
            problems.append(f"{where} line {lines[first]}, column {name!r}: "
                            f"{float(array[first, j])!r} is not finite"
                            + (f" ({int(bad.sum())} NaN/inf values in the column)"
                               if bad.sum() > 1 else ""))
        col = array[:, j]
        huge = np.isfinite(col) & (np.abs(col) > MAX_MAGNITUDE)
        if huge.any():
            first = int(np.argmax(huge))
            problems.append(f"{where} line {lines[first]}, column {name!r}: "
                            f"{float(array[first, j]):g} is larger than {MAX_MAGNITUDE:g} in size, "
                            "no quantity of these benches in SI units"
                            + (f" ({int(huge.sum())} such values)" if huge.sum() > 1 else ""))
    if header and header[0] == "time":
        t = array[:, 0]
        dt = np.diff(t)
        for kind, mask in (("repeats", dt == 0), ("decreases", dt < 0)):
            if mask.any():
                i = int(np.argmax(mask)) + 1
                problems.append(f"{where} line {lines[i]}: time {kind} ({float(t[i - 1])!r} "
                                f"then {float(t[i])!r} s)"
                                + (f", {int(mask.sum())} times in all" if mask.sum() > 1 else ""))
        if len(t) < 2:
            problems.append(f"{where} needs at least two samples")
    if len(problems) > before:
        return header, None, None
    return header, array[:, 0], array[:, 1:]


def _check_header(header: list[str], where: str, problems: list[str]) -> None:
    if not header or header[0] != "time":
        problems.append(f"{where} line 1: the first column must be 'time' "
                        f"(got {header[0] if header else ''!r})")
    seen = set()
    for j, name in enumerate(header[1:], start=2):
        try:
            Signal.parse(name)
        except ValueError:
            problems.append(f"{where} line 1, column {j}: {name!r} is not of the form "
                            "instance.variable")
        if name in seen or name == "time":
            problems.append(f"{where} line 1, column {j}: {name!r} appears twice")
        seen.add(name)
