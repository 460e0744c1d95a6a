"""Ideal open-loop actuation of §ideal-actuation: a sinusoidal actuator force and two friction
indicators.

The FMU's kernel (`KERNEL`): parameters `pack`, no state, no inputs, outputs y = [f_a, u1, u2].
"""
from __future__ import annotations

import math
from dataclasses import astuple, dataclass

import numpy as np

from musclesim.components.checks import require
from musclesim.fmu import Kernel, declare, jit, no_state


@dataclass(frozen=True)
class InputParams:
    """Signal parameters (defaults: §ideal-actuation nominal case). Each parameter is declared
    once here (`declare`): the FMU and the docs' tables read it."""

    f_mean: float = declare(10.28, "N", "Mean actuator force (the study's f_a oscillates between "
                            "0.66 N and 19.9 N)", source="§ideal-actuation")
    f_amp: float = declare(9.62, "N", "Amplitude of the actuator force", source="§ideal-actuation")
    f_f: float = declare(1.0, "Hz", "Frequency of the actuator force (the nominal case; all the "
                         "study's frequencies are at most 1 Hz)", source="§ideal-actuation")
    f_u: float = declare(1.0, "Hz", "Frequency of the friction indicators (the nominal case)",
                         source="§ideal-actuation")
    phi: float = declare(1.64, "rad", "Phase lag of u2 behind u1, which steers the direction "
                         "(the nominal case)", source="§ideal-actuation")
    direction: float = declare(1.0, "1", "1, as in the study; -1 swaps u1 and u2: the mirror "
                               "image of the gait, driven backward", type="Integer")

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, non_negative=("f_f", "f_u", "f_amp"))
        if self.direction not in (1.0, -1.0):
            raise ValueError(f"direction must be 1 or -1 (got {self.direction!r})")


def signals(t: float, p: InputParams) -> tuple[float, float, float]:
    """Return (f_a [N], u1, u2) of the signals `p` at time `t` [s]: u_i = 1 while its square
    wave is high (inflated)."""
    return signals_core(t, pack(p))


@jit
def signals_core(t: float, p: np.ndarray) -> tuple[float, float, float]:
    """`signals` at time `t` [s] of the packed parameters `p` (`pack`)."""
    f_mean, f_amp, f_f, f_u, phi, direction = p[0], p[1], p[2], p[3], p[4], p[5]
    f_a = f_mean + f_amp * math.sin(2 * math.pi * f_f * t)
    u1 = 1.0 if math.sin(2 * math.pi * f_u * t) >= 0 else 0.0
    u2 = 1.0 if math.sin(2 * math.pi * f_u * t - phi) >= 0 else 0.0
    return (f_a, u1, u2) if direction > 0 else (f_a, u2, u1)


def pack(p: InputParams) -> np.ndarray:
    """The kernel's parameters: `p`'s fields in their declared order (f_mean, f_amp, f_f, f_u,
    phi, direction)."""
    return np.array(astuple(p), dtype=float)


@jit
def evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """Kernel outputs `y` = [f_a, u1, u2] at time `t` [s] of the signals `p` (`pack`; the state
    `x` and the inputs `u` are empty)."""
    y[0], y[1], y[2] = signals_core(t, p)



KERNEL = Kernel(evaluate, no_state, inputs=(), outputs=("f_a", "u1", "u2"))
