"""The arithmetic of a prediction with a 90 % interval (§predictions): a fit's covariance from
its weighted Jacobian, an outcome's standard deviation through it (linearised), which
alternative models fit about as well as the reference, and how the two parts make one interval.

>>> cov = covariance(np.array([[2.0, 0.0], [0.0, 4.0]]))   # residuals over their sd
>>> float(outcome_sd(np.array([1.0, 1.0]), cov))           # sqrt(1/4 + 1/16)
0.5590169943749475
>>> [round(v, 4) for v in interval(10.0, 1.0, [9.0, 12.0])]  # spread [9, 12], +- 1.645 sd
[7.3551, 13.6449]
"""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

LEVEL = 0.90  # the intervals' level
# two-sided normal quantile of LEVEL: the fit's part is +- Z standard deviations. The quantiles
# are written out, as scipy.stats gives them (a test checks them): importing scipy.stats here
# would cost every `musclesim run` a second, since the run reads the shipped predictions
Z = 1.6448536269514722  # scipy.stats.norm.ppf(0.5 + LEVEL / 2)
# An alternative model is admitted to the spread when its chi-square on its data set is at most
# this much above the reference model's (the same data set fitted with nothing opened): the
# 90 % quantile of chi-square with one degree of freedom, what a likelihood-ratio test at 90 %
# tolerates for one parameter. Each alternative opens one or more values on top of the
# reference, so a proper fit can only lower its chi-square; one that ends far above it failed.
ADMIT = 2.705543454095404  # scipy.stats.chi2.ppf(LEVEL, 1)
# The fit's Jacobian is taken by central differences of this fraction of each value's bounds'
# range: above the scale at which the relay's metrics step (a switching instant resolved to one
# communication step; the fit's own forward differences, a thousandth of the range, measure that
# step), below the scale of the fit's uncertainty for the values the relay sets. An outcome's
# slopes are secants over one standard deviation of each value either side (`points`): its
# trend over the values the fit allows, which a slope at a point misses where the outcome bends.
STEP = 0.01

def covariance(weighted_jacobian: np.ndarray) -> np.ndarray:
    """Covariance ``(J^T J)^-1`` of fitted values from the Jacobian of their residuals, each row
    divided by its residual's standard deviation (`weighted_jacobian`, residuals x values).

    Raises
    ------
    numpy.linalg.LinAlgError
        When the residuals do not pin every value (a singular matrix).
    """
    J = np.asarray(weighted_jacobian, float)
    return np.linalg.inv(J.T @ J)


def outcome_sd(gradient: np.ndarray, cov: np.ndarray) -> float:
    """Standard deviation ``sqrt(g^T C g)`` of an outcome of `gradient` g (its slope in each
    fitted value) under the values' covariance `cov`: the linearised propagation."""
    g = np.asarray(gradient, float)
    return float(math.sqrt(max(float(g @ cov @ g), 0.0)))


def points(value: float, lower: float, upper: float, step: float) -> tuple[float, float]:
    """The two values a central difference of `step` at `value` runs, held within (`lower`,
    `upper`) (one-sided at a bound)."""
    return max(lower, value - step), min(upper, value + step)


def admitted(chi2: float, reference: float) -> bool:
    """Whether a model of chi-square `chi2` fits about as well as the `reference` model's
    (within `ADMIT`)."""
    return math.isfinite(chi2) and chi2 <= reference + ADMIT


def interval(value: float, sd: float, models: Sequence[float] = (),
             nonnegative: bool = False) -> tuple[float, float]:
    """The 90 % interval of an outcome: the span of `value` (the shipped model's) and the
    outcome under each admitted alternative model (`models`), widened on each side by `Z` times
    the fit's standard deviation `sd`; held at 0 from below for a `nonnegative` outcome (a
    peak-to-peak, a frequency, an RMS).

    The models' spread is not a sample of a distribution (they are the diagnosis's rivals, not
    draws), so it is taken whole, an envelope, and the fit's part is added to its ends: where the
    models agree this is the fit's linearised interval, where they disagree it covers each one's.
    """
    lo = min([value, *models]) - Z * sd
    hi = max([value, *models]) + Z * sd
    return (max(lo, 0.0) if nonnegative else lo), hi
