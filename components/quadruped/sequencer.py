"""The quadruped's leg sequencer (§quadruped): which leg's wire is pulsed when.

Every wire gets the study's pulse train (§quadruped: 5 V, 5 % duty at 4 Hz) shifted in time:
leg i's wire A at the phase phi_i (a fraction of the period), its wire B wire_delay later (0.5:
the alternating case of the bending actuator's test, 0.125 s at 4 Hz). A wire is at `voltage`
while its shifted cycle is in the first `duty` of a period, else at 0:

    u_iA(t) = V [frac(f t - phi_i) < duty],   u_iB(t) = V [frac(f t - phi_i - wire_delay) < duty]

The pulse is the SignalSource's square wave (`sources.signals.wave`, kind 2).

The FMU's kernel (`KERNEL`, compiled where numba is installed: `musclesim.fmu.compiled`) and
`voltages` run the same `voltages_into`: parameters `pack`; no state, no inputs; outputs y =
[u_1A, u_1B, u_2A, u_2B, ...] (`OUTPUTS`).
"""
from __future__ import annotations

from dataclasses import astuple, dataclass

import numpy as np

from musclesim.components.checks import require
from musclesim.components.sources.signals import KINDS, wave
from musclesim.fmu import Kernel, declare, jit, no_state

LEGS = 4


@dataclass(frozen=True)
class SequencerParams:
    """Pulse train and gait phasing (defaults: §quadruped's pulses; phasing open, §quadruped).
    Each parameter is declared once here (`declare`): the FMU and the docs' tables read it."""

    frequency: float = declare(4.0, "Hz", "Pulse frequency of every wire (the study's pulse "
                               "test: 4 Hz)", source="§quadruped")
    duty: float = declare(0.05, "1", "Share of a period a wire is heated (the study: 5 %, "
                          "12.5 ms per 250 ms)", source="§quadruped")
    voltage: float = declare(5.0, "V", "Pulse voltage (the study: 5 V)", source="§quadruped")
    wire_delay: float = declare(0.5, "1", "Periods from a leg's wire A pulse to its wire B pulse "
                                "(the study's alternating case: 0.125 s at 4 Hz)",
                                source="§quadruped")
    phase1: float = declare(0.0, "1", "Phase of leg 1's wire A (front left) in periods (open; "
                            "default: a trot, legs 1 and 4 together, 2 and 3 half a period "
                            "later)", source="§quadruped")
    phase2: float = declare(0.5, "1", "Phase of leg 2's wire A (front right) in periods (open; "
                            "default: a trot)", source="§quadruped")
    phase3: float = declare(0.5, "1", "Phase of leg 3's wire A (rear left) in periods (open; "
                            "default: a trot)", source="§quadruped")
    phase4: float = declare(0.0, "1", "Phase of leg 4's wire A (rear right) in periods (open; "
                            "default: a trot)", source="§quadruped")

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("frequency",), non_negative=("voltage",))
        if not 0.0 < self.duty < 1.0:
            raise ValueError(f"duty must be within (0, 1) (got {self.duty!r})")


def phases(p: SequencerParams) -> tuple[float, float, float, float]:
    """Phase of each leg's wire A [periods] of the sequencer `p`."""
    return (p.phase1, p.phase2, p.phase3, p.phase4)


# the kernel's parameters (`pack`): the fields in their declared order
FREQUENCY, DUTY, VOLTAGE, WIRE_DELAY, PHASE1 = range(5)  # PHASE1 + i: leg i + 1's phase
SQUARE = float(KINDS.index("square"))  # the square wave of `sources.signals.wave`
OUTPUTS = tuple(f"leg{i}.u{w}" for i in range(1, LEGS + 1) for w in "AB")


def pack(p: SequencerParams) -> np.ndarray:
    """The kernel's parameters: `p`'s fields in their declared order (frequency, duty, voltage,
    wire_delay, phase1, phase2, phase3, phase4)."""
    return np.array(astuple(p), dtype=float)


def voltages(t: float, p: SequencerParams) -> list[tuple[float, ...]]:
    """[(u_A, u_B) per leg] [V] of the sequencer `p` at time `t` [s] (module equation).

    Examples
    --------
    >>> p = SequencerParams()
    >>> voltages(0.01, p)[0], voltages(0.135, p)[0], voltages(0.135, p)[1]
    ((5.0, 0.0), (0.0, 5.0), (5.0, 0.0))
    """
    y = np.zeros(2 * LEGS)
    voltages_into(float(t), pack(p), y)
    u = y.tolist()
    return [(u[2 * i], u[2 * i + 1]) for i in range(LEGS)]


@jit
def voltages_into(t: float, p: np.ndarray, y: np.ndarray) -> None:
    """`voltages` at time `t` [s] of the packed parameters `p` (`pack`) into `y` = [u_1A, u_1B,
    u_2A, u_2B, ...] [V]."""
    for i in range(LEGS):
        cycles = p[FREQUENCY] * t - p[PHASE1 + i]
        y[2 * i] = p[VOLTAGE] if wave(SQUARE, cycles, p[DUTY]) > 0 else 0.0
        y[2 * i + 1] = p[VOLTAGE] if wave(SQUARE, cycles - p[WIRE_DELAY], p[DUTY]) > 0 else 0.0


@jit
def evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """Kernel outputs `y` (`OUTPUTS`) at time `t` [s] of the parameters `p` (`pack`; no state
    `x`, no inputs `u`): `voltages_into`."""
    voltages_into(t, p, y)


KERNEL = Kernel(evaluate, no_state, (), OUTPUTS)
