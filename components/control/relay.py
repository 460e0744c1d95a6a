"""Relay (bang-bang) controller with hysteresis, e.g. §bang-bang's heating of an SMA wire.

The relay is on or off. Sampled at the communication points, with y the measurement:

    off -> on   when y <= y_on    (falling through the lower threshold: §bang-bang, 75 C)
    on  -> off  when y >= y_off   (rising through the upper threshold: §bang-bang, 90 C)
    u = u_on when on, u_off when off

Between the thresholds the relay keeps its state, so the switching has hysteresis y_off - y_on.
The decision at a sample uses that sample's measurement (direct feedthrough), as the study's
relay on the measured temperature does. The switching is written once, as `jit` functions
(`switch_core`, `initial_core`, `output_core`), which the functions below and the BangBang FMU's
kernel call.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from musclesim.fmu import declare, jit

ZERO_C = 273.15


@dataclass(frozen=True)
class RelayParams:
    """Thresholds, output levels and the initial state (defaults: §multiplier-experiments in K; the
    supply voltage is open: see §bang-bang). The outputs and the initial state are declared here
    once (`declare`); the BangBang FMU declares the thresholds as temperatures, T_on and T_off."""

    y_on: float = ZERO_C + 75.0  # K: switch on when falling to it (§multiplier-experiments)
    y_off: float = ZERO_C + 90.0  # K: switch off when rising to it (§multiplier-experiments)
    u_on: float = declare(1.0, "1", "Output when on: the heating supply voltage [V]. The study "
                          "leaves it open; the scenarios set 32.7 V per metre of wire, 7.0 V on "
                          "the 214 mm multiplier and 1.832 V on the 56 mm straight wire, so that "
                          "both heat alike per unit length", source="§multiplier-experiments")
    u_off: float = declare(0.0, "1", "Output when off (the supply switched off)")
    initially_on: float = declare(1.0, "1", "State at the start when the measurement lies "
                                  "between the thresholds (1 on, 0 off): a wire started between "
                                  "them heats first", type="Boolean")

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        for name in ("y_on", "y_off", "u_on", "u_off"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"{name} must be finite (got {getattr(self, name)!r})")
        if not self.y_on < self.y_off:
            raise ValueError(f"y_on ({self.y_on!r}) must lie below y_off ({self.y_off!r}): the "
                             "relay switches on when falling to y_on and off when rising to y_off")
        if self.initially_on not in (0.0, 1.0):
            raise ValueError(f"initially_on must be 0 or 1 (got {self.initially_on!r})")


@jit
def switch_core(on: bool, y: float, y_on: float, y_off: float) -> bool:
    """The relay's state after seeing `y` in state `on`, thresholds `y_on` < `y_off` (`switch`)."""
    if on:
        return not y >= y_off
    return y <= y_on


@jit
def initial_core(y: float, y_on: float, y_off: float, initially_on: float) -> bool:
    """The relay's state at the start, measuring `y` (`initial_state`): on at or below `y_on`,
    off at or above `y_off`, else on if `initially_on` is 1."""
    if y <= y_on:
        return True
    if y >= y_off:
        return False
    return initially_on == 1.0


@jit
def output_core(on: bool, u_on: float, u_off: float) -> float:
    """`u_on` or `u_off` as the relay is `on` or not."""
    return u_on if on else u_off


def switch(on: bool, y: float, p: RelayParams) -> bool:
    """The state of the relay `p` after seeing measurement `y` in state `on`.

    Examples
    --------
    >>> p = RelayParams(y_on=75.0, y_off=90.0)
    >>> [switch(True, y, p) for y in (80.0, 90.0)], [switch(False, y, p) for y in (80.0, 75.0)]
    ([True, False], [False, True])
    """
    if math.isnan(y):
        raise ValueError("the relay's measurement is NaN")
    return bool(switch_core(bool(on), float(y), p.y_on, p.y_off))


def initial_state(y: float, p: RelayParams) -> bool:
    """State of the relay `p` at the start, measuring `y`: on below y_on, off above y_off,
    ``initially_on`` in between."""
    return bool(initial_core(float(y), p.y_on, p.y_off, p.initially_on))


def output(on: bool, p: RelayParams) -> float:
    """u_on or u_off of the relay `p`, as it is `on` or not."""
    return float(output_core(bool(on), p.u_on, p.u_off))


def sequence(ys: Sequence[float], p: RelayParams) -> list[bool]:
    """States of the relay `p` after each sample of the measurement trace `ys`, starting from
    `initial_state`.

    Examples
    --------
    >>> p = RelayParams(y_on=75.0, y_off=90.0)
    >>> sequence([70.0, 85.0, 91.0, 80.0, 74.0], p)
    [True, True, False, False, True]
    """
    on = initial_state(ys[0], p)
    states = []
    for y in ys:
        on = switch(on, y, p)
        states.append(on)
    return states
