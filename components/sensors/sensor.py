"""A scalar sensor: first-order lag, gain, bias, seeded noise and quantisation, all off by default.

The core of every sensor FMU (thermocouple, load cell, laser displacement sensor; §sma-bench,
§named-effects): the sensing element follows the measured signal with time constant tau; the reading
scales it by a gain about the sensor's origin (0 C for a thermocouple, 0 for the others), adds a
bias and Gaussian noise and is rounded to the quantisation step.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from musclesim.components.checks import require
from musclesim.fmu import declare


@dataclass(frozen=True)
class SensorParams:
    """Lag, gain, bias, noise and quantisation of a scalar sensor; the defaults = a perfect
    sensor (§sensors). Each parameter is declared here once (`declare`); what differs per sensor
    its slave overrides: `bias`, `noise_std` and `quantum` are in the signal's unit (declared
    "1" here), and the diagnosis roles (effect bounds, calibrations) are each sensor's own."""

    tau: float = declare(0.0, "s", "Time constant of the sensing element's first-order lag "
                         "(0 = none)", source="§sensors")
    gain: float = declare(1.0, "1", "Reading gain about the sensor's origin (0 C for a "
                          "thermocouple, 0 for the others; 1 = exact)", source="§sensors")
    origin: float = 0.0  # signal value the gain leaves as it is (a thermocouple's 0 C)
    bias: float = declare(0.0, "1", "Reading bias (0 = off)", source="§sensors")
    noise_std: float = declare(0.0, "1", "Standard deviation of the reading's Gaussian noise "
                               "(0 = off)", source="§sensors")
    quantum: float = declare(0.0, "1", "Quantisation step of the reading (0 = off)",
                             source="§sensors")
    seed: float = declare(0.0, "1", "Seed of the noise generator (>= 0)", type="Integer")

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("gain",), non_negative=("tau", "noise_std", "quantum"))
        if self.seed != int(self.seed) or self.seed < 0:
            raise ValueError(f"seed must be a non-negative whole number (got {self.seed!r})")


def lag_weights(dt: float, tau: float) -> tuple[float, float]:
    """(a, b) of the exact first-order lag of time constant `tau` over `dt` for an input linear
    between two samples:
    y1 = a y0 + (1 - a - b) u0 + b u1, with a = exp(-dt/tau), b = 1 - tau (1 - a) / dt.

    Continuous in tau: at tau = 0 the reading is the signal itself (a = 0, b = 1), and a lag
    much shorter than the step is a small delay, not a whole step of it (as a held input gives).

    >>> lag_weights(0.02, 0.0)
    (0.0, 1.0)
    >>> a, b = lag_weights(0.02, 1e-9); round(a, 12), round(b, 6)
    (0.0, 1.0)
    """
    if tau <= 0:
        return 0.0, 1.0
    a = math.exp(-dt / tau)
    return a, 1.0 - tau * (-math.expm1(-dt / tau)) / dt


def noise_sample(p: SensorParams, rng: np.random.Generator) -> float:
    """One noise sample of the reading of the sensor `p` from `rng` (0 when the noise is off; the
    generator is not used then)."""
    return p.noise_std * rng.standard_normal() if p.noise_std > 0 else 0.0


def reading(x: float, p: SensorParams, noise: float = 0.0) -> float:
    """Reading of the sensor `p` of the (lagged) signal `x`: gain about the origin, bias, the
    `noise` sample,
    quantisation.

    Examples
    --------
    >>> reading(300.26, SensorParams(bias=-1.0, quantum=0.25))
    299.25
    >>> round(reading(373.15, SensorParams(gain=1.01, origin=273.15)), 6)  # 100 C reads 101 C
    374.15
    """
    if p.gain != 1.0:
        x = p.origin + p.gain * (x - p.origin)
    y = x + p.bias + noise
    if p.quantum > 0:
        y = p.quantum * round(y / p.quantum)
    return y


def make_rng(p: SensorParams) -> np.random.Generator:
    """The random generator of the sensor `p` (its state is part of the FMU state)."""
    return np.random.default_rng(int(p.seed))
