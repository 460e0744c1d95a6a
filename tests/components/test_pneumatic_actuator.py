"""Soft pneumatic actuator (components/pneumatic/actuator.py; §crawler-hardware, §gait, §valves)
against hand solutions: the ISO 6358 valve law, choked filling at constant volume, PWM-averaged
flow, valve delays, polytropic compression, contact build-up, effects off = nominal exactly."""
import math

import numpy as np
import pytest

from hypothesis import given, settings, strategies as st
from scipy.integrate import solve_ivp

from musclesim.components.pneumatic import actuator as pa
from musclesim.components.pneumatic.actuator import P_ATM, R_AIR, ActuatorParams, mass_flow

C, B = 5e-10, 0.3
HUGE = dict(central=0.0, V0=1.0, dV_contact=0.0)  # the pressure barely moves


def run(params, duties, h=1e-3, elongations=None):
    """Step an actuator through the duties (one per step of h); returns the pressures and contacts
    at t_0..t_n and the masses delivered per step."""
    act = pa.Actuator(params)
    p, u, m = [act.pressure], [act.contact], []
    for k, duty in enumerate(duties):
        m.append(act.step(k * h, h, duty, 0.0 if elongations is None else elongations[k]))
        p.append(act.pressure)
        u.append(act.contact)
    return np.array(p), np.array(u), np.array(m)


def test_choked_flow_is_c_p_up_rho_0():
    # r = 100/500 = 0.2 <= b: 5e-10 m3/(s Pa) x 500 kPa x 1.185 kg/m3
    assert mass_flow(500e3, 100e3, C, B) == pytest.approx(2.9625e-4, rel=1e-14)
    assert mass_flow(500e3, 150e3, C, B) == mass_flow(500e3, 100e3, C, B)  # r = b: still choked
    # four times the reference temperature: sqrt(T_0 / T) = 1/2
    assert mass_flow(500e3, 100e3, C, B, 4 * 293.15) == pytest.approx(2.9625e-4 / 2, rel=1e-14)


def test_unchoked_flow_hand_number():
    # r = 150/200 = 0.75: (0.75 - 0.3) / 0.7 = 0.642857, sqrt(1 - 0.413265) = 0.765986;
    # C p_up rho_0 = 5e-10 x 200e3 x 1.185 = 1.185e-4 kg/s
    assert mass_flow(200e3, 150e3, C, B) == pytest.approx(1.185e-4 * 0.765986, rel=1e-6)


def test_flow_is_continuous_at_b_zero_at_1_and_falls_with_r():
    p_up = 300e3
    choked = mass_flow(p_up, B * p_up, C, B)
    assert mass_flow(p_up, B * p_up * (1 + 1e-9), C, B) == pytest.approx(choked, rel=1e-8)
    assert mass_flow(p_up, p_up, C, B) == 0.0
    assert mass_flow(p_up, p_up * (1 - 1e-12), C, B) < 1e-5 * choked
    q = [mass_flow(p_up, r * p_up, C, B) for r in np.linspace(0, 1, 201)]
    assert np.all(np.diff(q) <= 0) and q[0] == choked and q[-1] == 0.0
    assert pa.signed_flow(150e3, 200e3, C, B) == -mass_flow(200e3, 150e3, C, B)
    assert mass_flow(100e3, 200e3, C, B) == 0.0  # never against the pressure difference


def test_zero_duty_no_flow_constant_pressure():
    for params in (ActuatorParams(), ActuatorParams(C_leak=1e-10, t_open_delay=0.003)):
        p, u, m = run(params, [0.0] * 200)
        assert np.all(p == 0.0) and np.all(m == 0.0) and np.all(u == 0.0)


def test_choked_filling_at_constant_volume_is_linear():
    # 400 kPa gauge supply: the flow stays choked while the chamber is below 0.3 x 501.325 kPa
    # absolute (49 kPa gauge); isothermal (kappa = 1): dp/dt = R T q / V0, q = C p_sup rho_0
    params = ActuatorParams(central=0.0, dV_contact=0.0, p_supply=400e3, kappa=1.0)
    q = C * (P_ATM + 400e3) * 1.185
    rate = R_AIR * 293.15 * q / params.V0  # 4.26e5 Pa/s
    p, _, m = run(params, [1.0] * 100)
    t = np.arange(101) * 1e-3
    np.testing.assert_allclose(p, rate * t, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(m, q * 1e-3, rtol=1e-9)
    k = np.flatnonzero(p >= 30e3)[0]  # the time to reach 30 kPa
    t30 = t[k - 1] + (30e3 - p[k - 1]) / (p[k] - p[k - 1]) * 1e-3
    assert t30 == pytest.approx(30e3 / rate, rel=1e-9)


def test_unchoked_filling_matches_an_ode_solver():
    params = ActuatorParams()  # central at rest: constant volume; 40 kPa supply: unchoked
    gain = params.kappa * R_AIR * params.T / params.V0
    sol = solve_ivp(lambda t, y: [gain * mass_flow(P_ATM + 40e3, P_ATM + y[0], C, B)],
                    (0, 0.3), [0.0], rtol=1e-10, atol=1e-6)
    p, _, _ = run(params, [1.0] * 300)
    assert p[-1] == pytest.approx(sol.y[0, -1], rel=1e-3)
    assert 20e3 < p[-1] < 40e3


def test_mass_balance_holds_through_the_clamp_at_the_supply():
    params = ActuatorParams()
    p, _, m = run(params, [1.0] * 800)  # reaches the supply pressure (clamped) at about 0.65 s
    assert p[-1] == 40e3 and p.max() == 40e3
    gain = params.kappa * R_AIR * params.T / params.V0  # constant volume: dp = gain dm
    np.testing.assert_allclose(np.cumsum(m) * gain, p[1:], rtol=1e-9, atol=1e-6)


@pytest.mark.parametrize("duty", [0.1, 0.25, 1 / 3, 0.5, 0.73, 1.0, -0.4, -1.0])
def test_pwm_delivers_duty_times_the_continuous_flow(duty):
    p, _, m = run(ActuatorParams(**HUGE), [duty] * 100)  # 5 carrier periods of 20 ms
    if duty > 0:
        q = mass_flow(P_ATM + 40e3, P_ATM, C, B)
    else:
        q = -mass_flow(P_ATM, P_ATM - 20e3, C, B)
    # the valve's edges are exact: no sub-step resolution error (1/3 of 20 ms is off the grid)
    assert m.sum() == pytest.approx(abs(duty) * q * 0.1, rel=1e-5)
    assert abs(p[-1]) < 1.0  # Pa: the huge chamber kept the flow at its start value


@pytest.mark.parametrize("t_open, t_close, open_per_period", [
    (0.002, 0.0, 0.008), (0.0, 0.003, 0.013), (0.002, 0.003, 0.011), (0.003, 0.0, 0.007)])
def test_valve_delays_shift_and_shorten_the_opening(t_open, t_close, open_per_period):
    params = ActuatorParams(**HUGE, t_open_delay=t_open, t_close_delay=t_close)
    _, _, m = run(params, [0.5] * 100)  # 10 ms pulses every 20 ms
    q = mass_flow(P_ATM + 40e3, P_ATM, C, B)
    assert m.sum() == pytest.approx(5 * open_per_period * q, rel=1e-5)
    assert np.all(m[:int(round(t_open * 1e3))] == 0.0)  # nothing until the valve opens


@pytest.mark.parametrize("phase", [0.5, 0.875, 1.5, -0.125])
def test_the_carrier_phase_moves_the_openings_not_their_share(phase):
    """Periods start at phase x 20 ms: 5 ms pulses from 10 ms (0.5), or from 17.5 ms across a
    period's end (0.875: the one begun before t = 0 open until 2.5 ms); over whole periods the
    same mass as with the periods starting at 0. The phase is periodic: 1.5 is 0.5, -0.125 is
    0.875."""
    _, _, m0 = run(ActuatorParams(**HUGE), [0.25] * 100)
    _, _, m = run(ActuatorParams(**HUGE, pwm_phase=phase), [0.25] * 100)
    assert m.sum() == pytest.approx(m0.sum(), rel=1e-9)
    on = np.flatnonzero(m[:20] > 1e-6 * m.max())  # steps with flow in the first period (not
    # a step whose t + h lands 1e-18 s beyond an edge)
    assert list(on) == ([10, 11, 12, 13, 14] if phase % 1 == 0.5 else [0, 1, 2, 17, 18, 19])


def test_a_pulse_shorter_than_the_delay_difference_never_opens_the_valve():
    params = ActuatorParams(**HUGE, t_open_delay=0.003)
    _, _, m = run(params, [0.05] * 100)  # 1 ms pulses
    assert np.all(m == 0.0)
    _, _, m = run(ActuatorParams(**HUGE, t_open_delay=0.005), [1.0] * 20)  # always on
    q = mass_flow(P_ATM + 40e3, P_ATM, C, B)
    assert np.all(m[:5] == 0.0) and m.sum() == pytest.approx(0.015 * q, rel=1e-5)


def test_compression_at_closed_valves_is_polytropic():
    params = ActuatorParams()  # central, kappa 1.2
    e = np.r_[np.linspace(-1e-3, -0.01, 10), [-0.01] * 5, np.linspace(-0.009, 0.0, 10), [0.0] * 3]
    p, _, _ = run(params, [0.0] * len(e), elongations=e)
    v0, v1 = params.V0, params.V0 - params.s_a * 0.01
    assert p[15] == pytest.approx(P_ATM * (v0 / v1) ** 1.2 - P_ATM, rel=1e-11)  # 21 kPa
    assert p[15] > 20e3 and np.all(np.diff(p[:11]) > 0)
    assert abs(p[-1]) < 1e-6  # back to the rest volume, back to the start pressure


def test_contact_builds_over_t_contact_above_p_contact():
    params = ActuatorParams(central=0.0, V0=1.41e-5)  # an extremal actuator
    p, u, _ = run(params, [1.0] * 600)
    k = np.flatnonzero(p > params.p_contact)[0]  # crossed between k-1 and k ms
    assert np.all(u[:k] == 0.0) and u[k] > 0
    assert u[k + 199] < 1.0 and np.all(u[k + 201:] == 1.0)  # 0.2 s later (within a step)
    np.testing.assert_allclose(np.diff(u[k + 1:k + 199]), 1e-3 / 0.2, rtol=1e-9)
    # deflating: the contact falls at the same rate once the pressure drops below p_contact
    act = pa.Actuator(params)
    for i in range(600):
        act.step(i * 1e-3, 1e-3, 1.0, 0.0)
    us, ps = [], []
    for i in range(600, 1000):
        act.step(i * 1e-3, 1e-3, -1.0, 0.0)
        us.append(act.contact)
        ps.append(act.pressure)
    j = np.flatnonzero(np.array(ps) <= params.p_contact)[0]
    assert us[j - 1] == 1.0 and us[j + 201] == 0.0 and 0 < us[j + 100] < 1


def test_contact_at_once_bulges_at_p_contact():
    # t_contact = 0: the extremal chamber bulges as the inflow allows, holding p at p_contact
    params = ActuatorParams(central=0.0, V0=1.41e-5, t_contact=0.0)
    p, u, _ = run(params, [1.0] * 200)
    sliding = (u > 0) & (u < 1)
    assert sliding.sum() > 30 and np.all(np.diff(u) >= 0) and u[-1] == 1.0
    np.testing.assert_allclose(p[sliding], 8e3, rtol=1e-12)
    assert np.all(np.diff(p) >= -1e-9)
    # the central actuator's volume does not depend on its contact: the contact jumps
    p, u, _ = run(ActuatorParams(t_contact=0.0), [1.0] * 100)
    assert np.array_equal(u, (p > 8e3).astype(float))


def test_effects_off_are_the_nominal_model_bit_for_bit():
    duties = np.r_[np.full(300, 0.6), np.full(200, 0.0), np.full(200, -0.3)]
    nominal = run(ActuatorParams(), duties)
    off = run(ActuatorParams(C_leak=0.0, supply_drop=0.0, t_open_delay=0.0, t_close_delay=0.0),
              duties)
    for a, b in zip(nominal, off):
        assert np.array_equal(a, b)
    leak = run(ActuatorParams(C_leak=1e-11), duties)[0]
    assert np.all(nominal[0][301:500] == nominal[0][300])  # closed valves hold the pressure
    assert np.all(np.diff(leak[301:500]) < 0)  # a leak lets it fall
    drop = run(ActuatorParams(supply_drop=0.5), [1.0] * 1000)[0]
    assert drop.max() == 20e3 and drop[-1] == 20e3  # the sagged supply bounds the pressure


@settings(max_examples=25)
@given(central=st.sampled_from([0.0, 1.0]), t_contact=st.sampled_from([0.0, 0.02, 0.2]),
       dV_contact=st.sampled_from([0.0, 3e-6]), phase=st.floats(0.0, 1.0),
       delays=st.sampled_from([(0.0, 0.0), (0.01, 0.005), (0.003, 0.008)]),
       leak=st.sampled_from([0.0, 1e-11]), seed=st.integers(0, 2**31 - 1))
def test_a_step_without_flow_or_motion_is_the_sub_steps_to_the_bit(central, t_contact,
                                                                     dV_contact, phase, delays,
                                                                     leak, seed):
    # the shortcut (valves shut, no leak, contact at its target, volume still) against every
    # step taken through its sub-steps: pressures, contacts, masses the same to the bit
    rng = np.random.default_rng(seed)
    params = ActuatorParams(central=central, t_contact=t_contact, dV_contact=dV_contact,
                            pwm_phase=phase, t_open_delay=delays[0], t_close_delay=delays[1],
                            C_leak=leak)
    n = 100
    duties = np.where(rng.random(n) < 0.5, 0.0, rng.uniform(-1, 1, n)).repeat(5)
    held = rng.random(5 * n) < 0.5  # the elongation stands still at about half the steps
    elongations = np.cumsum(np.where(held, 0.0, rng.normal(0, 1e-4, 5 * n)))
    shortcut = run(params, duties, elongations=elongations)
    taken = []
    holds = pa.Actuator._holds
    with pytest.MonkeyPatch.context() as mp:  # every step through its sub-steps
        mp.setattr(pa.Actuator, "_holds", lambda self, *a: taken.append(holds(self, *a)) or False)
        through = run(params, duties, elongations=elongations)
    for a, b in zip(shortcut, through):
        assert a.tobytes() == b.tobytes()
    assert any(taken) or leak  # the shortcut was taken (and so compared); never with a leak


@pytest.mark.parametrize("field, value", [
    ("central", 0.5), ("V0", 0.0), ("b", 1.0), ("kappa", 1.5), ("p_exhaust", 1e3),
    ("supply_drop", 1.0), ("C_leak", -1e-10), ("t_open_delay", -1e-3), ("f_pwm", math.nan),
    ("pwm_phase", math.inf)])
def test_bad_parameters_are_named(field, value):
    with pytest.raises(ValueError, match=field):
        ActuatorParams(**{field: value}).check()


def test_the_kernel_is_the_actuators_step_compiled_and_as_python():
    # the FMU's kernel (u = [duty, flange_a.s, flange_b.s], y = [p, f_a, u, m_flow]) against
    # Actuator.step, and its compiled functions against their Python source, to the bit
    params = ActuatorParams(central=0.0, V0=1.41e-5, t_open_delay=0.004, t_close_delay=0.002,
                            pwm_phase=0.3, C_leak=1e-11)
    kp = pa.pack(params)
    compiled = getattr(pa.advance, "py_func", None) is not None
    xa, xb, ya, yb = pa.start_state(kp), pa.start_state(kp), np.zeros(4), np.zeros(4)
    act = pa.Actuator(params)
    duties = np.r_[np.full(150, 0.7), np.full(100, 0.0), np.full(150, -0.45)]
    contacts = []
    for k, duty in enumerate(duties):
        u = np.array([duty, 0.0, 0.0])
        pa.advance(kp, xa, u, ya, k * 1e-3, 1e-3)
        mass = act.step(k * 1e-3, 1e-3, duty, 0.0)
        assert xa[pa.M_FLOW] == mass / 1e-3  # the rest of the state is the Actuator's
        assert np.delete(xa, pa.M_FLOW).tobytes() == np.delete(act.x, pa.M_FLOW).tobytes()
        pa.evaluate(kp, xa, u, (k + 1) * 1e-3, ya)
        assert ya.tolist() == [act.pressure, params.s_a * act.pressure, act.contact, mass / 1e-3]
        contacts.append(ya[2])
        if compiled:
            pa.advance.py_func(kp, xb, u, yb, k * 1e-3, 1e-3)
            pa.evaluate.py_func(kp, xb, u, (k + 1) * 1e-3, yb)
            assert xa.tobytes() == xb.tobytes() and ya.tobytes() == yb.tobytes()
    assert max(contacts) > 0.9 and ya[2] < max(contacts) and ya[0] < params.p_contact
    if compiled:  # the step's own functions, as Python, on copies of the state
        xc = xa.copy()
        m1 = pa.step(kp, xa, 0.4, 1e-3, 0.9, 0.0)
        m2 = pa.step.py_func(kp, xc, 0.4, 1e-3, 0.9, 0.0)
        assert m1 == m2 and xa.tobytes() == xc.tobytes()


def test_a_valve_holds_its_pending_switchings_in_its_state():
    # 20 ms delays, the command toggled at every 0.1 ms step: more switchings pending than the
    # state was sized for is an error, not a lost switching
    params = ActuatorParams(t_open_delay=0.02, t_close_delay=0.02)
    assert pa.pending_capacity(params) == 2 + 400 + 8
    act = pa.Actuator(params)
    for k in range(100):  # every 1 ms: within the capacity
        act.step(k * 1e-3, 1e-3, 1.0 if k % 2 else 0.0, 0.0)
    assert act.x[pa.VALVES + pa.N_PENDING] == 20  # the command's edges of the last 20 ms
    with pytest.raises(ValueError, match="pending"):
        for k in range(5000):
            act.step(0.1 + k * 2e-5, 2e-5, 1.0 if k % 2 else 0.0, 0.0)
