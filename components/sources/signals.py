"""Test signals: constant, sine, square and triangle waves around an offset, and a ramp.

    y(t) = offset                                  for t < t_start or kind = constant
    y(t) = offset + amplitude w(f (t - t_start) + phase / 2 pi)   otherwise

with w the unit wave of the kind (sine; square: +1 over the first `duty` of each period, -1 over
the rest; triangle: -1 -> +1 -> -1; ramp: 0 -> 1 over the first period, then held), so a square
wave alternates between two set-points (offset = amplitude = V/2: a pulse train 0 / V of that
duty) and a ramp rises by `amplitude` over 1/f seconds.

A square wave's edge belongs to the part after it, and a time within `EDGE` periods of an edge
is taken on it: a master samples at t0 + k h, and f t + phase / 2 pi rounds either side of an
edge that falls on a sample, so that otherwise a pulse of 25 steps could take 26 (the bending
actuator's wire B, half a period behind wire A).

The waves are written once, as `jit` functions on numbers (`wave`, `value_core`), which `value`
and the SignalSource FMU's kernel call.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from musclesim.components.checks import require
import numpy as np

from musclesim.fmu import declare, jit

KINDS = ("constant", "sine", "square", "triangle", "ramp")
EDGE = 1e-9  # periods: the rounding of a sample's phase, far below any step a master takes


@dataclass(frozen=True)
class SignalParams:
    """Wave kind (an index into KINDS), offset, amplitude, frequency [Hz], phase [rad], start [s],
    share of the period a square wave is high; each declared here once (`declare`)."""

    kind: float = declare(0.0, "1", "Wave: 0 constant, 1 sine, 2 square, 3 triangle, 4 ramp "
                          "(rises by amplitude over 1/frequency s, then holds)", type="Integer")
    # of the quantity the output carries, whose unit the scenario's wiring gives
    offset: float = declare(0.0, "1", "Offset (the value before t_start)", same_unit_as="y")
    amplitude: float = declare(0.0, "1", "Amplitude", same_unit_as="y", plausible="difference")
    frequency: float = declare(0.0, "Hz", "Frequency")
    phase: float = declare(0.0, "rad", "Phase")
    t_start: float = declare(0.0, "s", "Start of the wave")
    duty: float = declare(0.5, "1", "Square wave: share of each period at offset + amplitude "
                          "(0..1 exclusive; a pulse train of this duty)")

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        if self.kind not in range(len(KINDS)):
            raise ValueError(f"kind must be one of 0..{len(KINDS) - 1} ({', '.join(KINDS)}), "
                             f"got {self.kind!r}")
        require(self, non_negative=("frequency",))
        if not 0.0 < self.duty < 1.0:
            raise ValueError(f"duty must be within (0, 1) (the share of a square wave's period "
                             f"at offset + amplitude; got {self.duty!r})")


@jit
def wave(kind: float, cycles: float, duty: float) -> float:
    """The unit wave of `kind` (an index into KINDS: 1 sine, 2 square, 4 ramp, any other the
    triangle) after `cycles` periods; `duty`: a square wave's high share (`unit_wave`)."""
    if kind == 4.0:  # ramp: Python's min(max(cycles, 0.0), 1.0)
        c = 0.0 if 0.0 > cycles else cycles
        return 1.0 if 1.0 < c else c
    frac = cycles - math.floor(cycles)
    if kind == 1.0:
        return math.sin(2 * math.pi * cycles)
    if kind == 2.0:  # edges belong to the part after them, to within EDGE
        shifted = cycles + EDGE
        return 1.0 if shifted - math.floor(shifted) < duty else -1.0
    return 4 * frac - 1 if frac < 0.5 else 3 - 4 * frac  # triangle


@jit
def value_core(t: float, p: np.ndarray) -> float:
    """y(`t`) of the signal packed in `p` (`pack`)."""
    kind, offset, amplitude, frequency, phase, t_start, duty = p[0], p[1], p[2], p[3], p[4], \
        p[5], p[6]
    if kind == 0.0 or t < t_start:
        return offset
    cycles = frequency * (t - t_start) + phase / (2 * math.pi)
    return offset + amplitude * wave(kind, cycles, duty)


def pack(p: SignalParams) -> np.ndarray:
    """The signal `p` as `value_core` reads it: [kind, offset, amplitude, frequency, phase,
    t_start, duty] (the fields' order)."""
    return np.array([p.kind, p.offset, p.amplitude, p.frequency, p.phase, p.t_start, p.duty],
                    dtype=float)


def unit_wave(kind: str, cycles: float, duty: float = 0.5) -> float:
    """The unit wave of `kind` after `cycles` periods (a float); `duty`: a square wave's high share.

    Examples
    --------
    >>> [unit_wave("square", c) for c in (0.25, 0.75)], unit_wave("triangle", 0.5)
    ([1.0, -1.0], 1.0)
    >>> [unit_wave("square", c, duty=0.1) for c in (0.05, 0.25)]
    [1.0, -1.0]
    >>> [unit_wave("ramp", c) for c in (0.25, 3.0)]
    [0.25, 1.0]
    """
    return float(wave(float(KINDS.index(kind)) if kind in KINDS else 3.0, float(cycles),
                      float(duty)))


def value(t: float, p: SignalParams) -> float:
    """y(`t`) of the signal `p` (module equation)."""
    return float(value_core(float(t), pack(p)))
