"""`musclesim sweep`: run a scenario over a parameter grid on Dask, resumable, with a plot.

A sweep file (`load`) names a scenario, its grid axes (`parse_axis`) and the plot; `run` checks
the scenario once, runs every case of the grid (`grid_cases`) not finished yet in its case folder
(`musclesim.batch.cases`), and writes sweep.csv and sweep.png.
"""
from __future__ import annotations

import csv
import itertools
import math
import time
import tomllib
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from musclesim.batch.cases import claim, finished, run_cases
from musclesim.cosim import ParamRef, Scenario, save_figure
from musclesim.errors import UserError

_SWEEP_KEYS = {"scenario", "grid", "description", "plot"}
_PLOT_KEYS = {"kind", "x", "y", "metrics"}


@dataclass(frozen=True)
class Sweep:
    """A sweep: the `scenario` file, the grid `axes` ``{"inst.param": values}`` (the sweep
    file's spelling, which names the cases and sweep.csv's columns), the `plot` to draw and its
    `title`."""

    scenario: Path
    axes: dict[str, tuple[float, ...]]
    plot: dict[str, Any] = field(default_factory=dict)  # {"kind", "x", "y", "metrics"}
    title: str = ""


def _number(token: str, axis: str, where: str) -> float:
    """A finite float from `token`; angles may be written ``pi``, ``2pi`` or ``2*pi``."""
    text = token.strip()
    try:
        if text.endswith("pi"):
            coef = text[:-2].rstrip("*").strip()
            value = float(coef + "1" if coef in ("", "+", "-") else coef) * math.pi
        else:
            value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise UserError(f"{where}: grid axis {axis!r} has {text!r}, which is not a finite number")
    return value


def parse_axis(text: str, where: str = "--grid") -> tuple[str, tuple[float, ...]]:
    """Parse one grid axis.

    Parameters
    ----------
    text : str
        ``"inst.param=start:stop:n"`` (n >= 2 evenly spaced points, both ends included) or
        ``"inst.param=a,b,c"``; numbers may be written as multiples of ``pi``.
    where : str
        Where the axis comes from, for error messages.

    Returns
    -------
    tuple
        ``("inst.param", values)``, values rounded to 12 significant digits (stable case ids).

    Raises
    ------
    UserError
        If the axis is malformed.

    Examples
    --------
    >>> parse_axis("inputs.f_f=0:1:3")
    ('inputs.f_f', (0.0, 0.5, 1.0))
    """
    name, sep, spec = text.partition("=")
    name = name.strip()
    try:
        ParamRef.parse(name)
    except ValueError:
        sep = ""
    if not sep or not spec.strip():
        raise UserError(f"{where}: grid axis {text!r} is not of the form inst.param=start:stop:n "
                        "or inst.param=a,b,c")
    if ":" in spec:
        parts = spec.split(":")
        count = parts[-1].strip()
        if len(parts) != 3 or not count.isdigit() or int(count) < 2:
            raise UserError(f"{where}: grid axis {text!r} needs start:stop:n with an integer "
                            "n >= 2")
        values: Iterable[float] = np.linspace(_number(parts[0], name, where),
                                              _number(parts[1], name, where), int(count))
    else:
        values = [_number(p, name, where) for p in spec.split(",")]
    return name, tuple(dict.fromkeys(float(f"{v:.12g}") for v in values))


def _axes(texts: Iterable[str], where: str) -> dict[str, tuple[float, ...]]:
    axes = {}
    for text in texts:
        name, values = parse_axis(text, where)
        if name in axes:
            raise UserError(f"{where}: grid axis {name!r} is given twice")
        axes[name] = values
    return axes


def load(path: str | Path, grid: Iterable[str] = ()) -> Sweep:
    """Read a sweep file (a TOML file with a ``[sweep]`` table) or take `path` as a scenario.

    Parameters
    ----------
    path : str or Path
        Sweep file (``scenario`` relative to it, ``grid``, ``description``, ``plot``) or scenario.
    grid : sequence of str
        Axes (``--grid``) added to the file's; an axis of the same parameter replaces the file's.

    Returns
    -------
    Sweep

    Raises
    ------
    UserError
        For a malformed sweep table or axis, or when there is no axis at all.
    """
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        data = {}  # not a sweep file: scenario.load reports what is wrong with it
    table = data.get("sweep")
    sweep = Sweep(path, {})
    if table is not None:
        where = f"sweep file {path}"
        plot = table.get("plot", {}) if isinstance(table, dict) else None
        if not isinstance(table, dict) or set(data) != {"sweep"} or set(table) - _SWEEP_KEYS \
                or not isinstance(table.get("scenario"), str) \
                or not isinstance(table.get("grid", []), list) \
                or not all(isinstance(g, str) for g in table.get("grid", [])) \
                or not isinstance(plot, dict) or set(plot) - _PLOT_KEYS:
            raise UserError(f"{where} must hold only a [sweep] table with scenario = \"FILE\", "
                            f"grid = [\"inst.param=start:stop:n\", ...], description and a plot "
                            f"table with keys {', '.join(sorted(_PLOT_KEYS))}")
        axes_named = [plot.get("x"), *([plot.get("y")] if plot.get("kind") == "heatmap" else [])]
        if plot and (plot.get("kind") not in ("line", "heatmap")
                     or not all(isinstance(a, str) for a in axes_named)
                     or not isinstance(plot.get("metrics"), list)):
            raise UserError(f"{where}: the plot needs kind = \"line\" (with x) or \"heatmap\" "
                            "(with x and y), and a metrics list")
        sweep = Sweep(path.parent / table["scenario"], _axes(table.get("grid", []), where), plot,
                      str(table.get("description", "")))
    axes = {**sweep.axes, **_axes(grid, "--grid")}
    if not axes:
        raise UserError(f"{path}: no grid axis (give --grid inst.param=start:stop:n)")
    return Sweep(sweep.scenario, axes, sweep.plot, sweep.title)


def grid_cases(axes: Mapping[str, Sequence[float]]) -> list[tuple[str, dict[str, float]]]:
    """Every point of the Cartesian grid of `axes` as ``(case id, {axis: value})``, in grid
    order.

    The id names the values (axes sorted by name), so it does not change between runs.

    Examples
    --------
    >>> grid_cases({"b.y": (0.5,), "a.x": (1.0, 2.0)})[0]
    ('a.x=1,b.y=0.5', {'b.y': 0.5, 'a.x': 1.0})
    """
    points = [dict(zip(axes, values)) for values in itertools.product(*axes.values())]
    return [(",".join(f"{n}={p[n]:.12g}" for n in sorted(p)), p) for p in points]


def _sets(point: Mapping[str, float]) -> list[str]:
    return [f"{name}={value!r}" for name, value in point.items()]


def _check(sweep: Sweep, path: str | Path, fmu_dir: str | Path, overrides: Sequence[str],
           point: Sequence[str], stop_time: float | None
           ) -> tuple[Scenario, Scenario, dict[str, str], dict[str, Any]]:
    """Check the scenario, axes and plot once, rather than fail every case the same way.

    `overrides` are the user's (``--set``), `point` the first case's grid values. Returns the
    scenario every case starts from (with `overrides` and `stop_time`), the scenario of the first
    case, the metrics' units and the plot to draw.
    """
    from musclesim.cosim import (Master, check_fresh, implausible, load_scenario, metric_unit,
                                 signal_units, unknown_instance)

    base = load_scenario(sweep.scenario, overrides, stop_time)
    instances = base.instances
    for axis in sweep.axes:
        inst = ParamRef.parse(axis).instance
        if inst not in instances:
            raise UserError(f"grid axis {axis!r}: "
                            f"{unknown_instance(inst, instances, f'{sweep.scenario} declares')}")
    # every value of the grid, before the first case runs (not as many failed cases)
    implausibles = [next(filter(None, (implausible(base, ParamRef.parse(axis), v,
                                                   f"grid axis {axis!r}: {axis}")
                                       for v in values)), None)
                    for axis, values in sweep.axes.items()]
    if any(implausibles):
        raise UserError(f"grid of {path}: " + "; ".join(p for p in implausibles if p))
    s = load_scenario(sweep.scenario, [*overrides, *point], stop_time)
    check_fresh(fmu_dir)
    sig_units = signal_units(Master(s, fmu_dir))
    units = {n: metric_unit(sig_units[m.signal], m.op, m.over is not None)
             for n, m in s.metrics.items()}
    plot_spec = sweep.plot or _default_plot(sweep.axes, s.metrics)
    unknown = [x for x in plot_spec.get("metrics", []) if x not in s.metrics]
    if unknown:
        raise UserError(f"sweep file {path}: plot metric(s) {', '.join(unknown)} not in the "
                        f"scenario's metrics ({', '.join(s.metrics)})")
    return base, s, units, plot_spec


def run(scenario_path: str | Path, grid: Sequence[str], out: str | Path,
        fmu_dir: str | Path = "fmus", scheduler: str | None = None, workers: int | None = None,
        overrides: Sequence[str] = (), stop_time: float | None = None) -> dict[str, Any]:
    """Run every case of a grid, write out/cases/<id>/, out/sweep.csv and out/sweep.png.

    Parameters
    ----------
    scenario_path : str or Path
        Sweep file or scenario file (see `load`).
    grid : sequence of str
        Extra or replacing axes, ``"inst.param=start:stop:n"`` or ``"inst.param=a,b,c"``.
    out : str or Path
        Output folder; re-running into it skips the cases that completed.
    fmu_dir : str or Path
        Folder of built FMUs.
    scheduler : str, optional
        Address of an existing Dask scheduler (its workers need none of this machine's files:
        they get the FMUs and the scenario from here, and send the results back).
    workers : int, optional
        Worker processes of the local cluster (default: the machine's cores).
    overrides : sequence of str
        ``"inst.param=value"`` applied to every case (the grid's values win).
    stop_time : float, optional
        Replaces the scenario's stop time.

    Returns
    -------
    dict
        Counts of cases (total, skipped, ran, completed), ``failed`` ({case id: error}), the
        files written and the wall time in seconds.

    Raises
    ------
    UserError
        For a bad sweep file, axis, scenario, parameter or output folder.
    """
    start = time.perf_counter()
    sweep = load(scenario_path, grid)
    if workers is not None and workers < 1:
        raise UserError(f"--workers must be at least 1 (got {workers})")
    out, fmu_dir, scen_path = Path(out).resolve(), Path(fmu_dir).resolve(), sweep.scenario.resolve()
    all_cases = grid_cases(sweep.axes)
    base, s, units, plot_spec = _check(sweep, scenario_path, fmu_dir, overrides,
                                       _sets(all_cases[0][1]), stop_time)
    claim(out, scen_path, overrides=list(overrides), stop_time=stop_time)

    columns = ["case", *sweep.axes, "completed", *s.metrics, "error"]
    done = {cid: finished(out / "cases" / cid) for cid, _ in all_cases}
    todo = [(cid, p) for cid, p in all_cases if done[cid] is None]
    failed = {}
    csv_path = out / "sweep.csv"

    points = dict(all_cases)

    def record(cid: str, summary: dict[str, Any], _: Any = None) -> None:
        point = points[cid]
        if not summary.get("completed"):
            failed[cid] = summary.get("error") or "the case did not complete"
        with csv_path.open("a", newline="") as f:
            csv.writer(f).writerow([cid, *point.values(), bool(summary.get("completed")),
                                    *(math.nan if summary.get(n) is None else summary[n]
                                      for n in s.metrics),
                                    summary.get("error") or ""])

    csv_path.write_text(",".join(columns) + "\n")
    for cid, _ in all_cases:
        summary = done[cid]
        if summary is not None:
            record(cid, summary)
    if todo:
        run_cases(out, [(cid, _sets(p)) for cid, p in todo], base, fmu_dir, scheduler, workers,
                  record)
    png = out / "sweep.png"
    drawn = _plot(csv_path, png, plot_spec, sweep.axes, units,
                  sweep.title or f"{s.name}, {s.stop_time:g} s")
    return {"sweep": str(scenario_path), "scenario": str(scen_path), "out": str(out),
            "cases": len(all_cases), "skipped": len(all_cases) - len(todo), "ran": len(todo),
            "completed": len(all_cases) - len(failed), "failed": failed, "csv": str(csv_path),
            "plot": str(png) if drawn else None, "seconds": round(time.perf_counter() - start, 1)}


def _default_plot(axes: Mapping[str, Any], metrics: Mapping[str, Any]) -> dict[str, Any]:
    names = list(axes)
    if len(names) == 1:
        return {"kind": "line", "x": names[0], "metrics": list(metrics)}
    if len(names) == 2:
        return {"kind": "heatmap", "x": names[0], "y": names[1], "metrics": list(metrics)}
    return {}


def _plot(csv_path: Path, png: Path, spec: dict[str, Any], axes: Mapping[str, Any],
          units: Mapping[str, str], title: str) -> bool:
    """Draw `spec` from sweep.csv into `png`; False if the plot's axes are not the grid's."""
    used: list[Any] = [spec.get("x"), *([spec.get("y")] if spec.get("kind") == "heatmap" else [])]
    if not spec or set(used) != set(axes) or not spec["metrics"]:
        return False
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with csv_path.open(newline="") as f:
        rows = list(csv.DictReader(f))
    col = {k: np.array([float(r[k]) for r in rows]) for k in [*used, *spec["metrics"]]}
    labels = {n: f"{n} [{units[n]}]" for n in spec["metrics"]}
    if spec["kind"] == "line":
        fig, ax = plt.subplots(figsize=(8, 4.5))
        order = np.argsort(col[used[0]])
        for name in spec["metrics"]:
            ax.plot(col[used[0]][order], col[name][order], marker="o", ms=3, label=labels[name])
        ax.set_xlabel(used[0])
        ax.legend()
        ax.grid(alpha=0.3)
    else:
        xs, ys = np.unique(col[used[0]]), np.unique(col[used[1]])
        n = len(spec["metrics"])
        fig, axs = plt.subplots(1, n, figsize=(5.5 * n, 4.5), squeeze=False)
        for ax, name in zip(axs[0], spec["metrics"]):
            z = np.full((len(ys), len(xs)), np.nan)  # failed or missing cases stay blank
            z[np.searchsorted(ys, col[used[1]]), np.searchsorted(xs, col[used[0]])] = col[name]
            lim = float(np.nanmax(np.abs(z))) if np.isfinite(z).any() else 1.0
            mesh = ax.pcolormesh(xs, ys, z, shading="nearest", cmap="RdBu_r", vmin=-lim, vmax=lim)
            fig.colorbar(mesh, ax=ax, label=labels[name])
            ax.set_xlabel(used[0])
            ax.set_ylabel(used[1])
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    save_figure(fig, png, dpi=110)
    plt.close(fig)
    return True
