"""Discrete PID and gain scheduling (§temperature-control) against hand-derived closed loops and
invariants."""
import math

import pytest

from musclesim.components.control import pid


def closed_loop(p, gains, a=0.9, b=0.1, r=1.0, n=400, dt=0.01):
    """PID on the discrete first-order plant y[k+1] = a y[k] + b u[k]; returns (y, u) lists."""
    state, y, ys, us = pid.PIDState(), 0.0, [], []
    for _ in range(n):
        u = pid.output(state, r, y, dt, gains, p)
        state = pid.update(state, r, y, dt, gains, p)
        ys.append(y)
        us.append(u)
        y = a * y + b * u
    return ys, us


def test_proportional_control_leaves_the_hand_derived_offset():
    K = 4.0
    ys, _ = closed_loop(pid.PIDParams(Kp=K), (K, 0.0, 0.0))
    # static gain of the plant b / (1 - a) = 1: y_ss = K / (1 + K) r
    assert ys[-1] == pytest.approx(K / (1 + K), rel=1e-9)


def test_integral_action_removes_the_offset():
    ys, _ = closed_loop(pid.PIDParams(Kp=2.0, Ki=5.0), (2.0, 5.0, 0.0), n=3000)
    assert ys[-1] == pytest.approx(1.0, abs=1e-6)


def test_output_limits_and_no_windup():
    p = pid.PIDParams(Kp=2.0, Ki=50.0, u_min=0.0, u_max=1.5)
    ys, us = closed_loop(p, (2.0, 50.0, 0.0), r=1.0, n=3000)
    assert max(us) <= 1.5 and min(us) >= 0.0
    assert ys[-1] == pytest.approx(1.0, abs=1e-6)
    # with the output pinned at its limit the integral stops growing
    state = pid.PIDState()
    for _ in range(100):
        state = pid.update(state, 10.0, 0.0, 0.01, (2.0, 50.0, 0.0), p)
    assert state.integral == 0.0


def test_derivative_acts_on_the_measurement_without_kick():
    p = pid.PIDParams(Kp=0.0, Kd=1.0, Tf=0.0)
    state = pid.PIDState()
    assert pid.output(state, 5.0, 0.0, 0.01, (0.0, 0.0, 1.0), p) == 0.0  # first sample: no kick
    state = pid.update(state, 5.0, 0.0, 0.01, (0.0, 0.0, 1.0), p)
    assert pid.output(state, 5.0, 0.02, 0.01, (0.0, 0.0, 1.0), p) == pytest.approx(-2.0)
    state = pid.update(pid.PIDState(), 0.0, 0.0, 0.01, (0.0, 0.0, 1.0), pid.PIDParams(Tf=0.09))
    assert pid.derivative_term(state, 0.02, 0.01, 1.0, 0.09) == pytest.approx(-0.2)  # -Kd
    #                                                                                  dy/(Tf+dt)


def test_scheduled_gains_interpolate_and_hold():
    x, table = [0.0, 1.0, 3.0], [(1.0, 0.0, 0.0), (2.0, 1.0, 0.5), (4.0, 3.0, 0.5)]
    assert pid.scheduled_gains(-1.0, x, table) == (1.0, 0.0, 0.0)
    assert pid.scheduled_gains(2.0, x, table) == (3.0, 2.0, 0.5)
    assert pid.scheduled_gains(9.0, x, table) == (4.0, 3.0, 0.5)


@pytest.mark.parametrize("field, value", [("Kd", -1.0), ("Tf", -0.1), ("u_max", -math.inf)])
def test_parameter_check_names_the_parameter(field, value):
    with pytest.raises(ValueError, match=field if field != "u_max" else "u_min"):
        pid.PIDParams(**{field: value}).check()
