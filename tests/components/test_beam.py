"""The beam pair (components/bending/beam.py, §bending-actuator) against Euler-Bernoulli by hand,
and its exact damped-oscillator step."""
import pytest

from musclesim.components.bending import beam


def test_beam_pair_under_an_end_moment_matches_the_cantilever_by_hand():
    """Cantilever of length L, end moment M: tip deflection M L^2 / 2EI, tip slope M L / EI; the
    rigid cap and foot above carry the slope on (w = w_L + slope (z - L))."""
    p = beam.BeamParams(length=0.01, n_beams=2, width=1e-3, thickness=0.2e-3, modulus=120e9)
    EI = 2 * 120e9 * 1e-3 * (0.2e-3) ** 3 / 12  # 1.6e-4 N m^2
    M = 1e-3  # N m
    theta = M / beam.rotational_stiffness(p)
    assert theta == pytest.approx(M * 0.01 / EI, rel=1e-12)
    assert beam.deflection(theta, 0.01, p) == pytest.approx(M * 0.01 ** 2 / (2 * EI), rel=1e-12)
    assert beam.deflection(theta, 0.017, p) == pytest.approx(
        M * 0.01 ** 2 / (2 * EI) + M * 0.01 / EI * 0.007, rel=1e-12)
    assert beam.deflection(theta, 0.005, p) == pytest.approx(M * 0.005 ** 2 / (2 * EI), rel=1e-12)


def test_oscillator_step_is_exact_in_every_damping_regime():
    for c in (0.0, 0.5, 4.0, 10.0):  # undamped, under-, critically, over-damped (K = J = 4)
        x, v = 1.0, 0.0
        for _ in range(100):
            x, v = beam.oscillator_step(x, v, 0.25, 4.0, c, 4.0, 0.01)
        big = beam.oscillator_step(1.0, 0.0, 0.25, 4.0, c, 4.0, 1.0)
        assert (x, v) == pytest.approx(big, rel=1e-9, abs=1e-12)
