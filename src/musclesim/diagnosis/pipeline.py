"""`musclesim diagnose`: where a model misses its bench, which unmodelled effect causes it, and how
far the gap shrinks once that effect is added, judged on held-out data (§diagnosis).

The steps, on a measured data set (`musclesim.diagnosis.dataset`), each printed as it starts:

1. Gap. The scenario runs with the data set's inputs replayed (`Master` ``inputs``) and every
   observed signal is compared: NRMSE by the measured range, bias (measured - model), lag (the
   shift of the model that best matches the data); scalar metrics by relative error. A sensor
   channel nothing in the model reads is compared allowing an acquisition latency of up to
   `MAX_ALIGN` samples, chosen on the training part in every comparison (`residuals`). Nothing
   deviating beyond the noise anywhere: verdict ``none``.
2. Calibration. A real bench differs from the model in nominal values no effect library lists
   (its ambient, h, material data, the hysteresis's temperature shift and strain scale, ...):
   every calibration parameter its components declare (`effects.CALIBRATION`; a value the data
   set states in ``[conditions]`` stays fixed) is fitted on the training part, from the nominal
   values (a periodic one, the PWM carrier's phase, from the best of a scan over its period);
   the report gives them with 95 % intervals and the gap before and after.
3. Where. Each component is re-simulated, calibrated, in its *isolation unit*: the component
   plus the upstream instances whose outputs were not measured, with every measured signal
   feeding the unit replayed. A unit deviates when the held-out gap of one of its signals
   exceeds `DEVIATES` times that signal's noise (estimated from the data's second differences,
   at least `NOISE_FLOOR` of the range; for a metric its uncertainty, else `METRIC_FLOOR`).
   Components of deviating units are located unless a unit that did not deviate isolates them.
   The calibrated residual is also split by regime and the worst windows are listed.
4. Which cause, by evidence. Every effect of a located component is fitted on the training part
   together with the fit unit's calibration parameters (from their calibrated values; a scan of
   the effect's box first). The candidates (calibration alone, each effect, and the pair of the
   two most probable effects when the most probable leaves a structured gap) are weighed by
   their evidence under a model of the mismatch calibration leaves (`weigh`, `evidence`):
   posterior probabilities, the credible set, the symmetries calibration makes with an effect
   and what would break them, a held-out predictive check each. Each effect's fit is also
   described against calibration on the signals it can change (`judging.judge`). Signals that
   share an upstream state place the gap in a sensor or in the plant (`consistency.cross_signal`).
5. How far it shrinks: held-out gap per signal nominal, calibrated and with the named (or most
   probable) effect (calibration refitted with it), with block-bootstrap intervals, in the model
   with every measured signal replayed (`Problem.replayed`).

Verdict (`weigh.section`): ``none`` when no signal deviates beyond the noise; ``recalibration``
when calibration alone leaves every signal within the noise, or is the candidate named; the
candidate whose probability reaches `NAME_LEVEL`, else the credible set (``A or B``);
``unexplained`` when no candidate passes the predictive check. ``complete`` is false when the
gap the named candidate leaves is structured (more than `STRUCTURED` noise floors and
`RESIDUAL_SHARE` of the nominal gap): a further difference outside the library.

The fits run on the ``pmap`` `diagnose` is given (`fitting.fit_all`): on Dask's (the CLI's, the
same local cluster or scheduler as sweeps) every simulation of every fit is a task, the fits
steered side by side from threads of this process; on any other map each fit is one task. A map
that can (``pmap.ship_fmus``, Dask's) gets the FMUs the data set's scenarios use as bytes, once
per worker, and the tasks name the workers' copies: the workers need none of this machine's files
(the units and their data travel as objects).

This module runs the stages, each returning its frozen section of the `Report`
(`musclesim.diagnosis.sections`); the work is in the package's other modules: the thresholds
named above in `musclesim.diagnosis.thresholds`, the units in `.problem`, simulation and residuals
in `.simulate`, statistics in `.stats`, regimes in `.regimes`, fits in `.fitting`, the
calibration parameters in `.parameters`, candidates in `.candidates`, their descriptions in
`.judging`, `.aliasing`, `.scoring` and `.consistency`, section 4 in `.which`, the evidence in `.evidence` and the
weighing and verdict in `.weigh`.
"""
from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any, Callable

from threadpoolctl import threadpool_limits

from musclesim.batch import serial_map
from musclesim.cosim import Signal, reuse_fmus
from musclesim.diagnosis.confidence import load as load_calibration
from musclesim.diagnosis.fitting import FitJob, fit_all, simulation_task, values_of
from musclesim.diagnosis.problem import Problem, Unit, affected
from musclesim.diagnosis.regimes import regime_table, regimes
from musclesim.diagnosis.sections import (CalibrationSection, GapSection, IsolationSection,
                                          Report, ShrinkageSection, VerdictSection)
from musclesim.diagnosis.judging import NO_GAP
from musclesim.diagnosis.openvalues import open_values
from musclesim.diagnosis.parameters import calibration, calibration_table, scanned
from musclesim.diagnosis.simulate import residuals, signal_gap, simulate
from musclesim.diagnosis.stages import Calibration, FitUnit, Isolation, Nominal, Residuals
from musclesim.diagnosis.stats import HELD_OUT, before_after, deviates, gap, noise_floor
from musclesim.diagnosis.which import which_effect
from musclesim.errors import UserError


def diagnose(ds: Any, fmu_dir: Any = "fmus", pmap: Callable[..., list] | None = None,
             progress: Callable[[str], None] | None = None,
             traces: dict[str, Any] | None = None) -> Report:
    """Diagnose measured data set `ds` (a `musclesim.diagnosis.DataSet`) with the FMUs in
    `fmu_dir`; return the `Report` (``Report.to_json()`` is report.json's document).

    `pmap` maps the fits, ``pmap(fn, items)`` (default: one after the other); `progress`
    is told what runs, ``progress(text)``; a dict given as `traces` receives the runs of `Problem.replayed`, nominal,
    calibrated and with the selected effects, for plots.
    """
    # BLAS on one thread, as beside a Dask cluster (batch.dask_client): a product's reduction
    # order, hence its last bits, depends on the thread count, and the report must not depend
    # on where the fits ran (measured: serial and Dask reports differed in the 13th digit)
    with reuse_fmus(), threadpool_limits(1, user_api="blas"):
        report = _diagnose(ds, fmu_dir, pmap or serial_map, progress or (lambda text: None),
                           traces)
    return with_confidence(report)


def with_confidence(report: Report) -> Report:
    """`report` with the calibrated set, probabilities and gate of its scenario's shipped
    calibration (`confidence`), unchanged where there is none (a scalar-only or a
    several-scenario data set, a scenario not calibrated)."""
    if not isinstance(report.scenario, str) or report.scalar_only:
        return report
    cal = load_calibration(Path(report.scenario).stem)
    if cal is None:
        return report
    conf = cal.assess(report.to_json())
    level = f"{conf['level'] * 100:.0f} %"
    said = (f"; calibrated on benches of many forms, at {level} the cause is one of: "
            + ", ".join(conf["set"]) if conf["set"] else "")
    if conf["gate"]["outside"]:
        said += " (but this bench is outside the calibrated family: no guarantee)"
    verdict = replace(report.verdict, explanation=report.verdict.explanation + said)
    return replace(report, confidence=conf, verdict=verdict)


def _diagnose(ds, fmu_dir, pmap, say, traces):
    problem = Problem(ds, fmu_dir)
    if hasattr(pmap, "ship_fmus"):  # workers that may not see this folder: what they read
        problem.fmu_dir = pmap.ship_fmus(fmu_dir, {
            i.component for s in problem.scenarios.values() for i in s.instances.values()})
    whole = problem.unit("model")
    say("1/5 the gap: nominal model")
    # calibrated with the loops cut open at the measurements (every measured signal replayed):
    # a closed loop's phase would pull nominal values anywhere to match an oscillation
    cut = problem.replayed()
    sims, units, cut_sims = _nominal_runs(problem, whole, cut, pmap)
    gap_section = _gap_section(problem, whole, sims)
    head = _head(problem)
    if not gap_section.deviates and not any(u.deviates for u in units):
        verdict = VerdictSection("none", NO_GAP, True, gap_section.noise_floor, [], [])
        return Report(**head, gap=gap_section, calibration=CalibrationSection({}),
                      isolation=None, evidence=None, verdict=verdict,
                      shrinkage=_shrinkage(problem, ({}, cut_sims), {}, traces, pmap))
    res_cut = residuals(cut, cut_sims)
    say(f"2/5 calibrating the model and {len(units)} isolation unit(s) on the training part")
    cal, isolated = _calibrate(problem, (cut, res_cut), units, pmap)
    cal_section = _calibration_section(cut, res_cut, cal)
    say("3/5 isolating components (each unit calibrated)")
    suspects, located = _locate(problem, isolated)
    masks = regimes(problem, whole)
    isolation = IsolationSection(located, [i.section() for i in isolated],
                                 regime_table(cut, cal.residuals, masks))
    values: dict = {}
    evidence = None
    if not deviates(cut, cal.residuals) and not any(i.deviates for i in isolated):
        floor = noise_floor(cut)
        verdict = VerdictSection("recalibration", (
            f"calibration alone takes the held-out gap from "
            f"{cal_section.heldout_gap_before:.3g} to {cal_section.heldout_gap_after:.3g}, "
            f"within the noise (floor {floor:.3g}): no unmodelled effect is needed"),
            True, floor, [], [])
    else:
        fitting = _fit_unit(cut, cal, isolated, suspects)
        say("4/5 which effect: candidates fitted with the calibration parameters")
        which = which_effect(problem, fitting, masks, pmap, say)
        values, evidence, verdict = which.values, which.evidence, which.verdict
    say("5/5 how far the gap shrinks")
    return Report(**head, gap=gap_section, calibration=cal_section, isolation=isolation,
                  evidence=evidence, verdict=verdict,
                  shrinkage=_shrinkage(problem, (cal.values, cut_sims), values, traces, pmap))


def _head(problem: Problem) -> dict[str, Any]:
    """The report's head: the data set, its scenario(s), scalar-only, its parts."""
    ds = problem.ds
    return {"data_set": str(ds.path), "scenario": ds.scenario or sorted(
        {e.scenario for e in ds.experiments.values()}), "scalar_only": problem.scalar_only,
        "train": list(problem.part_names[0]), "held_out": list(problem.part_names[1])}


def _gap_section(problem, whole, sims):
    """Section 1: the whole model's gap per signal and pooled."""
    res_whole = residuals(whole, sims)
    return GapSection(signal_gap(problem, whole, sims), gap(whole, res_whole, HELD_OUT),
                      noise_floor(whole), bool(deviates(whole, res_whole)))


def _same(unit, whole):
    """Whether isolation `unit` simulates what `whole` does: the same observed signals from the
    same instances (those of `whole` that act on an observed signal) fed the same replays."""
    if unit.observed != whole.observed:
        return False
    acting = {i for i in whole.instances if affected(whole, (i,))}
    return acting == set(unit.instances) and all(
        {k for k in a.inputs if k.instance in acting} == set(b.inputs)
        for a, b in zip(whole.runs, unit.runs))


def _nominal_runs(problem, whole, cut, pmap):
    """The nominal runs, mapped together: of the whole model (its failure, with its message,
    is the user's error), every isolation unit (a `Nominal` each, one whose simulation fails
    left out) and the model with every measured signal replayed `cut` (the whole model's again
    for scalar metrics)."""
    units = problem.isolation_units()
    extra = [] if problem.scalar_only else [cut]
    runs = pmap(simulation_task, [(u, {}, problem.fmu_dir, None) for u in [whole, *extra, *units]])
    if runs[0].failed:
        raise UserError(f"data set {problem.ds.path}: the nominal scenario fails: "
                        f"{runs[0].error}")
    nominal = []
    for u, r in zip(units, runs[1 + len(extra):]):
        if not r.failed:
            res = residuals(u, r.runs)
            nominal.append(Nominal(u, res, deviates(u, res)))
    return runs[0].runs, nominal, runs[1].runs if extra else runs[0].runs


def _calibrate(problem, cut, units, pmap):
    """Section 2: the calibration parameters of the model with every measured signal replayed
    (`cut`: that unit and its nominal residuals; the data set's open values where it declares
    them) and, separately, of every isolation unit
    (`Nominal` each) fitted on the training part from the nominal values (one mapped task
    each): a unit is judged on its own calibration, so that calibrating the whole model around
    a sensor's fault cannot make the plant's unit deviate. Return the model's `Calibration`
    and an `Isolation` per unit."""
    cut, res_cut = cut
    # the open values a data set declares ([[calibrate]]) are its model's calibration, as
    # `musclesim calibrate` fits them (and so of a unit that is the model again); any other
    # isolation unit takes its components' own
    declared = open_values(problem) if problem.ds.calibrate else None
    jobs = [(u, declared if declared is not None and (u is cut or _same(u, cut))
             else calibration(problem, u)) for u in [cut] + [n.unit for n in units]]
    # a unit that is the whole model again (the same instances, signals and replays) is
    # calibrated once
    same = [i for i, (u, _) in enumerate(jobs) if i and _same(u, cut)]
    fits = iter(fit_all([FitJob(u, free, problem.fmu_dir, scan=scanned(free))
                         for i, (u, free) in enumerate(jobs) if free and i not in same], pmap))
    cals: list[Calibration] = []
    for i, ((u, free), nominal) in enumerate(zip(jobs, [res_cut] + [n.residuals for n in units])):
        f = cals[0].fit if i in same else next(fits) if free else None
        nominal_gap = gap(u, nominal, HELD_OUT)
        if f is None or f.residuals is None:
            latency: dict[Signal, int] = {}
            residuals(u, simulate(u, {}, problem.fmu_dir), latency)
            cals.append(Calibration([], {}, nominal, None, {}, None, latency, nominal_gap))
        else:
            cals.append(Calibration(free, values_of(free, f.x), f.residuals, f.jac,
                                    calibration_table(free, f, u.components), f, f.latency,
                                    nominal_gap))
    isolated = [Isolation(n.unit, c, gap(n.unit, c.residuals, HELD_OUT), noise_floor(n.unit),
                          deviates(n.unit, c.residuals), c.nominal_gap)
                for n, c in zip(units, cals[1:])]
    return cals[0], isolated


def _calibration_section(cut: Unit, res_cut: Residuals, cal: Calibration) -> CalibrationSection:
    """Section 2: the calibrated values, the sensors' latencies, and the held-out gap before and
    after, pooled and per signal, of the model with every measured signal replayed (`cut`, its
    nominal residuals `res_cut`, its calibration `cal`)."""
    return CalibrationSection(
        cal.table, cal.latency, gap(cut, res_cut, HELD_OUT), gap(cut, cal.residuals, HELD_OUT),
        {c: before_after(cut, res_cut, cal.residuals, [c]) for c in cut.observed})


def _locate(problem, isolated):
    """Section 3: the suspect instances and the ranked ``located`` table from the isolation
    results.

    A unit that matches clears only its subjects (the instances it isolates): its other members
    may act on what it observes too weakly to show (the magnet's force on the temperature).
    """
    deviating = [u for u in isolated if u.deviates]
    cleared = set().union(*[set(u.unit.subjects) for u in isolated if not u.deviates])
    suspects = set().union(*[set(u.unit.instances) for u in deviating]) - cleared
    if deviating and not suspects:  # every member cleared alone: blame the interaction
        suspects = set(deviating[0].unit.instances)
    table = []
    for inst in problem.components:
        own = [u for u in isolated if inst in u.unit.subjects] or \
            [u for u in isolated if inst in u.unit.instances]
        if not own:
            continue
        u = own[0]  # its own unit, else the smallest holding it
        table.append({"instance": inst, "component": problem.components[inst],
                      "isolated_gap": u.gap, "noise_floor": u.floor, "unit": u.unit.name,
                      "deviates": u.deviates, "exonerated": inst in cleared,
                      "located": inst in suspects})
    table.sort(key=lambda r: (not r["located"], -r["isolated_gap"]))
    return suspects, table


def _fit_unit(whole: Unit, cal: Calibration, isolated: list[Isolation],
              suspects: set[str]) -> FitUnit:
    """The unit the candidates are fitted in: the smallest deviating isolation unit holding
    every suspect, else the model with every measured signal replayed (`whole`, calibrated as
    `cal`; whose every instance is a suspect when none was located), among `isolated`."""
    if not suspects:
        return FitUnit(whole, cal, frozenset(whole.instances))
    holders = [u for u in isolated if u.deviates and suspects <= set(u.unit.instances)]
    if holders:
        return FitUnit(holders[0].unit, holders[0].calibration, frozenset(suspects))
    return FitUnit(whole, cal, frozenset(suspects))


def _shrinkage(problem, calibrated, values, traces, pmap):
    """Section 5: the held-out gap per signal of the model with every measured signal replayed
    (`Problem.replayed`), nominal (``before``), calibrated and with the selected effects'
    `values` (``after``, calibration refitted with them), and the latencies found there
    (``aligned_samples``); the traces for the plots. `calibrated`: (the calibrated values, the
    nominal runs of that model). A failed run stands for the calibrated (else nominal) one."""
    unit = problem.replayed()
    calibrated, nominal = calibrated
    wanted = [v for v in (calibrated, {**calibrated, **values}) if v]
    wanted = [v for i, v in enumerate(wanted) if v not in wanted[:i]]
    got = pmap(simulation_task, [(unit, v, problem.fmu_dir, None) for v in wanted])
    runs = {"calibrated": nominal}
    for key, v in (("calibrated", calibrated), ("after", {**calibrated, **values})):
        run = got[wanted.index(v)] if v else None
        runs[key] = runs["calibrated"] if run is None or run.failed else run.runs
    shifts: dict[Signal, int] = {}
    before_res, cal_res = residuals(unit, nominal), residuals(unit, runs["calibrated"])
    after_res = residuals(unit, runs["after"], shifts)
    shrinkage = {c: {**before_after(unit, before_res, after_res, [c]),
                     "calibrated": gap(unit, cal_res, HELD_OUT, [c])} for c in unit.observed}
    shrinkage["all"] = {**before_after(unit, before_res, after_res),
                        "calibrated": gap(unit, cal_res, HELD_OUT)}
    if traces is not None:
        traces.update(unit=unit, nominal=nominal, calibrated=runs["calibrated"],
                      selected=runs["after"])
    return ShrinkageSection(shrinkage, shifts)
