"""The library of unmodelled effects the sim-to-real diagnosis can add (SPEC.md section 4).

Every effect is a set of parameters of an existing component whose values at ``off`` give the
nominal model exactly (they are the FMU's defaults), with bounds for fitting, the regime where it
should show (its signature) and the SPEC section it comes from. Adding an effect to a scenario is
therefore only a matter of parameter values on the instances of its component.
"""
from dataclasses import dataclass


@dataclass(frozen=True)
class Parameter:
    """One parameter of an effect: its value when the effect is off and its fitting bounds."""

    name: str
    off: float
    lower: float
    upper: float


@dataclass(frozen=True)
class Effect:
    """A candidate unmodelled effect.

    ``per_instance``: the effect may differ between instances of the component (the front and the
    back friction block slip differently, SPEC 1.5), so it is fitted per instance.
    """

    name: str
    component: str
    parameters: tuple
    regime: str
    spec: str
    description: str
    per_instance: bool = False

    def overrides(self, instance, values):
        """``--set`` strings that put this effect at `values` (one per parameter) on `instance`."""
        return [f"{instance}.{p.name}={v!r}" for p, v in zip(self.parameters, values)]


EFFECTS = (
    # SMA wire and its bench (SPEC 2, 4, 5)
    Effect("stress dependence ignored", "SmaWire",
           (Parameter("sigma_surface", 0.0, 105e6, 145e6),),
           "time-varying stress", "SPEC 2.4, 4",
           "one constant-stress surface used for every stress"),
    Effect("thermocouple lag", "Thermocouple", (Parameter("tau", 0.0, 0.0, 2.0),),
           "fast temperature changes", "SPEC 2.1, 4",
           "the junction follows the wire with a first-order lag"),
    Effect("thermocouple bias", "Thermocouple", (Parameter("bias", 0.0, -10.0, 10.0),),
           "every temperature, steady state included", "SPEC 4, 5",
           "the reading is offset from the wire's core temperature"),
    Effect("latent heat", "SmaWire", (Parameter("latent_heat", 0.0, 0.0, 30e3),),
           "inside the transformation band, heating and cooling", "SPEC 2.1, 5",
           "heat absorbed while austenite forms, released while martensite forms"),
    Effect("clamp heat loss", "SmaWire", (Parameter("clamp_conductance", 0.0, 0.0, 1e-3),),
           "high temperatures, steady state", "SPEC 4, 5",
           "conduction into the clamps at ambient temperature"),
    Effect("convection change", "SmaWire", (Parameter("h_exponent", 0.0, 0.0, 0.5),),
           "cooling, large excess temperatures", "SPEC 4, 5",
           "the convection coefficient grows with the excess temperature"),
    Effect("training drift", "SmaWire",
           (Parameter("drift_amplitude", 0.0, -0.2, 0.2), Parameter("drift_shift", 0.0, -10.0, 10.0)),
           "over many transformation cycles", "SPEC 2.6",
           "the major loop changes over the first cycles, then settles"),
    # crawler (SPEC 1, 4)
    Effect("anchoring slip", "FrictionBlock",
           (Parameter("mu_s_high", 1.0, 0.2, 1.0), Parameter("mu_k_high", 0.75, 0.15, 0.75)),
           "stance phases of the anchored block (stick)", "SPEC 1.5, 4",
           "the inflated actuator grips less than the slip-angle estimate", per_instance=True),
    Effect("friction switching time", "FrictionBlock", (Parameter("t_switch", 0.0, 0.0, 0.4),),
           "right after the friction indicator switches", "SPEC 1.1, 4",
           "contact builds over a transition time instead of at once"),
    Effect("pressure-dependent stiffness", "CrawlerBody", (Parameter("k_slope", 0.0, -0.04, 0.04),),
           "high actuator force", "SPEC 1.2, 4",
           "the central actuator's stiffness changes with its pressure"),
    Effect("viscous ground drag", "CrawlerBody", (Parameter("c_ground", 0.0, 0.0, 5.0),),
           "sliding phases", "SPEC 4",
           "the ground resists motion in proportion to the block's speed"),
)


def by_component(component):
    """The effects of one component (e.g. ``"SmaWire"``), in library order."""
    return [e for e in EFFECTS if e.component == component]


def find(name):
    """The effect called `name`; raise KeyError listing the known names otherwise."""
    for effect in EFFECTS:
        if effect.name == name:
            return effect
    raise KeyError(f"no effect {name!r} (known: {', '.join(e.name for e in EFFECTS)})")
