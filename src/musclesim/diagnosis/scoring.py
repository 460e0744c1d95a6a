"""Each candidate's fit described for the report (``effects``): its values, the pooled and
per-signal held-out gaps, the judgement on the signals it can change and the aliasing by the
calibration (`score`), and the candidates ranked (`rank`, a `Scored` each)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from musclesim.diagnosis.aliasing import aliasing_in
from musclesim.diagnosis.candidates import Candidate
from musclesim.diagnosis.fitting import FitResult
from musclesim.diagnosis.judging import judge
from musclesim.diagnosis.parameters import unit_of
from musclesim.diagnosis.problem import affected
from musclesim.diagnosis.stats import before_after

__all__ = ["score", "Scored", "rank"]


def score(unit, base, cand, f, masks, calib=()):
    """The report's entry of candidate `cand` fitted with the calibration parameters as `f` (a
    `fit` result, the effect's parameters first) in `unit`, against its `baseline` `base`:
    its values (with their units), the pooled held-out gaps, the per-signal before/after and the
    judgement on the signals it can change (`judge`), ``counts``; ``baseline`` says which it
    was."""
    k = len(cand.free)
    res = f.residuals
    entry = {"name": cand.effect.name, "label": cand.label, "component": cand.effect.component,
             "instances": list(cand.instances), "reference": cand.effect.reference,
             "parameters": {fr.name: {"value": x, "interval": list(iv), "lower": fr.lower,
                                      "upper": fr.upper, "off": fr.start,
                                      "unit": unit_of(cand.effect.component, fr.name)}
                            for fr, x, iv in zip(cand.free, f.x[:k], f.interval[:k])},
             "calibration": {fr.key: x
                             for fr, x in zip(calib, f.x[k:])},
             "applicable": f.applicable, "heldout_gap_before": base["heldout_gap"],
             "baseline": "its own fit with the effect off" if base.get("effect_off")
             else "calibration",
             "heldout_gap_after": f.heldout_gap, "aliasing": aliasing_in(f, k, calib)}
    entry["shrinkage"] = 1 - entry["heldout_gap_after"] / entry["heldout_gap_before"] \
        if entry["heldout_gap_before"] else 0.0
    if res is None:
        entry.update(judged=None, per_signal={}, interval=[0.0, 0.0], counts=False,
                     signature={"regime": cand.effect.regime, "gain_ratio": None,
                                "consistent": False})
        return entry
    j = judge(unit, base["residuals"], res, affected(unit, cand.instances), cand.effect.regime,
              masks)
    entry.update(judged=j, interval=j["interval"], signature=j["signature"],
                 per_signal={c: before_after(unit, base["residuals"], res, [c])
                             for c in unit.observed},
                 counts=bool(f.applicable and j["counts"]))
    return entry


@dataclass(frozen=True)
class Scored:
    """A candidate's report `entry` (`score`) with the `candidate` and its `fit`."""

    entry: dict[str, Any]
    candidate: Candidate
    fit: FitResult


def rank(unit, bases, cands, fits, masks, calib=()):
    """Score and rank the candidates `cands` fitted as `fits` in `unit`, each against its
    baseline in `bases` (counting ones first, then by pooled held-out gap after), each entry's
    ``margin`` to the next, with the regime `masks` and the calibration parameters `calib`
    (`score`): a `Scored` each, ranked."""
    scored = sorted((Scored(score(unit, b, c, f, masks, calib), c, f)
                     for b, c, f in zip(bases, cands, fits)),
                    key=lambda t: (not t.entry["counts"], t.entry["heldout_gap_after"]))
    entries = [t.entry for t in scored]
    for a, b in zip(entries, entries[1:] + [None]):
        a["margin"] = None if b is None else (b["heldout_gap_after"] - a["heldout_gap_after"]) \
            / a["heldout_gap_before"]
    return scored
