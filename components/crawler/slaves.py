"""FMU slaves of the crawler components: thin adapters from FMI variables to the physics cores."""
from __future__ import annotations

import numpy as np

from musclesim.components.crawler import body, friction, gait, inputs
from musclesim.fmu import KernelSlave, experiment


class CrawlerBody(KernelSlave):
    """Two-mass crawler body (§two-mass) discretised by zero-order hold at the communication
    step."""

    default_experiment = experiment(60.0, 0.001)  # crawler-ideal, §ideal-actuation
    description = ("Crawler body: two blocks joined by the central actuator's spring, damper and "
                   "force (§two-mass)")

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(body.BodyParams)
        self.input("f_a", 0.0, "N", "Actuator force pushing the blocks apart")
        self.input("flange_a.f", 0.0, "N", "Friction force on block 1")
        self.input("flange_b.f", 0.0, "N", "Friction force on block 2")
        for i, end in ((1, "a"), (2, "b")):  # the rear block 1, the front block 2
            self.output(f"flange_{end}.s", "m", f"Position of block {i} (variation from rest)")
            self.output(f"flange_{end}.v", "m/s", f"Velocity of block {i}")
            self.output(f"flange_{end}.f_n", "N",
                        f"Net non-friction force along the surface on block {i}", depends=["f_a"])
            self.output(f"flange_{end}.N", "N", f"Normal force of block {i} on the ground")
        self.output("x_cm", "m", "Position of the centre of mass")
        self.output("incline", "rad", "Incline of the ground, the parameter theta (for the "
                    "friction blocks' bending effect)")

    kernel = body.KERNEL  # masters with an integer clock (libcosim counts nanoseconds) hand
    # steps that differ in the last bits: the hold matrices are made anew only beyond rounding

    def setup(self) -> None:
        self.kp = body.pack(self.core_params(body.BodyParams))
        self.kx = body.initial_state()  # zero initial state (§ideal-actuation)


class FrictionBlock(KernelSlave):
    """Stick-slip friction of one block with coefficients switched by an indicator (§friction)."""

    default_experiment = experiment(60.0, 0.001)  # crawler-ideal, §ideal-actuation
    description = "Stick-slip friction block with switchable high/low coefficients (§friction)"

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(friction.FrictionParams)
        self.input("flange.v", 0.0, "m/s", "Velocity of the block")
        self.input("flange.f_n", 0.0, "N", "Net non-friction force along the surface on the block")
        self.input("flange.N", 0.0, "N", "Normal force of the block on the ground")
        self.input("u", 0.0, "1", "Friction indicator: 1 = inflated (high), 0 = deflated (low)")
        self.input("theta", 0.0, "rad", "Incline of the ground (from the body's output incline)")
        ins = ["flange.v", "flange.f_n", "flange.N", "u", "theta"]
        self.output("flange.f", "N", "Friction force on the block", depends=ins)
        self.output("contact", "1", "Contact state: 0 = low, 1 = high friction", depends=["u"])
        self.output("stuck", "1", "1 while the block sticks, else 0", depends=ins, type="Boolean")
        self.output("slip", "m", "Anchoring slip: distance slid while the contact is high")

    kernel = friction.KERNEL

    def setup(self) -> None:
        self.kp = friction.pack(self.core_params(friction.FrictionParams))
        self.kx = np.array([self.u, 0.0])  # contact state, slip

    def initialize(self) -> None:
        self.kx[0] = self.u  # the contact starts settled in the state the indicator asks for


class FrictionSwitchingInputs(KernelSlave):
    """Ideal actuation of §ideal-actuation: sinusoidal actuator force and square-wave friction
    indicators."""

    default_experiment = experiment(60.0, 0.001)  # crawler-ideal, §ideal-actuation
    description = ("Open-loop friction-switching inputs: f_a sinusoid and indicators u1, u2 "
                   "(§ideal-actuation)")

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(inputs.InputParams)
        self.output("f_a", "N", "Actuator force")
        self.output("u1", "1", "Friction indicator of block 1")
        self.output("u2", "1", "Friction indicator of block 2")

    kernel = inputs.KERNEL

    def setup(self) -> None:
        self.kp = inputs.pack(self.core_params(inputs.InputParams))


class GaitSequencer(KernelSlave):
    """Four-phase peristaltic gait (§gait): pressure references of the three actuators."""

    default_experiment = experiment(30.0, 0.001)  # crawler-gait-forward, §gait
    display_units = {**KernelSlave.display_units, "Pa": "kPa"}  # air pressures
    description = ("Peristaltic gait sequencer: pressure references of the back, central and front "
                   "actuators (§gait)")

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(gait.GaitParams)
        self.output("p_ref1", "Pa", "Pressure reference of the back extremal actuator 1")
        self.output("p_ref_c", "Pa", "Pressure reference of the central actuator")
        self.output("p_ref2", "Pa", "Pressure reference of the front extremal actuator 2")
        self.output("phase", "1", "Gait phase 1..4 (§gait)")
        # not "direction": that is the parameter's name
        self.output("stride_direction", "1",
                    "Direction of the current stride: +1 forward, -1 backward", type="Integer")
        self.output("stride", "1", "Index of the current stride since the start, from 1",
                    type="Integer")

    kernel = gait.KERNEL

    def setup(self) -> None:
        self.kp = gait.pack(self.core_params(gait.GaitParams))
