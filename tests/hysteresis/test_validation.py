"""musclesim.hysteresis.validation: the validation numbers of identified FORC surfaces
(§forc-identification): surface error, strain error, validation runs and the virtual wire's
memory checks, on the shipped sets and on cases whose answer is known by hand."""
import math

import numpy as np
import pytest

from musclesim.components.sma import datasets
from musclesim.components.sma.reference_wire import ReferenceWire
from musclesim.hysteresis import validation


def test_the_virtual_wire_is_rate_independent_wipes_out_and_has_congruent_loops():
    checks = validation.memory_checks()
    assert checks["rate_independence"] < 1e-12
    assert checks["wiping_out"] < 1e-12
    assert checks["congruency"] < 1e-12
    # the checks are not void: the histories differ before the erasure, the loops' starts differ
    assert checks["memory"] > 1e-3 and checks["offset"] > 1e-4 and checks["loop_span"] > 5e-4


def test_the_shipped_identified_set_validates_on_unseen_runs():
    surface = datasets.surface(2)
    err = validation.surface_error(surface)
    assert err["max_abs"] < 2e-4 and err["max_rel"] < 0.005
    runs = validation.validation_runs(surface, duration=200.0)
    assert set(runs) == {"minor loops, 120 MPa", "random peaks, 130 MPa", "LP I", "LP V"}
    for name, r in runs.items():
        assert r["rmse_percent"] < 1.5, name  # the 5 C grid itself costs ~0.5-0.9 %
        assert math.isfinite(r["max_abs"])


def test_the_exact_surface_has_no_error_and_an_offset_surface_its_offset():
    """The reference wire tabulated on a grid is its own F there (error 0 to rounding); a table
    raised by 1e-4 everywhere on the lower triangle errs by 1e-4, at the first stress that
    shows it."""
    wire = ReferenceWire()
    exact = wire.hypersurface(np.arange(30.0, 131.0, 10.0), [110e6, 140e6])
    err = validation.surface_error(exact, wire)
    assert err["max_abs"] < 1e-12 and set(err["per_stress"]) == {110e6, 140e6}
    raised = exact.table.copy()
    i, j = np.tril_indices(len(exact.temps))
    raised[:, i, j] += 1e-4

    class Raised:
        temps, stresses, table = exact.temps, exact.stresses, raised

    err = validation.surface_error(Raised, wire)
    assert err["max_abs"] == pytest.approx(1e-4, rel=1e-6)
    assert err["per_stress"][110e6] == pytest.approx(1e-4, rel=1e-6)
    assert err["max_rel"] == pytest.approx(1e-4 / float(wire.eps_max(err["at"][0])), rel=1e-6)


def test_the_strain_error_of_a_model_against_itself_and_against_an_offset():
    surface = datasets.surface(0)
    T = 80.0 - 40.0 * np.cos(np.linspace(0.0, 4 * math.pi, 400))
    own = validation.strain_error(surface, T, 120e6, np.full_like(T, 0.01))
    same = validation.strain_error(surface, T, 120e6, own["eps"])
    assert same["rmse"] == 0.0 and same["max_abs"] == 0.0
    shifted = validation.strain_error(surface, T, 120e6, own["eps"] + 1e-3)
    assert shifted["rmse"] == pytest.approx(1e-3, rel=1e-9)
    assert shifted["rmse_percent"] == pytest.approx(
        100 * 1e-3 / float(np.abs(own["eps"] + 1e-3).max()), rel=1e-9)


def test_the_validation_profiles_span_the_band_and_the_stresses_they_name():
    profiles = validation.validation_profiles(duration=100.0, dt=0.5)
    assert set(profiles) == {"minor loops, 120 MPa", "random peaks, 130 MPa", "LP I", "LP V"}
    for name, (t, T, sigma) in profiles.items():
        assert len(t) == len(T) == len(sigma) == 201, name
        assert t[0] == 0.0 and t[-1] == 100.0
        assert 30.0 - 1e-9 <= T.min() and T.max() <= 130.0 + 1e-9, name
    assert np.all(profiles["minor loops, 120 MPa"][2] == 120e6)
    assert np.all(profiles["random peaks, 130 MPa"][2] == 130e6)
    lp = profiles["LP I"][2]
    assert 105e6 - 1 <= lp.min() < lp.max() <= 145e6 + 1  # LP I: 105..145 MPa (§position-control)
