"""musclesim.analysis.design: the PI designs the linear analyses share, against python-control
and by hand."""
import cmath
import math

import control as ct
import numpy as np
import pytest

from musclesim.analysis.design import design_pi, discrete_pi, pi_margins


@pytest.mark.parametrize("a, b", [(-0.58, 0.31), (-0.1, 2.0), (-476.0, 480.0)])
def test_pi_placement_by_hand_is_python_controls_place(a, b):
    """design_pi's Kp = (2 zeta omega_n + a) / b, Ki = omega_n^2 / b (written out, no LAPACK) are
    the gains python-control's `place` finds on the plant augmented with the error's integral."""
    omega_n, zeta = 8.0, 0.9
    wd = omega_n * np.sqrt(1 - zeta ** 2)
    K = ct.place(np.array([[a, 0.0], [-1.0, 0.0]]), np.array([[b], [0.0]]),
                 [complex(-zeta * omega_n, wd), complex(-zeta * omega_n, -wd)])
    plant = ct.ss([[a]], [[b]], [[1.0]], [[0.0]])
    np.testing.assert_allclose(design_pi(plant, omega_n, zeta), (K[0, 0], -K[0, 1]), rtol=1e-12)


def test_margins_of_a_pi_cancelling_a_first_order_lag_are_an_integrators():
    """Plant 1 / (s + 1) under the PI 1 + 1 / s = (s + 1) / s: the loop is 1 / s, crossing 0 dB
    at 1 rad/s with -90 deg (phase margin 90 deg) and never reaching -180 deg (gain margin
    infinite). Sampled with a zero-order hold at T, the loop T / (z - 1) closes with its pole at
    1 - T; the lag's mode, cancelled in the product but kept in its realisation, samples to
    exp(-T), the larger radius."""
    plant = ct.ss([[-1.0]], [[1.0]], [[1.0]], [[0.0]])
    m = pi_margins(plant, 1.0, 1.0, 0.1)
    assert m["gain_margin"] is None
    assert m["phase_margin_deg"] == pytest.approx(90.0, abs=1e-6)
    assert m["crossover"] == pytest.approx(1.0, rel=1e-6)
    assert m["sampled_pole_radius"] == pytest.approx(math.exp(-0.1), rel=1e-9)
    assert pi_margins(plant, 1.0, 1.0, 1.5)["sampled_pole_radius"] == pytest.approx(0.5)


@pytest.mark.parametrize("crossover, zero_ratio, step", [(20.0, 4.0, 1e-3), (5.0, 2.0, 0.01)])
def test_a_discrete_pi_puts_the_loop_gain_at_one_on_the_crossover(crossover, zero_ratio, step):
    """For the discrete integrator T / (z - 1): the PI's zero ratio is Ki / Kp = crossover /
    zero_ratio, and |(Kp + Ki T / (z - 1)) P(z)| = 1 at z = exp(j crossover T)."""
    def plant(z):
        return step / (z - 1.0)

    Kp, Ki = discrete_pi(plant, crossover, zero_ratio, step)
    assert Ki / Kp == pytest.approx(crossover / zero_ratio, rel=1e-15)
    z = cmath.exp(1j * crossover * step)
    assert abs((Kp + Ki * step / (z - 1.0)) * plant(z)) == pytest.approx(1.0, rel=1e-12)
