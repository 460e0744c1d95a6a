"""Fitting free parameters of a unit on the training part: `Free`, `fit` and its 95 % intervals.

A fit scans the parameters' box coarsely, then runs bounded trust-region least squares from the
best point; it is scored on the held-out part by the caller. `fit_task` is the same as one
picklable task for a ``pmap`` (Dask).
"""
import itertools
import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize

from musclesim.cosim import reuse_fmus

from musclesim.diagnosis.simulate import Failed, residuals, simulate
from musclesim.diagnosis.stats import gap, part_rows, part_vector


@dataclass(frozen=True)
class Free:
    """A free parameter: on `instances`, `name` between `lower` and `upper` (absolute values)."""

    instances: tuple
    name: str
    lower: float
    upper: float
    start: float  # its nominal value


def values_of(free, x):
    """``{(instance, parameter): value}`` of the `Free` parameters `free` at values `x`."""
    return {(inst, f.name): v for f, v in zip(free, x) for inst in f.instances}


def fit(unit, free, fmu_dir, fixed=None, x0=None):
    """Fit `free` on the training part; return a dict with values, intervals and residuals.

    A coarse scan of the box (5 points per parameter, or the start and the corners' midpoints)
    picks the start of a bounded trust-region least-squares fit in box coordinates [0, 1].
    """
    fixed = dict(fixed or {})
    lo = np.array([f.lower for f in free])
    span = np.array([f.upper - f.lower for f in free])
    cache = {}

    def run(z):
        key = tuple(np.round(z, 12))
        if key not in cache:
            x = lo + span * np.clip(z, 0, 1)
            try:
                sims = simulate(unit, {**fixed, **values_of(free, x)}, fmu_dir)
                cache[key] = residuals(unit, sims)
            except Failed:
                cache[key] = None
        return cache[key]

    def train_vector(z):
        res = run(z)
        if res is None:
            return np.full(_train_size(unit), 1e3)
        return part_vector(unit, res, 0)

    starts = [np.clip((np.array([f.start for f in free]) - lo) / span, 0, 1)]
    if x0 is not None:
        starts.append(np.clip((np.asarray(x0) - lo) / span, 0, 1))
    grid = np.linspace(0, 1, 5) if len(free) == 1 else np.array([0.1, 0.5, 0.9])
    starts += [np.array(p) for p in itertools.product(grid, repeat=len(free))]
    costs = [float(np.sum(np.square(train_vector(z)))) for z in starts]
    z0 = starts[int(np.argmin(costs))]
    opt = optimize.least_squares(train_vector, z0, bounds=(0, 1), x_scale=1.0,
                                 diff_step=1e-3, max_nfev=12 * len(free) + 8, method="trf")
    z = opt.x  # trust-region steps never end above their start's cost
    x = lo + span * z
    interval = _interval(opt, lo, span)
    res = run(z)
    applicable = len({round(c, 12) for c in costs}) > 1
    return {"x": [float(v) for v in x], "interval": interval, "residuals": res,
            "train_gap": gap(unit, res, 0) if res else math.inf,
            "heldout_gap": gap(unit, res, 1) if res else math.inf,
            "applicable": applicable, "evaluations": len(cache)}


def fit_task(args):
    """One fit, as a Dask task: (unit, free, fmu_dir, fixed, x0) -> fit(), its FMUs read and
    unpacked once for all its runs."""
    with reuse_fmus():
        return fit(*args)


def _train_size(unit):
    return sum(int(np.count_nonzero(m)) for m in part_rows(unit, 0)) * len(unit.observed)


def _interval(opt, lo, span):
    """95 % intervals from the Jacobian, the residuals' autocorrelation widening them."""
    r, J = opt.fun, opt.jac
    m, n = J.shape
    rho = float(np.corrcoef(r[:-1], r[1:])[0, 1]) if m > 2 and np.std(r) > 0 else 0.0
    inflate = (1 + max(rho, 0)) / max(1 - max(rho, 0), 1e-3)
    s2 = 2 * opt.cost / max(m - n, 1) * inflate
    try:
        cov = s2 * np.linalg.inv(J.T @ J)
        half = 1.96 * np.sqrt(np.clip(np.diag(cov), 0, None))
    except np.linalg.LinAlgError:
        half = np.full(n, np.inf)
    out = []
    for z, h, l, w in zip(opt.x, half, lo, span):
        out.append((float(l + w * max(z - h, 0)), float(l + w * min(z + h, 1))))
    return out
