"""Ideal open-loop actuation of §ideal-actuation: a sinusoidal actuator force and two friction
indicators."""
from __future__ import annotations

import math
from dataclasses import dataclass

from musclesim.components.checks import require
from musclesim.fmu import declare


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
    f_a = p.f_mean + p.f_amp * math.sin(2 * math.pi * p.f_f * t)
    u1 = 1.0 if math.sin(2 * math.pi * p.f_u * t) >= 0 else 0.0
    u2 = 1.0 if math.sin(2 * math.pi * p.f_u * t - p.phi) >= 0 else 0.0
    return (f_a, u1, u2) if p.direction > 0 else (f_a, u2, u1)
