"""The library of unmodelled effects the sim-to-real diagnosis can add (§named-effects).

Every effect is a set of parameters of an existing component whose values at ``off`` give the
nominal model exactly (they are the FMU's defaults), with bounds for fitting, the regime where it
should show (its signature, a key of `REGIMES`) and the model reference section it comes from
(`reference`, a `§label`). Adding an
effect to a scenario is therefore only a matter of parameter values on the instances of its
component.

`CALIBRATION` lists, per component, the nominal values a real bench has differently (ambient,
convection, material data, the hysteresis's temperature shift and strain scale, ...), with bounds
and their model reference section: the diagnosis calibrates them before it tests any effect, and an
effect is fitted together with them, so that "raise h" cannot pose as "latent heat".

The rest of the per-component knowledge the diagnosis uses is declared here too, so that its
generic code names no component: which measured variables define regimes by their name
(`STRAIN_VARIABLES`, `FORCE_VARIABLES`, `SWITCHING_INDICATORS`; `musclesim.diagnosis.regimes`)
and which measured ports stay coupled when every measured signal is replayed (`COUPLED_PORTS`;
`musclesim.diagnosis.problem`).
"""
from dataclasses import dataclass


@dataclass(frozen=True)
class Parameter:
    """One parameter of an effect: its value when the effect is off and its fitting bounds."""

    name: str
    off: float
    lower: float
    upper: float


# Operating regimes an effect's gain should concentrate in; musclesim.diagnosis.regimes computes
# them from the measured signals (temperatures [K], strains, loads [N], positions [m], indicators).
REGIMES = {
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
SWITCHING_INDICATORS = {"FrictionSwitchingInputs": ("u1", "u2")}
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
    parameters: tuple
    regime: str
    reference: str
    description: str
    per_instance: bool = False

    def overrides(self, instance, values):
        """``--set`` strings that put this effect at `values` (one per parameter) on `instance`."""
        return [f"{instance}.{p.name}={v!r}" for p, v in zip(self.parameters, values)]


EFFECTS = (
    # SMA wire and its bench (§sma-bench, §named-effects, §sma-material)
    Effect("stress dependence ignored", "SmaWire", (Parameter("stress_blend", 0.0, 0.0, 1.0),),
           "stress_extremes", "§position-control, §named-effects",
           "the model uses one constant-stress surface (sigma_surface) but the wire follows the "
           "stress; applies where the scenario sets sigma_surface"),
    Effect("thermocouple lag", "Thermocouple", (Parameter("tau", 0.0, 0.0, 2.0),),
           "changing", "§sma-wire, §named-effects",
           "the junction follows the wire with a first-order lag"),
    Effect("thermocouple bias", "Thermocouple", (Parameter("bias", 0.0, -10.0, 10.0),),
           "all", "§named-effects, §sensors",
           "the reading is offset from the wire's core temperature"),
    Effect("latent heat", "SmaWire", (Parameter("latent_heat", 0.0, 0.0, 30e3),),
           "transformation", "§thermal-model, §sma-material",
           "heat absorbed while austenite forms, released while martensite forms"),
    Effect("clamp heat loss", "SmaWire", (Parameter("end_cooling", 0.0, 0.0, 1.0),),
           "hot", "§named-effects, §thermal-model",
           "the clamps conduct heat: the wire's ends stay colder than its core and transform "
           "later, so the wire contracts less than its core temperature says"),
    Effect("convection change", "SmaWire", (Parameter("h_exponent", 0.0, 0.0, 0.5),),
           "hot", "§named-effects, §convection",
           "the convection coefficient grows with the excess temperature"),
    Effect("training drift", "SmaWire",
           (Parameter("drift_amplitude", 0.0, -0.2, 0.2), Parameter("drift_shift", 0.0, -10.0, 10.0)),
           "late", "§drift",
           "the major loop changes over the first cycles, then settles"),
    # loads and sensors of the position-control bench (§sma-bench, §position-control,
    # §named-effects)
    Effect("load inertia", "DeadWeight", (Parameter("inertia", 0.0, 0.0, 1.0),),
           "transformation", "§position-control, §named-effects",
           "the weight rings on its link after a fast lift, pulling on the wire"),
    Effect("electromagnet force nonlinearity", "Electromagnet",
           (Parameter("nonlinearity", 0.0, -0.5, 0.5),), "high_force", "§loads, §named-effects",
           "the magnet's force grows faster or slower than its coil current"),
    Effect("load-cell lag", "LoadCell", (Parameter("tau", 0.0, 0.0, 0.5),), "load_changing",
           "§sma-bench, §named-effects",
           "the load cell follows the tension with a first-order lag"),
    Effect("laser noise", "LaserSensor", (Parameter("noise_std", 0.0, 0.0, 2e-5),), "all",
           "§sma-bench, §named-effects", "the laser's reading is noisy (noise raises the floor; a "
           "fit of it cannot shrink a gap)"),
    # crawler (§crawler, §named-effects)
    Effect("anchoring slip", "FrictionBlock",
           (Parameter("mu_s_high", 1.0, 0.2, 1.0), Parameter("mu_k_high", 0.75, 0.15, 0.75)),
           "stick", "§gait, §named-effects",
           "the inflated actuator grips less than the slip-angle estimate", per_instance=True),
    Effect("friction switching time", "FrictionBlock", (Parameter("t_switch", 0.0, 0.0, 0.4),),
           "switching", "§crawler-hardware, §named-effects",
           "contact builds over a transition time instead of at once"),
    Effect("pressure-dependent stiffness", "CrawlerBody", (Parameter("k_slope", 0.0, -0.04, 0.04),),
           "high_force", "§two-mass, §named-effects",
           "the central actuator's stiffness changes with its pressure"),
    Effect("viscous ground drag", "CrawlerBody", (Parameter("c_ground", 0.0, 0.0, 5.0),),
           "slip", "§named-effects",
           "the ground resists motion in proportion to the block's speed"),
    Effect("actuator bending on an incline", "FrictionBlock", (Parameter("bending", 0.0, 0.0, 4.0),),
           "stick", "§friction, §gait, §named-effects",
           "the inflated actuator bends under shear on a slope and grips less, the more the steeper"),
    Effect("friction decay", "FrictionBlock", (Parameter("mu_decay", 0.0, 0.0, 0.02),),
           "late", "§gait, §named-effects",
           "particles collect on the silicone and lower its friction over time"),
    # pneumatic actuation of the crawler (§crawler-hardware, §named-effects, §valves)
    # its gain can show at any sample: under PWM, unequal delays change the width of every pulse
    # (a 5 ms difference is a quarter of the 20 ms carrier's period in duty), which moves the
    # pressure a valve holds, not only where it changes, and the valves pulse nearly throughout
    # a gait; equal delays only shift each pulse
    Effect("valve delay", "SoftActuator",
           (Parameter("t_open_delay", 0.0, 0.0, 0.02), Parameter("t_close_delay", 0.0, 0.0, 0.02)),
           "all", "§named-effects, §valves",
           "the solenoid valves open and close a few ms after their PWM command: every pulse "
           "shifted and, where the delays differ, narrowed or widened"),
    Effect("supply-pressure drop", "SoftActuator", (Parameter("supply_drop", 0.0, 0.0, 0.5),),
           "pressurised", "§crawler-hardware, §named-effects",
           "the inflation pump does not hold its pressure"),
    Effect("chamber leakage", "SoftActuator", (Parameter("C_leak", 0.0, 0.0, 5e-11),),
           "pressurised", "§named-effects",
           "air leaks from the chamber to the atmosphere"),
    # fast actuation: the capstan multiplier (§capstan-multiplier, §named-effects); the hanging
    # load's inertia is "load inertia" above (DeadWeight, under the multiplier as under the straight
    # wire)
    Effect("capstan friction", "CapstanMultiplier", (Parameter("mu_f", 0.0237, 0.0, 0.1),),
           "transformation", "§capstan-multiplier, §named-effects",
           "the wire's friction on the capstans differs from §capstan-multiplier's 0.0237 (a "
           "worn or dirty groove): the segments nearer the clamp carry a different tension; off = "
           "the stated "
           "friction, the CapstanMultiplier's default"),
    Effect("composition difference", "CapstanMultiplier",
           (Parameter("composition_shift", 0.0, -10.0, 10.0),), "transformation",
           "§capstan-multiplier, §named-effects",
           "the multiplier's wire is not the composition the hysteresis was identified on: it "
           "transforms at temperatures shifted by a constant"),
    Effect("capstan heat loss", "CapstanMultiplier",
           (Parameter("contact_conductance", 0.0, 0.0, 0.01),), "cooling",
           "§capstan-multiplier, §named-effects",
           "the PTFE tubes draw heat from the wire lying in their grooves: the segments cool "
           "faster, the ones between two tubes fastest"),
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

    def bounds(self, nominal):
        """Absolute (lower, upper) around the scenario's `nominal` value (a relative pair on a
        negative value, such as a vacuum's gauge pressure, comes out in increasing order)."""
        if self.relative:
            return tuple(sorted((self.lower * nominal, self.upper * nominal)))
        return nominal + self.lower, nominal + self.upper


# Every component's calibration parameters (§convection gives h, the specific heat and the
# resistivities within about +-30 %; §ideal-actuation the crawler's k and c; the sensors' gains). A
# sensor's offset is not here where an effect owns it (the thermocouple's bias): calibration must
# not absorb an effect.
_WIRE_THERMAL = (
    Calibrated("SmaWire", "T_amb", -8.0, 8.0, False, "§thermal-model",
               "the bench's room air; stated in the data set's [conditions] when measured"),
    Calibrated("SmaWire", "h", 0.6, 1.6, True, "§convection",
               "convection depends on the air around the wire (§convection: 50-150 W/(m^2 K))"),
    Calibrated("SmaWire", "specific_heat", 0.8, 1.2, True, "§sma-material",
               "data-sheet value of NiTi, alloy dependent"),
    Calibrated("SmaWire", "rho_austenite", 0.85, 1.15, True, "§sma-material",
               "resistivity varies with the alloy and the contacts"),
    Calibrated("SmaWire", "rho_martensite", 0.85, 1.15, True, "§sma-material",
               "resistivity varies with the alloy and the contacts"),
)
CALIBRATION = (
    *_WIRE_THERMAL,
    # where the record starts: a bench holds the wire near the scenario's start before recording,
    # to a few kelvin; fixed, it would break the symmetry of a thermocouple's offset with the
    # ambient and the transformation temperatures all moved by it (§thermal-model)
    Calibrated("SmaWire", "T_init", -5.0, 5.0, False, "§thermal-model, §preisach",
               "the wire's temperature when the record starts"),
    Calibrated("SmaWire", "hysteresis_shift", -8.0, 8.0, False,
               "§preisach, §named-effects, §sma-material",
               "transformation temperatures shift with composition and training"),
    Calibrated("SmaWire", "strain_scale", 0.85, 1.15, True, "§forc-identification, §sma-material",
               "the recoverable strain differs from wire to wire"),
    # the multiplier is the same wire, folded (§capstan-multiplier); its hysteresis's shift is the
    # effect "composition difference"
    *(Calibrated("CapstanMultiplier", c.name, c.lower, c.upper, c.relative, c.reference, c.why)
      for c in _WIRE_THERMAL),
    Calibrated("CrawlerBody", "k", 0.7, 1.3, True, "§ideal-actuation",
               "the soft actuator's stiffness"),
    Calibrated("CrawlerBody", "c", 0.5, 2.0, True, "§ideal-actuation",
               "the soft actuator's damping"),
    Calibrated("FrictionBlock", "mu_k_low", 0.7, 1.3, True, "§friction",
               "the ground's kinetic friction"),
    # the casing's static friction too; not the silicone's (high) coefficients: on a constant
    # incline the effect "actuator bending on an incline" scales them by a constant
    Calibrated("FrictionBlock", "mu_s_low", 0.7, 1.3, True, "§friction",
               "the ground's static friction on the casing"),
    # the robot's own conditions (§crawler-hardware): a soft chamber's walls carry part of the
    # pressure force, a vacuum pump's level and the pressure of firm contact are assumptions. Not
    # the supply pressure: the effect "supply-pressure drop" scales it by a constant
    Calibrated("SoftActuator", "s_a", 0.8, 1.1, True, "§two-mass, §crawler-hardware",
               "the central actuator's effective area: its walls take part of the force"),
    Calibrated("SoftActuator", "p_exhaust", 0.7, 1.3, True, "§crawler-hardware",
               "the exhaust pump's vacuum"),
    Calibrated("SoftActuator", "p_contact", 0.7, 1.25, True, "§crawler-hardware, §gait",
               "the pressure above which an extremal actuator's silicone grips the ground"),
    # the valves' sonic conductances are assumptions (§crawler-hardware names no valve; §valves the
    # law)
    Calibrated("SoftActuator", "C_in", 0.5, 2.0, True, "§crawler-hardware, §valves",
               "inflation valve"),
    Calibrated("SoftActuator", "C_out", 0.5, 2.0, True, "§crawler-hardware, §valves",
               "exhaust valve"),
    # a bench's PWM timer starts anywhere on its log's clock: replayed duties act at another
    # instant of each period (§valves); one timer drives every valve
    Calibrated("SoftActuator", "pwm_phase", -0.5, 1.5, False, "§crawler-hardware, §valves",
               "where the valves' PWM carrier starts on the data's clock", period=1.0),
    # sensors' gains (their offsets: the thermocouple's is the effect "thermocouple bias"; the
    # others are zeroed on the bench before a run)
    Calibrated("Thermocouple", "gain", 0.9925, 1.0075, True, "§sma-bench",
               "a standard thermocouple's tolerance: 0.75 % of the reading in C (IEC 60584 "
               "class 2)"),
    *(Calibrated(c, "gain", 0.95, 1.05, True, ref, "the sensor's and its amplifier's "
                 "calibration") for c, ref in (("LoadCell", "§sma-bench"),
                                                 ("LaserSensor", "§sma-bench"),
                                                 ("PressureSensor", "§crawler-hardware"))),
)


def calibration_of(component):
    """The calibration parameters (`Calibrated`) of one component, in library order."""
    return [c for c in CALIBRATION if c.component == component]


def by_component(component):
    """The effects of one component (e.g. ``"SmaWire"``), in library order."""
    return [e for e in EFFECTS if e.component == component]


def find(name):
    """The effect called `name`; raise KeyError listing the known names otherwise."""
    for effect in EFFECTS:
        if effect.name == name:
            return effect
    raise KeyError(f"no effect {name!r} (known: {', '.join(e.name for e in EFFECTS)})")
