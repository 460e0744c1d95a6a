"""The controllers' FMUs (components/control/slaves.py): the PID and the gain-scheduled PID are
their core stepped by hand, with direct feedthrough of the error; bad schedules are named."""
import pytest

from musclesim.components.control import pid
from musclesim.components.control.slaves import PID, GainScheduledPID

from conftest import in_process

DT = 1e-3


def step(slave, u_s, u_m):
    """Set the inputs, read (y, e), then step: what a master does at a communication point."""
    slave.u_s, slave.u_m = u_s, u_m
    slave.set_real([], [])
    slave.get_real([])
    y, e = slave.y, slave.e
    slave.do_step(slave.time, DT)
    return y, e


def test_pid_is_its_core_stepped_by_hand():
    slave = in_process(PID, "pid", Kp=2.0, Ki=5.0, Kd=0.01, Tf=0.005, u_max=3.0)
    slave.enter_initialization_mode()
    slave.exit_initialization_mode()
    p = pid.PIDParams(2.0, 5.0, 0.01, 0.005, -1e30, 3.0)
    state, dt = pid.PIDState(), 0.0
    for k in range(200):
        r, y = 1.0, 0.002 * k  # a measurement creeping up to the reference
        assert step(slave, r, y) == (pid.output(state, r, y, dt, (2.0, 5.0, 0.01), p), r - y), k
        state, dt = pid.update(state, r, y, DT, (2.0, 5.0, 0.01), p), DT


def test_the_output_follows_the_inputs_at_once():
    slave = in_process(PID, "pid", Kp=4.0)
    assert PID.declarations()["y"].depends == ("u_s", "u_m")
    slave.enter_initialization_mode()
    slave.exit_initialization_mode()
    assert step(slave, 1.0, 0.25) == (3.0, 0.75)  # Kp e with no history


def test_scheduled_gains_are_interpolated_on_the_reference():
    params = {f"Kp[{i}]": float(i) for i in range(1, 22)}
    slave = in_process(GainScheduledPID, "gs", **params)
    slave.enter_initialization_mode()
    slave.exit_initialization_mode()
    x = [getattr(slave, f"x[{i}]") for i in range(1, 22)]
    table = [(float(i), 0.0, 0.0) for i in range(1, 22)]
    for r in (x[0], (x[3] + x[4]) / 2, x[-1]):
        slave.u_s = r
        assert slave.gains() == pid.scheduled_gains(r, x, table)
    assert slave.gains()[0] == 21.0
    slave.u_s = (x[3] + x[4]) / 2
    assert slave.gains()[0] == pytest.approx(4.5)


def test_a_schedule_that_does_not_increase_is_refused():
    slave = in_process(GainScheduledPID, "gs", **{"x[3]": 0.0})
    with pytest.raises(ValueError, match="scheduling points x\\[1..21\\] must increase"):
        slave.setup()


@pytest.mark.parametrize("cls, params", [
    (PID, {"Kp": 2.0, "Ki": 5.0, "Kd": 0.01, "Tf": 0.005, "u_max": 3.0, "u_min": -0.5}),
    (GainScheduledPID, {**{f"Kp[{i}]": 0.5 * i for i in range(1, 22)},
                        **{f"Ki[{i}]": 0.1 * i for i in range(1, 22)}, "Kd[4]": 0.01,
                        "Tf": 0.002, "u_max": 40.0})])
def test_the_compiled_kernel_is_its_python_bit_for_bit(cls, params):
    """The kernel's compiled evaluate and advance give the bits of their plain-Python source on a
    run through saturation and a reference sweeping the schedule."""
    import math

    from kernel_paths import assert_paths_agree

    def inputs(k):
        return {"u_s": 310.0 + 60.0 * math.sin(k / 40), "u_m": 300.0 + 0.3 * k}
    assert_paths_agree(in_process(cls, "c", **params), inputs, DT, 300)


def test_a_nan_reference_is_refused_by_the_scheduled_pid():
    slave = in_process(GainScheduledPID, "gs")
    slave.enter_initialization_mode()
    slave.exit_initialization_mode()
    slave.u_s = float("nan")
    with pytest.raises(ValueError, match="input u_s is NaN at t = 0 s"):
        slave.do_step(0.0, DT)
