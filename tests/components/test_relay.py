"""The relay (components/control/relay.py): its switching sequence on a hand-made trace, its
start from its measurement."""
import pytest

from musclesim.components.control import relay
from musclesim.components.control.slaves import BangBang

from conftest import in_process

DT = 1e-3


def test_relay_switching_sequence_on_a_hand_made_trace():
    C = 273.15
    # cold start (on), heat through 90 C (off), cool through 75 C (on), a wobble between the
    # thresholds changes nothing, exactly at a threshold switches
    trace = [20, 60, 89.9, 90, 95, 80, 76, 75.1, 75, 80, 89, 85, 90.5, 74]
    expected = [1, 1, 1, 0, 0, 0, 0, 0, 1, 1, 1, 1, 0, 1]
    p = relay.RelayParams()
    assert [int(s) for s in relay.sequence([C + y for y in trace], p)] == expected
    slave = in_process(BangBang, "relay", u_on=7.0)
    slave.T = C + trace[0]
    slave.enter_initialization_mode()
    slave.exit_initialization_mode()
    seen = []
    for k, y in enumerate(trace):
        slave.T = C + y
        slave.set_real([], [])
        slave.get_real([])
        seen.append((slave.on, slave.y))
        slave.do_step(k * DT, DT)
    assert seen == [(float(s), 7.0 * s) for s in expected]


def test_relay_starts_from_its_measurement():
    p = relay.RelayParams(initially_on=0.0)
    assert relay.initial_state(p.y_on - 1, p) and not relay.initial_state(p.y_off, p)
    assert not relay.initial_state((p.y_on + p.y_off) / 2, p)
    with pytest.raises(ValueError, match="y_on .* must lie below y_off"):
        relay.RelayParams(y_on=400.0).check()


def test_the_compiled_kernel_is_its_python_bit_for_bit():
    from kernel_paths import assert_paths_agree

    trace = [20, 60, 89.9, 90, 95, 80, 76, 75.1, 75, 80, 89, 85, 90.5, 74] * 3
    assert_paths_agree(in_process(BangBang, "relay", u_on=7.0, T=293.15),
                       lambda k: {"T": 273.15 + trace[k]}, DT, len(trace))


def test_a_nan_temperature_is_refused():
    slave = in_process(BangBang, "relay")
    slave.enter_initialization_mode()
    slave.exit_initialization_mode()
    slave.T = float("nan")
    slave.set_real([], [])
    with pytest.raises(ValueError, match="input T is NaN at t = 0 s"):
        slave.get_real([])
