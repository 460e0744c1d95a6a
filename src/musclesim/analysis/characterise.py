"""The crawler's off-line characterisation (§pressure-control): the gait's pressure references.

`scenarios/crawler-characterisation.toml` ramps the central actuator's pressure reference with
both extremal actuators deflated, then the extremal actuators' references. From its results:

- ``p_central``: the measured central pressure at which the elongation (front minus back block
  position) first reaches the target elongation on the rising ramp;
- ``p_anchor1``, ``p_anchor2``: the lowest measured pressure at which each extremal actuator's
  contact is firm (indicator >= `FIRM`), the study's "minimum pressure for firm ground contact",
  raised by `ANCHOR_MARGIN`: a slow ramp finds the contact threshold itself, which a tracked
  pressure with its PWM ripple crosses back and forth, building contact at half speed.
"""
from __future__ import annotations

from pathlib import Path
from typing import Protocol

import numpy as np

from musclesim.cosim import Signal
from musclesim.errors import UserError

# m: assumption, about half the central actuator's 83 mm length (§crawler-hardware); the study names
# no elongation, only that the references came from the pressure-elongation curve (§gait)
ELONGATION_TARGET = 0.04
FIRM = 0.99  # contact indicator counted as firm ground contact
# assumption: the study set its anchoring references by eye (§gait); a quarter above the
# lowest firm-contact pressure keeps the contact firm through the loop's ripple and overshoot
ANCHOR_MARGIN = 0.25
CENTRAL_RAMP_END = 20.0  # s, end of the central ramp in the characterisation scenario


class Recorded(Protocol):
    """What `references` reads of a run's results (`musclesim.cosim.Master`'s): the time and a
    recorded signal's values."""

    time: np.ndarray

    def __getitem__(self, signal: Signal, /) -> np.ndarray: ...


def references(res: Recorded, elongation_target: float = ELONGATION_TARGET) -> dict[str, float]:
    """Gait references from the characterisation's results `res` (of a `musclesim.cosim.Master`
    run), the central pressure where the elongation reaches `elongation_target` [m].

    Returns ``{"p_central", "p_anchor1", "p_anchor2"}`` in Pa, plus the firm-contact pressures
    ``p_firm1``, ``p_firm2`` [Pa] and the elongation reached at the end of the central ramp [m];
    raises UserError naming what the run did not reach.
    """
    rising = res.time <= CENTRAL_RAMP_END
    elongation = (res[Signal("body", "flange_b.s")] - res[Signal("body", "flange_a.s")])[rising]
    p = res[Signal("sensorc", "p_meas")][rising]
    reached = np.flatnonzero(elongation >= elongation_target)
    if not len(reached):
        raise UserError(f"the central actuator reaches only {elongation.max():.4g} m of the "
                        f"{elongation_target:g} m elongation target by t = {CENTRAL_RAMP_END:g} s")
    k = reached[0]
    # interpolate the pressure between the samples around the crossing
    w = (elongation_target - elongation[k - 1]) / (elongation[k] - elongation[k - 1]) if k else 0.0
    out = {"p_central": float(p[k - 1] + w * (p[k] - p[k - 1])) if k else float(p[0])}
    for i in (1, 2):
        firm = np.flatnonzero(res[Signal(f"act{i}", "u")] >= FIRM)
        if not len(firm):
            raise UserError(f"extremal actuator act{i} never reaches firm contact "
                            f"(indicator >= {FIRM}) in the characterisation")
        out[f"p_firm{i}"] = float(res[Signal(f"sensor{i}", "p_meas")][firm[0]])
        out[f"p_anchor{i}"] = (1.0 + ANCHOR_MARGIN) * out[f"p_firm{i}"]
    out["elongation_at_ramp_end"] = float(elongation[-1])
    return out


def references_toml(refs: dict[str, float], scenario_path: str | Path) -> str:
    """The GaitSequencer parameters of `refs` (`references`'), as the TOML the gait scenarios
    read, saying it came from `scenario_path`."""
    return "\n".join([
        "# Pressure references of the four-phase gait (§gait), written by",
        f"# `musclesim characterise` from {scenario_path}: do not edit, rerun it.",
        f"p_central = {refs['p_central']!r}  # Pa: elongation {ELONGATION_TARGET:g} m on the "
        "pressure-elongation curve",
        f"p_anchor1 = {refs['p_anchor1']!r}  # Pa: firm ground contact of the back actuator "
        f"from {refs['p_firm1']:.1f} Pa, + {ANCHOR_MARGIN:.0%}",
        f"p_anchor2 = {refs['p_anchor2']!r}  # Pa: firm ground contact of the front actuator "
        f"from {refs['p_firm2']:.1f} Pa, + {ANCHOR_MARGIN:.0%}", ""])
