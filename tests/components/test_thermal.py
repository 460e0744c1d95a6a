"""The lumped thermal model of the SMA wire (components/sma/thermal.py) against hand solutions
(§thermal-model, §sma-material), and its effects: off they change nothing bit for bit, on they
move the temperature the way the physics says."""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.special import expit

from musclesim.components.sma import drift
from musclesim.components.sma.thermal import (ThermalInputs, ThermalParams, derivative,
                                              heat_capacity, joule_power, lateral_surface,
                                              martensite_fraction, resistance, step, step_coupled,
                                              time_constant)

NOMINAL = ThermalParams()
CURRENT = ThermalParams(drive="current")
DT = 4e-4  # s, the study's 2.5 kHz loop (§sma-bench)
T_AMB = 20.0


def run(T, inputs, p, seconds, dt=DT):
    """Temperature trace [C] every dt over `seconds`, inputs held."""
    trace = [T]
    for _ in range(round(seconds / dt)):
        T = step(T, inputs, dt, p)
        trace.append(T)
    return np.array(trace)


def test_time_constant_is_rho_c_d_over_4h():
    p = NOMINAL
    assert time_constant(p) == pytest.approx(p.density * p.specific_heat * p.diameter / (4 * p.h))
    assert 1.5 <= time_constant(p) <= 1.8  # ~1.6 s by §convection, 1.5 s data-sheet cooling


def test_resistance_per_metre_matches_the_data_sheet():
    assert resistance(1.0, NOMINAL) / NOMINAL.length == pytest.approx(63.2, abs=0.1)
    assert resistance(0.0, NOMINAL) / NOMINAL.length == pytest.approx(78.9, abs=0.1)
    assert joule_power(2.0, 1.0, NOMINAL) == pytest.approx(4.0 / resistance(1.0, NOMINAL))
    assert joule_power(0.3, 0.0, CURRENT) == pytest.approx(0.09 * resistance(0.0, CURRENT))


def test_free_cooling_is_exponential():
    trace = run(100.0, ThermalInputs(u=0.0, T_amb=T_AMB), NOMINAL, 5.0)
    t = np.arange(len(trace)) * DT
    expected = T_AMB + 80.0 * np.exp(-t / time_constant(NOMINAL))
    assert np.max(np.abs(trace - expected)) < 1e-9


@pytest.mark.parametrize("p, u, xi",
                         [(CURRENT, 0.15, 1.0), (CURRENT, 0.15, 0.0), (NOMINAL, 0.5, 0.4)],
                         ids=["current-martensite", "current-austenite", "voltage-mixed"])
def test_heating_approaches_the_steady_state_exponentially(p, u, xi):
    inputs = ThermalInputs(u=u, T_amb=T_AMB, xi=xi)
    T_ss = T_AMB + joule_power(u, xi, p) / (p.h * lateral_surface(p))
    trace = run(T_AMB, inputs, p, 3.0)
    t = np.arange(len(trace)) * DT
    expected = T_ss - (T_ss - T_AMB) * np.exp(-t / time_constant(p))
    assert np.max(np.abs(trace - expected)) < 1e-9
    assert derivative(T_ss, inputs, p) == pytest.approx(0.0, abs=1e-9)


def test_fast_heating_at_2_5V_is_stable_at_2_5kHz():
    # 2.5 V (§thermal-model) over 3.7 Ohm heats at ~420 K/s: 0.17 K per 0.4 ms step
    inputs = ThermalInputs(u=2.5, T_amb=T_AMB)
    trace = run(T_AMB, inputs, NOMINAL, 0.25)
    assert np.all(np.diff(trace) > 0)
    tau = time_constant(NOMINAL)
    T_ss = T_AMB + joule_power(2.5, 1.0, NOMINAL) / (NOMINAL.h * lateral_surface(NOMINAL))
    assert trace[-1] == pytest.approx(T_ss - (T_ss - T_AMB) * math.exp(-0.25 / tau), rel=1e-12)
    assert 100 < trace[-1] < 130  # 0.25 s at 2.5 V crosses the whole transformation


def test_effects_off_are_the_nominal_model_bit_for_bit():
    inputs = ThermalInputs(u=0.7, T_amb=T_AMB, xi=0.6, xi_rate=-2.0)
    off = ThermalParams(latent_heat=0.0, h_exponent=0.0, h_dT_ref=10.0)
    nominal_inputs = ThermalInputs(u=0.7, T_amb=T_AMB, xi=0.6)
    for T in (20.0, 65.3, 140.0):
        assert step(T, inputs, DT, off) == step(T, nominal_inputs, DT, NOMINAL)
        assert step_coupled(T, inputs, DT, off, lambda _: 0.3) == (
            step(T, nominal_inputs, DT, NOMINAL), 0.3)
    d = drift.DriftParams(cycles_to_settle=5.0)
    assert drift.strain_scale(1e4, d) == 1.0 and drift.temperature_shift(1e4, d) == 0.0


def test_latent_heat_balance_with_prescribed_transformation():
    # no losses: m c_p dT = P dt + m L dxi exactly; austenite forming (xi 1 -> 0) absorbs heat
    p = ThermalParams(drive="current", h=0.0, latent_heat=20e3)
    T, xi, u = 60.0, 1.0, 0.1
    for _ in range(2500):
        T = step(T, ThermalInputs(u=u, T_amb=T_AMB, xi=xi, xi_rate=-1.0), DT, p)
        xi -= DT
    energy = sum(joule_power(u, 1.0 - k * DT, p) * DT for k in range(2500))
    mass = heat_capacity(p) / p.specific_heat
    assert T - 60.0 == pytest.approx((energy - mass * 20e3) / heat_capacity(p), rel=1e-10)
    assert -20e3 / p.specific_heat < T - 60.0 - energy / heat_capacity(p) + 1e-9  # about -23.9 K


def _xi_sharp(T):
    """A steep, hysteresis-free martensite fraction around 80 C (|dxi/dT| up to 0.5 / K)."""
    return float(expit(-(T - 80.0) / 0.5))


def _heat_through_transformation(p, seconds=0.4):
    """(T, xi) every step while 2 V heat the wire from ambient past 80 C."""
    T, xi, trace = T_AMB, 1.0, []
    for _ in range(round(seconds / DT)):
        T, xi = step_coupled(T, ThermalInputs(u=2.0, T_amb=T_AMB, xi=xi), DT, p, _xi_sharp)
        trace.append((T, xi))
    return np.array(trace)


def test_coupled_latent_heat_is_stable_and_balances_energy():
    # L |dxi/dT| / c_p = 24e3 * 0.5 / 837 = 14: an explicit coupling would oscillate
    p = ThermalParams(h=0.0, latent_heat=24e3)
    trace = _heat_through_transformation(p)
    assert np.all(np.diff(trace[:, 0]) > 0) and np.all(np.diff(trace[:, 1]) <= 1e-12)
    assert trace[-1, 1] < 1e-6  # fully transformed
    xi = np.concatenate([[1.0], trace[:, 1]])
    energy = sum(joule_power(2.0, x, p) * DT for x in xi[:-1])
    mass = heat_capacity(p) / p.specific_heat
    dT = (energy + mass * p.latent_heat * (xi[-1] - 1.0)) / heat_capacity(p)
    assert trace[-1, 0] - T_AMB == pytest.approx(dT, rel=1e-8)


def test_latent_heat_slows_heating_and_cooling_through_the_transformation():
    base, latent = ThermalParams(), ThermalParams(latent_heat=20e3)
    hot_base, hot_latent = _heat_through_transformation(base), _heat_through_transformation(latent)
    assert hot_latent[-1, 0] < hot_base[-1, 0] - 5  # endothermic austenite formation
    T = {}
    for name, p in (("base", base), ("latent", latent)):
        t, xi = 100.0, 0.0
        for _ in range(round(1.5 / DT)):
            t, xi = step_coupled(t, ThermalInputs(u=0.0, T_amb=T_AMB, xi=xi), DT, p, _xi_sharp)
        T[name] = t
    assert T["latent"] > T["base"] + 5  # exothermic martensite formation holds the wire warm


@pytest.mark.parametrize("h_exponent", [0.0, 0.12], ids=["one exact update", "sub-stepped"])
def test_coupled_step_ends_where_its_own_fraction_change_takes_it(h_exponent):
    # the root's defining property: T_new is the step with xi_rate = (xi_at(T_new) - xi) / dt,
    # whether the search uses the update's affine dependence on xi_rate (h constant) or steps
    p = ThermalParams(latent_heat=20e3, h_exponent=h_exponent)
    for T, u, xi in ((78.0, 1.5, 0.7), (82.0, 0.0, 0.2), (60.0, 2.5, 1.0)):
        inputs = ThermalInputs(u=u, T_amb=T_AMB, xi=xi)
        T_new, xi_new = step_coupled(T, inputs, 0.02, p, _xi_sharp)
        assert xi_new == pytest.approx(_xi_sharp(T_new), abs=1e-12) and xi_new != xi
        rate = (xi_new - xi) / 0.02
        assert T_new == pytest.approx(step(T, inputs._replace(xi_rate=rate), 0.02, p), abs=1e-8)


def test_convection_growing_with_excess_temperature():
    p = ThermalParams(drive="current", h_exponent=0.15)
    hot = ThermalInputs(u=0.25, T_amb=T_AMB)  # ~124 K excess nominally
    warm = ThermalInputs(u=0.1, T_amb=T_AMB)  # ~20 K excess nominally
    for inputs, sign in ((hot, -1), (warm, +1)):
        nominal = run(T_AMB, inputs, CURRENT, 15.0, dt=0.01)[-1]
        effect = run(T_AMB, inputs, p, 15.0, dt=0.01)[-1]
        assert sign * (effect - nominal) > 1.0  # h > 100 above 50 K excess, below it under


@pytest.mark.parametrize("dt", [DT, 0.02])  # the study's loop; a 50 Hz bench (sub-steps)
def test_convection_effect_matches_a_reference_ode_solution(dt):
    p = ThermalParams(h_exponent=0.5)
    inputs = ThermalInputs(u=0.0, T_amb=T_AMB)
    trace = run(130.0, inputs, p, 4.0, dt)
    ref = solve_ivp(lambda t, y: [derivative(y[0], inputs, p)], (0, 4.0), [130.0],
                    rtol=1e-11, atol=1e-11, t_eval=np.arange(len(trace)) * dt)
    assert np.max(np.abs(trace - ref.y[0])) < 1e-5  # a thermocouple resolves 0.05 K
    # h > 100 at more than 50 K excess: it cools faster from 110 K excess at first
    early = round(0.5 / dt)
    assert trace[early] < run(130.0, inputs, NOMINAL, 0.5, dt)[-1]


def test_martensite_fraction_from_strain():
    assert martensite_fraction(0.0, 0.04) == 1.0
    assert martensite_fraction(0.01, 0.04) == 0.75
    assert martensite_fraction(0.041, 0.04) == 0.0


@pytest.mark.parametrize("params, name", [
    (ThermalParams(diameter=0.0), "diameter"), (ThermalParams(h=-1.0), "h"),
    (ThermalParams(drive="power"), "drive"), (ThermalParams(latent_heat=-1.0), "latent_heat"),
    (drift.DriftParams(cycles_to_settle=0.0), "cycles_to_settle"),
], ids=["diameter", "h", "drive", "latent_heat", "cycles_to_settle"])
def test_check_names_the_bad_parameter(params, name):
    with pytest.raises(ValueError, match=name):
        params.check()
    ThermalParams().check()
    drift.DriftParams().check()
