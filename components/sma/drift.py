"""Training/fatigue drift of an SMA wire over transformation cycles (§drift), off by default.

A new wire's major loop changes markedly over its first ~13 tests of 20 cycles each, then settles
(§drift). The drift saturates with the accumulated cycles N (one cycle = xi swept 1 -> 0 -> 1):

    progress(N) = 1 - exp(-N / N_settle)
    eps  = (1 + amplitude_change progress) eps_model(T - shift progress, sigma)

so the hysteresis model sees a shifted temperature and its strain is scaled. Both changes are 0
by default, which leaves the nominal strain untouched bit for bit.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from musclesim.components.checks import require
from musclesim.fmu import jit


@dataclass(frozen=True)
class DriftParams:
    """Settled drift and its pace (defaults: no drift; pace from §drift)."""

    amplitude_change: float = 0.0  # relative change of the strain amplitude once settled; 0 = off
    shift: float = 0.0  # K, settled shift of the transformation temperatures; 0 = off
    cycles_to_settle: float = 87.0  # cycles, e-folding: 95 % after 13 tests x 20 cycles (§drift)

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("cycles_to_settle",))
        if not self.amplitude_change > -1:
            raise ValueError(f"amplitude_change must exceed -1 (got {self.amplitude_change!r})")


def count_cycles(n_cycles: float, xi_old: float, xi_new: float) -> float:
    """Accumulated cycles after `n_cycles` when xi moved from `xi_old` to `xi_new`: each full
    sweep 1 -> 0 -> 1 is one.

    Examples
    --------
    >>> count_cycles(count_cycles(0.0, 1.0, 0.0), 0.0, 1.0)
    1.0
    """
    return count_cycles_k(n_cycles, xi_old, xi_new)


@jit
def count_cycles_k(n_cycles: float, xi_old: float, xi_new: float) -> float:
    """`count_cycles` of `n_cycles`, `xi_old`, `xi_new`, compiled."""
    return n_cycles + abs(xi_new - xi_old) / 2


def progress(n_cycles: float, p: DriftParams) -> float:
    """Share of the settled drift `p` reached after `n_cycles`, 1 - exp(-N / N_settle)."""
    return progress_k(n_cycles, p.cycles_to_settle)


def strain_scale(n_cycles: float, p: DriftParams) -> float:
    """Factor on the hysteresis model's strain after `n_cycles` of drift `p`, exactly 1.0 with the
    effect off."""
    return strain_scale_k(n_cycles, p.amplitude_change, p.cycles_to_settle)


def temperature_shift(n_cycles: float, p: DriftParams) -> float:
    """Shift [K] of the transformation temperatures after `n_cycles` of drift `p` (the model sees
    T - shift); 0.0 when off."""
    return temperature_shift_k(n_cycles, p.shift, p.cycles_to_settle)


# --- the same on floats, for the compiled cores (`musclesim.fmu.compiled`) ---------------------

@jit
def progress_k(n_cycles: float, cycles_to_settle: float) -> float:
    """`progress` after `n_cycles` at the drift's pace `cycles_to_settle`."""
    return -math.expm1(-n_cycles / cycles_to_settle)


@jit
def strain_scale_k(n_cycles: float, amplitude_change: float, cycles_to_settle: float) -> float:
    """`strain_scale` after `n_cycles` of the drift `amplitude_change`, `cycles_to_settle`."""
    if amplitude_change == 0:
        return 1.0
    return 1.0 + amplitude_change * progress_k(n_cycles, cycles_to_settle)


@jit
def temperature_shift_k(n_cycles: float, shift: float, cycles_to_settle: float) -> float:
    """`temperature_shift` [K] after `n_cycles` of the drift `shift`, `cycles_to_settle`."""
    if shift == 0:
        return 0.0
    return shift * progress_k(n_cycles, cycles_to_settle)
