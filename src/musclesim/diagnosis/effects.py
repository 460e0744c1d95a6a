"""The library of unmodelled effects the sim-to-real diagnosis can add (§named-effects).

Every effect is a set of parameters of an existing component whose defaults give the nominal
model exactly (the effect off), the regime where it should show (its signature, a key of
`REGIMES`) and the model reference section it comes from (`reference`, a `§label`). Adding an
effect to a scenario is therefore only a matter of parameter values on the instances of its
component. The component declares each of those parameters once, with its default and fitting
bounds (``declare(..., effect=(lower, upper))``, read through `musclesim.components.declarations`);
this library names them.

`CALIBRATION` lists, per component, the nominal values a real bench has differently (ambient,
convection, material data, the hysteresis's temperature shift and strain scale, ...), with bounds
and their model reference section: the diagnosis calibrates them before it tests any effect, and an
effect is fitted together with them, so that "raise h" cannot pose as "latent heat". The
components declare them (``declare(..., calibrate=Calibration(...))``); `calibration_of` reads one
component's from its declarations when first asked, and `CALIBRATION` collects every component's,
in catalogue order, when first read: importing this library creates no slave.

The rest of the per-component knowledge the diagnosis uses is declared here too, so that its
generic code names no component: which measured variables define regimes by their name
(`STRAIN_VARIABLES`, `FORCE_VARIABLES`, `SWITCHING_INDICATORS`; `musclesim.diagnosis.regimes`)
and which measured ports stay coupled when every measured signal is replayed (`COUPLED_PORTS`;
`musclesim.diagnosis.problem`).
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache

from musclesim.components import CATALOGUE, declarations
from musclesim.cosim import ParamRef


@dataclass(frozen=True)
class Parameter:
    """One parameter of an effect: its value when the effect is off and its fitting bounds."""

    name: str
    off: float
    lower: float
    upper: float


# Operating regimes an effect's gain should concentrate in; musclesim.diagnosis.regimes computes
# them from the measured signals (temperatures [K], strains, loads [N], positions [m], indicators).
REGIMES: dict[str, str] = {
    "all": "every sample",
    "changing": "the temperature changes faster than its median rate",
    "heating": "the temperature rises",
    "cooling": "the temperature falls",
    "hot": "the top fifth of the measured temperatures",
    "transformation": "the measured strain changes (the wire transforms)",
    "late": "the second half of each experiment",
    "stress_extremes": "the load is more than one standard deviation from its median",
    "stick": "a block stands still",
    "slip": "a block slides",
    "switching": "within 0.5 s after a friction indicator switches",
    "high_force": "the actuator force is above its median",
    "load_changing": "the measured load changes faster than its median rate",
    "pressure_changing": "a measured pressure changes faster than its median rate",
    "pressurised": "a measured pressure is above its median",
}

# Measured signals that define regimes by their variable's name (the others are found by their
# unit: the first temperature in K, the first load in N or Pa, the first pressure in Pa, every
# position in m). A column whose variable is named here, on any instance:
STRAIN_VARIABLES = ("strain",)  # SmaWire's strain: "transformation" where it changes
# an actuation force (FrictionSwitchingInputs', SoftActuator's f_a): the load of
# "stress_extremes", "high_force" and "load_changing" when no column in N or Pa is measured
FORCE_VARIABLES = ("f_a",)
# {component: its friction indicators}: "switching" is the 0.5 s after one of these changes, when
# the data set replays them as inputs (§ideal-actuation's ideal actuation; not its force f_a)
SWITCHING_INDICATORS: dict[str, tuple[str, ...]] = {"FrictionSwitchingInputs": ("u1", "u2")}
# Prefixes of physical port variables (half of a two-way mechanical coupling, such as the crawler
# body's flange position into its central actuator): a measured port stays coupled in the model
# with every measured signal replayed, since the element it drives would differentiate the
# measurement's noise and quantisation.
COUPLED_PORTS = ("flange",)


@dataclass(frozen=True)
class Effect:
    """A candidate unmodelled effect.

    ``regime`` is a key of `REGIMES`. ``per_instance``: the effect may differ between instances
    of the component (the front and the back friction block slip differently, §gait), so it is
    fitted per instance.
    """

    name: str
    component: str
    names: tuple[str, ...]  # its parameters, each declared by the component with its bounds
    regime: str
    reference: str
    description: str
    per_instance: bool = False

    @property
    def parameters(self) -> tuple[Parameter, ...]:
        """Its `Parameter`s: off at the component's declared default, the declared bounds."""
        declared, out = declarations(self.component), []
        for name in self.names:
            d = declared[name]
            assert d.effect is not None  # an effect's parameter is declared with its bounds
            out.append(Parameter(name, d.default, *d.effect))
        return tuple(out)

    def values(self, instance: str, values: Sequence[float]) -> dict[ParamRef, float]:
        """The parameter values (for `musclesim.cosim.with_values`) that put this effect at
        `values` (one per parameter) on `instance`."""
        return {ParamRef(instance, name): float(v) for name, v in zip(self.names, values)}


EFFECTS = (
    # SMA wire and its bench (§sma-bench, §named-effects, §sma-material)
    Effect("stress dependence ignored", "SmaWire", ("stress_blend",),
           "stress_extremes", "§position-control, §named-effects",
           "the model uses one constant-stress surface (sigma_surface) but the wire follows the "
           "stress; applies where the scenario sets sigma_surface"),
    Effect("thermocouple lag", "Thermocouple", ("tau",),
           "changing", "§sma-wire, §named-effects",
           "the junction follows the wire with a first-order lag"),
    Effect("thermocouple bias", "Thermocouple", ("bias",),
           "all", "§named-effects, §sensors",
           "the reading is offset from the wire's core temperature"),
    Effect("latent heat", "SmaWire", ("latent_heat",),
           "transformation", "§thermal-model, §sma-material",
           "heat absorbed while austenite forms, released while martensite forms"),
    Effect("clamp heat loss", "SmaWire", ("end_cooling",),
           "hot", "§named-effects, §thermal-model",
           "the clamps conduct heat: the wire's ends stay colder than its core and transform "
           "later, so the wire contracts less than its core temperature says"),
    Effect("convection change", "SmaWire", ("h_exponent",),
           "hot", "§named-effects, §convection",
           "the convection coefficient grows with the excess temperature"),
    Effect("training drift", "SmaWire",
           ("drift_amplitude", "drift_shift"),
           "late", "§drift",
           "the major loop changes over the first cycles, then settles"),
    # loads and sensors of the position-control bench (§sma-bench, §position-control,
    # §named-effects)
    Effect("load inertia", "DeadWeight", ("inertia",),
           "transformation", "§position-control, §named-effects",
           "the weight rings on its link after a fast lift, pulling on the wire"),
    Effect("electromagnet force nonlinearity", "Electromagnet",
           ("nonlinearity",), "high_force", "§loads, §named-effects",
           "the magnet's force grows faster or slower than its coil current"),
    Effect("load-cell lag", "LoadCell", ("tau",), "load_changing",
           "§sma-bench, §named-effects",
           "the load cell follows the tension with a first-order lag"),
    Effect("laser noise", "LaserSensor", ("noise_std",), "all",
           "§sma-bench, §named-effects", "the laser's reading is noisy (noise raises the floor; a "
           "fit of it cannot shrink a gap)"),
    # crawler (§crawler, §named-effects)
    Effect("anchoring slip", "FrictionBlock",
           ("mu_s_high", "mu_k_high"),
           "stick", "§gait, §named-effects",
           "the inflated actuator grips less than the slip-angle estimate", per_instance=True),
    Effect("friction switching time", "FrictionBlock", ("t_switch",),
           "switching", "§crawler-hardware, §named-effects",
           "contact builds over a transition time instead of at once"),
    Effect("pressure-dependent stiffness", "CrawlerBody", ("k_slope",),
           "high_force", "§two-mass, §named-effects",
           "the central actuator's stiffness changes with its pressure"),
    Effect("viscous ground drag", "CrawlerBody", ("c_ground",),
           "slip", "§named-effects",
           "the ground resists motion in proportion to the block's speed"),
    Effect("actuator bending on an incline", "FrictionBlock", ("bending",),
           "stick", "§friction, §gait, §named-effects",
           "the inflated actuator bends under shear on a slope and grips less, the more the steeper"),
    Effect("friction decay", "FrictionBlock", ("mu_decay",),
           "late", "§gait, §named-effects",
           "particles collect on the silicone and lower its friction over time"),
    # pneumatic actuation of the crawler (§crawler-hardware, §named-effects, §valves)
    # its gain can show at any sample: under PWM, unequal delays change the width of every pulse
    # (a 5 ms difference is a quarter of the 20 ms carrier's period in duty), which moves the
    # pressure a valve holds, not only where it changes, and the valves pulse nearly throughout
    # a gait; equal delays only shift each pulse
    Effect("valve delay", "SoftActuator",
           ("t_open_delay", "t_close_delay"),
           "all", "§named-effects, §valves",
           "the solenoid valves open and close a few ms after their PWM command: every pulse "
           "shifted and, where the delays differ, narrowed or widened"),
    Effect("supply-pressure drop", "SoftActuator", ("supply_drop",),
           "pressurised", "§crawler-hardware, §named-effects",
           "the inflation pump does not hold its pressure"),
    Effect("chamber leakage", "SoftActuator", ("C_leak",),
           "pressurised", "§named-effects",
           "air leaks from the chamber to the atmosphere"),
    # fast actuation: the capstan multiplier (§capstan-multiplier, §named-effects); the hanging
    # load's inertia is "load inertia" above (DeadWeight, under the multiplier as under the straight
    # wire)
    Effect("capstan friction", "CapstanMultiplier", ("mu_f",),
           "transformation", "§capstan-multiplier, §named-effects",
           "the wire's friction on the capstans differs from §capstan-multiplier's 0.0237 (a "
           "worn or dirty groove): the segments nearer the clamp carry a different tension; off = "
           "the stated "
           "friction, the CapstanMultiplier's default"),
    Effect("composition difference", "CapstanMultiplier",
           ("composition_shift",), "transformation",
           "§capstan-multiplier, §named-effects",
           "the multiplier's wire is not the composition the hysteresis was identified on: it "
           "transforms at temperatures shifted by a constant"),
    Effect("capstan heat loss", "CapstanMultiplier",
           ("contact_conductance",), "cooling",
           "§capstan-multiplier, §named-effects",
           "the PTFE tubes draw heat from the wire lying in their grooves: the segments cool "
           "faster, the ones between two tubes fastest"),
    Effect("supply resistance", "CapstanMultiplier",
           ("source_resistance",), "heating",
           "§pulse-gap, §named-effects",
           "the voltage supply, its leads and its switch have a resistance in series with the "
           "wire: the wire takes less than V^2 / R, the less the colder (martensite) it is"),
    Effect("hysteresis above the data's stresses", "CapstanMultiplier",
           ("stress_rise",), "stress_extremes",
           "§pulse-gap, §named-effects",
           "above the hysteresis data's highest stress the wire transforms hotter the higher "
           "the stress (Clausius-Clapeyron) where the nominal model holds the highest stress's "
           "hysteresis"),
)


@dataclass(frozen=True)
class Calibrated:
    """A nominal value a real bench has differently: calibrated before any effect is tested.

    The bounds are factors on the scenario's value (`relative`) or offsets added to it; an input
    (such as the ambient temperature) is calibrated as a constant unless the data set states it
    as a bench condition, which then fixes it. A `period` (> 0) makes the parameter periodic (a
    phase): its cost repeats every period and may have several wells in one, so the calibration
    scans one whole period before its local fit, and its bounds span more than one period, so
    that the fit can follow a well across the period's ends.
    """

    component: str
    name: str
    lower: float
    upper: float
    relative: bool
    reference: str
    why: str
    period: float = 0.0

    def bounds(self, nominal: float) -> tuple[float, float]:
        """Absolute (lower, upper) around the scenario's `nominal` value (a relative pair on a
        negative value, such as a vacuum's gauge pressure, comes out in increasing order)."""
        if self.relative:
            lo, hi = sorted((self.lower * nominal, self.upper * nominal))
            return lo, hi
        return nominal + self.lower, nominal + self.upper


# Every component's calibration parameters, as the components declare them (§convection gives h,
# the specific heat and the resistivities within about +-30 %; §ideal-actuation the crawler's k
# and c; the sensors' gains). A sensor's offset is not one where an effect owns it (the
# thermocouple's bias): calibration must not absorb an effect. Read from one component's
# declarations when it is first asked for (a slave of that component is created then, once), not
# at import: `CALIBRATION`, every component's, is built when first read (module `__getattr__`).
@cache
def _calibration_of(component: str) -> tuple[Calibrated, ...]:
    """The `Calibrated` parameters `component` declares, in its declaration order."""
    return tuple(Calibrated(component, d.name, c.lower, c.upper, c.relative, d.source, c.why,
                            c.period)
                 for d in declarations(component).values() if (c := d.calibrate) is not None)


def __getattr__(name: str) -> tuple[Calibrated, ...]:
    """`CALIBRATION`: every component's calibration parameters, in catalogue order, built when
    first read (`name` is the module attribute asked for)."""
    if name == "CALIBRATION":
        return tuple(c for component in CATALOGUE for c in _calibration_of(component))
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def calibration_of(component: str) -> list[Calibrated]:
    """The calibration parameters (`Calibrated`) of one component (a key of
    `musclesim.components.CATALOGUE`), in library order."""
    return list(_calibration_of(component))


def by_component(component: str) -> list[Effect]:
    """The effects of one `component` (e.g. ``"SmaWire"``), in library order."""
    return [e for e in EFFECTS if e.component == component]


def find(name: str) -> Effect:
    """The effect called `name`; raise KeyError listing the known names otherwise."""
    for effect in EFFECTS:
        if effect.name == name:
            return effect
    raise KeyError(f"no effect {name!r} (known: {', '.join(e.name for e in EFFECTS)})")
