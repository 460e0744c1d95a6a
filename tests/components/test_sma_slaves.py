"""The SmaWire FMU (§sma-wire, §preisach, §sma-material) against its cores stepped by hand, its
effects (off: nominal bit for bit; on: the change the physics predicts), its response to heating,
and its errors."""
import math
from types import SimpleNamespace

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

from musclesim.cosim import host
from musclesim.components.sma import datasets, drift, ends
from musclesim.components.sma.preisach import PreisachModel
from musclesim.components.sma.slaves import LOAD_150G, SmaWire
from musclesim.components.sma.surface import Hypersurface
from musclesim.components.sma.thermal import (ThermalInputs, ThermalParams, cross_section,
                                              joule_power, martensite_fraction,
                                              resistance, step)
from musclesim.components.sma.reference_wire import ReferenceWire

from conftest import in_process

DT = 4e-4  # s, the study's 2.5 kHz loop (§sma-bench)
ZERO_C = 273.15
AREA = cross_section(ThermalParams())
OUTPUTS = ("T", "strain", "flange.s", "stress", "R", "P", "xi")


@pytest.fixture(scope="module")
def wire_fmu(fmu_dir, tmp_path_factory):
    """(model description, unzipped folder) of the built SmaWire FMU."""
    path = fmu_dir / "SmaWire.fmu"
    return read_model_description(str(path)), extract(path, tmp_path_factory.mktemp("smawire"))


def simulate(fmu, u, params=None, T_amb=293.15, f=LOAD_150G, dt=DT, log=None):
    """Run the FMU through FMI with u[k] (and T_amb, f: scalars or per step) held over step k.

    Returns {output: array at t_0 .. t_n}. With `log` (a list), the FMU's messages go there as
    (status, message) pairs.
    """
    md, unzipped = fmu
    n = len(u)
    T_amb, f = np.broadcast_to(T_amb, n), np.broadcast_to(f, n)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    slave = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, instanceName="wire",
                      modelIdentifier=md.coSimulation.modelIdentifier)
    key = id(slave)
    host.LOG_SINKS[key] = {"wire": SimpleNamespace(log=log if log is not None else [])}
    try:
        slave.instantiate(callbacks=host.callbacks(key), loggingOn=True)
        slave.setupExperiment(startTime=0.0)
        for name, value in (params or {}).items():
            slave.setReal([vr[name]], [value])
        slave.enterInitializationMode()
        inputs = [vr["u"], vr["T_amb"], vr["flange.f"]]
        slave.setReal(inputs, [u[0], T_amb[0], f[0]])
        slave.exitInitializationMode()
        outs = [vr[name] for name in OUTPUTS]
        rows = [slave.getReal(outs)]
        for k in range(n):
            slave.setReal(inputs, [u[k], T_amb[k], f[k]])
            slave.doStep(k * dt, dt)
            rows.append(slave.getReal(outs))
        slave.terminate()
        slave.freeInstance()
    finally:
        del host.LOG_SINKS[key]
    return dict(zip(OUTPUTS, np.array(rows).T))


def monolithic(u, hysteresis, T_amb=293.15, f=LOAD_150G, T_init=293.15, dt=DT):
    """The same run with the pure cores stepped by hand (nominal model: no effects)."""
    p = ThermalParams()
    surface = datasets.surface(hysteresis)
    model = PreisachModel(surface)

    def seen(T):
        return min(max(T, surface.t_lo), surface.t_hi)

    def eps_max(sigma):
        return surface.F(surface.t_hi, surface.t_lo, sigma)

    sigma = f / cross_section(p)
    T = T_init - ZERO_C
    eps = model.reset(seen(T), sigma)
    xi = martensite_fraction(eps, eps_max(sigma))
    rows = [(T + ZERO_C, eps, xi, resistance(xi, p), joule_power(u[0], xi, p))]
    for uk in u:
        P = joule_power(uk, xi, p)  # what heats the wire over this step
        T = step(T, ThermalInputs(uk, T_amb - ZERO_C, xi), dt, p)
        eps = model.step(seen(T), sigma)
        xi = martensite_fraction(eps, eps_max(sigma))
        rows.append((T + ZERO_C, eps, xi, resistance(xi, p), P))
    return dict(zip(("T", "strain", "xi", "R", "P"), np.array(rows).T))


def pulse(volts, on, total, dt=DT):
    """u held at `volts` for `on` seconds, then 0, over `total` seconds."""
    n = round(total / dt)
    return np.where(np.arange(n) < round(on / dt), volts, 0.0)


def cycles(volts, on, period, count, dt):
    """`count` periods of a heating pulse of `volts` for `on` seconds."""
    return np.tile(pulse(volts, on, period, dt), count)


HEAT_COOL = pulse(2.0, 0.5, 3.0)  # heat through the transformation, then cool most of the way


# --- the FMU is the cores -------------------------------------------------------------------

@pytest.mark.parametrize("hysteresis", [0.0, 1.0], ids=["reference-wire", "forc-data-set-1"])
def test_fmu_equals_the_cores_stepped_by_hand(wire_fmu, hysteresis):
    f = 142e6 * AREA  # between stress levels of both data sets: the stress interpolation counts
    fmu = simulate(wire_fmu, HEAT_COOL, {"hysteresis": hysteresis}, T_amb=295.0, f=f)
    ref = monolithic(HEAT_COOL, hysteresis, T_amb=295.0, f=f)
    for name in ("T", "strain", "xi", "R"):
        assert np.array_equal(fmu[name], ref[name]), name
    assert np.array_equal(fmu["P"], ref["P"])  # at t_k+1: the power over [t_k, t_k+1]
    assert np.array_equal(fmu["flange.s"], fmu["strain"] * ThermalParams().length)
    assert np.all(fmu["stress"] == f / AREA)
    assert fmu["strain"].max() > 0.03 and fmu["strain"][-1] < fmu["strain"].max() / 2


def test_shipped_forc_data_set_is_the_reference_wire_on_the_study_grid():
    path, _ = datasets.forc_sets()[1]
    expected = Hypersurface.from_function(ReferenceWire().F)
    # bit for bit: the wire takes the C library's exp and expm1, not numpy's, whose AVX-512
    # paths (chosen per CPU) differed from the file's machine by up to 4e-16 relative
    assert np.array_equal(Hypersurface.load(path).table, expected.table)


# --- heating, cooling, resistance -----------------------------------------------------------

def test_voltage_step_contracts_the_wire_and_cooling_returns_it(wire_fmu):
    length = ThermalParams().length
    r = simulate(wire_fmu, pulse(2.0, 0.5, 6.5))
    heating = slice(0, round(0.5 / DT) + 1)
    assert np.all(np.diff(r["T"][heating]) > 0)
    eps_max = float(ReferenceWire().eps_max(LOAD_150G / AREA))
    assert r["strain"][heating][-1] > 0.95 * eps_max  # fully contracted: 3.8 % at 116 MPa
    assert np.all(np.diff(r["strain"][heating]) >= 0)
    assert r["T"][-1] < 303.15 and r["strain"][-1] == 0.0  # cooled below 30 C: all martensite
    # about 63-79 Ohm/m between martensite and austenite (§sma-material)
    assert r["R"][0] / length == pytest.approx(63.2, abs=0.1)
    assert r["R"][heating][-1] / length == pytest.approx(78.9, abs=0.2)
    assert np.all((r["R"] >= r["R"][0]) & (r["R"] / length <= 78.95))
    assert r["P"][0] == pytest.approx(4.0 / r["R"][0], rel=1e-12)


def test_current_drive_contracts_in_about_a_second_at_0_3_A(wire_fmu):
    # §sma-material: roughly 0.3 A for a 1 s contraction of the 127 um wire
    r = simulate(wire_fmu, np.full(round(1.0 / DT), 0.3), {"drive_current": 1.0})
    eps_max = float(ReferenceWire().eps_max(LOAD_150G / AREA))
    assert r["strain"][round(0.5 / DT)] < 0.1 * eps_max < 0.75 * eps_max < r["strain"][-1]
    assert r["P"][-1] == pytest.approx(0.09 * r["R"][-2], rel=1e-12)  # R at the step's start


# --- effects --------------------------------------------------------------------------------

def test_effects_off_are_the_nominal_model_bit_for_bit(wire_fmu):
    off = {"latent_heat": 0.0, "end_cooling": 0.0, "h_exponent": 0.0, "sigma_surface": 0.0,
           "drift_amplitude": 0.0, "drift_shift": 0.0, "drift_settle_cycles": 5.0,
           "drift_cycles_start": 50.0}
    nominal = simulate(wire_fmu, HEAT_COOL)
    explicit = simulate(wire_fmu, HEAT_COOL, off)
    for name in OUTPUTS:
        assert np.array_equal(nominal[name], explicit[name]), name


def test_latent_heat_slows_heating_through_the_transformation(wire_fmu):
    u = pulse(2.0, 0.5, 0.5)
    base = simulate(wire_fmu, u)
    latent = simulate(wire_fmu, u, {"latent_heat": 20e3})  # §sma-material: 12-24 kJ/kg
    before = base["T"] < 303.15  # below 30 C nothing transforms: the same heating
    assert np.max(np.abs(latent["T"][before] - base["T"][before])) < 1e-8
    half = np.argmax(base["xi"] < 0.5)  # the nominal wire half transformed
    assert latent["T"][half] < base["T"][half] - 3 and latent["xi"][half] > 0.5
    assert np.argmax(latent["xi"] < 0.05) > np.argmax(base["xi"] < 0.05) + round(0.01 / DT)


def test_cold_ends_are_zones_of_the_wire_with_their_own_memory(wire_fmu):
    # current drive: the core heats as the nominal wire does; each end zone is a hysteresis model
    # of its own at T_amb + g (T_core - T_amb), the strain the length's average (ends.zones)
    u, beta, T_amb = HEAT_COOL * 0.15, 0.9, 293.15
    params = {"drive_current": 1.0}
    base = simulate(wire_fmu, u, params)
    cold = simulate(wire_fmu, u, {**params, "end_cooling": beta})
    assert np.array_equal(cold["T"], base["T"])  # a long wire's core does not feel its clamps
    p = ThermalParams()
    table = ends.zones(beta, p.length, p.diameter, 18.0, p.h)
    surface = datasets.surface(0.0)
    sigma = LOAD_150G / AREA
    core = base["strain"]
    zone = []
    for _, g in table:
        model, temps = PreisachModel(surface), T_amb + g * (base["T"] - T_amb) - ZERO_C
        seen = np.clip(temps, surface.t_lo, surface.t_hi)
        zone.append([model.reset(seen[0], sigma)] + [model.step(T, sigma) for T in seen[1:]])
    expected = (1 - sum(w for w, _ in table)) * core + sum(
        w * np.array(z) for (w, _), z in zip(table, zone))
    np.testing.assert_allclose(cold["strain"], expected, rtol=1e-12, atol=1e-15)
    eps_max = surface.F(surface.t_hi, surface.t_lo, sigma)
    np.testing.assert_allclose(cold["xi"], 1 - expected / eps_max, rtol=1e-12, atol=1e-15)
    # hot, the ends nearest the clamps stay martensite: less contraction than the nominal wire
    assert cold["strain"].max() < base["strain"].max() - table[0][0] * 0.9 * base["strain"].max()


def test_convection_growing_with_temperature_lowers_a_hot_steady_state(wire_fmu):
    u, dt = np.full(1500, 1.0), 0.01  # ~100 K above ambient, where h(T) > h
    base = simulate(wire_fmu, u, dt=dt)
    effect = simulate(wire_fmu, u, {"h_exponent": 0.15}, dt=dt)
    assert base["T"][-1] - 293.15 > 60 and effect["T"][-1] < base["T"][-1] - 3


def test_stress_ignored_uses_one_surface_for_every_stress(wire_fmu):
    ignored = {"sigma_surface": 105e6}
    at_105 = 105e6 * AREA
    same = simulate(wire_fmu, HEAT_COOL, ignored, f=at_105)
    assert np.max(np.abs(same["strain"] - simulate(wire_fmu, HEAT_COOL, f=at_105)["strain"])) < 1e-12
    at_145 = 145e6 * AREA
    other = simulate(wire_fmu, HEAT_COOL, ignored, f=at_145)
    nominal = simulate(wire_fmu, HEAT_COOL, f=at_145)
    assert np.max(np.abs(other["strain"] - nominal["strain"])) > 2e-3  # misses the 145 MPa loop
    assert np.max(np.abs(other["strain"] - same["strain"])) < 1e-12  # the load no longer matters
    assert other["stress"][0] == pytest.approx(145e6)


def test_stress_blend_puts_the_ignored_stress_back(wire_fmu):
    ignored = {"sigma_surface": 125e6}
    f = 145e6 * AREA
    flat = simulate(wire_fmu, HEAT_COOL, ignored, f=f)
    assert np.array_equal(flat["strain"],
                          simulate(wire_fmu, HEAT_COOL, {**ignored, "stress_blend": 0.0}, f=f)["strain"])
    full = simulate(wire_fmu, HEAT_COOL, {**ignored, "stress_blend": 1.0}, f=f)
    nominal = simulate(wire_fmu, HEAT_COOL, f=f)  # the stress-aware wire
    assert np.max(np.abs(full["strain"] - nominal["strain"])) < 1e-9
    half = simulate(wire_fmu, HEAT_COOL, {**ignored, "stress_blend": 0.5}, f=f)

    def rms(a, b):
        return np.sqrt(np.mean(np.square(a["strain"] - b["strain"])))

    # half the stress change moves the loop part of the way (not pointwise: the hysteresis
    # remembers where it turned)
    assert 1e-4 < rms(half, flat) < rms(full, flat) and rms(half, full) < rms(flat, full)
    # without sigma_surface the wire follows the stress anyway: stress_blend changes nothing
    assert np.array_equal(simulate(wire_fmu, HEAT_COOL, {"stress_blend": 0.5}, f=f)["strain"],
                          nominal["strain"])


def test_drift_changes_the_loop_over_cycles(wire_fmu):
    dt, period, count = 0.01, 7.0, 5
    u = cycles(2.0, 0.8, period, count, dt)  # heats past 130 C + shift, cools below 30 C
    n = round(period / dt)
    shift, amplitude, settle = 5.0, -0.1, 2.0
    d = simulate(wire_fmu, u, {"drift_shift": shift, "drift_amplitude": amplitude,
                               "drift_settle_cycles": settle}, dt=dt)
    base = simulate(wire_fmu, u, dt=dt)
    nominal = base["strain"][-n:]
    assert np.max(np.abs(nominal - base["strain"][-2 * n:-n])) < 1e-6  # nominal: no drift
    first_change = np.argmax(base["xi"] < 1)
    assert np.array_equal(d["strain"][:first_change], base["strain"][:first_change])
    # every cycle sweeps xi 1 -> 0 -> 1: at the end of the last heating pulse, saturated,
    # count - 1/2 cycles are done
    last, hot = d["strain"][-n:], round(0.8 / dt) - 1
    scale = drift.strain_scale(count - 0.5, drift.DriftParams(amplitude, shift, settle))
    assert last[hot] == pytest.approx(scale * nominal[hot], rel=1e-9)
    assert np.max(np.abs(last - nominal)) > 5e-3  # the loop moved: hotter and smaller


# --- out-of-range input and bad parameters --------------------------------------------------

def test_out_of_range_stress_is_clamped_with_one_logged_warning(wire_fmu):
    log = []
    low = 40e6 * AREA  # below the reference wire's 60 MPa
    r = simulate(wire_fmu, pulse(2.0, 0.5, 1.0), f=low, log=log)
    clamped = simulate(wire_fmu, pulse(2.0, 0.5, 1.0), f=60e6 * AREA)
    assert np.array_equal(r["strain"], clamped["strain"]) and r["stress"][0] == pytest.approx(40e6)
    assert len(log) == 1, log  # once; room temperature (below 30 C) is saturation, no warning
    status, message = log[0]
    assert status == 1  # fmi2Warning
    assert "stress 4e+07 Pa" in message and "clamped to 6e+07 Pa" in message


def _wire(**params):
    return in_process(SmaWire, "wire", **params)


@pytest.mark.parametrize("params, match", [
    ({"hysteresis": 7.0}, r"hysteresis = 7 is no data set.*\[1, 2\]"),
    ({"hysteresis": 0.5}, "hysteresis must be 0"),
    ({"sigma_surface": 300e6}, r"sigma_surface must be 0 .*\[6e\+07, 2e\+08\] Pa"),
    ({"drive_current": 2.0}, "drive_current must be 0"),
    ({"diameter": 0.0}, "diameter must be positive"),
    ({"drift_settle_cycles": 0.0}, "cycles_to_settle must be positive"),
    ({"T_init": -1.0}, "T_init must be positive"),
    ({"stress_blend": 1.5}, r"stress_blend must be within \[0, 1\] \(got 1.5\)"),
], ids=["unknown-set", "fractional-set", "sigma-surface", "drive", "diameter", "drift", "T_init",
        "stress-blend"])
def test_bad_parameters_name_themselves(params, match):
    with pytest.raises(ValueError, match=match):
        _wire(**params).exit_initialization_mode()


def test_non_finite_input_is_an_error_naming_it():
    wire = _wire()
    wire.exit_initialization_mode()
    wire.flange_f = math.nan
    with pytest.raises(ValueError, match=r"input flange\.f is nan at t = 0\.5 s"):
        wire.do_step(0.5, DT)


def test_no_output_is_direct_feedthrough(fmu_dir):
    # the wire closes loops (temperature controller, spring or magnet load) with no algebraic loop
    md = read_model_description(str(fmu_dir / "SmaWire.fmu"))
    assert md.outputs and all(u.dependencies == [] for u in md.outputs)


@pytest.mark.parametrize("params", [
    {}, {"latent_heat": 20e3, "end_cooling": 0.8, "hysteresis": 1.0},
    {"latent_heat": 15e3, "h_exponent": 0.1, "sigma_surface": 120e6, "stress_blend": 0.5,
     "drift_amplitude": 0.1, "drift_shift": 3.0, "drift_settle_cycles": 2.0}],
    ids=["nominal", "latent-ends", "latent-h(T)-blend-drift"])
def test_kernel_paths_agree(params):
    """The SmaWire's compiled kernel gives the bits of its plain-Python source along a run through
    heating, cooling and a load swinging past the data set's stresses."""
    from kernel_paths import assert_paths_agree

    def inputs(k):
        return {"u": 2.2 if k < 700 else 0.0, "flange_f": LOAD_150G * (1 + 0.9 * math.sin(k / 90))}
    assert_paths_agree(_wire(**params), inputs, DT, 1200)


def test_a_failed_root_search_is_the_error_scipy_raises():
    """The kernel cannot raise: a latent-heat root search that fails (f(a), f(b) of one sign, as
    scipy's brentq finds it) sets an error flag in the state, which the slave raises after the
    step, as the Python core raised scipy's error."""
    from musclesim.components.sma import wirekernel
    wire = _wire(latent_heat=20e3)
    wire.exit_initialization_mode()
    wire.do_step(0.0, DT)
    wire.kx[wirekernel.X_ERROR] = 1.0  # as _brentq sets it
    with pytest.raises(ValueError, match="f\\(a\\) and f\\(b\\) must have different signs"):
        wire.do_step(DT, DT)
    assert wire.kx[wirekernel.X_ERROR] == 0.0
