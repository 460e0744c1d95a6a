"""`musclesim table sma-position`: the study's position-control matrix (§position-control) as
tables.

Three tables, each cell one run of scenarios/sma-position-control.toml with ``--set`` overrides:

- ``constant-stress``: SP I-IV (rows) at each constant stress 105..145 MPa (columns);
- ``stress-aware``: SP I-IV (rows) under LP I-VI (columns), the stress-aware inverse;
- ``stress-ignored``: SP IV under LP I-VI (rows) with each single-surface inverse base
  105..145 MPa (columns).

A cell is the strain RMSE between the reference and the laser's strain (contraction / wire
length) and that RMSE as a percentage of the maximum reference strain. Runs go to Dask (the
case folders of ``musclesim.batch``: a local cluster or ``--scheduler``), one folder per case,
resumable; each table is written as CSV and Markdown with the mean and standard deviation of its
cells (a case that failed is a ``failed`` cell, counted in neither), and every case gets a figure
(reference vs measured strain, stress, temperature).
"""
from __future__ import annotations

import csv
import json
import math
from pathlib import Path
from typing import Any, Collection, Iterable, Sequence

import numpy as np

from musclesim.components.sma import profiles
from musclesim.cosim import Results, Scenario, Signal, envelope, replace_file, save_figure
from musclesim.errors import UserError

STRESSES = (105e6, 115e6, 125e6, 135e6, 145e6)  # Pa (§position-control)
SP = profiles.STRAIN_PROFILES
LP = profiles.LOADING_PROFILES


Case = tuple[str, str, str, list[str]]  # row, column, case id, its --set overrides
Cell = tuple[float, float]  # strain RMSE, % of the maximum reference strain


def cases() -> dict[str, list[Case]]:
    """{table: [(row, column, case id, overrides)]} of the study's matrix."""
    def mpa(s: float) -> str:
        return f"{s / 1e6:g} MPa"

    out: dict[str, list[Case]] = {"constant-stress": [], "stress-aware": [], "stress-ignored": []}
    for i, sp in enumerate(SP, 1):
        for s in STRESSES:
            out["constant-stress"].append((sp, mpa(s), f"const-{i}-{s / 1e6:g}", [
                f"strain.profile={i}.0", f"loading.lo={s!r}", f"loading.hi={s!r}"]))
        for j, lp in enumerate(LP, 1):
            out["stress-aware"].append((sp, lp, f"aware-{i}-{j}", [
                f"strain.profile={i}.0", f"loading.profile={j}.0"]))
    for j, lp in enumerate(LP, 1):
        for s in STRESSES:
            out["stress-ignored"].append((lp, mpa(s), f"ignored-{j}-{s / 1e6:g}", [
                "strain.profile=4.0", f"loading.profile={j}.0", f"inverse.sigma_surface={s!r}"]))
    return out


SIGNALS = ("strain.eps_ref", "laser.s_meas", "loading.sigma_ref", "wire.stress", "inverse.T_ref",
           "thermocouple.T_meas")  # what a cell and its figure read from a case's results.csv


def read_case(results_csv: str | Path, names: Sequence[str] = SIGNALS
              ) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """(time, {name: values}) of the columns `names` of a run's `results_csv` (the master's own
    output: a header, then plain numbers, so numpy's parser reads it; a missing column is the
    user's error)."""
    try:
        with open(results_csv, encoding="utf-8") as f:
            header = [h.strip() for h in f.readline().split(",")]
    except OSError as exc:
        raise UserError(f"{results_csv} cannot be read: {exc}") from None
    missing = [n for n in names if n not in header]
    if header[:1] != ["time"] or missing:
        raise UserError(f"{results_csv} has no column {', '.join(missing) or 'time'} "
                        f"(the scenario must record {', '.join(names)})")
    try:
        data = np.loadtxt(results_csv, delimiter=",", skiprows=1, ndmin=2,
                          usecols=[0] + [header.index(n) for n in names])
    except ValueError as exc:
        raise UserError(f"{results_csv} is not a run's results: {exc}") from None
    return data[:, 0], {n: data[:, j] for j, n in enumerate(names, 1)}


def wire_length(s: Scenario, fmu_dir: str | Path) -> float:
    """The length [m] of scenario `s`'s `wire`: its parameter if the scenario sets it, else the
    start value in the SmaWire FMU of `fmu_dir` (the laser's contraction over it is the measured
    strain)."""
    from musclesim.cosim import read_fmu

    inst = s.instances["wire"]
    if "length" in inst.parameters:
        return float(inst.parameters["length"])
    md = read_fmu(Path(fmu_dir) / f"{inst.component}.fmu")
    return float(next(v.start for v in md.modelVariables if v.name == "length"))


def strain_error(col: dict[str, np.ndarray], length: float) -> Cell:
    """(RMSE, % of the maximum reference strain) of a run's columns `col`; laser strain = s /
    `length`."""
    ref = col["strain.eps_ref"]
    err = ref - col["laser.s_meas"] / length
    rmse = float(np.sqrt(np.mean(err ** 2)))
    return rmse, 100.0 * rmse / float(np.max(ref)) if np.max(ref) > 0 else math.nan


def write_table(out: Path, name: str, rows: Sequence[str], columns: Sequence[str],
                cells: dict[tuple[str, str], Cell | None],
                failed: Collection[tuple[str, str]] = ()) -> dict[str, Any]:
    """Write `out`/<`name`>.csv and `out`/<`name`>.md, a table of `rows` by `columns`;
    `cells[(row, column)]` = (RMSE, %) or None (not run yet, or in `failed`: its case failed).
    Return the table's stats: its number of cells, the mean and std of the RMSE and of the %."""
    values = [v for v in cells.values() if v is not None]
    stats: dict[str, Any] = {"cells": len(values)}
    for k, label in ((0, "rmse"), (1, "percent")):
        xs = [v[k] for v in values]
        stats[label] = (float(np.mean(xs)), float(np.std(xs))) if xs else (math.nan, math.nan)

    def status(r: str, c: str) -> str:
        return "failed" if (r, c) in failed else "not run" if cells.get((r, c)) is None else "done"

    with open(out / f"{name}.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["row", "column", "strain_rmse", "percent_of_max_reference", "status"])
        for r in rows:
            for c in columns:
                v = cells.get((r, c))
                w.writerow([r, c, *(("", "") if v is None else (repr(v[0]), repr(v[1]))),
                            status(r, c)])
        for k, label in ((0, "mean"), (1, "std")):
            w.writerow([label, "", repr(stats["rmse"][k]), repr(stats["percent"][k]), ""])

    def text(r: str, c: str) -> str:
        v = cells.get((r, c))
        if (r, c) in failed or v is None:
            return "failed" if (r, c) in failed else "-"
        return f"{v[0] * 1e3:.3f} ({v[1]:.2f} %)"

    lines = [f"### {name}: strain RMSE [1e-3] (% of the maximum reference strain)", "",
             "| | " + " | ".join(columns) + " |", "|---" * (len(columns) + 1) + "|"]
    for r in rows:
        lines.append(f"| {r} | " + " | ".join(text(r, c) for c in columns) + " |")
    total = len(rows) * len(columns)
    lines += ["", f"Mean {stats['rmse'][0] * 1e3:.3f}e-3 (std {stats['rmse'][1] * 1e3:.3f}e-3); "
              f"{stats['percent'][0]:.2f} % (std {stats['percent'][1]:.2f} %) over "
              f"{len(values)} of {total} cells." if values else
              f"No cell finished yet (0 of {total}).", ""]
    if failed:
        lines[-1:-1] = [f"{len(failed)} failed: their errors are in summary.json in their case "
                        "folders."]
    replace_file(out / f"{name}.md", "\n".join(lines))
    return stats


def figure(path: Path, t: np.ndarray, col: dict[str, np.ndarray], length: float,
           title: str) -> None:
    """Write `path` (PNG), titled `title`: reference vs measured strain, stress, temperature of a
    run's columns `col` at times `t` (the laser's strain over the wire's `length`)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(9, 7))
    panels = [(("strain.eps_ref", 1, "reference"), ("laser.s_meas", 1 / length, "laser")),
              (("loading.sigma_ref", 1e-6, "reference"), ("wire.stress", 1e-6, "wire")),
              (("inverse.T_ref", 1, "inverse T_ref"), ("thermocouple.T_meas", 1, "thermocouple"))]
    for ax, panel, label in zip(axes, panels, ("strain [1]", "stress [MPa]", "temperature [K]")):
        for name, scale, legend in panel:
            ax.plot(*envelope(t, col[name] * scale, 4000), lw=0.8, label=legend)
        ax.set_ylabel(label, fontsize=8)
        ax.legend(fontsize=7, loc="upper right")
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    save_figure(fig, path, dpi=90)
    plt.close(fig)


def sma_position(out: str | Path, scenario_path: str | Path, fmu_dir: str | Path = "fmus",
                 stop_time: float | None = None, scheduler: str | None = None,
                 workers: int | None = None, only: Iterable[str] | None = None,
                 run: bool = True) -> dict[str, Any]:
    """Run the matrix of `scenario_path` on the FMUs of `fmu_dir` (or the tables named in
    `only`; with `run` False, none of their cases) and write the tables of the cases finished;
    return their stats, with ``failed`` ({case id: error}) for each table. `out` keeps the cases
    of one scenario file, stop time and build of the FMUs: another one is refused (its cells would
    not be comparable). `stop_time` overrides the scenario's; the cases run on the Dask cluster
    at `scheduler` or on a local one of `workers` workers."""
    from musclesim.batch import case_summary, claim, finished, run_cases
    from musclesim.cosim import check_fresh, load_scenario

    out, scenario_path = Path(out).resolve(), Path(scenario_path).resolve()
    s = load_scenario(scenario_path, (), stop_time)  # checked once, not in every case
    check_fresh(fmu_dir)
    length = wire_length(s, fmu_dir)
    claim(out, scenario_path, table="sma-position", stop_time=s.stop_time)
    matrix = {k: v for k, v in cases().items() if not only or k in only}
    titles = {cid: f"{name}: {r}, {c}" for name, rows in matrix.items() for r, c, cid, _ in rows}
    todo = [(cid, sets) for rows in matrix.values() for _, _, cid, sets in rows
            if finished(out / "cases" / cid) is None]
    fresh: dict[str, Cell] = {}  # the cells of the cases run here, from their results in memory

    def tabulate(cid: str, summary: dict[str, Any], results: Results | None) -> None:
        """A fresh case's cell and figure, drawn while the workers run the next cases."""
        if summary.get("completed") and results is not None:
            col = {n: results[Signal.parse(n)] for n in SIGNALS}
            fresh[cid] = strain_error(col, length)
            figure(out / "cases" / cid / "figure.png", results.time, col, length, titles[cid])

    if todo and run:
        run_cases(out, todo, s, fmu_dir, scheduler, workers, tabulate)
    report = {}
    for name, rows in matrix.items():
        cells: dict[tuple[str, str], Cell | None] = {}
        failed: dict[str, str] = {}
        failed_cells: set[tuple[str, str]] = set()
        for r, c, cid, _ in rows:
            case_dir = out / "cases" / cid
            if finished(case_dir) is None:
                cells[(r, c)] = None
                summary = case_summary(case_dir)
                if summary is not None:  # it ran, and failed
                    failed[cid] = summary.get("error") or "the case did not complete"
                    failed_cells.add((r, c))
                continue
            if cid in fresh:
                cells[(r, c)] = fresh[cid]
                continue
            time, col = read_case(case_dir / "results.csv")
            cells[(r, c)] = strain_error(col, length)
            figure(case_dir / "figure.png", time, col, length, titles[cid])
        row_names = list(dict.fromkeys(r for r, _, _, _ in rows))
        col_names = list(dict.fromkeys(c for _, c, _, _ in rows))
        report[name] = {**write_table(out, name, row_names, col_names, cells, failed_cells),
                        "failed": failed}
    replace_file(out / "tables.json", json.dumps(report, indent=2) + "\n")
    return report
