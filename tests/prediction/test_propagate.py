"""The prediction's arithmetic (musclesim.prediction.propagate) on cases worked by hand."""
import math

import numpy as np
import pytest

from musclesim.prediction import (ADMIT, LEVEL, Z, admitted, covariance, interval, outcome_sd,
                                  points)


def test_a_linear_outcome_of_a_linear_fit_has_the_textbook_interval():
    """One value theta measured twice, y1 = theta (sd 0.1) and y2 = 2 theta (sd 0.2): the weighted
    Jacobian is [10, 10], so var(theta) = 1 / 200. An outcome 3 theta + 1 has sd 3 / sqrt(200),
    and its slope by central differences at `points` is exactly 3."""
    def outcome(theta):
        return 3 * theta + 1

    J = np.array([[1 / 0.1], [2 / 0.2]])
    cov = covariance(J)
    assert cov[0, 0] == pytest.approx(1 / 200)
    lo, hi = points(0.5, 0.0, 1.0, math.sqrt(cov[0, 0]))  # a secant over one sd either side
    slope = (outcome(hi) - outcome(lo)) / (hi - lo)
    assert slope == pytest.approx(3.0)
    sd = outcome_sd(np.array([slope]), cov)
    assert sd == pytest.approx(3 / math.sqrt(200))
    low, high = interval(outcome(0.5), sd)
    assert (low, high) == pytest.approx((2.5 - 1.6448536 * sd, 2.5 + 1.6448536 * sd))
    assert LEVEL == 0.9 and Z == pytest.approx(1.6448536, abs=1e-7)


def test_two_correlated_values_propagate_through_their_covariance():
    """y1 = a + b, y2 = a - b, y3 = a (sd 1): J^T J = [[3, 0], [0, 2]]; an outcome a + b has
    variance 1/3 + 1/2."""
    cov = covariance(np.array([[1.0, 1.0], [1.0, -1.0], [1.0, 0.0]]))
    assert outcome_sd(np.array([1.0, 1.0]), cov) == pytest.approx(math.sqrt(1 / 3 + 1 / 2))


def test_values_the_residuals_do_not_pin_have_no_covariance():
    with pytest.raises(np.linalg.LinAlgError):
        covariance(np.array([[1.0, 2.0], [2.0, 4.0]]))


def test_a_difference_at_a_bound_is_one_sided():
    assert points(0.0, 0.0, 0.3, 0.003) == pytest.approx((0.0, 0.003))
    assert points(14.9, -5.0, 15.0, 0.2) == pytest.approx((14.7, 15.0))


def test_the_interval_is_the_models_envelope_widened_by_the_fit():
    assert interval(10.0, 0.0, [9.0, 12.0]) == (9.0, 12.0)  # no fit uncertainty: the spread
    lo, hi = interval(10.0, 2.0, [11.0])
    assert lo == pytest.approx(10.0 - 2 * Z) and hi == pytest.approx(11.0 + 2 * Z)
    assert interval(1e-7, 1e-6, [1e-6], nonnegative=True)[0] == 0.0  # a peak-to-peak


def test_a_model_is_admitted_when_it_fits_about_as_well_as_the_reference():
    assert ADMIT == pytest.approx(2.7055, abs=1e-4)  # chi-square, one degree of freedom, 90 %
    assert admitted(160.0, 163.0) and admitted(165.0, 163.0)
    assert not admitted(166.0, 163.0) and not admitted(math.inf, 163.0)


def test_the_written_out_quantiles_are_scipys():
    from scipy import stats

    assert Z == float(stats.norm.ppf(0.5 + LEVEL / 2))
    assert ADMIT == float(stats.chi2.ppf(LEVEL, 1))
