"""Four-phase peristaltic gait of the real crawler (§gait) as pressure references.

Three actuators: back extremal (1), central (c), front extremal (2). A forward stride:

=====  ===========================  ==========  ==========  ==========
phase  what happens                 p_ref1      p_ref_c     p_ref2
=====  ===========================  ==========  ==========  ==========
1      anchor back                  p_anchor1   p_off       p_off
2      protrusion: front slides     p_anchor1   p_central   p_off
3      anchor front                 p_anchor1   p_central   p_anchor2
4      deflate back and central     p_off       p_off       p_anchor2
=====  ===========================  ==========  ==========  ==========

A backward stride is the mirror image: back and front swap roles (phase 1 anchors the front,
phase 3 the back, phase 4 deflates the front and the central actuator); each extremal actuator
keeps its own anchoring pressure. Phase 2 lasts the protrusion time; the stance time is split
equally over phases 1, 3 and 4 (an assumption: §gait gives only the protrusion and stance
times). With t_reverse > 0 the direction flips every t_reverse seconds and a new stride starts at
phase 1 in the other direction (§gait bidirectional test).

The FMU's kernel (`KERNEL`): parameters `pack`, no state, no inputs, outputs y = [p_ref1, p_ref_c,
p_ref2, phase, stride_direction, stride] (`references`).
"""
from __future__ import annotations

import math
from dataclasses import astuple, dataclass

import numpy as np

from musclesim.components.checks import require
from musclesim.fmu import Kernel, declare, jit, no_state

# s: times within this of a phase boundary count as past it, so that a time accumulated step by
# step (0.001 + 0.001 + ...) switches on the same sample as the exact time would
EPS = 1e-9


@dataclass(frozen=True)
class GaitParams:
    """Gait timing and pressure references (defaults: §gait timing). Each parameter is declared
    once here (`declare`): the FMU and the docs' tables read it."""

    t_protrusion: float = declare(1.2, "s", "Protrusion time, phase 2 (the study's)",
                                  source="§gait")
    t_stance: float = declare(1.8, "s", "Stance time, split equally over phases 1, 3 and 4, "
                              "0.6 s each (assumption: the study gives only the protrusion and "
                              "stance times; a stride takes 3 s)", source="§gait")
    direction: float = declare(1.0, "1", "Direction of the first stride: +1 forward, -1 "
                               "backward", source="§gait", type="Integer")
    t_reverse: float = declare(0.0, "s", "Direction reversal period; 0 = never (the study's "
                               "bidirectional test: 32.5 s)", source="§gait")
    # scenarios set these from the off-line characterisation (scenarios/params,
    # §pressure-control); the defaults only make the FMU runnable on its own
    p_central: float = declare(10e3, "Pa", "Central actuator reference while protruding (a "
                               "placeholder: the scenarios set the characterisation's, "
                               "scenarios/params/crawler-gait-references.toml)",
                               source="§pressure-control", plausible="inflating pressure")
    p_anchor1: float = declare(10e3, "Pa", "Back extremal actuator reference while anchoring (a "
                               "placeholder, as p_central)", source="§pressure-control",
                               plausible="inflating pressure")
    p_anchor2: float = declare(10e3, "Pa", "Front extremal actuator reference while anchoring (a "
                               "placeholder, as p_central)", source="§pressure-control",
                               plausible="inflating pressure")
    p_off: float = declare(0.0, "Pa", "Reference of a deflated actuator",
                           plausible="gauge pressure")

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("t_protrusion", "t_stance"), non_negative=("t_reverse",))
        if self.direction not in (1.0, -1.0):
            raise ValueError(f"direction must be +1 (forward) or -1 (backward) "
                             f"(got {self.direction!r})")
        for name in ("p_central", "p_anchor1", "p_anchor2", "p_off"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"{name} must be a finite pressure (got {getattr(self, name)!r})")


def period(p: GaitParams) -> float:
    """Stride period [s] of the gait `p`: protrusion plus stance time (3 s in §gait)."""
    return p.t_protrusion + p.t_stance


def phase_ends(p: GaitParams) -> tuple[float, float, float]:
    """Times since the start of a stride of the gait `p` at which phases 1, 2 and 3 end [s]."""
    d = p.t_stance / 3
    return d, d + p.t_protrusion, 2 * d + p.t_protrusion


def references(t: float, p: GaitParams) -> tuple[float, float, float, float, float, float]:
    """Pressure references and gait state at time t.

    Parameters
    ----------
    t : float
        Time since the start of the gait [s].
    p : GaitParams
        Gait parameters.

    Returns
    -------
    tuple of float
        (p_ref1, p_ref_c, p_ref2) [Pa] for the back extremal, central and front extremal actuator,
        then phase (1..4), direction (+1 forward, -1 backward) and stride (index of the stride
        since the start, counted from 1).

    Examples
    --------
    >>> references(0.0, GaitParams(p_central=5e3, p_anchor1=2e3, p_anchor2=3e3))
    (2000.0, 0.0, 0.0, 1.0, 1.0, 1.0)
    >>> references(2.0, GaitParams(p_central=5e3, p_anchor1=2e3, p_anchor2=3e3))
    (2000.0, 5000.0, 3000.0, 3.0, 1.0, 1.0)
    """
    return _references(t, pack(p))


def pack(p: GaitParams) -> np.ndarray:
    """The kernel's parameters: `p`'s fields in their declared order (t_protrusion, t_stance,
    direction, t_reverse, p_central, p_anchor1, p_anchor2, p_off)."""
    return np.array(astuple(p), dtype=float)


@jit
def _references(t, p):
    t_protrusion, t_stance, first, t_reverse = p[0], p[1], p[2], p[3]
    p_central, p_anchor1, p_anchor2, off = p[4], p[5], p[6], p[7]
    T = t_protrusion + t_stance  # `period`
    if t_reverse > 0:
        k = math.floor((t + EPS) / t_reverse)  # reversals so far
        t = t - k * t_reverse
        per_segment = math.floor((t_reverse - EPS) / T) + 1  # strides started between reversals
    else:
        k, per_segment = 0, 0
    j = math.floor((t + EPS) / T)  # strides completed since the last reversal
    tau = t - j * T + EPS
    d = t_stance / 3  # `phase_ends`
    phase = 1 + (tau >= d) + (tau >= d + t_protrusion) + (tau >= 2 * d + t_protrusion)
    direction = first * (1.0 if k % 2 == 0 else -1.0)
    central = p_central if phase == 2 or phase == 3 else off
    anchor_first = phase < 4  # the actuator that anchors first holds through phases 1 to 3
    anchor_second = phase >= 3  # the other one anchors from phase 3 on
    if direction > 0:
        back, front = anchor_first, anchor_second
    else:  # mirror image: the front actuator anchors first
        back, front = anchor_second, anchor_first
    p_back = p_anchor1 if back else off
    p_front = p_anchor2 if front else off
    return p_back, central, p_front, float(phase), float(direction), float(k * per_segment + j + 1)


@jit
def evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """Kernel outputs `y` = `references` at time `t` [s] of the gait `p` (`pack`; the state `x`
    and the inputs `u` are empty)."""
    y[0], y[1], y[2], y[3], y[4], y[5] = _references(t, p)



KERNEL = Kernel(evaluate, no_state, inputs=(),
                outputs=("p_ref1", "p_ref_c", "p_ref2", "phase", "stride_direction", "stride"))
