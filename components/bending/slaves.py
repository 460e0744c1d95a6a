"""FMU slave of the bending actuator (§bending-actuator): a thin adapter over
`actuator.BendingActuator`."""
import math

from musclesim.components.bending import actuator, beam
from musclesim.components.sma import datasets, thermal, wire
from musclesim.fmu import Slave, experiment

ZERO_C = 273.15  # K; the FMU speaks K, the cores C
LASER_HEIGHT = 17e-3  # m, where the study's laser reads the deflection (§bending-actuator)


class BendingActuator(Slave):
    """Bending actuator: two 50 um SMA wires beside a carbon-fibre beam pair (§bending-actuator).

    Per communication step, inputs held from its start: each wire's temperature (lumped thermal
    model, voltage through a series resistance), its hysteresis (at the pretension's stress),
    then the beams' first bending mode in exact sub-steps. No output depends directly on an input.
    Equations, parameters and their reasons: §bending-actuator (docs/model/bending.md).
    """

    default_experiment = experiment(4.0, 0.0005)  # bending-one-wire, §bending-actuator
    description = ("Bending actuator: two antagonistic 50 um SMA wires (thermal model, modified "
                   "Preisach hysteresis) bending a carbon-fibre beam pair, first bending mode "
                   "(§bending-actuator)")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        b, w = beam.BeamParams(), actuator.WireLayout()
        self.parameter("length", b.length, "m", "Free beam length between the caps "
                       "(§bending-actuator: caps 10 mm apart)")
        self.parameter("n_beams", b.n_beams, "1", "Number of coplanar beams (§bending-actuator: 2)")
        self.parameter("width", b.width, "m", "Width of each beam (open, §bending-actuator)")
        self.parameter("thickness", b.thickness, "m", "Thickness of each beam in the bending "
                       "direction (open, §bending-actuator)")
        self.parameter("modulus", b.modulus, "Pa", "Young's modulus of the beams (open, "
                       "§bending-actuator)")
        self.parameter("density", b.density, "kg/m3", "Density of the beams (open, "
                       "§bending-actuator)")
        self.parameter("tip_mass", b.tip_mass, "kg", "Mass of the top cap and foot (open, "
                       "§bending-actuator)")
        self.parameter("tip_height", b.tip_height, "m", "Height of their centre of mass above the "
                       "base (open, §bending-actuator)")
        self.parameter("damping_ratio", b.damping_ratio, "1", "Damping ratio of the first "
                       "bending mode with both wires cold (open, §bending-actuator)")
        self.parameter("offset", w.offset, "m", "Distance of each wire from the beams "
                       "(§bending-actuator)")
        self.parameter("wire_length", w.length, "m", "Free length of each wire (§bending-actuator: "
                       "about the cap spacing)")
        self.parameter("pretension", w.pretension, "N", "Tension of each cold wire at rest "
                       "(open, §bending-actuator: 100 MPa)")
        self.parameter("modulus_martensite", w.modulus_martensite, "Pa",
                       "Young's modulus of the wires' martensite (open, §bending-actuator)")
        self.parameter("modulus_austenite", w.modulus_austenite, "Pa",
                       "Young's modulus of the wires' austenite (open, §bending-actuator)")
        self.parameter("series_resistance", w.series_resistance, "Ohm", "Driver and lead "
                       "resistance in series with each wire (open; fitted to the study's one-wire "
                       "tip-to-tip, §study-outcomes)")
        self.parameter("max_substep", w.max_substep, "s", "Longest mechanical sub-step")
        t = actuator.wire_thermal(w.length)
        self.parameter("diameter", t.diameter, "m", "Wire diameter (§bending-actuator: 50 um)")
        self.parameter("wire_density", t.density, "kg/m3", "Density of NiTi (§sma-material)")
        self.parameter("specific_heat", t.specific_heat, "J/(kg.K)",
                       "Specific heat of NiTi (§sma-material)")
        self.parameter("rho_martensite", t.rho_martensite, "Ohm.m", "Resistivity of the wire's "
                       "martensite (§sma-material: 470 Ohm/m on 50 um)")
        self.parameter("rho_austenite", t.rho_austenite, "Ohm.m", "Resistivity of the wire's "
                       "austenite (§sma-material: 490 Ohm/m on 50 um)")
        self.parameter("h", t.h, "W/(m2.K)", "Convection coefficient of the 50 um wire "
                       "(§convection: 230)")
        self.parameter("T_init", 293.15, "K", "Initial temperature of both wires (martensitic, "
                       "heated to it)")
        self.parameter("z_tip", LASER_HEIGHT, "m", "Height above the base where tip.s is read "
                       "(§bending-actuator: the laser, 17 mm)")
        self.input("wireA.u", 0.0, "V", "Voltage across wire A and its series resistance")
        self.input("wireB.u", 0.0, "V", "Voltage across wire B and its series resistance")
        self.input("T_amb", 293.15, "K", "Ambient air temperature")
        self.output("tip.s", "m", "Deflection at z_tip, positive toward wire A")
        self.output("tip.v", "m/s", "Velocity at z_tip")
        self.output("theta", "rad", "Rotation of the top cap")
        for side in actuator.SIDES:
            self.output(f"wire{side}.T", "K", f"Temperature of wire {side}")
            self.output(f"wire{side}.strain", "1", f"Contraction of wire {side} from its "
                        "installed length, elastic stretch excluded (positive = shorter)")
            self.output(f"wire{side}.f", "N", f"Tension of wire {side}")
            self.output(f"wire{side}.stress", "Pa", f"Tensile stress of wire {side}, tension / "
                        "cross-section")
            self.output(f"wire{side}.P", "W", f"Joule power in wire {side} over the last step")

    def setup(self):
        b = self.core_params(beam.BeamParams)
        layout = actuator.WireLayout(
            offset=self.offset, length=self.wire_length, pretension=self.pretension,
            modulus_martensite=self.modulus_martensite, modulus_austenite=self.modulus_austenite,
            series_resistance=self.series_resistance, max_substep=self.max_substep)
        layout.check()
        if not self.T_init > 0 or not self.z_tip >= 0:
            raise ValueError(f"T_init must be positive in K and z_tip non-negative (got "
                             f"T_init = {self.T_init!r}, z_tip = {self.z_tip!r})")
        wire_p = thermal.ThermalParams(
            length=self.wire_length, diameter=self.diameter, density=self.wire_density,
            specific_heat=self.specific_heat, rho_martensite=self.rho_martensite,
            rho_austenite=self.rho_austenite, h=self.h, drive="current")
        sigma = self.pretension / thermal.cross_section(wire_p)  # the hysteresis' stress
        #                                                          (§bending-actuator)
        params = wire.load_params(datasets.shipped(self.resources) / datasets.WIRE_PARAMS)
        surface = actuator.hysteresis_surface(params, sigma)
        self.core = self.logged(actuator.BendingActuator, b, layout, wire_p, surface)
        self._start()

    def initialize(self):
        self._start()

    def _start(self):
        self.logged(self.core.reset, self.T_init - ZERO_C)

    def evaluate(self):
        core = self.core
        self.tip_s = core.deflection(self.z_tip)
        self.tip_v = core.velocity(self.z_tip)
        self.theta = core.theta
        for i, side in enumerate(actuator.SIDES):
            setattr(self, f"wire{side}_T", core.T[i] + ZERO_C)
            setattr(self, f"wire{side}_strain", core.eps[i])
            setattr(self, f"wire{side}_f", core.tension[i])
            setattr(self, f"wire{side}_stress", core.tension[i] / core.area)
            setattr(self, f"wire{side}_P", core.power[i])

    def advance(self, t, dt):
        for name, value in (("wireA.u", self.wireA_u), ("wireB.u", self.wireB_u),
                            ("T_amb", self.T_amb)):
            if not math.isfinite(value):
                raise ValueError(f"input {name} is {value!r} at t = {t:g} s")
        self.logged(self.core.step, dt, (self.wireA_u, self.wireB_u), self.T_amb - ZERO_C, t)
