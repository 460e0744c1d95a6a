"""Run outputs: results.csv, summary.json (metrics) and a plot, written into one folder.

results.csv is a plain CSV as the FMI cross-check rules ask of result files: the header on its
first line (``time``, then ``<instance>.<variable>``), then one row per communication point; no
comment line, so pandas, numpy, the csv module and FMPy read it as it is.

A run's outputs are written as it goes and always belong together (`RunWriter`): the previous
run's files are removed first (summary first), then summary.json says ``completed: false``
(``status: running``) with a new run id, and the rows grow, whole rows at a time, in
``results.csv.part``, a name that says the run is in progress. At the end, however the run ends
(completed, failed, interrupted), ``results.csv.part`` becomes ``results.csv``, then
results.png and the final summary.json are written under temporary names and renamed in place.
A run killed at any moment (even by SIGKILL) leaves the previous run's files or only this run's
(its summary saying ``running`` beside its rows so far, in ``results.csv.part``, or in
``results.csv`` when the kill came as the run ended), never one run's results beside another
run's summary; a killed write may cut the last row, which then has no line end.
"""
from __future__ import annotations

import io
import json
import math
import os
import uuid
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from musclesim.cosim.address import Signal
from musclesim.cosim.outputs import envelope, replace_file, save_figure
from musclesim.cosim.scenario import Metric, Panel, Scenario

PART = ".part"  # suffix of a file whose run is still writing it
OUTPUTS = ("summary.json", "results.csv", "results.csv" + PART, "results.png")
PLOT_BINS = 2000  # a plotted signal's min-max pairs: 4000 points over the plot's ~1000 pixels


@dataclass
class Results:
    """Recorded signals: `time` ``[i]`` and `data` ``[i, j]`` for the column `names` ``[j]``,
    rows 0..n-1; ``results[signal]`` is the column of a `Signal`.

    `error` is None for a complete run, else the sentence saying which instance failed, when
    and why; the rows before the failure are kept. `warnings` holds what the FMUs logged as
    warnings (e.g. an input clamped to a model's valid range), each prefixed with its instance.
    """

    time: np.ndarray
    names: tuple[Signal, ...]
    data: np.ndarray
    error: str | None = None
    warnings: list[str] = field(default_factory=list)

    def __getitem__(self, signal: Signal) -> np.ndarray:
        """The column of `signal`."""
        return self.data[:, self.names.index(signal)]


def clear_run_outputs(out_dir: str | Path) -> None:
    """Remove a run's outputs from `out_dir`, the summary first: without it, no file there
    claims to be a whole run."""
    for name in OUTPUTS:
        (Path(out_dir) / name).unlink(missing_ok=True)



def _rate(t: np.ndarray, y: np.ndarray) -> float:
    return (y[-1] - y[0]) / (t[-1] - t[0]) if t[-1] > t[0] else math.nan


def _frequency(t: np.ndarray, y: np.ndarray) -> float:
    """Oscillation frequency [Hz]: rising crossings of the middle of the range, (count - 1) over
    the time from the first to the last (linear between samples); NaN with fewer than two."""
    if len(y) < 3:
        return math.nan
    mid = (float(np.max(y)) + float(np.min(y))) / 2
    k = np.flatnonzero((y[:-1] < mid) & (y[1:] >= mid))
    if len(k) < 2:
        return math.nan
    crossings = t[k] + (mid - y[k]) / (y[k + 1] - y[k]) * (t[k + 1] - t[k])
    return (len(k) - 1) / (crossings[-1] - crossings[0])


def _cycle_peak_to_peak(t: np.ndarray, y: np.ndarray, period: float) -> float:
    """Mean over the whole periods in the window (from its first sample) of each one's
    peak-to-peak; NaN without a whole period."""
    if not len(t):
        return math.nan
    cycle = np.floor((t - t[0]) / period * (1 + 1e-12)).astype(int)
    whole = int((t[-1] - t[0]) / period * (1 + 1e-12))
    spans = [np.ptp(y[cycle == c]) for c in range(whole) if np.any(cycle == c)]
    return float(np.mean(spans)) if spans else math.nan


# op -> (function of (time, values, metric), how the unit changes)
_OPS: dict[str, tuple[Callable[[np.ndarray, np.ndarray, Any], float], str]] = {
    "final": (lambda t, y, m: y[-1], "{}"),
    "initial": (lambda t, y, m: y[0], "{}"),
    "mean": (lambda t, y, m: float(np.mean(y)), "{}"),
    "min": (lambda t, y, m: float(np.min(y)), "{}"),
    "max": (lambda t, y, m: float(np.max(y)), "{}"),
    "max_abs": (lambda t, y, m: float(np.max(np.abs(y))), "{}"),
    "rms": (lambda t, y, m: float(np.sqrt(np.mean(np.square(y)))), "{}"),
    "peak_to_peak": (lambda t, y, m: float(np.ptp(y)), "{}"),
    # mean rate of change over the run, e.g. mean speed from a position
    "rate": (lambda t, y, m: _rate(t, y), "{}/s"),
    # mean change per period, e.g. stride length from a position and the stride period
    "per_period": (lambda t, y, m: _rate(t, y) * m.period, "{}"),
    # oscillation frequency, e.g. of a relay-heated wire's contraction
    "frequency": (lambda t, y, m: _frequency(t, y), "Hz"),
    # mean peak-to-peak per period, e.g. per heating pulse
    "cycle_peak_to_peak": (lambda t, y, m: _cycle_peak_to_peak(t, y, m.period), "{}"),
}


def metric_unit(unit: str | None, op: str, ratio: bool = False) -> str:
    """Unit of a metric computed with `op` from a signal in `unit` ("1" for a `ratio`: the same
    op on another signal divides it, the metric's ``over``)."""
    return "1" if ratio else _OPS[op][1].format(unit or "1")


def compute_metrics(results: Results, metrics: Mapping[str, Metric]) -> dict[str, float]:
    """Evaluate `metrics` (``{name: Metric}``) on `results`; a metric without a value (no sample in its
    window, no oscillation to count, nothing to divide by) is NaN, written null in summary.json."""
    out = {}
    for name, m in metrics.items():
        # the times t0 + k h are doubles: a window edge on a sample counts it in
        tol = 1e-9 * max(1.0, abs(results.time[-1])) if len(results.time) else 0.0
        window = (results.time >= m.start - tol) & (results.time <= m.stop + tol)
        t, y = results.time[window], results[m.signal][window]
        value = m.scale * float(_OPS[m.op][0](t, y, m)) if len(y) else math.nan
        if m.over is not None and len(y):  # the same op on another signal divides it
            den = float(_OPS[m.op][0](t, results[m.over][window], m))
            value = value / den if den else math.nan  # nothing to compare with: no ratio
        out[name] = value
    return out


def _no_value(m: Metric, results: Results, end: float) -> str:
    """Why metric `m` has no value on `results` (a run ending at `end` s), in a few words."""
    tol = 1e-9 * max(1.0, abs(end))
    window = (results.time >= m.start - tol) & (results.time <= m.stop + tol)
    if not window.any():
        return f"no sample in its window ({m.start:g} to {m.stop:g} s) of a run ending at {end:g} s"
    if m.op == "frequency":
        return (f"no value: {m.signal} crosses the middle of its range fewer than twice in its "
                "window")
    if m.op == "cycle_peak_to_peak":
        return f"no value: its window holds no whole period of {m.period:g} s"
    if m.over is not None:
        return f"no value: {m.op} of {m.over} is 0 in its window, nothing to divide by"
    return f"no value: {m.op} needs more than the one sample in its window"


def csv_rows(time: np.ndarray, data: np.ndarray) -> str:
    """Rows ``time,<values>`` of `time` and `data` at full double precision, each ending in a
    line end."""
    buf = io.StringIO()
    np.savetxt(buf, np.column_stack([time, data]), delimiter=",", fmt="%.17g")
    return buf.getvalue()


def plot(path: Path, results: Results, panels: Sequence[Panel], units: Mapping[Signal, str],
         title: str = "") -> None:
    """Save at `path` a stacked time plot of `results` titled `title`, one of the `panels` above
    the other (each signal with its unit from `units`), or one panel per signal without."""
    import warnings

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = panels or [Panel(str(name), (name,)) for name in results.names]
    fig, axes = plt.subplots(len(panels), 1, sharex=True, squeeze=False,
                             figsize=(9, 2.2 * len(panels) + 0.8))
    # values near the float limit (a run that failed as a signal overflowed) make matplotlib's
    # autoscaling overflow: a RuntimeWarning on stderr beside the run's one sentence, so silenced
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        for ax, panel in zip(axes[:, 0], panels):
            for sig in panel.signals:
                ax.plot(*envelope(results.time, results[sig], PLOT_BINS), label=f"{sig} [{units.get(sig) or '1'}]",
                        lw=0.8)
            ax.set_title(panel.title, fontsize=9)
            ax.legend(fontsize=7, loc="best")
            ax.grid(alpha=0.3)
        axes[-1, 0].set_xlabel("time [s]")
        fig.suptitle(title, fontsize=10)
        fig.tight_layout()
        save_figure(fig, path, dpi=110)
    plt.close(fig)


class RunWriter:
    """One run's outputs in `out_dir`, written as the run goes (see the module docstring).

    `start` before the run, `rows` as the master hands rows over (`Master.run`'s ``on_rows``),
    `finish` with the run's `Results`. `units` maps each recorded signal to its unit.
    """

    def __init__(self, out_dir: str | Path, scenario: Scenario, columns: Sequence[Signal],
                 units: Mapping[Signal, str], with_plot: bool = True) -> None:
        """The writer of a run of `scenario` recording `columns` into `out_dir` (see the
        class docstring; the plot only `with_plot`)."""
        self.out, self.scenario, self.columns = Path(out_dir), scenario, list(columns)
        self.units, self.with_plot = units, with_plot
        self.run_id = uuid.uuid4().hex
        self.csv: Any = None

    def start(self) -> None:
        """Remove the previous run's outputs and open this run's (``completed: false``)."""
        self.out.mkdir(parents=True, exist_ok=True)
        clear_run_outputs(self.out)
        self._summary({"completed": False, "error": None, "status": "running"})
        replace_file(self.partial, ",".join(["time", *map(str, self.columns)]) + "\n")
        self.csv = open(self.partial, "ab", buffering=0)

    @property
    def partial(self) -> Path:
        """The file the rows grow in while the run goes: results.csv.part."""
        return self.out / ("results.csv" + PART)

    def rows(self, time: np.ndarray, data: np.ndarray) -> None:
        """Append whole rows (`time`, `data`) to results.csv.part (one write)."""
        if len(time):
            self.csv.write(csv_rows(time, data).encode())

    def finish(self, results: Results, extra: Mapping[str, Any] | None = None
               ) -> dict[str, Any]:
        """Close the rows and name them results.csv, draw the plot of `results`, write the final
        summary (with the entries of `extra`, which a layer above gives); return the summary.

        Raises
        ------
        ValueError
            If a key of `extra` is a metric's or one of the run's state (its identity, written
            last, wins over `extra`).
        """
        if self.csv is not None:
            self.csv.close()
            self.csv = None
            os.replace(self.partial, self.out / "results.csv")
        metrics = compute_metrics(results, self.scenario.metrics)
        end = results.time[-1] if len(results.time) else self.scenario.start_time
        warnings = list(results.warnings) + [
            f"metric {name}: {_no_value(m, results, end)}"
            for name, m in self.scenario.metrics.items()
            if math.isnan(metrics[name]) and results.error is None]  # a stopped run says why
        if self.with_plot and len(results.time) > 1:
            s = self.scenario
            plot(self.out / "results.png", results, s.plots, self.units,
                 title=f"{s.name} ({s.reference})" if s.reference else s.name)
        state = {
            **{name: None if math.isnan(v) else v for name, v in metrics.items()},  # JSON null
            "units": {name: metric_unit(self.units.get(m.signal), m.op, m.over is not None)
                      for name, m in self.scenario.metrics.items()},
            "completed": results.error is None, "error": results.error,
            "status": "completed" if results.error is None else "stopped",
            "warnings": warnings,
            "end_time": float(results.time[-1]) if len(results.time) else None}
        if clash := set(extra or {}) & set(state):
            raise ValueError(f"summary entries {sorted(clash)} would replace the run's own")
        return self._summary({**state, **(extra or {})})

    def _summary(self, state: dict[str, Any]) -> dict[str, Any]:
        s = self.scenario
        summary = {**state, "run_id": self.run_id, "scenario": s.name,
                   "description": s.description, "scenario_file": str(s.path),
                   "reference": s.reference, "algorithm": s.algorithm, "step": s.step, "start_time": s.start_time,
                   "stop_time": s.stop_time,
                   "parameters": {n: i.parameters for n, i in s.instances.items()}}
        replace_file(self.out / "summary.json", json.dumps(summary, indent=2, allow_nan=True) + "\n")
        return summary


def write_all(out_dir: str | Path, scenario: Scenario, results: Results,
              units: Mapping[Signal, str], with_plot: bool = True,
              rows: bytes | None = None) -> dict[str, Any]:
    """Write results.csv, summary.json and (unless not `with_plot`) results.png of a finished
    run of `scenario` (its `results`, the signals' `units`) into `out_dir`; return the summary
    dict (metrics at top level, their units under ``"units"``, the run's id, scenario,
    algorithm, step, times, parameters and error). `rows`: results.csv's rows as `csv_rows`
    formats them (encoded), where they were formatted already (by the worker that ran it)."""
    writer = RunWriter(out_dir, scenario, results.names, units, with_plot)
    writer.start()
    if rows is None:
        writer.rows(results.time, results.data)
    elif rows:
        writer.csv.write(rows)
    return writer.finish(results)

