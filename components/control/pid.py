"""Discrete PID with derivative filter, output limits and anti-windup, and its gain scheduling.

Parallel form u = Kp e + I + D with e = r - y, sampled at the communication step dt:

    I[k+1] = I[k] + Ki e[k] dt            (held while the output saturates in the error's direction)
    D[k]   = Tf/(Tf + dt) D[k-1] - Kd/(Tf + dt) (y[k] - y[k-1])   (on the measurement: no kick)
    u[k]   = clip(Kp e[k] + I[k] + D[k], u_min, u_max)

The integral is stored already multiplied by Ki, so changing gains (scheduling) does not bump u.
"""
from __future__ import annotations

import bisect
import math
from collections.abc import Sequence
from dataclasses import dataclass

from musclesim.components.checks import require
from musclesim.fmu import declare

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


def derivative_term(state: PIDState, y: float, dt: float, Kd: float, Tf: float) -> float:
    """Filtered derivative of -`y` at this sample, after `dt` [s] in `state`, with gain `Kd` and
    filter time `Tf` [s] (0 on the first sample)."""
    if math.isnan(state.y_last) or dt <= 0 or Kd == 0:
        return 0.0
    return (Tf * state.derivative - Kd * (y - state.y_last)) / (Tf + dt)


def output(state: PIDState, r: float, y: float, dt: float, gains: Sequence[float],
           p: PIDParams) -> float:
    """Output of the controller `p` in `state` for reference `r` and measurement `y`, `dt` [s]
    after the last sample; `gains` = (Kp, Ki, Kd)."""
    Kp, _, Kd = gains
    u = Kp * (r - y) + state.integral + derivative_term(state, y, dt, Kd, p.Tf)
    return min(max(u, p.u_min), p.u_max)


def update(state: PIDState, r: float, y: float, dt: float, gains: Sequence[float],
           p: PIDParams) -> PIDState:
    """Advance `state` over one sample of `dt` [s] with reference `r`, measurement `y`, `gains`
    (Kp, Ki, Kd) and the controller `p` (conditional integration as anti-windup)."""
    Kp, Ki, Kd = gains
    e = r - y
    d = derivative_term(state, y, dt, Kd, p.Tf)
    unclipped = Kp * e + state.integral + d
    winding_up = (unclipped > p.u_max and e > 0) or (unclipped < p.u_min and e < 0)
    return PIDState(state.integral + (0.0 if winding_up else Ki * e * dt), d, y)


def scheduled_gains(x: float, breakpoints: Sequence[float],
                    table: Sequence[tuple[float, float, float]]) -> tuple[float, ...]:
    """Gains (Kp, Ki, Kd) of `table` at scheduling variable `x`, linear between `breakpoints`,
    held at the ends.

    Examples
    --------
    >>> scheduled_gains(2.5, [0.0, 5.0], [(1.0, 0.0, 0.0), (3.0, 1.0, 0.0)])
    (2.0, 0.5, 0.0)
    """
    if x <= breakpoints[0]:
        return tuple(table[0])
    if x >= breakpoints[-1]:
        return tuple(table[-1])
    i = bisect.bisect_right(breakpoints, x) - 1  # breakpoints[i] <= x < breakpoints[i + 1]
    w = (x - breakpoints[i]) / (breakpoints[i + 1] - breakpoints[i])
    return tuple(a + w * (b - a) for a, b in zip(table[i], table[i + 1]))
