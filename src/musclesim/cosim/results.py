"""Run outputs: results.csv, summary.json (metrics) and a plot, written into one folder."""
import json
import math
from pathlib import Path

import numpy as np

from musclesim.cosim.scenario import split_signal

def _rate(t, y):
    return (y[-1] - y[0]) / (t[-1] - t[0]) if t[-1] > t[0] else math.nan


# op -> (function of (time, values, metric), how the unit changes)
_OPS = {
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
}


def metric_unit(unit, op):
    """Unit of a metric computed with `op` from a signal in `unit`."""
    return _OPS[op][1].format(unit or "1")


def compute_metrics(results, metrics):
    """Evaluate ``{name: Metric}`` on `results`; a metric without samples in its window is NaN."""
    out = {}
    for name, m in metrics.items():
        # the master accumulates time step by step: a window edge on a sample counts it in
        tol = 1e-9 * max(1.0, abs(results.time[-1])) if len(results.time) else 0.0
        window = (results.time >= m.start - tol) & (results.time <= m.stop + tol)
        t, y = results.time[window], results[m.signal][window]
        out[name] = m.scale * float(_OPS[m.op][0](t, y, m)) if len(y) else math.nan
    return out


def write_csv(path, results):
    """Write ``time`` then one column per signal, full double precision."""
    header = ",".join(["time", *results.names])
    np.savetxt(path, np.column_stack([results.time, results.data]), delimiter=",",
               header=header, comments="", fmt="%.17g")


def plot(path, results, panels, units, title=""):
    """Save a stacked time plot, one panel per ``{"title", "signals"}`` entry."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = panels or [{"title": name, "signals": [name]} for name in results.names]
    fig, axes = plt.subplots(len(panels), 1, sharex=True, squeeze=False,
                             figsize=(9, 2.2 * len(panels) + 0.8))
    for ax, panel in zip(axes[:, 0], panels):
        for sig in panel["signals"]:
            ax.plot(results.time, results[sig], label=f"{sig} [{units.get(sig) or '1'}]", lw=0.8)
        ax.set_title(panel.get("title", ""), fontsize=9)
        ax.legend(fontsize=7, loc="best")
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("time [s]")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_all(out_dir, scenario, results, units, with_plot=True):
    """Write results.csv, summary.json and (unless not `with_plot`) results.png into `out_dir`.

    Returns the summary dict.

    `units` maps each recorded signal to its unit. The summary holds the metrics at top level
    (with their units under ``"units"``), and the run's scenario, algorithm, step, times and error.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    write_csv(out / "results.csv", results)
    metrics = compute_metrics(results, scenario.metrics)
    summary = {
        **metrics,
        "units": {name: metric_unit(units.get(m.signal), m.op)
                  for name, m in scenario.metrics.items()},
        "scenario": scenario.name,
        "description": scenario.description,
        "scenario_file": str(scenario.path),
        "spec": scenario.spec,
        "algorithm": scenario.algorithm,
        "step": scenario.step,
        "start_time": scenario.start_time,
        "stop_time": scenario.stop_time,
        "parameters": {n: i.parameters for n, i in scenario.instances.items()},
        "completed": results.error is None,
        "error": results.error,
        "warnings": results.warnings,
        "end_time": float(results.time[-1]) if len(results.time) else None,
    }
    (out / "summary.json").write_text(json.dumps(summary, indent=2, allow_nan=True) + "\n")
    if with_plot and len(results.time) > 1:
        plot(out / "results.png", results, scenario.plots, units,
             title=f"{scenario.name} ({scenario.spec})" if scenario.spec else scenario.name)
    return summary


def signal_units(master):
    """Unit of every recorded column of a `musclesim.cosim.Master`."""
    units = {}
    for sig in master.columns:
        inst, var = split_signal(sig)
        units[sig] = master.instances[inst].vars[var].unit or "1"
    return units
