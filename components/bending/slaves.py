"""FMU slave of the bending actuator (§bending-actuator): a thin adapter over the compiled kernel
of `actuator.BendingActuator`."""
from __future__ import annotations

import math

from musclesim.components.bending import actuator, beam
from musclesim.components.sma import datasets, reference_wire, thermal
from musclesim.fmu import KernelSlave, experiment

ZERO_C = actuator.ZERO_C  # K; the FMU speaks K, the cores C
LASER_HEIGHT = 17e-3  # m, where the study's laser reads the deflection (§bending-actuator)


class BendingActuator(KernelSlave):
    """Bending actuator: two 50 um SMA wires beside a carbon-fibre beam pair (§bending-actuator).

    Per communication step, inputs held from its start: each wire's temperature (lumped thermal
    model, voltage through a series resistance), its hysteresis (at the pretension's stress),
    then the beams' first bending mode in exact sub-steps. No output depends directly on an input.
    Equations, parameters and their reasons: §bending-actuator (docs/model/bending.md). The
    physics is `actuator.BendingActuator`'s compiled kernel (`actuator.KERNEL`).
    """

    kernel = actuator.KERNEL

    default_experiment = experiment(4.0, 0.0005)  # bending-one-wire, §bending-actuator
    description = ("Bending actuator: two antagonistic 50 um SMA wires (thermal model, modified "
                   "Preisach hysteresis) bending a carbon-fibre beam pair, first bending mode "
                   "(§bending-actuator)")

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(beam.BeamParams)
        self.parameters_of(actuator.WireLayout)
        # not fields of a core's dataclass: the wires' length is WireLayout.length (the FMU's
        # length is the beams'); the thermal values are the 50 um wire file's, through
        # sma.thermal.ThermalParams (whose density is the FMU's wire_density); the FMU speaks K
        # where the core takes T_init in C
        length = actuator.WireLayout().length
        self.parameter("wire_length", length, "m", "Free length of each wire (the study: about "
                       "the cap spacing)", source="§bending-actuator")
        t = actuator.wire_thermal(length)
        self.parameter("diameter", t.diameter, "m", "Wire diameter (the study: 50 um)",
                       source="§bending-actuator")
        self.parameter("wire_density", t.density, "kg/m3", "Density of NiTi (public data)",
                       source="§sma-material")
        self.parameter("specific_heat", t.specific_heat, "J/(kg.K)",
                       "Specific heat of NiTi (public data)", source="§sma-material")
        self.parameter("rho_martensite", t.rho_martensite, "Ohm.m", "Resistivity of the wire's "
                       "martensite (the data sheets' 470 Ohm/m on 50 um, not the bulk "
                       "80 uOhm cm, which would give 407 Ohm/m)", source="§sma-material")
        self.parameter("rho_austenite", t.rho_austenite, "Ohm.m", "Resistivity of the wire's "
                       "austenite (the data sheets' 490 Ohm/m on 50 um, not the bulk "
                       "100 uOhm cm, which would give 509 Ohm/m)", source="§sma-material")
        self.parameter("h", t.h, "W/(m2.K)", "Convection coefficient of the 50 um wire (natural "
                       "convection; time constant rho c d / 4h = 0.29 s)", source="§convection")
        self.parameter("T_init", 293.15, "K", "Initial temperature of both wires (room "
                       "temperature, martensitic, heated to it)")
        self.parameter("z_tip", LASER_HEIGHT, "m", "Height above the base where tip.s is read "
                       "(the study: the laser, 17 mm)", source="§bending-actuator")
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

    def setup(self) -> None:
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
        params = reference_wire.load_params(
            datasets.shipped(self.resources) / datasets.WIRE_PARAMS)
        surface = actuator.hysteresis_surface(params, sigma)
        self.core = self.logged(actuator.BendingActuator, b, layout, wire_p, surface, self.z_tip)
        self.kp, self.kx = self.core.kp, self.core.kx
        self._start()

    def initialize(self) -> None:
        self._start()

    def _start(self) -> None:
        self.logged(self.core.reset, self.T_init - ZERO_C)

    def advance(self, t: float, dt: float) -> None:
        """Advance the state over [`t`, `t` + `dt`] [s] with the inputs held."""
        for name, value in (("wireA.u", self.wireA_u), ("wireB.u", self.wireB_u),
                            ("T_amb", self.T_amb)):
            if not math.isfinite(value):
                raise ValueError(f"input {name} is {value!r} at t = {t:g} s")
        super().advance(t, dt)
