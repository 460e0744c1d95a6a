"""FMU slaves of the quadruped (§quadruped): thin adapters over `body.Quadruped` and
`sequencer.voltages`."""
from __future__ import annotations

import math

from musclesim.components.quadruped import body, sequencer
from musclesim.fmu import Slave, experiment


class QuadrupedBody(Slave):
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
                       "forward")
            self.input(f"leg{i}.v", 0.0, "m/s", f"Rate of leg {i}'s deflection")
        self.output("x", "m", "Position of the body along the walking axis")
        self.output("v", "m/s", "Velocity of the body")
        for i in range(1, body.LEGS + 1):
            self.output(f"foot{i}.s", "m", f"Position of foot {i}")
            self.output(f"foot{i}.f", "N", f"Friction force on foot {i} over the last sub-step")
            self.output(f"foot{i}.stuck", "1", f"1 while foot {i} holds still, else 0",
                        type="Boolean")

    def setup(self) -> None:
        self.core = body.Quadruped(self.core_params(body.QuadrupedParams))

    def initialize(self) -> None:
        self.core.reset()

    def evaluate(self) -> None:
        c = self.core
        self.x, self.v = c.x, c.v
        for i in range(body.LEGS):
            setattr(self, f"foot{i + 1}_s", c.feet_x[i])
            setattr(self, f"foot{i + 1}_f", c.forces[i])
            setattr(self, f"foot{i + 1}_stuck", 1.0 if c.stuck(i) else 0.0)

    def advance(self, t: float, dt: float) -> None:
        """Advance the state over [`t`, `t` + `dt`] [s] with the inputs held."""
        s: list[float] = []
        v: list[float] = []
        for i in range(1, body.LEGS + 1):
            for name, out in ((f"leg{i}.s", s), (f"leg{i}.v", v)):
                value = getattr(self, name.replace(".", "_"))
                if not math.isfinite(value):
                    raise ValueError(f"input {name} is {value!r} at t = {t:g} s")
                out.append(value)
        self.core.step(dt, s, v)


class LegSequencer(Slave):
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

    def setup(self) -> None:
        self.p = self.core_params(sequencer.SequencerParams)

    def evaluate(self) -> None:
        for i, (uA, uB) in enumerate(sequencer.voltages(self.time, self.p), start=1):
            setattr(self, f"leg{i}_uA", uA)
            setattr(self, f"leg{i}_uB", uB)
