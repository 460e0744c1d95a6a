"""Section 4 of the diagnosis, which cause: the candidate effects fitted with the calibration,
described, weighed by evidence, and the verdict (`which_effect`, giving a `Which`).

Every candidate effect of the suspects is fitted together with the fit unit's calibration
parameters (`musclesim.diagnosis.fitting`), each fit described against calibration alone
(`musclesim.diagnosis.scoring.rank`), and the candidates weighed by their evidence
(`musclesim.diagnosis.weigh`): probabilities, the credible set, symmetries, the verdict.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from musclesim.cosim import ParamRef
from musclesim.diagnosis.fitting import FitJob, FitResult, fit_all, known_columns, values_of
from musclesim.diagnosis.problem import Problem, Unit
from musclesim.diagnosis.sections import (EvidenceSection, FitUnitSection, VerdictSection)
from musclesim.diagnosis.candidates import Candidate, candidates, refine
from musclesim.diagnosis.consistency import cross_signal
from musclesim.diagnosis.judging import explained
from musclesim.diagnosis.scoring import rank
from musclesim.diagnosis.stages import Calibration, FitUnit
from musclesim.diagnosis.stats import HELD_OUT, TRAIN, gap, noise_floor, part_segments
from musclesim.diagnosis.weigh import (CALIBRATION_ONLY, Weighed, profile_jobs, symmetries,
                                       weigh, with_symmetries)
from musclesim.diagnosis.weigh import section as weigh_section

__all__ = ["Which", "which_effect"]


@dataclass(frozen=True)
class Which:
    """What section 4 found: the `values` of the candidate named (or, undecided, the most
    probable) {ParamRef: value}, calibration refitted with it (empty: calibration
    alone), the `evidence` section and the `verdict`."""

    values: dict[ParamRef, float]
    evidence: EvidenceSection
    verdict: VerdictSection


def which_effect(problem: Problem, fitting: FitUnit, masks: dict[str, list[np.ndarray]],
                 pmap: Callable[..., list], say: Callable[[str], None]) -> Which:
    """Section 4 for `problem`: every candidate effect of the suspects of `fitting` fitted in
    its unit together with its calibration parameters (from their calibrated values), then
    weighed by evidence against calibration alone (`weigh`): probabilities, the credible set,
    symmetries; the pair of the two most probable effects when the most probable single leaves
    a structured gap. Each effect's fit is also scored descriptively against calibration on the
    signals it can change (``effects``, regime masks `masks`). The fits run on `pmap`; `say` is
    told what runs."""
    unit, cal = fitting.unit, fitting.calibration
    fmu_dir = problem.fmu_dir
    calib, jac = cal.free, cal.jac
    x_cal = [cal.values[fr.refs[0]] for fr in calib]
    base = {"residuals": cal.residuals, "heldout_gap": gap(unit, cal.residuals, HELD_OUT)}
    cands = candidates(problem, unit, fitting.suspects)
    say(f"fitting {len(cands)} candidate effect(s), each with {len(calib)} calibration "
        "parameter(s)")
    jobs = [FitJob(unit, c.free + calib, fmu_dir, x0=[fr.start for fr in c.free] + x_cal,
                   scan=len(c.free), known=known_columns(jac, len(c.free)), latency=cal.latency)
            for c in cands]
    fits = refine(unit, cands, fit_all(jobs, pmap), calib, cal.latency, fmu_dir, pmap)
    floor = noise_floor(unit)
    scored = rank(unit, [base] * len(cands), cands, fits, masks, calib)
    calibration_only = Weighed(CALIBRATION_ONLY, cal.fit or _unfitted(unit, cal), calib, 0)
    single: dict[Weighed, Candidate] = {
        Weighed(c.label, f, c.free + calib, len(c.free)): c for c, f in zip(cands, fits)
        if f.applicable and f.residuals is not None}
    singles = list(single)
    weighed, disc = weigh(unit, calibration_only, singles)
    effects = [w for w in weighed if w.k]
    top = weighed[0]
    if top.k and len(effects) > 1 and not explained(top.fit.heldout_gap, cal.nominal_gap,
                                                    floor):
        say("a pair: the two most probable effects together")
        pair = _pair(fitting, (effects[0], effects[1]), single, fmu_dir, pmap)
        if pair is not None:
            weighed, disc = weigh(unit, calibration_only, singles, [pair], disc)
    profiles = profile_jobs(unit, singles, calibration_only, disc, fmu_dir)
    say(f"symmetries: {len(profiles)} profile fit(s), each effect moved and the calibration "
        "fitted again")
    fitted = fit_all([job for _, _, job in profiles], pmap)
    symmetric = symmetries(weighed, [(w, length, f) for (w, length, _), f
                                     in zip(profiles, fitted)], disc, problem)
    weighed = with_symmetries(weighed, symmetric)
    judgement = weigh_section(unit, weighed, symmetric, disc, cal.nominal_gap, floor, explained)
    chosen = judgement.chosen
    entries = [t.entry for t in scored]
    selected = [t.entry for t in scored if t.candidate is single.get(chosen)]
    evidence = EvidenceSection(
        FitUnitSection(list(unit.instances), list(unit.observed), cal.latency), entries,
        judgement.evidence, cross_signal(unit, entries, selected))
    verdict = VerdictSection(
        judgement.verdict, judgement.explanation, judgement.complete, floor,
        [chosen.name] if chosen.k and judgement.verdict == chosen.name else [],
        [s["candidates"][0] for s in symmetric])
    return Which(values_of(chosen.free, chosen.fit.x) if chosen.k else {}, evidence, verdict)


def _pair(fitting: FitUnit, best: tuple[Weighed, Weighed], single: dict[Weighed, Candidate],
          fmu_dir: Any, pmap: Callable[..., list]) -> Weighed | None:
    """The two most probable effects `best` (their candidates in `single`) fitted together in
    `fitting`'s unit with its calibration, the second's parameters scanned from their off values
    and the rest from the first's fit; None when its run fails."""
    unit, cal = fitting.unit, fitting.calibration
    w1, w2 = best
    c1, c2 = single[w1], single[w2]
    pair_fit, = fit_all([FitJob(
        unit, c2.free + c1.free + cal.free, fmu_dir, x0=[f.start for f in c2.free] + w1.fit.x,
        scan=len(c2.free), known=known_columns(cal.jac, len(c2.free) + len(c1.free)),
        latency=cal.latency)], pmap)
    if pair_fit.residuals is None:
        return None
    return Weighed(f"{w1.name} + {w2.name}", pair_fit, c2.free + c1.free + cal.free,
                   len(c2.free) + len(c1.free))


def _unfitted(unit: Unit, cal: Calibration) -> FitResult:
    """A `FitResult` of the nominal values of `unit` where nothing was calibrated (`cal`)."""
    res = cal.residuals
    return FitResult([], [], res, gap(unit, res, TRAIN), gap(unit, res, HELD_OUT), True, 0, None,
                     cal.latency, np.zeros(0), part_segments(unit, res, TRAIN))
