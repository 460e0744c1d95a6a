"""The SmaWire's core (components/sma/smawire.py): its parameters declared once with their
checks, and `SmaWireCore` against the thermal and Preisach cores stepped by hand."""
import dataclasses

import numpy as np
import pytest

from musclesim.components.sma import datasets, drift, submodels, thermal
from musclesim.components.sma.preisach import PreisachModel
from musclesim.components.sma.smawire import SmaWireCore, SmaWireParams
from musclesim.fmu import Calibration

ROOT = datasets.PACKAGE_DIR
WIRE = thermal.ThermalParams()
F = 1.47  # N, about 116 MPa on the 127 um wire
DT = 4e-4  # s, the study's 2.5 kHz loop (§sma-bench)


def core(**params):
    return SmaWireCore(SmaWireParams(hysteresis=1.0, **params), WIRE, ROOT)


def test_every_parameter_is_declared_once_with_its_role():
    fields = {f.name: f.metadata for f in dataclasses.fields(SmaWireParams)}
    assert list(fields) == [
        "T_init", "drive_current", "hysteresis", "sigma_surface", "stress_blend", "end_cooling",
        "conductivity", "drift_amplitude", "drift_shift", "drift_settle_cycles",
        "drift_cycles_start", "hysteresis_shift", "strain_scale"]
    assert all(m["unit"] and m["source"].startswith("§") for m in fields.values())
    assert {n for n, m in fields.items() if m["effect"]} == {
        "stress_blend", "end_cooling", "drift_amplitude", "drift_shift"}
    assert isinstance(fields["T_init"]["calibrate"], Calibration)
    # the drift's defaults are its core's (off, and its pace)
    p = SmaWireParams()
    assert p.drift_params() == drift.DriftParams()
    assert SmaWireParams(drift_amplitude=0.1, drift_shift=2.0, drift_settle_cycles=9.0
                         ).drift_params() == drift.DriftParams(0.1, 2.0, 9.0)
    assert (p.drive, SmaWireParams(drive_current=1.0).drive) == ("voltage", "current")


@pytest.mark.parametrize("params, match", [
    ({"drive_current": 0.5}, "drive_current must be 0"), ({"T_init": 0.0}, "T_init must be"),
    ({"stress_blend": 1.5}, "stress_blend must be within"),
    ({"strain_scale": 0.0}, "strain_scale must be positive"),
    ({"hysteresis_shift": float("nan")}, "hysteresis_shift finite"),
    ({"drift_cycles_start": -1.0}, "drift_cycles_start must be non-negative"),
])
def test_check_names_the_bad_parameter(params, match):
    with pytest.raises(ValueError, match=match):
        SmaWireParams(**params).check()
    SmaWireParams().check()


def test_the_core_checks_its_submodels_parameters():
    with pytest.raises(ValueError, match="diameter"):
        SmaWireCore(SmaWireParams(), thermal.ThermalParams(diameter=0.0), ROOT)
    with pytest.raises(ValueError, match="cycles_to_settle"):
        core(drift_settle_cycles=0.0)
    with pytest.raises(ValueError, match="end_cooling"):
        core(end_cooling=1.5)


def test_submodels_follow_the_effects():
    assert type(core().thermal) is submodels.Lumped and type(core().ends) is submodels.NoEnds
    c = SmaWireCore(SmaWireParams(hysteresis=1.0, end_cooling=0.9),
                    thermal.ThermalParams(latent_heat=20e3), ROOT)
    assert type(c.thermal) is submodels.LumpedLatent and type(c.ends) is submodels.ColdEnds


def test_stress_blend_puts_back_its_share_of_the_stress():
    assert core().stress_seen(F) == F / thermal.cross_section(WIRE)
    c = core(sigma_surface=125e6, stress_blend=0.25)
    sigma = F / thermal.cross_section(WIRE)
    assert c.stress_seen(F) == 125e6 + 0.25 * (sigma - 125e6)
    assert core(sigma_surface=125e6).stress_seen(F) == sigma  # one surface: stress ignored


def test_core_is_the_thermal_and_preisach_cores_stepped_by_hand():
    """Nominal wire under 2 V for 0.4 s, then cooling: the temperature by `thermal.step` with the
    resistance of the last step's fraction, the strain by the Preisach model at the new
    temperature."""
    c = core()
    sigma = c.stress_seen(F)
    c.start(0.0, 20.0, F, sigma, 0.0)
    surface = datasets.surface(1.0, 0.0, ROOT)
    model = PreisachModel(surface)
    T = 293.15 - 273.15
    eps_max = surface.F(surface.t_hi, surface.t_lo, sigma)
    eps = model.reset(min(max(T, surface.t_lo), surface.t_hi), sigma, 0.0)
    xi = thermal.martensite_fraction(eps, eps_max)
    peak = 0.0
    for k in range(2000):
        u = 2.0 if k < 1000 else 0.0
        c.step(u, 20.0, F, sigma, k * DT, DT)
        T = thermal.step(T, thermal.ThermalInputs(u, 20.0, xi), DT, WIRE)
        eps = model.step(min(max(T, surface.t_lo), surface.t_hi), sigma, (k + 1) * DT)
        xi = thermal.martensite_fraction(eps, eps_max)
        assert (c.T_C, c.eps, c.xi) == (T, eps, xi), k
        peak = max(peak, c.eps)
    assert peak > 0.5 * eps_max and c.eps < peak  # it transformed, and cooling gave some back
    assert c.stress_held == F / c.area and c.resistance() == thermal.resistance(xi, WIRE)


@pytest.mark.parametrize("params, wire", [
    ({}, WIRE),
    ({"end_cooling": 0.8, "drift_amplitude": 0.1, "drift_shift": 4.0, "drift_settle_cycles": 2.0},
     thermal.ThermalParams(latent_heat=20e3)),
    ({"sigma_surface": 120e6, "stress_blend": 0.5},
     thermal.ThermalParams(latent_heat=15e3, h_exponent=0.1)),
], ids=["nominal", "latent-ends-drift", "latent-h(T)-blend"])
def test_compiled_kernel_is_its_python_bit_for_bit(params, wire):
    """The kernel's `advance` and `evaluate` compiled against their plain-Python bodies
    (`.py_func`) on copies of the same arrays, step by step through heating and cooling."""
    from musclesim.components.sma import wirekernel as wk
    if getattr(wk.advance, "py_func", None) is None:
        pytest.skip("numba is not installed: the kernel runs as Python")
    c = SmaWireCore(SmaWireParams(hysteresis=1.0, **params), wire, ROOT)
    c.start(0.0, 20.0, F, c.stress_seen(F), 0.0)
    p, x = c.kp, c.kx
    x_py = x.copy()
    y, y_py = np.zeros(len(wk.OUTPUTS)), np.zeros(len(wk.OUTPUTS))
    for k in range(1500):
        u = np.array([2.0 if k < 700 else 0.0, 293.15, F * (1 + 0.2 * np.sin(k * 1e-2))])
        wk.evaluate(p, x, u, k * DT, y)
        wk.evaluate.py_func(p, x_py, u, k * DT, y_py)
        assert y.tobytes() == y_py.tobytes(), k
        wk.advance(p, x, u, y, k * DT, DT)
        wk.advance.py_func(p, x_py, u, y_py, k * DT, DT)
        assert x.tobytes() == x_py.tobytes(), k
    assert 0 < c.eps < 0.05 and x[wk.X_ERROR] == 0


def test_the_state_holds_the_stack_bound_of_each_memory():
    """Each Preisach memory of the state has max_extrema + 1 slots: the most `push_extremum`
    holds before it forgets a pair."""
    from musclesim.components.sma import preisach, wirekernel as wk
    c = core(end_cooling=0.5)
    size = len(preisach.memory())
    assert size == preisach.M_HEAD + 3 * (preisach.MemoryParams().max_extrema + 1)
    assert len(c.kx) == wk.X_MEMORIES + (len(c.ends.zones) + 2) * size
