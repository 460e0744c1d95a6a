"""Temperature reference of the FORC identification experiments (§forc-identification).

Run j = 0 .. n-1 (n = (T_high - T_low) / T_step + 1, 21 on the study's 5 K grid) occupies
[t_start + j P, t_start + (j + 1) P) and heats from T_low to its peak a_j = T_low + j T_step along a
raised cosine, then cools back to T_low along the mirror image:

    T_ref(t) = T_low + (a_j - T_low) (1 - cos(2 pi tau / P)) / 2,   tau = t - t_start - j P

so each run starts and ends at T_low with zero slope. Besides the reference the source outputs
the run index j and a phase flag (+1 heating, tau < P / 2; -1 cooling), which is what the
identification (`musclesim.hysteresis.identify`) segments the records with. Outside the runs (before
t_start, after the last run) the reference holds T_low, the run index is -1 and the phase 0.

The period P must let the closed loop follow the cooling half: the wire cools by convection alone
(time constant tau ~1.7 s toward the ambient air), and the falling reference must never be faster
than free cooling. `min_period` gives the bound: about 16 s for the 100 K run with T_low 10 K above
the ambient air.

The reference is written once, as the `jit` function `value_core` on numbers, which `value` and
the ForcReference FMU's kernel call.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from musclesim.components.checks import require
import numpy as np

from musclesim.fmu import declare, jit

IDLE, HEATING, COOLING = 0.0, 1.0, -1.0  # values of the phase flag


@dataclass(frozen=True)
class ForcParams:
    """Grid [K], grid step [K], period of one run [s] and start of the first run [s]; each
    declared here once (`declare`)."""

    T_low: float = declare(303.15, "K", "Lower grid temperature b0, start and end of every run "
                           "(the study's 30 C, a saturation temperature)",
                           source="§forc-identification")
    T_high: float = declare(403.15, "K", "Peak of the last run a0 (the study's 130 C, a "
                            "saturation temperature)", source="§forc-identification")
    T_step: float = declare(5.0, "K", "Grid step between the runs' peaks (the study's grid); "
                            "T_high - T_low must be a whole number of it", source="§preisach",
                            plausible="difference")
    period: float = declare(20.0, "s", "Duration of one run, heating half and cooling half "
                            "(assumption: the shortest period free cooling can follow, 16.2 s, "
                            "with a margin for the temperature loop)",
                            source="§forc-identification")
    t_start: float = declare(0.0, "s", "Start of the first run, T_low held before (assumption: "
                             "at once)")

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        if not self.T_low < self.T_high:
            raise ValueError(f"T_low must be below T_high (got {self.T_low!r}, {self.T_high!r})")
        require(self, positive=("T_step",))
        n = (self.T_high - self.T_low) / self.T_step
        if abs(n - round(n)) > 1e-9 * max(1.0, n):
            raise ValueError(f"T_high - T_low = {self.T_high - self.T_low!r} K must be a whole "
                             f"number of T_step = {self.T_step!r} K")
        require(self, positive=("period",))
        if not math.isfinite(self.t_start):
            raise ValueError(f"t_start must be finite (got {self.t_start!r})")

    @property
    def n_runs(self) -> int:
        """Number of runs: one per grid peak, T_low (a flat run) to T_high."""
        return int(round((self.T_high - self.T_low) / self.T_step)) + 1

    @property
    def duration(self) -> float:
        """End of the last run [s], counted from t = 0."""
        return self.t_start + self.n_runs * self.period


def peak(j: float, p: ForcParams) -> float:
    """Peak temperature a_j [K] of run `j` of the experiments `p`.

    Examples
    --------
    >>> p = ForcParams()
    >>> p.n_runs, round(peak(0, p), 2), round(peak(20, p), 2)
    (21, 303.15, 403.15)
    """
    return float(peak_core(j, p.T_low, p.T_step))


@jit
def peak_core(j: float, T_low: float, T_step: float) -> float:
    """Peak temperature a_j [K] of run `j` on the grid from `T_low` by `T_step` (`peak`)."""
    return T_low + j * T_step


@jit
def value_core(t: float, p: np.ndarray) -> tuple[float, float, float]:
    """(T_ref [K], run index, phase flag) at time `t` [s] of the experiments packed in `p`
    (`pack`)."""
    T_low, T_step, period, t_start, n_runs = p[0], p[1], p[2], p[3], p[4]
    tau_all = t - t_start
    if tau_all < 0:
        return T_low, -1.0, IDLE
    j = int(math.floor(tau_all / period))
    if j >= n_runs:
        return T_low, -1.0, IDLE
    tau = tau_all - j * period
    x = tau / period
    T = T_low + (peak_core(j, T_low, T_step) - T_low) * 0.5 * (1.0 - math.cos(2.0 * math.pi * x))
    return T, float(j), HEATING if x < 0.5 else COOLING


def pack(p: ForcParams) -> np.ndarray:
    """The experiments `p` as `value_core` reads them: [T_low, T_step, period, t_start,
    n_runs]."""
    return np.array([p.T_low, p.T_step, p.period, p.t_start, p.n_runs], dtype=float)


def value(t: float, p: ForcParams) -> tuple[float, float, float]:
    """(T_ref [K], run index, phase flag) of the experiments `p` at time `t` [s] (module
    equation).

    Examples
    --------
    >>> p = ForcParams(period=20.0)
    >>> [tuple(round(x, 6) for x in value(t, p)) for t in (25.0, 30.0, 35.0, 500.0)]
    [(305.65, 1.0, 1.0), (308.15, 1.0, -1.0), (305.65, 1.0, -1.0), (303.15, -1.0, 0.0)]
    """
    T, run, phase = value_core(float(t), pack(p))
    return float(T), float(run), float(phase)


def min_period(amplitude: float, T_low_above_ambient: float, tau: float) -> float:
    """Shortest period [s] whose falling half of `amplitude` [K] never outruns free cooling
    (heating power 0, time constant `tau` [s], `T_low_above_ambient` [K]).

    With x = the phase left to the end of the run, the reference falls at A pi sin(x) / P and is
    then at A (1 - cos x) / 2 above T_low; free cooling from there manages (D + A (1 - cos x) / 2)
    / tau with D = T_low - T_amb. The bound is the maximum over x of tau A pi sin(x) / (D + A (1 -
    cos x) / 2) (evaluated on a fine grid).

    Examples
    --------
    >>> round(min_period(100.0, 10.0, 1.71), 1)
    16.2
    """
    best = 0.0
    for k in range(1, 2000):
        x = math.pi * k / 2000
        best = max(best, tau * amplitude * math.pi * math.sin(x)
                   / (T_low_above_ambient + amplitude * (1 - math.cos(x)) / 2))
    return best
