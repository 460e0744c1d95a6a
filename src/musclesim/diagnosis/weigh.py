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
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from musclesim.diagnosis import evidence as ev
from musclesim.diagnosis.fitting import FitJob, FitResult, Free, values_of
from musclesim.diagnosis.parameters import unit_of
from musclesim.diagnosis.stats import HELD_OUT, gap, part_segments
from musclesim.diagnosis.thresholds import (NAME_LEVEL, PREDICTIVE_MAX, PROFILE_SCALE,
                                           SYMMETRY_CHI2)

CALIBRATION_ONLY = "calibration only"


@dataclass(eq=False)
class Weighed:
    """One candidate as weighed: its name, its fit (a `FitResult`), its free parameters (the
    effect's first, `k` of them, then the calibration's), and what the weighing found."""

    name: str
    fit: FitResult
    free: list[Free]
    k: int
    evidence: ev.Evidence | None = None
    probability: float = 0.0
    predictive: float | None = None  # RMS of the standardised held-out innovations
    prior: float = 0.0


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
    priors = ev.prior([w.name for w in ones], [w.name for w in twos])
    for w, p in zip(ones + twos, priors):
        w.prior = float(p)
    return _posterior(ones + twos), disc


def _posterior(weighed):
    """`weighed` with their posterior probabilities, most probable first."""
    probs = ev.posterior([w.evidence.log_evidence for w in weighed], [w.prior for w in weighed])
    for w, p in zip(weighed, probs):
        w.probability = float(p)
    return sorted(weighed, key=lambda w: -w.probability)


def with_symmetries(weighed, symmetric):
    """`weighed` weighed again with every effect in `symmetric` given calibration only's
    evidence: along a symmetry the likelihood is the calibration's wherever the effect sits in
    its box, so the effect's direction integrates to 1 (it costs and gains nothing), which
    Laplace's Gaussian, built on differences a model with kinks does not add up, misses. Its
    probability is then its prior share of calibration only's."""
    names = {s["candidates"][0] for s in symmetric}
    cal = next((w for w in weighed if w.name == CALIBRATION_ONLY), None)
    if not names or cal is None:
        return weighed
    for w in weighed:
        if w.name in names:
            w.evidence = replace(w.evidence, log_evidence=cal.evidence.log_evidence,
                                 occam=cal.evidence.log_evidence - w.evidence.log_likelihood)
    return _posterior(list(weighed))


def profile_jobs(unit, singles, calibration, disc, fmu_dir, scale=PROFILE_SCALE):
    """The profile fits of the symmetry test (`symmetries`) on fit `unit`, two for each effect
    of `singles` (weighed single effects) that does not fit the training part better than
    `calibration` (weighed calibration alone) by SYMMETRY_CHI2 or more under the discrepancy
    `disc` (one that does is told from a recalibration by its own fit): its parameters moved
    `scale` of their box one way and the other from its fit, along the direction the linear
    test (`evidence.symmetry`) finds the data distinguish best, and held there while the
    calibration parameters are fitted again from their values at the effect's fit (its
    Jacobian's columns of them the start's, a quasi-Newton start: every step is still checked
    on the true cost). Each way that the effect's box has room for the whole move, else the
    way with the most room if it is a quarter of the move or more (its chi2 then scaled up to
    the whole move, `symmetries`). Returns
    [(the candidate, the length of its move, the `FitJob`)]."""
    out = []
    reference = _quadratic(calibration.fit.train, disc) if calibration.fit.train else None
    for w in singles:
        if not w.k or w.fit.jac is None or w.fit.train is None or (
                reference is not None
                and reference - _quadratic(w.fit.train, disc) >= SYMMETRY_CHI2):
            continue
        z0 = np.asarray(w.fit.z[:w.k], float)
        u = ev.symmetry(w.evidence.information, w.k)[1]
        known = {i: w.fit.jac[:, w.k + i] for i in range(len(w.free) - w.k)}
        room = {sign: _room(z0, sign * u, scale) for sign in (1, -1)}
        signs = [s for s in room if room[s] >= scale] or [max(room, key=lambda s: room[s])]
        for sign in signs:
            if room[sign] < scale / 4:  # pinned in a corner: nothing to extrapolate from
                continue
            z = np.clip(z0 + sign * room[sign] * u, 0, 1)
            x = [f.lower + (f.upper - f.lower) * v for f, v in zip(w.free, z)]
            out.append((w, room[sign], FitJob(
                unit, w.free[w.k:], fmu_dir, fixed=values_of(w.free[:w.k], x),
                x0=list(w.fit.x[w.k:]), scan=0, known=known, latency=w.fit.latency,
                train_only=True)))
    return out


def _room(z, step, most):
    """How far, up to `most`, the box [0, 1] lets `z` move along the unit vector `step`."""
    with np.errstate(divide="ignore", invalid="ignore"):
        limits = np.where(step > 0, (1 - z) / step, np.where(step < 0, -z / step, np.inf))
    return float(max(min(most, limits.min()), 0.0))


def symmetries(weighed, profiles, disc, problem, scale=PROFILE_SCALE):
    """The effects the calibration parameters reproduce on these data, by either of two tests.
    The linear one (`evidence.symmetry`, at half the effect's box) reads the Fisher information;
    a hysteresis's responses to a shift of the temperature and of its transformation
    temperatures each have kinks (reversals), so differences taken one parameter at a time can
    fail to add up to the joint move along a symmetry, and the profile reads the model itself.
    `profiles`: [(the candidate, the length of its move, the `FitResult` of a `profile_jobs`
    fit)]; a profile's chi2 is twice the change of the log likelihood, under the discrepancy
    `disc`, from the effect's fit to the effect moved and the calibration fitted again there,
    either way (a profile that fits better says as much as one that fits worse), scaled to a
    whole move; an effect's is the smaller of its two. Below SYMMETRY_CHI2 no fit to these data
    tells the effect from a recalibration. Returns [{"candidates", "chi2", "test", "with",
    "breaks_with"}]: the calibration parameters that moved most (in the data's metric) and what
    would separate them, a condition the data set can state first."""
    best: dict[str, tuple[float, FitResult]] = {}
    for w, length, prof in profiles:
        if prof.train is not None:
            chi2 = abs(_quadratic(prof.train, disc) - _quadratic(w.fit.train, disc)) * (
                scale / length) ** 2
            if w.name not in best or chi2 < best[w.name][0]:
                best[w.name] = (chi2, prof)
    out = []
    for w in weighed:
        if not w.k or w.fit.jac is None or w.name == CALIBRATION_ONLY:
            continue
        chi2, _, carried = ev.symmetry(w.evidence.information, w.k)
        test = "linear"
        if w.name in best and best[w.name][0] < chi2:
            (chi2, prof), test = best[w.name], "profile"
            info = np.sqrt(np.clip(np.diag(w.evidence.information)[w.k:], 0, None))
            carried = np.abs(np.asarray(prof.z) - np.asarray(w.fit.z[w.k:])) * info
        if chi2 >= SYMMETRY_CHI2:
            continue
        calib = w.free[w.k:]
        partners = [calib[i] for i in np.argsort(-carried, kind="stable")[:2] if carried[i] > 0]
        out.append({"candidates": [w.name, CALIBRATION_ONLY], "chi2": chi2, "test": test,
                    "with": [f.key for f in partners],
                    "breaks_with": sorted((_breaks(problem, f) for f in partners),
                                          key=lambda b: not b.startswith("state "))
                    or ["an experiment in which the effect acts and the calibration cannot"]})
    return out


def _quadratic(segments, disc):
    """r'C^-1 r of training residual `segments` ({signal: [array per run]}) under `disc`."""
    return float(sum(disc[c].weighted(segs)[0] for c, segs in segments.items() if c in disc))


def _breaks(problem, free):
    """What separates an effect from calibration parameter `free`: stating it, when the data
    set can (an input nothing in the scenario feeds, such as a room's temperature), else
    measuring it apart or an experiment that moves it alone."""
    ref = free.refs[0]
    var = problem.vars.get(ref.instance, {}).get(ref.name)
    name = str(ref)
    if var is not None and var.causality == "input":
        return f"state {name} in the data set's [conditions] (measure it on the bench)"
    return (f"measure {name} apart, or record an experiment in which it acts differently "
            "from the effect")


@dataclass(frozen=True)
class Judgement:
    """What the weighing concludes: the report's `evidence` section, the `verdict`, its
    `explanation`, whether the gap left is unstructured (`complete`) and the candidate named
    or, undecided, the most probable (`chosen`)."""

    evidence: dict[str, Any]
    verdict: str
    explanation: str
    complete: bool
    chosen: Weighed


def section(unit, weighed, symmetric, disc, nominal_gap, floor, explained):
    """The report's ``evidence`` section and the verdict as a `Judgement`, from the candidates
    `weighed` in fit `unit` (most probable first), the `symmetric` effects (`symmetries`), the
    discrepancies `disc`, the held-out gap of the nominal values `nominal_gap` and the noise
    `floor`; `explained(after, before, floor)` says whether a gap left is unstructured."""
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
            "parameters": {f.key: {
                "value": x, "interval": list(iv), "lower": f.lower, "upper": f.upper,
                "unit": unit_of(unit.components.get(f.instances[0], ""), f.name)}
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
    return Judgement(out, verdict, text, complete, chosen)
