"""Discrete PID with derivative filter, output limits and anti-windup, and its gain scheduling.

Parallel form u = Kp e + I + D with e = r - y, sampled at the communication step dt:

    I[k+1] = I[k] + Ki e[k] dt            (held while the output saturates in the error's direction)
    D[k]   = Tf/(Tf + dt) D[k-1] - Kd/(Tf + dt) (y[k] - y[k-1])   (on the measurement: no kick)
    u[k]   = clip(Kp e[k] + I[k] + D[k], u_min, u_max)

The integral is stored already multiplied by Ki, so changing gains (scheduling) does not bump u.

The equations are written once, as `jit` scalar functions (`derivative_core`, `output_core`,
`update_core`, `gains_at`); the dataclass functions below and the FMU's kernel
(`musclesim.components.control.slaves`) both call them.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from musclesim.components.checks import require
from musclesim.fmu import declare, jit

# §temperature-control: 21 operating points of the temperature reference, 30..130 C every 5 C (in
# K): the GainScheduledPID's default scheduling points, and those its gains are designed at
SCHEDULE_K = [273.15 + 30.0 + 5.0 * i for i in range(21)]


@dataclass(frozen=True)
class PIDParams:
    """Gains, derivative filter time and output limits (defaults: a unit P controller, §pid).
    The gains and the filter time are declared here once (`declare`); the FMUs declare the limits,
    whose "none" is a finite 1e30 there (FMI start values must be finite)."""

    Kp: float = declare(1.0, "1", "Proportional gain (neutral default: the scenarios set it)")
    Ki: float = declare(0.0, "1", "Integral gain [1/s]")
    Kd: float = declare(0.0, "1", "Derivative gain [s]")
    Tf: float = declare(0.0, "s", "Derivative filter time constant (0: none, a plain backward "
                        "difference)")
    u_min: float = -math.inf
    u_max: float = math.inf

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, non_negative=("Kd", "Tf"))
        if not self.u_min < self.u_max:
            raise ValueError(f"u_min {self.u_min!r} must be below u_max {self.u_max!r}")


@dataclass
class PIDState:
    """Integral term, last derivative term and last measurement."""

    integral: float = 0.0
    derivative: float = 0.0
    y_last: float = math.nan  # NaN: no sample yet, so no derivative kick on the first one


@jit
def derivative_core(d_last: float, y_last: float, y: float, dt: float, Kd: float,
                    Tf: float) -> float:
    """Filtered derivative of -`y` after `dt` [s], the last term `d_last` at measurement `y_last`
    (NaN: no sample yet, 0), with gain `Kd` and filter time `Tf` [s]."""
    if math.isnan(y_last) or dt <= 0 or Kd == 0:
        return 0.0
    return (Tf * d_last - Kd * (y - y_last)) / (Tf + dt)


@jit
def output_core(integral: float, d_last: float, y_last: float, r: float, y: float, dt: float,
                Kp: float, Kd: float, Tf: float, u_min: float, u_max: float) -> float:
    """The controller's output (`output`) from its state (`integral`, `d_last`, `y_last`) for
    reference `r` and measurement `y`, `dt` [s] after the last sample, with gains `Kp`, `Kd`,
    filter time `Tf` [s] and limits `u_min`, `u_max`."""
    u = Kp * (r - y) + integral + derivative_core(d_last, y_last, y, dt, Kd, Tf)
    if u_min > u:  # Python's max(u, u_min), then min(., u_max): NaN and zeros' signs kept
        u = u_min
    if u_max < u:
        u = u_max
    return u


@jit
def update_core(integral: float, d_last: float, y_last: float, r: float, y: float, dt: float,
                Kp: float, Ki: float, Kd: float, Tf: float, u_min: float,
                u_max: float) -> tuple[float, float, float]:
    """The state (integral, derivative, last measurement) after one sample (`update`) of `dt`
    [s] from the state (`integral`, `d_last`, `y_last`), with reference `r`, measurement `y`,
    gains `Kp`, `Ki`, `Kd`, filter time `Tf` [s] and limits `u_min`, `u_max`."""
    e = r - y
    d = derivative_core(d_last, y_last, y, dt, Kd, Tf)
    unclipped = Kp * e + integral + d
    winding_up = (unclipped > u_max and e > 0) or (unclipped < u_min and e < 0)
    step = 0.0 if winding_up else Ki * e * dt
    return integral + step, d, y


@jit
def gains_at(x: float, p: np.ndarray, o: int, n: int) -> tuple[float, float, float]:
    """Gains (Kp, Ki, Kd) at scheduling variable `x` of the schedule packed in `p` from `o`: `n`
    increasing breakpoints, then the n values of Kp, of Ki and of Kd (`scheduled_gains`)."""
    if x <= p[o]:
        return p[o + n], p[o + 2 * n], p[o + 3 * n]
    if x >= p[o + n - 1]:
        return p[o + 2 * n - 1], p[o + 3 * n - 1], p[o + 4 * n - 1]
    i = 0
    while i < n - 2 and p[o + i + 1] <= x:  # to p[o + i] <= x < p[o + i + 1]
        i += 1
    w = (x - p[o + i]) / (p[o + i + 1] - p[o + i])
    a, b, c = p[o + n + i], p[o + 2 * n + i], p[o + 3 * n + i]
    return (a + w * (p[o + n + i + 1] - a), b + w * (p[o + 2 * n + i + 1] - b),
            c + w * (p[o + 3 * n + i + 1] - c))


def derivative_term(state: PIDState, y: float, dt: float, Kd: float, Tf: float) -> float:
    """Filtered derivative of -`y` at this sample, after `dt` [s] in `state`, with gain `Kd` and
    filter time `Tf` [s] (0 on the first sample)."""
    return float(derivative_core(state.derivative, state.y_last, y, dt, Kd, Tf))


def output(state: PIDState, r: float, y: float, dt: float, gains: Sequence[float],
           p: PIDParams) -> float:
    """Output of the controller `p` in `state` for reference `r` and measurement `y`, `dt` [s]
    after the last sample; `gains` = (Kp, Ki, Kd)."""
    Kp, _, Kd = gains
    return float(output_core(state.integral, state.derivative, state.y_last, r, y, dt, Kp, Kd,
                             p.Tf, p.u_min, p.u_max))


def update(state: PIDState, r: float, y: float, dt: float, gains: Sequence[float],
           p: PIDParams) -> PIDState:
    """Advance `state` over one sample of `dt` [s] with reference `r`, measurement `y`, `gains`
    (Kp, Ki, Kd) and the controller `p` (conditional integration as anti-windup)."""
    Kp, Ki, Kd = gains
    integral, d, y_last = update_core(state.integral, state.derivative, state.y_last, r, y, dt,
                                      Kp, Ki, Kd, p.Tf, p.u_min, p.u_max)
    return PIDState(float(integral), float(d), float(y_last))


def pack_schedule(breakpoints: Sequence[float],
                  table: Sequence[Sequence[float]]) -> np.ndarray:
    """The schedule as `gains_at` reads it: the `breakpoints`, then the column of Kp, of Ki and
    of Kd of `table` (rows (Kp, Ki, Kd))."""
    return np.array([*breakpoints, *(row[k] for k in range(3) for row in table)], dtype=float)


def scheduled_gains(x: float, breakpoints: Sequence[float],
                    table: Sequence[tuple[float, float, float]]) -> tuple[float, ...]:
    """Gains (Kp, Ki, Kd) of `table` at scheduling variable `x`, linear between `breakpoints`,
    held at the ends.

    Examples
    --------
    >>> scheduled_gains(2.5, [0.0, 5.0], [(1.0, 0.0, 0.0), (3.0, 1.0, 0.0)])
    (2.0, 0.5, 0.0)
    """
    if math.isnan(x):
        raise ValueError("the scheduling variable is NaN")
    return tuple(float(g) for g in gains_at(float(x), pack_schedule(breakpoints, table), 0,
                                            len(breakpoints)))
