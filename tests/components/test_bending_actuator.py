"""The bending actuator's core (components/bending/actuator.py, §bending-actuator): the whole
actuator settling at the static balance worked out by hand, its first mode ringing at the
resonance, the wires' sides and slack, the 50 um wire's data (§sma-material)."""
import math

import pytest

from musclesim.components.bending import actuator, beam
from musclesim.components.sma import thermal
from musclesim.components.sma.reference_wire import load_params
from component_runs import AREA, make_bending



def test_heated_wire_settles_at_the_static_balance_by_hand():
    """Wire A held warm (constant voltage) until still: the cap's rotation equals the balance of
    the beams (EI / L) and both wires' elastic tensions about their transformed lengths."""
    core = make_bending()
    for _ in range(6000):  # 3 s: the wire's temperature (tau 0.29 s) and the mode (0.1 s) settle
        core.step(5e-4, (1.5, 0.0), 20.0)  # ~68 C
    lay, p = core.layout, core.beam
    (eps_a, eps_b), (xi_a, xi_b) = core.eps, core.xi
    assert 0.003 < eps_a and eps_b == 0.0  # wire A transformed in part, B cold
    E_a = 1 / (xi_a / 28e9 + (1 - xi_a) / 75e9)
    E_b = 28e9
    eps0 = lay.pretension / (28e9 * AREA)
    EI = 2 * 120e9 * 1e-3 * (0.2e-3) ** 3 / 12
    e, L = 1.7e-3, 0.01
    theta = e * AREA * (E_a * (eps_a + eps0) - E_b * eps0) / (EI / L + e * e * AREA * (E_a + E_b) / L)
    assert core.theta == pytest.approx(theta, rel=1e-6)
    assert core.deflection(0.017) == pytest.approx(theta * 0.012, rel=1e-6)
    assert core.deflection(0.017) > 0  # toward wire A
    T_a, T_b = core.tension
    assert T_a == pytest.approx(E_a * AREA * (eps_a + eps0 - e * theta / L), rel=1e-6)
    assert T_b == pytest.approx(E_b * AREA * (eps0 + e * theta / L), rel=1e-6)


def test_first_mode_rings_at_its_resonance_with_its_damping():
    core = make_bending()
    core.theta = 0.01  # released from a bent rest: free vibration of the first mode
    period = 1 / beam.natural_frequency(core.cold_stiffness(), core.beam)
    dt = period / 200
    zero_crossings, peaks, prev, prev_omega = [], [], core.theta, core.omega
    for k in range(1, 2001):  # ten periods
        core.step(dt, (0.0, 0.0), 20.0)
        if prev > 0 >= core.theta:
            zero_crossings.append(k * dt)
        if prev_omega > 0 >= core.omega:
            peaks.append(core.theta)
        prev, prev_omega = core.theta, core.omega
    zeta = core.beam.damping_ratio
    measured = (zero_crossings[-1] - zero_crossings[0]) / (len(zero_crossings) - 1)
    assert measured == pytest.approx(period / math.sqrt(1 - zeta ** 2), rel=1e-3)
    decrement = math.log(peaks[0] / peaks[1])
    assert decrement == pytest.approx(2 * math.pi * zeta / math.sqrt(1 - zeta ** 2), rel=1e-2)


def test_wires_mirror_each_other_and_slack_wires_pull_nothing():
    a, b = make_bending(), make_bending()
    tips = []
    for k in range(1000):  # pulses of 12.5 ms at 4 Hz on one wire for 0.5 s
        u = 5.0 if k % 500 < 25 else 0.0
        a.step(5e-4, (u, 0.0), 20.0)
        b.step(5e-4, (0.0, u), 20.0)
        tips.append((a.deflection(0.017), b.deflection(0.017)))
    assert max(t_a for t_a, _ in tips) > 1e-5  # toward the heated wire A
    assert all(t_b == -t_a for t_a, t_b in tips)
    lay = actuator.WireLayout()
    # bent far toward A with no strain: A goes slack, B alone pulls back
    T_a, T_b = actuator.tensions(0.5, (0.0, 0.0), (1.0, 1.0), AREA, lay)
    assert T_a == 0.0 and T_b > lay.pretension
    M0, K_w = actuator.moment_terms(0.5, (0.0, 0.0), (1.0, 1.0), AREA, lay)
    assert M0 - K_w * 0.5 == pytest.approx(-lay.offset * T_b, rel=1e-12)


def test_fifty_micron_wire_has_the_data_sheet_values():
    w = actuator.wire_thermal(1.0)
    assert thermal.resistance(1.0, w) == pytest.approx(470.0)  # Ohm/m (§sma-material)
    assert thermal.resistance(0.0, w) == pytest.approx(490.0)
    assert thermal.time_constant(w) == pytest.approx(0.29, abs=0.01)  # §sma-material: about 0.3 s
    # the hysteresis is the 127 um wire's against stress: at 0.35 N (§sma-material's 172 MPa) the
    # 50 um wire's full strain is the 127 um wire's at 2.2 N
    s50 = actuator.hysteresis_surface(load_params(), 0.35 / AREA)
    s127 = actuator.hysteresis_surface(load_params(), 2.2 / (math.pi * 63.5e-6 ** 2))
    assert s50.F(130.0, 30.0, 0.0) == pytest.approx(s127.F(130.0, 30.0, 0.0), rel=0.02)
