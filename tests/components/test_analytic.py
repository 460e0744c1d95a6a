"""Closed-form FORC surfaces (components/sma/analytic.py): the uniform density's increment by
hand, and the SMA-like surface's saturation, amplitude growth and Clausius-Clapeyron shift."""
import pytest

from musclesim.components.sma.analytic import SmaLikeParams, sma_like_surface, uniform


def test_uniform_increment_is_half_c_times_the_square_of_the_width():
    F = uniform(2e-5)
    assert F(130.0, 30.0, 125e6) == 0.5 * 2e-5 * 100.0 ** 2 == pytest.approx(0.1)
    assert F(70.0, 70.0, 0.0) == 0.0
    assert F(80.0, 60.0, 1.0) == F(80.0, 60.0, 2e8)  # no stress dependence


def test_sma_like_surface_saturates_at_the_grid_ends():
    p = SmaLikeParams()
    assert p.F(p.hi, p.lo, p.sigma_ref) == pytest.approx(p.eps_max, rel=1e-12)
    assert p.F(p.lo, p.lo, 125e6) == 0.0 and p.F(p.hi, p.hi, 125e6) == 0.0
    # the amplitude grows linearly with stress
    ratio = p.F(p.hi, p.lo, 145e6) / p.F(p.hi, p.lo, p.sigma_ref)
    assert ratio == pytest.approx(1 + p.growth * 40e6, rel=1e-12)


def test_transitions_shift_with_stress_by_the_clausius_clapeyron_slope():
    p = SmaLikeParams()
    # heating from the cold end to T: the same share of the full strain at T + d sigma / slope
    for T in (80.0, 93.0, 100.0):
        at_mid = p.F(T, p.lo, p.sigma_mid) / p.F(p.hi, p.lo, p.sigma_mid)
        shifted = T + 14e6 / p.slope
        at_high = p.F(shifted, p.lo, p.sigma_mid + 14e6) / p.F(p.hi, p.lo, p.sigma_mid + 14e6)
        assert at_high == pytest.approx(at_mid, abs=2e-3)


def test_tabulated_surface_is_the_function_on_its_grid():
    s = sma_like_surface()
    p = SmaLikeParams()
    for a, b, sigma in ((130.0, 30.0, 105e6), (95.0, 65.0, 125e6), (100.0, 40.0, 145e6)):
        assert s.F(a, b, sigma) == pytest.approx(p.F(a, b, sigma), rel=1e-12, abs=1e-15)
