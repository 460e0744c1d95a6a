"""FMU slaves of the loads: thin adapters over musclesim.components.loads.loads.

Every load reads the wire's contraction `flange.s` [m] and gives the tension `flange.f` [N] it
puts on the wire (the SmaWire FMU's convention); equations in §loads.
"""
from musclesim.components.loads import loads
from musclesim.fmu import Slave, experiment

S_DESCRIPTION = "Contraction of the wire (SmaWire flange.s); positive = the wire shortens"


class BiasSpring(Slave):
    """Preloaded bias spring stretched by the wire's contraction (§loads)."""

    default_experiment = experiment(10.0, 0.00025)  # §multiplier-experiments (pulses)
    description = "Bias spring: tension preload + k s on the wire (§loads: 490 N/m, ~125 MPa)"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        d = loads.SpringParams()
        self.parameter("k", d.k, "N/m", "Spring stiffness (§loads: 490 N/m)")
        self.parameter("preload", d.preload, "N", "Tension at zero contraction: 125 MPa on the "
                       "127 um wire (the preload of §multiplier-experiments)")
        self.input("flange.s", 0.0, "m", S_DESCRIPTION)
        self.output("flange.f", "N", "Tension of the spring on the wire", depends=["flange.s"])

    def setup(self):
        self.p = self.core_params(loads.SpringParams)

    def evaluate(self):
        self.flange_f = loads.spring_tension(self.flange_s, self.p)


class DeadWeight(Slave):
    """Weight hanging from the wire, quasi-static by default; inertia is an effect (§loads,
    §named-effects)."""

    default_experiment = experiment(20.0, 0.0004)  # §multiplier-experiments (bang-bang)
    description = ("Dead weight on the wire: tension m g, or (inertia effect) a mass on a "
                   "spring link pulled by the wire, its motion damped: m g + k_link (s - lift)")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        d = loads.WeightParams()
        self.parameter("mass", d.mass, "kg", "Mass of the weight: 125 MPa on the 127 um wire "
                       "(§loads)")
        self.parameter("g", d.g, "m/s2", "Gravitational acceleration (standard gravity)")
        self.parameter("inertia", d.inertia, "1", "Inertia of the weight (effect): 0 = off, "
                       "tension m g; r in (0, 1]: the share r of the weight moving on its link")
        self.parameter("k_link", d.k_link, "N/m", "Stiffness of the link from the wire to the "
                       "weight (assumption: 300 N/m, softer than the wire's transformation)")
        self.parameter("zeta", d.zeta, "1", "Damping ratio of the weight's motion on its link "
                       "(assumption)")
        self.input("flange.s", 0.0, "m", S_DESCRIPTION + ", lifting the weight")
        self.output("flange.f", "N", "Tension of the weight on the wire", depends=["flange.s"])
        self.output("lift", "m", "Lift of the weight (= flange.s unless its inertia is on)",
                    depends=["flange.s"])

    def setup(self):
        self.p = self.core_params(loads.WeightParams)
        self.phi = {}  # step -> the link's transition matrix over it
        self.initialize()

    def initialize(self):
        self.x, self.v = self.flange_s, 0.0  # at rest at the wire's end
        self.last = (self.time, self.flange_s)

    def evaluate(self):
        self.flange_f = loads.weight_tension(self.x, self.flange_s, self.p)
        self.lift = loads.weight_lift(self.x, self.flange_s, self.p)

    def advance(self, t, dt):
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

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        d = loads.MagnetParams()
        self.parameter("m_cal", d.m_cal, "kg", "Calibration weight (§sma-bench: 100 g)")
        self.parameter("g", d.g, "m/s2", "Gravitational acceleration (standard gravity)")
        self.parameter("V_supply", d.V_supply, "V", "Supply voltage switched by the PWM "
                       "(assumption: 12 V)")
        self.parameter("R", d.R, "Ohm", "Coil resistance (assumption: 24 Ohm, 0.5 A at full duty)")
        self.parameter("L", d.L, "H", "Coil inductance (assumption: 0.05 H, L/R = 2.1 ms)")
        self.parameter("k_f", d.k_f, "N/A", "Force per coil current (assumption: 2 N/A, so the "
                       "duty range spans 77..156 MPa, covering §loads's 105..145 MPa)")
        self.parameter("nonlinearity", d.nonlinearity, "1/A", "Force nonlinearity (effect, "
                       "0 = off = linear): force k_f i (1 + nonlinearity i)")
        self.input("duty", 0.0, "1", "PWM duty of the coil voltage, 0..1 (clamped, with one "
                   "warning)")
        self.input("flange.s", 0.0, "m", S_DESCRIPTION + " (the force does not depend on it)")
        self.output("flange.f", "N", "Tension on the wire: calibration weight plus the coil's pull")
        self.output("i", "A", "Coil current")

    def setup(self):
        self.p = self.core_params(loads.MagnetParams)
        self.current = 0.0

    def initialize(self):
        duty = self.clamped_input("duty", 0.0, 1.0, self.time)
        self.current = loads.coil_steady(duty, self.p)  # settled at the start

    def evaluate(self):
        self.i = self.current
        self.flange_f = loads.magnet_tension(self.current, self.p)

    def advance(self, t, dt):
        duty = self.clamped_input("duty", 0.0, 1.0, t)
        self.current = loads.coil_step(self.current, duty, dt, self.p)
