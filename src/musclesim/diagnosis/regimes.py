"""Operating regimes: row masks of `effects.REGIMES` from the measured signals, the gap per regime.

Which column defines which regime is found by its unit (a temperature in K, a load in N or Pa, a
pressure in Pa, positions in m) or, for the variables the effect library declares
(`effects.STRAIN_VARIABLES`, `FORCE_VARIABLES`, `SWITCHING_INDICATORS`), by its name:
`regime_signals`. `run_masks` computes one run's masks from plain arrays.

>>> import numpy as np
>>> t = np.linspace(0.0, 10.0, 101)
>>> T = 300 + 20 * np.minimum(t, 10 - t)  # 5 s heating to 400 K, 5 s cooling
>>> w_T = Signal("w", "T")
>>> masks = run_masks(t, {w_T: T}, Signals(temperature=w_T))
>>> sorted(masks)  # no strain, load, pressure, position or indicator measured
['all', 'changing', 'cooling', 'heating', 'hot', 'late']
>>> int(masks["heating"].sum()), int(masks["cooling"].sum()), int(masks["hot"].sum())
(50, 50, 21)

The peak's sample (t = 5 s), whose smoothed rate is zero, is neither heating nor cooling.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from musclesim.cosim import Signal
from musclesim.diagnosis.effects import (FORCE_VARIABLES, REGIMES, STRAIN_VARIABLES,
                                         SWITCHING_INDICATORS)
from musclesim.diagnosis.stats import smooth_rate, worst_windows

SWITCHING_WINDOW = 0.5  # s after a friction indicator changes (REGIMES["switching"])


@dataclass(frozen=True)
class Signals:
    """The measured columns that define the regimes (None or empty: not measured)."""

    temperature: Signal | None = None
    force: Signal | None = None
    strain: Signal | None = None
    pressure: Signal | None = None
    positions: tuple[Signal, ...] = ()
    indicators: tuple[Signal, ...] = ()


def _first(columns, units, want):
    return next((c for c in columns if units.get(c) in want), None)


def regime_signals(outputs, inputs, units, components):
    """The `Signals` among a data set's `outputs` and `inputs` (column names), given the columns'
    `units` ({column: unit}) and the scenario's `components` ({instance: component})."""
    columns = list(outputs) + list(inputs)
    force = _first(columns, units, ("N", "Pa")) or next(
        (c for c in columns if c.variable in FORCE_VARIABLES), None)
    return Signals(
        temperature=_first(columns, units, ("K",)), force=force,
        strain=next((c for c in columns if c.variable in STRAIN_VARIABLES), None),
        pressure=_first(columns, units, ("Pa",)),
        positions=tuple(c for c in columns if units[c] == "m"),
        indicators=tuple(c for c in inputs if c.variable in SWITCHING_INDICATORS.get(
            components.get(c.instance), ())))


def run_masks(t, cols, signals):
    """``{regime: row mask}`` of one run: times `t`, measured ``{column: values}`` `cols`, the
    `Signals` that define the regimes. A regime whose signal is not measured is left out."""
    out = {"all": np.ones(len(t), bool), "late": t >= 0.5 * t[-1]}
    if signals.temperature:
        temp = cols[signals.temperature]
        rate = smooth_rate(t, temp)
        out["changing"] = np.abs(rate) > np.median(np.abs(rate))
        out["heating"] = rate > 0
        out["cooling"] = rate < 0
        out["hot"] = temp >= np.percentile(temp, 80)
    if signals.strain:
        rate = np.abs(smooth_rate(t, cols[signals.strain]))
        out["transformation"] = rate > 0.1 * np.percentile(rate, 95)
    if signals.force:
        f = cols[signals.force]
        out["stress_extremes"] = np.abs(f - np.median(f)) > max(np.std(f), 1e-12)
        out["high_force"] = f > np.median(f)
        rate = np.abs(smooth_rate(t, f))
        out["load_changing"] = rate > np.median(rate)
    if signals.pressure:
        rate = np.abs(smooth_rate(t, cols[signals.pressure]))
        out["pressure_changing"] = rate > np.median(rate)
        out["pressurised"] = cols[signals.pressure] > np.median(cols[signals.pressure])
    if signals.positions:
        speed = np.max([np.abs(smooth_rate(t, cols[c], 0.05)) for c in signals.positions], axis=0)
        moving = speed > 0.1 * np.percentile(speed, 95)
        out["slip"] = moving
        out["stick"] = ~moving
    if signals.indicators:
        near = np.zeros(len(t), bool)
        for c in signals.indicators:
            for ts in t[1:][np.diff(cols[c]) != 0]:
                near |= (t >= ts) & (t < ts + SWITCHING_WINDOW)
        out["switching"] = near
    return out


def regimes(problem, unit):
    """``{regime: [row mask per run]}`` of `effects.REGIMES` that the measured columns define."""
    ds = problem.ds
    if problem.scalar_only:
        return {"all": [np.ones(1, bool) for _ in unit.runs]}
    signals = regime_signals(ds.outputs, ds.inputs, problem.units_of, problem.components)
    out: dict[str, list[np.ndarray]] = {k: [] for k in REGIMES}
    for run in unit.runs:
        _, cols = ds.experiment(run.experiment)
        for key, mask in run_masks(run.time, cols, signals).items():
            out[key].append(mask)
    return {k: v for k, v in out.items() if len(v) == len(unit.runs)}


def regime_table(unit, res, masks):
    """The report's ``regimes``: share of samples and nominal gap per regime of `masks`, and the
    worst time windows of residuals `res`."""
    out = {}
    for key, per_run in masks.items():
        sq = np.concatenate([np.nansum([np.square(res[c][i][m]) for c in unit.observed], axis=0)
                             for i, m in enumerate(per_run)])
        n = sum(int(m.sum()) for m in per_run)
        total = sum(m.size for m in per_run)
        out[key] = {"fraction": n / total if total else 0.0,
                    "gap": math.sqrt(sq.sum() / (n * len(unit.observed))) if n else None,
                    "description": REGIMES[key]}
    return {"by_regime": out, "worst_windows": [] if unit.runs[0].time is None
            else worst_windows(unit, res)}
