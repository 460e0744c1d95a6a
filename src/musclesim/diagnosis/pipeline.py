"""`musclesim diagnose`: where a model misses its bench, which unmodelled effect causes it, and how
far the gap shrinks once that effect is added, judged on held-out data (DESIGN.md, "Sim-to-real
gap diagnosis").

The steps, on a measured data set (`musclesim.diagnosis.dataset`):

1. Gap. The scenario runs with the data set's inputs replayed (`Master` ``inputs``) and every
   observed signal is compared: NRMSE by the measured range, bias (measured - model), lag (the
   shift of the model that best matches the data); scalar metrics by relative error. A sensor
   channel nothing in the model reads is compared allowing an acquisition latency of up to
   `MAX_ALIGN` samples, chosen on the training part in every comparison (`residuals`).
2. Where. Each component is re-simulated in its *isolation unit*: the component plus the upstream
   instances whose outputs were not measured, with every measured signal feeding the unit
   replayed. A unit deviates when the held-out gap of one of its signals exceeds `DEVIATES` times
   that signal's noise (estimated from the data's second differences, at least `NOISE_FLOOR` of
   the range; for a metric its uncertainty, else `METRIC_FLOOR`). Components of deviating units
   are located unless a unit that did not deviate isolates them (they are exonerated). The
   nominal residual is also split by regime and the worst windows are listed.
3. Which effect. Every effect of a located component (`musclesim.diagnosis.effects`) is fitted on
   the training part (bounded least squares after a coarse scan) and scored on the held-out part.
   It counts only if it shrinks the held-out gap by at least `MIN_SHRINKAGE`, leaves at most
   `BEAT_RECALIBRATED` of the gap of the nominal model with as many nominal parameters
   recalibrated (`effects.CALIBRATION`), and its gain per sample in the regime the effect
   predicts is at least `SIGNATURE_MIN` of its average (signature). Greedy forward selection
   adds a second effect when it shrinks the remaining gap by `MIN_SHRINKAGE` again.
4. How far it shrinks: held-out gap per signal before and after, with block-bootstrap intervals,
   in the model with every measured signal replayed (`Problem.replayed`).

Verdict: ``none`` when no signal deviates beyond the noise; the best effect's name when the gap
left after it is unstructured (within `STRUCTURED` noise floors or `RESIDUAL_SHARE` of the gap
before), and also when it explains at least `MOST` of the gap but leaves a structured rest
(``complete`` false: a further difference outside the library); ``recalibration`` when no effect
counts but a recalibrated nominal parameter leaves an unstructured gap (a parameter is off, no
effect is missing); ``unexplained`` otherwise.

The fits are independent tasks: `diagnose` maps them with the ``pmap`` it is given (the CLI passes
Dask's, the same local cluster or scheduler as sweeps).

This module runs the stages; the work is in the package's other modules: the thresholds named
above in `musclesim.diagnosis.thresholds`, the units in `.problem`, simulation and residuals in
`.simulate`, statistics in `.stats`, regimes in `.regimes`, fits in `.fitting`, scoring,
selection and verdict in `.selection`.
"""
from musclesim.batch import serial_map
from musclesim.cosim import reuse_fmus
from musclesim.diagnosis.fitting import fit_task
from musclesim.diagnosis.problem import Problem
from musclesim.diagnosis.regimes import regime_table, regimes
from musclesim.diagnosis.selection import (candidates, complete, rank, recalibrated, select,
                                           selected_values, verdict)
from musclesim.diagnosis.simulate import Failed, residuals, signal_gap, simulate
from musclesim.diagnosis.stats import before_after, deviates, gap, noise_floor
from musclesim.errors import UserError


def diagnose(ds, fmu_dir="fmus", pmap=None, progress=None, traces=None):
    """Diagnose measured data set `ds` (a `musclesim.diagnosis.DataSet`); return the report dict.

    `pmap(fn, items)` maps the fits (default: one after the other); `progress(text)` is told
    what runs; a dict given as `traces` receives the runs of `Problem.replayed`, nominal and with
    the selected effects, for plots.
    """
    with reuse_fmus():  # some hundred runs of the same FMUs: each read and unpacked once
        return _diagnose(ds, fmu_dir, pmap or serial_map, progress or (lambda text: None),
                         traces)


def _diagnose(ds, fmu_dir, pmap, say, traces):
    problem = Problem(ds, fmu_dir)
    whole = problem.unit("model")
    say("nominal model")
    try:
        sims = simulate(whole, {}, fmu_dir)
    except Failed as exc:
        raise UserError(f"data set {ds.path}: the nominal scenario fails: {exc}") from None
    res_whole = residuals(whole, sims)
    report = _gap_section(problem, whole, sims, res_whole)
    say("isolating components")
    isolated = _isolate(problem)
    suspects = _where(problem, report, isolated)
    masks = regimes(problem, whole)
    report["regimes"] = regime_table(whole, res_whole, masks)
    if not report["gap"]["deviates"] and not any(u["deviates"] for u in isolated):
        floor = report["gap"]["noise_floor"]
        none, explanation = verdict([], None, {}, [], floor, deviates=False)
        report.update(effects=[], recalibrated=[], selected=[], verdict=none,
                      explanation=explanation, noise_floor=floor, complete=True)
        _shrinkage(problem, report, {}, traces)
        return report
    fit_unit, res_nom, suspects = _fit_unit(whole, res_whole, isolated, suspects)
    report["fit_unit"] = {"instances": list(fit_unit.instances),
                          "observed": list(fit_unit.observed)}
    _which_effect(problem, report, (fit_unit, res_nom, suspects, masks), pmap, say)
    _shrinkage(problem, report, selected_values(report["effects"], report["selected"]),
               traces)
    return report


def _gap_section(problem, whole, sims, res_whole):
    """The report's head and section 1: the whole model's gap per signal and pooled."""
    ds = problem.ds
    return {
        "data_set": str(ds.path), "scenario": ds.scenario or sorted(
            {e.scenario for e in ds.experiments.values()}), "scalar_only": problem.scalar_only,
        "parts": {"train": list(problem.part_names[0]), "held_out": list(problem.part_names[1])},
        "gap": {"signals": signal_gap(problem, whole, sims),
                "heldout_gap": gap(whole, res_whole, 1), "noise_floor": noise_floor(whole),
                "deviates": bool(deviates(whole, res_whole))},
    }


def _isolate(problem):
    """Every isolation unit simulated nominally (one whose simulation fails is left out)."""
    isolated = []
    for u in problem.isolation_units():
        try:
            r = residuals(u, simulate(u, {}, problem.fmu_dir))
        except Failed:
            continue
        isolated.append({"unit": u, "gap": gap(u, r, 1), "floor": noise_floor(u),
                         "deviates": deviates(u, r), "res": r})
    return isolated


def _where(problem, report, isolated):
    """Section 2 into `report` (``located``, ``units``); return the suspect instances."""
    suspects, located = _locate(problem, isolated)
    report["located"] = located
    report["units"] = [{"instances": list(u["unit"].instances),
                        "observed": list(u["unit"].observed), "heldout_gap": u["gap"],
                        "noise_floor": u["floor"], "deviates": u["deviates"]} for u in isolated]
    return suspects


def _locate(problem, isolated):
    """Suspect instances and the ranked `located` table from the isolation results.

    A unit that matches clears only its subjects (the instances it isolates): its other members
    may act on what it observes too weakly to show (the magnet's force on the temperature).
    """
    deviating = [u for u in isolated if u["deviates"]]
    cleared = set().union(*[set(u["unit"].subjects) for u in isolated if not u["deviates"]])
    suspects = set().union(*[set(u["unit"].instances) for u in deviating]) - cleared
    if deviating and not suspects:  # every member cleared alone: blame the interaction
        suspects = set(deviating[0]["unit"].instances)
    table = []
    for inst in problem.components:
        own = [u for u in isolated if inst in u["unit"].subjects] or \
            [u for u in isolated if inst in u["unit"].instances]
        if not own:
            continue
        u = own[0]  # its own unit, else the smallest holding it
        table.append({"instance": inst, "component": problem.components[inst],
                      "isolated_gap": u["gap"], "noise_floor": u["floor"], "unit": u["unit"].name,
                      "deviates": u["deviates"], "exonerated": inst in cleared,
                      "located": inst in suspects})
    table.sort(key=lambda r: (not r["located"], -r["isolated_gap"]))
    return suspects, table


def _fit_unit(whole, res_whole, isolated, suspects):
    """The unit the candidates are fitted in, its nominal residuals and the suspects: the
    smallest deviating isolation unit holding every suspect, else the whole model (whose every
    instance is a suspect when none was located)."""
    if not suspects:
        return whole, res_whole, set(whole.instances)
    holders = [u for u in isolated if u["deviates"] and suspects <= set(u["unit"].instances)]
    if holders:
        return holders[0]["unit"], holders[0]["res"], suspects
    return whole, res_whole, suspects


def _which_effect(problem, report, fitting, pmap, say):
    """Section 3 into `report`: the candidates and their recalibrated rivals fitted in the fit
    unit, ranked and selected; the verdict. `fitting`: (unit, nominal residuals, suspects,
    regime masks)."""
    unit, res_nom, suspects, masks = fitting
    fmu_dir = problem.fmu_dir
    cands, calib = candidates(problem, unit, suspects)
    say(f"fitting {len(cands)} candidate effect(s) and {len(calib)} recalibration(s)")
    fits = pmap(fit_task, [(unit, c.free, fmu_dir, None, None) for c in cands]
                + [(unit, [f], fmu_dir, None, None) for f in calib])
    recal, recal_table = recalibrated(unit, res_nom, calib, fits[len(cands):],
                                      max((len(c.free) for c in cands), default=1), fmu_dir)
    report["recalibrated"] = recal_table
    floor = noise_floor(unit)
    entries, counting = rank(unit, res_nom, cands, fits[:len(cands)], recal, masks)
    selected, final = select(unit, counting, floor, masks, pmap, fmu_dir, say)
    report["effects"] = entries
    report["selected"] = [e["name"] for e in selected]
    report["verdict"], report["explanation"] = verdict(selected, final, recal, recal_table, floor)
    report["complete"] = complete(selected, final, floor)
    report["noise_floor"] = floor


def _shrinkage(problem, report, values, traces):
    """report["shrinkage"]: the held-out gap per signal of the model with every measured signal
    replayed (`Problem.replayed`), nominal and with `values`; the traces for the plots."""
    unit = problem.replayed()
    nominal = simulate(unit, {}, problem.fmu_dir)
    after = nominal
    if values:
        try:
            after = simulate(unit, values, problem.fmu_dir)
        except Failed:
            pass
    shifts = {}
    before_res, after_res = residuals(unit, nominal), residuals(unit, after, shifts)
    report["shrinkage"] = {c: before_after(unit, before_res, after_res, [c])
                           for c in unit.observed}
    report["shrinkage"]["all"] = before_after(unit, before_res, after_res)
    report["aligned_samples"] = shifts
    if traces is not None:
        traces.update(unit=unit, nominal=nominal, selected=after)
