"""Plausible values (issue 59): every declaration's range, read from its unit, its meaning (a
difference, a gauge pressure) or its own bounds, holds its default and refuses a value written in
another unit with the value likely meant (`musclesim.cosim.plausible`). No FMU is built."""
import pytest

from musclesim.components import CATALOGUE, declarations
from musclesim.cosim import Signal
from musclesim.cosim.plausible import problem, signal_unit
from musclesim.fmu import PLAUSIBLE, Plausible, declare
from musclesim.fmu.declaration import resolve

# every variable a scenario may set (parameters and inputs), by component
SETTABLE = [(c, n, d) for c in CATALOGUE for n, d in declarations(c).items()
            if d.causality != "output"]
KELVIN = [(c, n, d) for c, n, d in SETTABLE if d.unit == "K"]
# the K variables that are temperature differences, not temperatures: each one read for its
# meaning (a bias, a shift, a step, a noise level); a new K variable must be put on a side here
DIFFERENCES = {("Thermocouple", "bias"), ("Thermocouple", "noise_std"),
               ("Thermocouple", "quantum"), ("SmaWire", "drift_shift"),
               ("SmaWire", "hysteresis_shift"), ("CapstanMultiplier", "composition_shift"),
               ("ForcReference", "T_step")}


def _id(case):
    return f"{case[0]}.{case[1]}"


def test_every_kelvin_variable_is_a_temperature_or_a_declared_difference():
    assert len(KELVIN) == 20
    for component, name, decl in KELVIN:
        what = decl.plausible_range().what
        expected = "a temperature difference" if (component, name) in DIFFERENCES else \
            "a temperature"
        assert what == expected, f"{component}.{name}"


@pytest.mark.parametrize("case", KELVIN, ids=_id)
def test_a_kelvin_default_passes_and_45_is_refused_as_celsius_where_it_is_a_temperature(case):
    component, name, decl = case
    assert problem(component, f"x.{name}", name, decl.default) is None
    refused = problem(component, f"x.{name}", name, 45.0)
    if (component, name) in DIFFERENCES:  # 45 K more or less is a plausible difference
        assert refused is None
    else:
        assert refused == (f"x.{name} = 45 K is below the plausible 150-1500 K for a "
                           "temperature; 45 looks like degrees Celsius: write 318.15 K")
        assert "write 253.15 K" in problem(component, f"x.{name}", name, -20.0)
        assert problem(component, f"x.{name}", name, 2000.0).endswith(
            "is above the plausible 150-1500 K for a temperature")  # no likely slip: the range


@pytest.mark.parametrize("case", [c for c in SETTABLE if c[2].plausible_range()], ids=_id)
def test_every_declared_default_lies_in_its_range(case):
    """Not only the zero a feature off may take (the check lets it pass): the range itself."""
    component, name, decl = case
    rng = decl.plausible_range()
    assert rng.lo <= decl.default <= rng.hi or decl.default == 0.0, f"{component}.{name}"


@pytest.mark.parametrize("component, name, value, message", [
    ("SmaWire", "length", 58.42, "58.42 m is above the plausible 0-10 m for a length; 58.42 "
     "looks like mm: write 0.05842 m"),
    ("SmaWire", "diameter", 127.0, "127 looks like um: write 0.000127 m"),  # nearest the default
    ("CrawlerBody", "m1", 1e-300, "m1 = 1e-300 kg is below the plausible 1e-07 to 100 kg for a "
     "mass"),
    ("CrawlerBody", "m1", 200.0, "200 looks like g: write 0.2 kg"),
    ("LoadingProfile", "lo", 105.0, "105 looks like MPa: write 105000000 Pa"),
    ("SoftActuator", "p_supply", 40.0, "40 Pa is below the plausible 100 to 1e+07 Pa for an "
     "inflating gauge pressure; 40 looks like kPa: write 40000 Pa"),
    ("BendingActuator", "modulus", 120.0, "120 looks like GPa: write 120000000000 Pa"),
    ("SmaWire", "density", 6.45, "6.45 looks like g/cm3: write 6450 kg/m3"),
    ("SignalSource", "t_start", -1.0, "t_start = -1 s is below the plausible 0 to 1e+06 s for a "
     "time"),
    ("StrainProfile", "hi", 3.76, "hi = 3.76 is above its plausible 0-1"),
], ids=lambda v: str(v))
def test_a_sample_of_other_units_refuses_a_slip_with_the_value_likely_meant(component, name,
                                                                            value, message):
    said = problem(component, f"x.{name}", name, value)
    assert said is not None and message in said


@pytest.mark.parametrize("component, name, value", [
    ("SoftActuator", "p_exhaust", -20e3),  # a gauge pressure may be negative
    ("Thermocouple", "bias", -5.0), ("LaserSensor", "s", -1e-3),  # differences, signed
    ("SmaWire", "sigma_surface", 0.0),  # 0 = off, below a wire's plausible stress
    ("SmaWire", "sigma_surface", 120e6),
    ("PID", "Kp", 1e6), ("CrawlerBody", "k", -1.0),  # no range: the core's check says
    ("NotOurs", "T", 45.0), ("SmaWire", "no_such_name", 45.0),  # the wiring check's to say
])
def test_what_is_plausible_or_not_ours_to_judge_passes(component, name, value):
    assert problem(component, "x", name, value) is None


def test_a_value_read_from_a_parameters_file_is_not_repeated():
    said = problem("SmaWire", "wire.T_init in params/w.toml", "T_init", 45.0, show=False)
    assert said == ("wire.T_init in params/w.toml is below the plausible 150-1500 K for a "
                    "temperature; it looks like degrees Celsius: add 273.15 K")
    said = problem("SmaWire", "wire.length in p.toml", "length", 58.42, show=False)
    assert said.endswith("it looks like mm: multiply it by 0.001") and "58" not in said


def test_a_unitless_signal_takes_the_unit_its_wiring_gives():
    """A signal source's offset is of its output's quantity: fed to a controller's reference,
    whose measurement is a thermocouple's reading, it is a temperature; fed to a wire's load, a
    force (no default range)."""
    components = {"ref": "SignalSource", "pid": "GainScheduledPID", "tc": "Thermocouple",
                  "wire": "SmaWire", "load": "SignalSource"}
    wiring = [(Signal("ref", "y"), Signal("pid", "u_s")), (Signal("tc", "T_meas"),
                                                          Signal("pid", "u_m")),
              (Signal("pid", "y"), Signal("wire", "u")), (Signal("load", "y"),
                                                          Signal("wire", "flange.f"))]
    assert signal_unit(components, wiring, Signal("ref", "offset")) == "K"
    assert signal_unit(components, wiring, Signal("pid", "x[3]")) == "K"
    assert signal_unit(components, wiring, Signal("load", "amplitude")) == "N"
    assert signal_unit(components, wiring[:1], Signal("ref", "offset")) == "1"  # nothing says
    # the controller's error carries its measurement's quantity; its output does not
    assert signal_unit(components, wiring, Signal("pid", "e")) == "K"
    assert signal_unit(components, wiring, Signal("pid", "y")) == "1"
    assert "75 looks like degrees Celsius" in problem("SignalSource", "ref.offset", "offset", 75.0,
                                                      unit="K")
    assert problem("SignalSource", "ref.amplitude", "amplitude", 30.0, unit="K") is None


def test_a_declaration_takes_only_ranges_it_understands():
    assert resolve(None, "K") == PLAUSIBLE["K"] and resolve(None, "N") is None
    assert resolve("gauge pressure", "Pa").lo < 0 and resolve((1.0, 2.0), "1") == Plausible(1, 2)
    for bad in ((2.0, 1.0), "plausible", (1.0,)):
        with pytest.raises(ValueError, match="plausible"):
            declare(1.0, "m", "a length", plausible=bad)
