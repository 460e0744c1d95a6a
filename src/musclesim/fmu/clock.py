"""Time in a musclesim FMU: `experiment`, a component's FMI default experiment, and `step_end`,
the clock every slave keeps, so that a time-driven output reads the same instant whoever steps it.

Shipped inside every FMU with the rest of `musclesim.fmu`: the standard library and pythonfmu.
"""
from __future__ import annotations

from pythonfmu import DefaultExperiment


def step_end(t0: float, t: float, h: float) -> float:
    """The time a step of `h` from `t` ends at: t0 + (k + 1) h where `t` is the point t0 + k h of
    a master counting its points from the start time `t0` (musclesim's, FMPy's), so that a
    time-driven output reads the same instant whoever steps it; t + h otherwise.

    Examples
    --------
    >>> step_end(0.0, 9 * 0.001, 0.001), 9 * 0.001 + 0.001
    (0.01, 0.010000000000000002)
    """
    k = round((t - t0) / h) if h > 0 else None
    return t0 + (k + 1) * h if k is not None and t0 + k * h == t else t + h


def experiment(stop_time: float, step: float) -> DefaultExperiment:
    """The FMI default experiment of a component: from 0 to `stop_time` [s] in steps of `step`
    [s]."""
    return DefaultExperiment(start_time=0.0, stop_time=stop_time, step_size=step)
