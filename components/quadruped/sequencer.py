"""The quadruped's leg sequencer (§quadruped): which leg's wire is pulsed when.

Every wire gets the study's pulse train (§quadruped: 5 V, 5 % duty at 4 Hz) shifted in time:
leg i's wire A at the phase phi_i (a fraction of the period), its wire B wire_delay later (0.5:
the alternating case of the bending actuator's test, 0.125 s at 4 Hz). A wire is at `voltage`
while its shifted cycle is in the first `duty` of a period, else at 0:

    u_iA(t) = V [frac(f t - phi_i) < duty],   u_iB(t) = V [frac(f t - phi_i - wire_delay) < duty]

The pulse is the SignalSource's square wave (`sources.signals.unit_wave`).
"""
from dataclasses import dataclass

from musclesim.components.checks import require
from musclesim.components.sources.signals import unit_wave

LEGS = 4


@dataclass(frozen=True)
class SequencerParams:
    """Pulse train and gait phasing (defaults: §quadruped's pulses; phasing open, §quadruped)."""

    frequency: float = 4.0  # Hz (§quadruped)
    duty: float = 0.05  # 12.5 ms on per 250 ms (§quadruped)
    voltage: float = 5.0  # V (§quadruped)
    wire_delay: float = 0.5  # periods from a leg's wire A to its wire B (§quadruped: 0.125 s)
    phase1: float = 0.0  # periods, leg 1 (front left) (open: a trot, diagonal pairs together)
    phase2: float = 0.5  # leg 2 (front right)
    phase3: float = 0.5  # leg 3 (rear left)
    phase4: float = 0.0  # leg 4 (rear right)

    def check(self):
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("frequency",), non_negative=("voltage",))
        if not 0.0 < self.duty < 1.0:
            raise ValueError(f"duty must be within (0, 1) (got {self.duty!r})")


def phases(p):
    """Phase of each leg's wire A [periods]."""
    return (p.phase1, p.phase2, p.phase3, p.phase4)


def voltages(t, p):
    """[(u_A, u_B) per leg] [V] at time t [s] (module equation).

    Examples
    --------
    >>> p = SequencerParams()
    >>> voltages(0.01, p)[0], voltages(0.135, p)[0], voltages(0.135, p)[1]
    ((5.0, 0.0), (0.0, 5.0), (5.0, 0.0))
    """
    out = []
    for phi in phases(p):
        cycles = p.frequency * t - phi
        out.append(tuple(p.voltage if unit_wave("square", c, p.duty) > 0 else 0.0
                         for c in (cycles, cycles - p.wire_delay)))
    return out
