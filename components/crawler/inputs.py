"""Ideal open-loop actuation of §ideal-actuation: a sinusoidal actuator force and two friction
indicators."""
import math
from dataclasses import dataclass

from musclesim.components.checks import require

@dataclass(frozen=True)
class InputParams:
    """Signal parameters (defaults: §ideal-actuation nominal case)."""

    f_mean: float = 10.28  # N, mean of f_a, which oscillates between 0.66 N and 19.9 N
    #                        (§ideal-actuation)
    f_amp: float = 9.62  # N, amplitude of f_a (§ideal-actuation)
    f_f: float = 1.0  # Hz, frequency of f_a (§ideal-actuation)
    f_u: float = 1.0  # Hz, frequency of the friction indicators (§ideal-actuation)
    phi: float = 1.64  # rad, phase lag of u2 behind u1; steers the direction (§ideal-actuation)
    direction: float = 1.0  # +1; -1 swaps the indicators: the mirror image, driven backward

    def check(self):
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, non_negative=("f_f", "f_u", "f_amp"))
        if self.direction not in (1.0, -1.0):
            raise ValueError(f"direction must be 1 or -1 (got {self.direction!r})")


def signals(t, p):
    """Return (f_a [N], u1, u2) at time t: u_i = 1 while its square wave is high (inflated)."""
    f_a = p.f_mean + p.f_amp * math.sin(2 * math.pi * p.f_f * t)
    u1 = 1.0 if math.sin(2 * math.pi * p.f_u * t) >= 0 else 0.0
    u2 = 1.0 if math.sin(2 * math.pi * p.f_u * t - p.phi) >= 0 else 0.0
    return (f_a, u1, u2) if p.direction > 0 else (f_a, u2, u1)
