"""FMU slaves of the loads: thin adapters over musclesim.components.loads.loads.

Every load reads the wire's contraction `flange.s` [m] and gives the tension `flange.f` [N] it
puts on the wire (the SmaWire FMU's convention); equations in §loads.
"""
from __future__ import annotations

from musclesim.components.loads import loads
from musclesim.fmu import Slave, experiment

S_DESCRIPTION = "Contraction of the wire (SmaWire flange.s); positive = the wire shortens"


class BiasSpring(Slave):
    """Preloaded bias spring stretched by the wire's contraction (§loads)."""

    default_experiment = experiment(10.0, 0.00025)  # §multiplier-experiments (pulses)
    description = "Bias spring: tension preload + k s on the wire (§loads: 490 N/m, ~125 MPa)"

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(loads.SpringParams)
        self.input("flange.s", 0.0, "m", S_DESCRIPTION)
        self.output("flange.f", "N", "Tension of the spring on the wire", depends=["flange.s"])

    def setup(self) -> None:
        self.p = self.core_params(loads.SpringParams)

    def evaluate(self) -> None:
        self.flange_f = loads.spring_tension(self.flange_s, self.p)


class DeadWeight(Slave):
    """Weight hanging from the wire, quasi-static by default; inertia is an effect (§loads,
    §named-effects)."""

    default_experiment = experiment(20.0, 0.0004)  # §multiplier-experiments (bang-bang)
    description = ("Dead weight on the wire: tension m g, or (inertia effect) a mass on a "
                   "spring link pulled by the wire, its motion damped: m g + k_link (s - lift)")

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(loads.WeightParams)
        self.input("flange.s", 0.0, "m", S_DESCRIPTION + ", lifting the weight")
        self.output("flange.f", "N", "Tension of the weight on the wire", depends=["flange.s"])
        self.output("lift", "m", "Lift of the weight (= flange.s unless its inertia is on)",
                    depends=["flange.s"])

    def setup(self) -> None:
        self.p = self.core_params(loads.WeightParams)
        # step -> the link's transition matrix over it
        self.phi: dict[float, list[list[float]]] = {}
        self.initialize()

    def initialize(self) -> None:
        self.x, self.v = self.flange_s, 0.0  # at rest at the wire's end
        self.last = (self.time, self.flange_s)

    def evaluate(self) -> None:
        self.flange_f = loads.weight_tension(self.x, self.flange_s, self.p)
        self.lift = loads.weight_lift(self.x, self.flange_s, self.p)

    def advance(self, t: float, dt: float) -> None:
        """Advance the state over [`t`, `t` + `dt`] [s] with the inputs held."""
        if not self.p.inertia:
            return
        t0, s0 = self.last
        u = (self.flange_s - s0) / (t - t0) if t > t0 else 0.0
        if dt not in self.phi:
            self.phi[dt] = loads.link_transition(dt, self.p)
        self.x, self.v = loads.weight_step(self.x, self.v, self.flange_s, u, self.phi[dt], dt,
                                           self.p)
        self.last = (t, self.flange_s)


class Electromagnet(Slave):
    """Calibration weight plus a PWM-driven coil pulling a rare-earth magnet (§sma-bench,
    §loads)."""

    default_experiment = experiment(550.0, 0.0004)  # sma-position-control, §position-control
    description = ("Electromagnet load: 100 g calibration weight plus a coil (L di/dt = V duty - "
                   "R i) pulling a magnet with k_f i (1 + nonlinearity i) (§sma-bench)")

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(loads.MagnetParams)
        self.input("duty", 0.0, "1", "PWM duty of the coil voltage, 0..1 (clamped, with one "
                   "warning)")
        self.input("flange.s", 0.0, "m", S_DESCRIPTION + " (the force does not depend on it)")
        self.output("flange.f", "N", "Tension on the wire: calibration weight plus the coil's pull")
        self.output("i", "A", "Coil current")

    def setup(self) -> None:
        self.p = self.core_params(loads.MagnetParams)
        self.current = 0.0

    def initialize(self) -> None:
        duty = self.clamped_input("duty", 0.0, 1.0, self.time)
        self.current = loads.coil_steady(duty, self.p)  # settled at the start

    def evaluate(self) -> None:
        self.i = self.current
        self.flange_f = loads.magnet_tension(self.current, self.p)

    def advance(self, t: float, dt: float) -> None:
        """Advance the state over [`t`, `t` + `dt`] [s] with the inputs held."""
        duty = self.clamped_input("duty", 0.0, 1.0, t)
        self.current = loads.coil_step(self.current, duty, dt, self.p)
