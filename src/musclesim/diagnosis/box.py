"""Box coordinates of a fit (a value is ``lower + (upper - lower) * z``, z in [0, 1]): the
scan's points (`axis`, `period_axis`, `scan`), the forward-difference `step`, and 95 %
intervals of values from a Jacobian (`box_intervals`, `residual_intervals`).

>>> axis(0.0)  # from an effect's off value at a bound: 1/8, 1/2 and all of the way
[0.0, 0.125, 0.5, 1.0]
"""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from musclesim.diagnosis.thresholds import PERIOD_POINTS

__all__ = ["step", "scan", "moved", "axis", "period_axis", "residual_intervals",
           "box_intervals"]


def step(z: float) -> float:
    """Forward-difference step in box coordinates, toward the box's inside."""
    return 1e-3 if z <= 0.5 else -1e-3


def scan(base: np.ndarray, axes: Sequence[Sequence[float]],
         cost: Callable[[np.ndarray], float],
         simulated: Callable[[list[np.ndarray]], object]) -> tuple[np.ndarray, bool]:
    """(start, applicable) from a scan, by `cost`, of the first coordinates around `base`, one
    for each of `axes` (its points): each along its axis alone, then the best of each together.
    ``applicable``: the cost changes at all. `simulated` runs the points of the axes together
    first (``simulated(points)``)."""
    count = len(axes)
    axes = [[p for p in pts if p != base[i]] for i, pts in enumerate(axes)]
    simulated([base] + [moved(base, i, p) for i, pts in enumerate(axes) for p in pts])
    c0 = cost(base)
    best, costs = base.copy(), [c0]
    for i, pts in enumerate(axes):
        cs = [cost(moved(base, i, p)) for p in pts]
        costs += cs
        if cs and min(cs) < c0:
            best[i] = pts[int(np.argmin(cs))]
    candidates = [(c0, base)]
    if count > 1 and not np.array_equal(best, base):
        candidates.append((cost(best), best))
    for i in range(count):  # each axis's best alone
        if best[i] != base[i]:
            z = moved(base, i, best[i])
            candidates.append((cost(z), z))
    return min(candidates, key=lambda t: t[0])[1], len({round(v, 12) for v in costs}) > 1


def moved(z: np.ndarray, i: int, value: float) -> np.ndarray:
    """`z` with coordinate `i` at `value` (a copy)."""
    out = z.copy()
    out[i] = value
    return out


def axis(z0: float) -> list[float]:
    """Scan points of one parameter in box coordinates: from its start `z0` (an effect's off
    value) toward each bound at 1/8, 1/2 and all of the way: effects are mostly small next to
    their bounds, so the points crowd near off, where a narrow optimum (a 0.2 s lag in [0, 2] s)
    would fall between even steps."""
    fractions = (0.125, 0.5, 1.0)
    points = {z0} | {z0 + f * (1 - z0) for f in fractions} | {z0 - f * z0 for f in fractions}
    return sorted(points)


def period_axis(z0: float, width: float) -> list[float]:
    """Scan points of a periodic parameter in box coordinates: `PERIOD_POINTS` evenly over one
    period (`width` in box coordinates) from its start `z0`, each moved by whole periods into
    the box [0, 1] where it falls outside."""
    points = (z0 + k * width / PERIOD_POINTS for k in range(PERIOD_POINTS))
    return sorted(p - width * math.floor(p / width) if not 0 <= p <= 1 else p for p in points)


def residual_intervals(r: np.ndarray, J: np.ndarray, z: np.ndarray, lo: np.ndarray,
                       span: np.ndarray) -> list[tuple[float, float]]:
    """95 % intervals of the values at box coordinates `z` from the residuals `r` and Jacobian
    `J` there, the residuals' autocorrelation widening them."""
    m, n = J.shape
    rho = float(np.corrcoef(r[:-1], r[1:])[0, 1]) if m > 2 and np.std(r) > 0 else 0.0
    inflate = (1 + max(rho, 0)) / max(1 - max(rho, 0), 1e-3)
    return box_intervals(J, z, lo, span, float(r @ r) / max(m - n, 1) * inflate)


def box_intervals(J: np.ndarray, z: np.ndarray, lo: Sequence[float] | np.ndarray,
                  span: Sequence[float] | np.ndarray,
                  variance: float = 1.0) -> list[tuple[float, float]]:
    """95 % intervals of values at box coordinates `z` (a value is ``lo + span * z``) from the
    Jacobian `J` of residuals of `variance` there (1: residuals already weighed by their standard
    deviations): covariance ``variance (J^T J)^-1``, clipped to the box; a value the residuals do
    not pin (a singular matrix) spans its bounds."""
    try:
        cov = variance * np.linalg.inv(J.T @ J)
        half = 1.96 * np.sqrt(np.clip(np.diag(cov), 0, None))
    except np.linalg.LinAlgError:
        half = np.full(J.shape[1], np.inf)
    return [(float(l + w * max(c - h, 0)), float(l + w * min(c + h, 1)))
            for c, h, l, w in zip(z, half, lo, span)]
