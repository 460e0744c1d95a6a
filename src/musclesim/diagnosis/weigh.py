"""Weighing the candidate causes by evidence: the report's ``evidence`` section and the verdict.

The candidates are the fit unit's calibration alone (``calibration only``), every effect of the
located components fitted together with the calibration parameters, and, when the most
probable single effect leaves a structured gap, the pair of the two most probable effects. Each
gets its evidence under its autoregressive discrepancy (`musclesim.diagnosis.evidence`), a
posterior probability from the documented priors, a held-out predictive check, and the held-out
gap per signal. The credible set holds CREDIBLE of the probability; an effect whose change the
calibration parameters reproduce on these data is listed in ``symmetries`` with what would
break the symmetry. The verdict names the most probable candidate when its probability reaches
NAME_LEVEL (``recalibration`` for calibration only), else the credible set (``A or B``);
``unexplained`` when no candidate passes the predictive check.
"""
import math
from dataclasses import dataclass

import numpy as np

from musclesim.diagnosis import evidence as ev
from musclesim.diagnosis.stats import HELD_OUT, gap, part_segments
from musclesim.diagnosis.thresholds import NAME_LEVEL, PREDICTIVE_MAX, SYMMETRY_CHI2

CALIBRATION_ONLY = "calibration only"


@dataclass(eq=False)
class Weighed:
    """One candidate as weighed: its name, its fit (a `FitResult`), its free parameters (the
    effect's first, `k` of them, then the calibration's), and what the weighing found."""

    name: str
    fit: object
    free: list
    k: int
    evidence: object = None
    probability: float = 0.0
    predictive: float = None  # RMS of the standardised held-out innovations


def discrepancies(unit, calibration):
    """{signal: `Discrepancy`} estimated on the calibrated model's training residuals, sigma at
    least the signal's noise."""
    return {c: ev.Discrepancy.fit(segs, floor=unit.noise[c])
            for c, segs in calibration.fit.train.items()}


def _predictive(unit, w, disc):
    """RMS of the candidate's standardised AR innovations on the held-out part."""
    if w.fit.residuals is None:
        return math.inf
    held = part_segments(unit, w.fit.residuals, HELD_OUT)
    z = np.concatenate([disc[c].innovations(segs) for c, segs in held.items() if c in disc])
    return float(np.sqrt(np.mean(z * z))) if z.size else 0.0


def weigh(unit, calibration, singles, pairs=(), disc=None):
    """Weigh the candidates: `calibration` and every one of `singles` and `pairs`, `Weighed`
    with their fits, under one discrepancy model (`disc`, estimated on the calibration's
    residuals unless given). Returns (the weighed candidates in order of probability, the
    discrepancies). Candidates whose fit failed are left out."""
    disc = disc or discrepancies(unit, calibration)
    ones = [w for w in [calibration, *singles] if w.fit.train is not None]
    twos = [w for w in pairs if w.fit.train is not None]
    for w in ones + twos:
        w.evidence = ev.evidence(w.fit.train, w.fit.jac if w.free else None,
                                 w.fit.z if w.free else [], disc)
        w.predictive = _predictive(unit, w, disc)
    probs = ev.posterior([w.evidence.log_evidence for w in ones + twos],
                         ev.prior([w.name for w in ones], [w.name for w in twos]))
    for w, p in zip(ones + twos, probs):
        w.probability = float(p)
    return sorted(ones + twos, key=lambda w: -w.probability), disc


def symmetries(weighed, problem):
    """The effects the calibration parameters reproduce on these data: the part of an effect's
    change at half its box that no change of the calibration parameters makes, in the
    discrepancy's metric, below SYMMETRY_CHI2 in its most distinguishable direction:
    [{"candidates", "chi2", "with", "breaks_with"}], a condition the data set can state first."""
    out = []
    for w in weighed:
        if not w.k or w.fit.jac is None or w.name == CALIBRATION_ONLY:
            continue
        chi2, carried = ev.symmetry(w.evidence.information, w.k)
        if chi2 >= SYMMETRY_CHI2:
            continue
        calib = w.free[w.k:]
        order = np.argsort(-carried)[:2] if len(carried) else []
        partners = [calib[i] for i in order if carried[i] > 0]
        out.append({"candidates": [w.name, CALIBRATION_ONLY], "chi2": chi2,
                    "with": [f"{','.join(f.instances)}.{f.name}" for f in partners],
                    "breaks_with": sorted((_breaks(problem, f) for f in partners),
                                          key=lambda b: not b.startswith("state "))
                    or ["an experiment in which the effect acts and the calibration cannot"]})
    return out


def _breaks(problem, free):
    """What separates an effect from calibration parameter `free`: stating it, when the data
    set can (an input nothing in the scenario feeds, such as a room's temperature), else
    measuring it apart or an experiment that moves it alone."""
    inst = free.instances[0]
    var = problem.vars.get(inst, {}).get(free.name)
    name = f"{inst}.{free.name}"
    if var is not None and var.causality == "input":
        return f"state {name} in the data set's [conditions] (measure it on the bench)"
    return (f"measure {name} apart, or record an experiment in which it acts differently "
            "from the effect")


def section(unit, weighed, symmetric, disc, nominal_gap, floor, explained):
    """The report's ``evidence`` section and the verdict: (section, verdict, explanation,
    complete, the candidate named or most probable)."""
    names = [w.name for w in weighed]
    probs = [w.probability for w in weighed]
    credible = ev.credible_set(names, probs)
    top = weighed[0]
    rows = []
    for w in weighed:
        rows.append({
            "name": w.name, "probability": w.probability,
            "log_evidence": w.evidence.log_evidence,
            "log_likelihood": w.evidence.log_likelihood, "occam": w.evidence.occam,
            "predictive": w.predictive,
            "parameters": {f"{','.join(f.instances)}.{f.name}": {
                "value": x, "interval": list(iv), "lower": f.lower, "upper": f.upper}
                for f, x, iv in zip(w.free, w.fit.x, w.fit.interval)},
            "heldout_gap": {c: gap(unit, w.fit.residuals, HELD_OUT, [c]) for c in unit.observed}
            if w.fit.residuals is not None else {},
            "heldout_gap_all": w.fit.heldout_gap,
            "excluded": None if w.name in credible else
            f"log Bayes factor {w.evidence.log_evidence - top.evidence.log_evidence:.1f} "
            f"against {top.name}"})
    discrepancy = {c: {"order": len(d.phi), "phi": [float(v) for v in d.phi], "sigma": d.sigma}
                   for c, d in disc.items()}
    passing = [w for w in weighed if w.predictive <= PREDICTIVE_MAX]
    named = top if top.probability >= NAME_LEVEL else None
    if not passing:
        verdict = "unexplained"
        text = (f"no candidate, calibration included, describes the held-out data (the best "
                f"predictive check {min(w.predictive for w in weighed):.2g} against "
                f"{PREDICTIVE_MAX:g}): a difference the library does not hold")
    elif named is not None:
        verdict = "recalibration" if named.name == CALIBRATION_ONLY else named.name
        text = (f"{named.name} with probability {named.probability:.2f}"
                + (f"; the others together {1 - named.probability:.2f}"
                   if len(weighed) > 1 else ""))
    else:
        verdict = " or ".join(credible)
        text = ("these data cannot tell apart " + ", ".join(
            f"{w.name} ({w.probability:.2f})" for w in weighed if w.name in credible))
    if symmetric:
        text += "; " + "; ".join(
            f"{s['candidates'][0]} is a recalibration of {', '.join(s['with']) or 'nothing'} on "
            f"these data: {s['breaks_with'][0]}" for s in symmetric)
    chosen = named or top
    complete = explained(chosen.fit.heldout_gap, nominal_gap, floor)
    out = {"candidates": rows, "set": credible, "symmetries": symmetric,
           "discrepancy": discrepancy, "level": NAME_LEVEL}
    return out, verdict, text, complete, chosen
