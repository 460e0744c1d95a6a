"""The effect library (issue 4): every effect is parameters of an existing component, off gives the
nominal model exactly, and on it changes the simulation."""
import numpy as np
import pytest
from fmpy import read_model_description

from musclesim.components import CATALOGUE
from musclesim.cosim import Master, load_scenario, with_values
from musclesim.diagnosis import effects

from conftest import SCENARIOS

# a scenario and an instance per component to switch effects on in
WHERE = {"CrawlerBody": ("crawler-ideal", "body"),
         # on the incline, so that bending shows; the gait anchors the back block at once
         "FrictionBlock": ("crawler-gait-incline", "friction1"),
         "SoftActuator": ("crawler-gait-forward", "act1"),
         "SmaWire": ("sma-temperature-tracking", "wire"),
         "Thermocouple": ("sma-temperature-tracking", "thermocouple"),
         "DeadWeight": ("sma-dead-weight", "weight"), "LaserSensor": ("sma-dead-weight", "laser"),
         "Electromagnet": ("sma-position-control", "magnet"),
         "LoadCell": ("sma-position-control", "loadcell"),
         "CapstanMultiplier": ("sma-bench-multiplier", "mult")}
# context that lets a slow effect show within a short run (no effect by itself when it is off)
CONTEXT = {"training drift": ["wire.drift_cycles_start=200"],
           # a model ignoring stress (one surface at 125 MPa) of a wire loaded with 145 MPa
           "stress dependence ignored": ["wire.sigma_surface=125e6",
                                         f"load.offset={145e6 * 1.26677e-8!r}"],
           # a weight that stresses the fold above its hysteresis data's 200 MPa (about 260 MPa
           # at the load end)
           "hysteresis above the data's stresses": ["weight.mass=0.34"]}
IDS = [e.name for e in effects.EFFECTS]


def test_library_covers_the_issue_list():
    assert {"stress dependence ignored", "thermocouple lag", "thermocouple bias", "latent heat",
            "clamp heat loss", "convection change", "training drift", "anchoring slip",
            "friction switching time", "pressure-dependent stiffness",
            "viscous ground drag", "load inertia", "electromagnet force nonlinearity",
            "load-cell lag", "laser noise", "valve delay", "supply-pressure drop",
            "chamber leakage", "actuator bending on an incline", "friction decay",
            "capstan friction", "composition difference", "capstan heat loss",
            "supply resistance", "hysteresis above the data's stresses"} <= set(IDS)
    assert effects.find("anchoring slip").per_instance
    with pytest.raises(KeyError, match="known: stress dependence ignored"):
        effects.find("gremlins")


@pytest.mark.parametrize("effect", effects.EFFECTS, ids=IDS)
def test_off_values_are_the_fmu_defaults(fmu_dir, effect):
    assert effect.component in CATALOGUE and effect.reference.startswith("§")
    assert effect.regime in effects.REGIMES
    md = read_model_description(str(fmu_dir / f"{effect.component}.fmu"))
    variables = {v.name: v for v in md.modelVariables}
    for p in effect.parameters:
        v = variables[p.name]
        assert v.causality == "parameter" and float(v.start) == p.off
        assert p.lower < p.upper


def _run(fmu_dir, name, overrides, values=None):
    s = load_scenario(SCENARIOS / f"{name}.toml", overrides, stop_time=2.0)
    res = Master(with_values(s, values or {}), fmu_dir).run()
    assert res.error is None, res.error
    return res.data


_NOMINAL = {}


def _nominal(fmu_dir, name, context):
    """The run of scenario `name` with the `context` overrides alone, run once for this file's
    tests (runs are deterministic: each effect's "off" run is compared with it bit for bit)."""
    key = (str(fmu_dir), name, tuple(context))
    if key not in _NOMINAL:
        _NOMINAL[key] = _run(fmu_dir, name, context)
    return _NOMINAL[key]


@pytest.mark.parametrize("effect", effects.EFFECTS, ids=IDS)
def test_off_is_nominal_exactly_and_on_changes_the_run(fmu_dir, effect):
    name, instance = WHERE[effect.component]
    context = CONTEXT.get(effect.name, [])
    nominal = _nominal(fmu_dir, name, context)
    off = _run(fmu_dir, name, context, effect.values(instance, [p.off for p in effect.parameters]))
    assert np.array_equal(nominal, off)
    # on: the bound farthest from off, for every parameter
    far = [p.upper if abs(p.upper - p.off) >= abs(p.lower - p.off) else p.lower
           for p in effect.parameters]
    on = _run(fmu_dir, name, context, effect.values(instance, far))
    assert not np.allclose(nominal, on, rtol=1e-6, atol=1e-9)


def test_calibration_parameters_are_nominal_values_of_their_component(fmu_dir):
    """Every calibration parameter is a parameter (or the SmaWire's ambient input) of its component,
    owned by no effect, with bounds around its nominal value and a model reference section."""
    assert {c.name for c in effects.calibration_of("SmaWire")} >= {
        "T_amb", "h", "specific_heat", "rho_austenite", "rho_martensite", "hysteresis_shift",
        "strain_scale"}
    for c in effects.CALIBRATION:
        md = read_model_description(str(fmu_dir / f"{c.component}.fmu"))
        v = {v.name: v for v in md.modelVariables}[c.name]
        effect_params = {p.name for e in effects.by_component(c.component) for p in e.parameters}
        assert v.causality in ("parameter", "input") and c.name not in effect_params
        lo, hi = c.bounds(float(v.start))
        assert lo < float(v.start) < hi and c.reference.startswith("§") and c.why


@pytest.mark.parametrize("name, value", [("hysteresis_shift", 5.0), ("strain_scale", 1.1)])
def test_wire_calibration_parameters_are_exact_at_nominal_and_act_when_set(fmu_dir, name, value):
    nominal = _nominal(fmu_dir, "sma-temperature-tracking", [])
    default = {"hysteresis_shift": 0.0, "strain_scale": 1.0}[name]
    assert np.array_equal(nominal, _run(fmu_dir, "sma-temperature-tracking",
                                        [f"wire.{name}={default!r}"]))
    assert not np.allclose(nominal, _run(fmu_dir, "sma-temperature-tracking",
                                         [f"wire.{name}={value!r}"]), rtol=1e-6, atol=1e-9)


def test_importing_the_library_creates_no_slave():
    """The catalogues are read from the components' declarations when first asked for: importing
    the library imports no slave module (creating 25 slaves at import was its cost)."""
    import subprocess
    import sys

    code = ("import sys, musclesim.diagnosis.effects as e\n"
            "assert not [m for m in sys.modules if m.endswith('.slaves')], sys.modules\n"
            "e.calibration_of('CrawlerBody')\n"
            "print(sorted(m for m in sys.modules if m.endswith('.slaves')))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "['musclesim.components.crawler.slaves']"


def test_the_crawler_stiffness_reaches_the_calibration_from_its_one_declaration():
    """The crawler body's `k` is declared once, on its core's dataclass field; the calibration
    catalogue carries that declaration's bounds and section, per component as in the whole."""
    import dataclasses

    from musclesim.components.crawler.body import BodyParams

    field = {f.name: f for f in dataclasses.fields(BodyParams)}["k"]
    declared = field.metadata["calibrate"]
    k = {c.name: c for c in effects.calibration_of("CrawlerBody")}["k"]
    assert (k.lower, k.upper, k.relative, k.why) == (declared.lower, declared.upper,
                                                    declared.relative, declared.why)
    assert k.reference == field.metadata["source"]
    for component in CATALOGUE:
        assert effects.calibration_of(component) == [
            c for c in effects.CALIBRATION if c.component == component]
    with pytest.raises(AttributeError, match="no attribute 'CALIBRATIONS'"):
        effects.CALIBRATIONS
