"""FMU slaves of the quadruped (§quadruped): kernels (`musclesim.fmu.kernel`) over the jit cores
of `body` (`body.KERNEL`, the step `Quadruped` takes) and `sequencer` (`sequencer.KERNEL`, the
voltages `sequencer.voltages` gives); their packed layouts are `body.pack`'s and
`sequencer.pack`'s."""
from __future__ import annotations

import numpy as np

from musclesim.components.quadruped import body, sequencer
from musclesim.fmu import KernelSlave, experiment


class QuadrupedBody(KernelSlave):
    """Quadruped body on four legs with anisotropic-friction feet, moving along x (§quadruped).

    Inputs: each leg's unloaded deflection at its foot and its rate (a BendingActuator's tip.s,
    tip.v), held as a first-order hold over the step. Equations: §quadruped (docs/model/bending.md).
    """

    default_experiment = experiment(4.0, 0.0005)  # quadruped-walk, §quadruped
    description = ("Quadruped body on four bending-actuator legs, feet with direction-dependent "
                   "stick-slip friction (§quadruped, friction of §friction)")

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(body.QuadrupedParams)
        for i in range(1, body.LEGS + 1):
            self.input(f"leg{i}.s", 0.0, "m", f"Unloaded deflection of leg {i} at its foot, +x "
                       "forward", plausible="difference")
            self.input(f"leg{i}.v", 0.0, "m/s", f"Rate of leg {i}'s deflection")
        self.output("x", "m", "Position of the body along the walking axis")
        self.output("v", "m/s", "Velocity of the body")
        for i in range(1, body.LEGS + 1):
            self.output(f"foot{i}.s", "m", f"Position of foot {i}")
            self.output(f"foot{i}.f", "N", f"Friction force on foot {i} over the last sub-step")
            self.output(f"foot{i}.stuck", "1", f"1 while foot {i} holds still, else 0",
                        type="Boolean")

    kernel = body.KERNEL  # a NaN input is refused ("input leg1.s is NaN at t = ...")

    def setup(self) -> None:
        self.kp = body.pack(self.core_params(body.QuadrupedParams))  # checks the parameters
        self.kx = np.zeros(body.STATE)

    def initialize(self) -> None:
        self.kx[:] = 0.0  # at rest at x = 0, legs straight


class LegSequencer(KernelSlave):
    """Pulse voltages of the quadruped's eight wires: which leg's wire is pulsed when
    (§quadruped)."""

    default_experiment = experiment(4.0, 0.0005)  # quadruped-walk, §quadruped
    description = ("Leg sequencer of the quadruped: the study's heating pulses (5 V, 5 % at "
                   "4 Hz, §quadruped) per wire, phased per leg")

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(sequencer.SequencerParams)
        for i in range(1, sequencer.LEGS + 1):
            self.output(f"leg{i}.uA", "V", f"Voltage on leg {i}'s wire A")
            self.output(f"leg{i}.uB", "V", f"Voltage on leg {i}'s wire B")

    kernel = sequencer.KERNEL

    def setup(self) -> None:
        self.kp = sequencer.pack(self.core_params(sequencer.SequencerParams))
