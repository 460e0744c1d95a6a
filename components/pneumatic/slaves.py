"""FMU slave of the soft pneumatic actuator: a thin adapter over components/pneumatic/actuator.py.

Equations, ports and sign conventions: §pneumatics (docs/model/pneumatics.md).
"""
from __future__ import annotations

from typing import Any

from musclesim.components.pneumatic import actuator
from musclesim.fmu import KernelSlave, Slave, experiment


class SoftActuator(KernelSlave):
    """Silicone chamber fed through two PWM solenoid valves by an inflation and an exhaust pump
    (§crawler-hardware, §gait, §valves)."""

    kernel = actuator.KERNEL
    default_experiment = experiment(30.0, 0.001)  # crawler-gait-forward, §gait
    display_units = {**Slave.display_units, "Pa": "kPa"}  # air pressures
    description = ("Soft pneumatic actuator: chamber (polytropic) filled and emptied through two "
                   "PWM solenoid valves (ISO 6358) from an inflation and an exhaust pump "
                   "(§crawler-hardware, §gait, §valves)")

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.parameters_of(actuator.ActuatorParams)
        self.input("duty", 0.0, "1", "PWM duty, -1..1 (clamped, with one warning): > 0 drives the "
                   "inflation valve, < 0 the exhaust valve with duty -duty")
        self.input("flange_a.s", 0.0, "m", "Position of the rear block (central actuator; "
                   "variation from rest)", plausible="difference")
        self.input("flange_b.s", 0.0, "m", "Position of the front block (central actuator; "
                   "variation from rest); elongation = flange_b.s - flange_a.s",
                   plausible="difference")
        self.output("p", "Pa", "Gauge pressure of the chamber")
        self.output("f_a", "N", "Actuator force s_a p pushing the blocks apart (§two-mass)")
        self.output("u", "1", "Contact of the extremal actuator with the ground, 0 (casing) .. 1 "
                    "(silicone): the friction indicator")
        self.output("m_flow", "kg/s", "Net mass flow into the chamber, averaged over the last "
                    "step")

    def setup(self) -> None:
        self.params = self.core_params(actuator.ActuatorParams)
        self.kp = actuator.pack(self.params)
        self.initialize()

    def initialize(self) -> None:
        """At rest, the volume at the elongation the inputs give now."""
        self.kx = actuator.start_state(self.kp, self.flange_b_s - self.flange_a_s)
