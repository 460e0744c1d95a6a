"""Statistics of the diagnosis on plain arrays: noise, gaps, lag, rates, block bootstrap, windows.

The array functions (`noise_estimate`, `advance`, `moving_mean`, `smooth_rate`, `rms`, `pooled`,
`lag`, `interval95`, `split_blocks`, `block_bootstrap`, `window_gaps`) need no model. The others
are thin wrappers that read a unit's arrays: anything with ``observed`` (column names), ``noise``
({column: normalised noise std}) and ``runs`` (each with ``part``, a row mask source holding
`Part` values: ``TRAIN`` or ``HELD_OUT``; and for windows ``time``, ``t0`` and ``experiment``), as
`musclesim.diagnosis.problem.Unit` has them. Residuals are ``{column: [array per run]}``.

>>> import numpy as np
>>> rms(np.array([3.0, -4.0]))  # sqrt((9 + 16) / 2)
3.5355339059327378
>>> interval95(np.arange(101.0))
[2.5, 97.5]
"""
from __future__ import annotations

import math
from collections.abc import Iterable
from enum import IntEnum
from typing import Any

import numpy as np
from scipy import signal

from musclesim.diagnosis.thresholds import BLOCKS, BOOTSTRAP, DEVIATES, WINDOWS


class Part(IntEnum):
    """The part of a data set a row (or a scalar run) belongs to: the fits see only ``TRAIN``;
    ``HELD_OUT`` judges them. Stored in the runs' ``part`` arrays as these integers."""

    TRAIN = 0
    HELD_OUT = 1


TRAIN, HELD_OUT = Part.TRAIN, Part.HELD_OUT


# ---- on arrays --------------------------------------------------------------------------------

def noise_estimate(y):
    """Std of white measurement noise in `y` from its second differences (var = 6 sigma^2)."""
    if len(y) < 4:
        return 0.0
    d2 = np.diff(y, 2)
    # the median absolute deviation keeps the signal's own curvature at its corners out
    return float(1.4826 * np.median(np.abs(d2 - np.median(d2))) / math.sqrt(6))


def advance(y, samples):
    """`y` moved `samples` earlier (its last value held at the end)."""
    if not samples:
        return y
    return np.concatenate([y[samples:], np.full(samples, y[-1])])


def moving_mean(y, n):
    """Centred mean of `y` over `n` samples, as ``np.convolve(y, ones(n) / n, "same")`` (zeros
    beyond the ends), summed slice by slice in one order: np.convolve sums through the CPU's BLAS
    kernel, whose last digits differ between CPUs, and a rate that is zero in exact arithmetic
    (quantised data) would take their sign."""
    padded = np.concatenate((np.zeros(n // 2), y, np.zeros((n - 1) // 2)))
    total = padded[:len(y)].copy()
    for k in range(1, n):
        total += padded[k:k + len(y)]
    return total / n


def smooth_rate(t, y, window=0.25):
    """dy/dt after a centred moving average over about `window` seconds."""
    if len(t) < 3:
        return np.zeros_like(y)
    n = max(1, int(round(window / np.median(np.diff(t)))))
    return np.gradient(moving_mean(np.asarray(y, float), n), t)


def rms(v):
    """Root mean square of `v` (nan when `v` is empty)."""
    return float(np.sqrt(np.mean(np.square(v)))) if v.size else math.nan


def pooled(stds):
    """Pooled std of independent noises: the root mean square of `stds`."""
    return math.sqrt(np.mean([s ** 2 for s in stds]))


def lag(t, meas, model):
    """Shift [s] of the model that best matches the data (positive: the data lags the model),
    searched within a tenth of the span."""
    a, b = meas - np.mean(meas), model - np.mean(model)
    if len(t) < 3 or not np.any(a) or not np.any(b):
        return 0.0
    dt = float(np.median(np.diff(t)))
    corr = signal.correlate(a, b, mode="full", method="fft")
    lags = signal.correlation_lags(len(a), len(b), mode="full")
    window = np.abs(lags) * dt <= 0.1 * (t[-1] - t[0])
    return float(lags[window][np.argmax(corr[window])] * dt)


def interval95(samples):
    """The central 95 % interval of `samples`: [2.5th, 97.5th percentile]."""
    return [float(np.percentile(samples, 2.5)), float(np.percentile(samples, 97.5))]


def split_blocks(mask, count=BLOCKS):
    """The rows where `mask` holds, in at most `count` contiguous chunks of indices."""
    idx = np.flatnonzero(mask)
    if not idx.size:
        return []
    return np.array_split(idx, max(1, min(count, idx.size)))


def block_bootstrap(sums, counts, seed=0, resamples=BOOTSTRAP):
    """Block-bootstrap RMS values: array [resample, set].

    `sums` [block, set] holds each block's sum of squared residuals per residual set, `counts`
    [block] its number of values; every resample draws as many blocks with replacement.
    """
    rng = np.random.default_rng(seed)
    pick = rng.integers(0, len(counts), size=(resamples, len(counts)))
    return np.sqrt(sums[pick].sum(axis=1) / counts[pick].sum(axis=1)[:, None])


def window_gaps(sq, columns, fraction=0.05):
    """(gap, first row, last row) of consecutive windows, each a `fraction` of the rows.

    `sq` is per row the sum of squared residuals over `columns` columns; a window's gap is the
    RMS of its residuals.
    """
    n = max(2, int(len(sq) * fraction))
    return [(math.sqrt(sq[j:j + n].mean() / columns), j, j + n - 1)
            for j in range(0, len(sq) - n + 1, n)]


# ---- on a unit's residuals --------------------------------------------------------------------

def part_rows(unit, part):
    """Per run, the row mask of `part` (a `Part`)."""
    return [run.part == part for run in unit.runs]


def part_vector(unit, res, part, columns=None):
    """The residuals of `part` (a `Part`) in one vector (a metric a run lacks
    dropped)."""
    rows = part_rows(unit, part)
    v = np.concatenate([r[m] for c in columns or unit.observed for r, m in zip(res[c], rows)])
    return v[np.isfinite(v)]


def part_segments(unit, res, part):
    """The residuals of `part` as {column: [array per run]}, each array in time order without
    its non-finite values: `part_vector`'s values, column by column and run by run."""
    rows = part_rows(unit, part)
    return {c: [r[m][np.isfinite(r[m])] for r, m in zip(res[c], rows)] for c in unit.observed}


def gap(unit: Any, res: dict[Any, list[np.ndarray]], part: Part,
        columns: Iterable[Any] | None = None) -> float:
    """Pooled gap of `part` of `unit`: RMS of the normalised residuals `res` (of `columns`,
    default all)."""
    return rms(part_vector(unit, res, part, columns))


def deviates(unit, res):
    """Whether some observed signal's held-out gap exceeds DEVIATES times its own noise."""
    return any(gap(unit, res, HELD_OUT, [c]) > DEVIATES * unit.noise[c] for c in unit.observed)


def noise_floor(unit, columns=None):
    """Pooled noise floor of the unit's observed columns (of `columns`, default all;
    normalised)."""
    return pooled([unit.noise[c] for c in columns or unit.observed])


def row_squares(unit, res, part, columns=None):
    """Per run, per row of `part`: the sum over observed columns (of `columns`, default all) of
    the squared residuals."""
    rows = part_rows(unit, part)
    return [np.nansum([np.square(res[c][i][m]) for c in columns or unit.observed], axis=0)
            for i, m in enumerate(rows)]


def bootstrap(unit, residual_sets, columns=None, seed=0):
    """Block-bootstrap resamples of held-out gaps: array [resample, set] for each residual set."""
    blocks = [(i, chunk) for i, m in enumerate(part_rows(unit, HELD_OUT))
              for chunk in split_blocks(m)]
    cols = columns or unit.observed
    sums = np.array([[sum(float(np.nansum(np.square(res[c][i][chunk]))) for c in cols)
                      for res in residual_sets] for i, chunk in blocks])
    counts = np.array([chunk.size * len(cols) for _, chunk in blocks], float)
    return block_bootstrap(sums, counts, seed)


def before_after(unit, before, after, columns=None):
    """Held-out gap of residuals `before` and `after` (of `columns`, default all) with their 95 %
    block-bootstrap intervals."""
    b = bootstrap(unit, [before, after], columns)
    return {"before": gap(unit, before, HELD_OUT, columns),
            "after": gap(unit, after, HELD_OUT, columns),
            "interval_before": interval95(b[:, 0]), "interval_after": interval95(b[:, 1])}


def worst_windows(unit, res, count=WINDOWS, fraction=0.05):
    """The `count` time windows (a `fraction` of each experiment) with the largest gap."""
    rows = []
    for i, run in enumerate(unit.runs):
        sq = np.nansum([np.square(res[c][i]) for c in unit.observed], axis=0)
        rows += [(g, run.experiment, run.t0 + float(run.time[a]), run.t0 + float(run.time[b]))
                 for g, a, b in window_gaps(sq, len(unit.observed), fraction)]
    rows.sort(reverse=True)
    return [{"experiment": e, "t0": a, "t1": b, "gap": g} for g, e, a, b in rows[:count]]
