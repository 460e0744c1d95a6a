"""The reference wire: calibration to the study's figures (§forc-identification), saturation, stress
dependence, and a FORC increment that is a valid Preisach surface and the integral of the
density."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from musclesim.components.sma import reference_wire as wire
from musclesim.components.sma.preisach import Hypersurface
from musclesim.hysteresis.loops import loops

P = wire.load_params()
WIRE = wire.ReferenceWire(P)
GRID = np.linspace(30.0, 130.0, 101)
STRESSES = (0.0, 50e6, 105e6, 125e6, 145e6, 155e6, 200e6)

# (stress Pa, T_hi C, T_lo C, strain, tolerance): §forc-identification and issue 3 item 2
FIGURES = [(105e6, 130, 30, 0.0376, 0.001),
           (155e6, 130, 30, 0.040, 0.002),
           (155e6, 100, 50, 0.033, 0.002),
           (155e6, 85, 60, 0.021, 0.002)]
FIGURE_IDS = ["max-strain-105MPa", "major-30-130-155MPa", "minor-50-100-155MPa",
              "minor-60-85-155MPa"]


@pytest.mark.parametrize("sigma, hi, lo, target, tol", FIGURES, ids=FIGURE_IDS)
def test_forc_increment_meets_the_measured_figure(sigma, hi, lo, target, tol):
    assert abs(WIRE.F(hi, lo, sigma) - target) <= tol


@pytest.mark.parametrize("sigma, hi, lo, target, tol", FIGURES, ids=FIGURE_IDS)
def test_cycled_loop_reaches_the_figure_in_simulation(sigma, hi, lo, target, tol):
    (loop,) = loops(WIRE, sigma, [(lo, hi)])
    assert loop["peak_to_peak"] == pytest.approx(float(WIRE.F(hi, lo, sigma)), rel=1e-9)
    assert abs(loop["peak_to_peak"] - target) <= tol


def test_identified_style_surface_on_the_5C_grid_gives_the_same_loops():
    h = Hypersurface.from_function(WIRE.F)  # §preisach grid and stresses, as `identify` will write
    (loop,) = loops(h, 125e6, ["50:100"])
    assert loop["peak_to_peak"] == pytest.approx(float(WIRE.F(100, 50, 125e6)), rel=1e-9)


def test_stored_width_quadrature_is_gauss_legendre():
    """The stored 48-node rule (no LAPACK at run time) is numpy's leggauss to rounding, and
    integrates x^k over [-1, 1] to 2 / (k + 1) for even k, 0 for odd, up to degree 95."""
    nodes, weights = np.polynomial.legendre.leggauss(48)
    np.testing.assert_allclose(wire._NODES, nodes, rtol=0, atol=1e-15)
    np.testing.assert_allclose(wire._WEIGHTS, weights, rtol=0, atol=1e-15)
    for k in range(96):
        exact = 2.0 / (k + 1) if k % 2 == 0 else 0.0
        assert float(np.sum(wire._WEIGHTS * wire._NODES ** k)) == pytest.approx(exact, abs=1e-14)


@pytest.mark.parametrize("sigma", [105e6, 125e6, 145e6, 155e6])
def test_saturates_at_30_and_130C(sigma):
    assert WIRE.F(130, 30, sigma) == pytest.approx(float(WIRE.eps_max(sigma)), rel=1e-12)
    assert WIRE.F(200, -10, sigma) == WIRE.F(130, 30, sigma)  # no hysterons outside
    assert wire.outside_mass(sigma, P) < 0.025  # the truncated tails are small
    assert WIRE.F(125, 35, sigma) > 0.97 * WIRE.F(130, 30, sigma)  # flat near saturation
    a, b = np.meshgrid(np.linspace(0, 160, 33), np.linspace(0, 160, 33), indexing="ij")
    outside = (a > 130) | (b < 30) | (a < b)
    assert np.all(WIRE.mu(a, b, sigma)[outside] == 0.0)


@pytest.mark.parametrize("sigma", STRESSES)
def test_forc_increment_is_a_valid_preisach_surface(sigma):
    a, b = np.meshgrid(GRID, GRID, indexing="ij")
    F = np.where(a >= b, WIRE.F(a, b, sigma), 0.0)
    assert np.all(F >= 0)
    assert np.all(np.diag(F) == 0)
    assert np.all(np.diff(F, axis=0)[np.tril_indices(100)] >= -1e-15)  # non-decreasing in a
    assert np.all(np.diff(F, axis=1)[np.tril_indices(100, -1)] <= 1e-15)  # non-increasing in b


@settings(max_examples=60)
@given(st.floats(30, 130), st.floats(30, 130), st.floats(30, 130), st.floats(0, 200e6))
def test_forc_increment_monotone_at_random_points(x, y, z, sigma):
    b, a1, a2 = sorted((x, y, z))
    assert 0 <= WIRE.F(a1, b, sigma) <= WIRE.F(a2, b, sigma) + 1e-15
    assert WIRE.F(a2, a1, sigma) <= WIRE.F(a2, b, sigma) + 1e-15


@pytest.mark.parametrize("sigma", [105e6, 155e6])
def test_forc_increment_is_the_integral_of_the_density(sigma):
    h = 0.05
    t = np.arange(30 + h / 2, 130, h)
    a, b = np.meshgrid(t, t, indexing="ij")
    mu = WIRE.mu(a, b, sigma)
    for hi, lo in [(130, 30), (100, 50), (85, 60)]:
        region = (b >= lo) & (a <= hi)
        assert mu[region].sum() * h * h == pytest.approx(float(WIRE.F(hi, lo, sigma)), rel=2e-4)


def test_stress_raises_the_amplitude_and_the_transformation_temperatures():
    sigmas = np.linspace(0.0, 250e6, 26)
    eps_max = WIRE.eps_max(sigmas)
    assert eps_max[0] == 0 and np.all(np.diff(eps_max) > 0)
    # the normalised heating branch F(T, 30)/eps_max and cooling branch 1 - F(130, T)/eps_max
    # move to higher temperatures: at every T they fall as stress grows
    s = sigmas[1:, None]
    heating = WIRE.F(GRID[None, :], 30.0, s) / WIRE.eps_max(s)
    cooling = 1 - WIRE.F(130.0, GRID[None, :], s) / WIRE.eps_max(s)
    assert np.all(np.diff(heating, axis=0) <= 1e-12)
    assert np.all(np.diff(cooling, axis=0) <= 1e-12)
    assert wire.centre(165e6, P) - wire.centre(155e6, P) == pytest.approx(1e7 / P.cc_slope)


def test_heating_branch_lies_above_cooling_branch_in_temperature():
    # hysteresis: at 155 MPa half the strain is reached on heating well above where it is lost
    # on cooling (by about the mean hysteron width)
    T = np.linspace(30, 130, 2001)
    heat = WIRE.F(T, 30.0, 155e6) / WIRE.eps_max(155e6)
    cool = 1 - WIRE.F(130.0, T, 155e6) / WIRE.eps_max(155e6)
    gap = T[np.searchsorted(heat, 0.5)] - T[np.searchsorted(cool, 0.5)]
    assert gap == pytest.approx(P.width_mean, abs=1.0)


def test_bad_inputs_are_refused():
    with pytest.raises(ValueError, match="non-negative"):
        WIRE.F(100, 50, -1.0)
    with pytest.raises(ValueError, match="finite"):
        WIRE.F(np.nan, 50, 1e8)


def test_parameter_file_entries_each_name_their_source():
    lines = [ln for ln in wire.DEFAULT_PARAMS.read_text().splitlines()
             if "=" in ln and not ln.startswith("#")]
    assert len(lines) == 12
    for line in lines:
        assert "§" in line.split("#", 1)[1], line


@pytest.mark.parametrize("edit, message", [
    (lambda s: s.replace("cc_slope = 10e6", "cc_slope = 10e6\nextra = 1"), "unknown entry 'extra'"),
    (lambda s: s.replace("diffuse_sd = 17.0", ""), "missing entry 'diffuse_sd'"),
    (lambda s: s.replace("width_mean = 15.0", 'width_mean = "15"'),
     "'width_mean' must be a number"),
    (lambda s: s.replace("width_sd = 3.75", "width_sd = -1"), "width_sd must be positive"),
    (lambda s: s.replace("[hysteresis]", "[thermal]"), "no.*hysteresis|hysteresis"),
], ids=["unknown", "missing", "not-a-number", "out-of-range", "no-table"])
def test_loader_names_file_and_entry(tmp_path, edit, message):
    path = tmp_path / "bad.toml"
    path.write_text(edit(wire.DEFAULT_PARAMS.read_text()))
    with pytest.raises(ValueError, match=message) as info:
        wire.load_params(path)
    assert "bad.toml" in str(info.value)
