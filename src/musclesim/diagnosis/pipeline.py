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
   described against calibration on the signals it can change (`selection.judge`). Signals that
   share an upstream state place the gap in a sensor or in the plant (`selection.cross_signal`).
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

This module runs the stages; the work is in the package's other modules: the thresholds named
above in `musclesim.diagnosis.thresholds`, the units in `.problem`, simulation and residuals in
`.simulate`, statistics in `.stats`, regimes in `.regimes`, fits in `.fitting`, candidates
and their descriptions in `.selection`, the evidence in `.evidence` and the weighing and verdict
in `.weigh`.
"""
from dataclasses import dataclass

import numpy as np
from threadpoolctl import threadpool_limits

from musclesim.batch import serial_map
from musclesim.cosim import reuse_fmus, split_signal
from musclesim.diagnosis.fitting import (FitJob, FitResult, fit_all, known_columns,
                                         simulation_task, values_of)
from musclesim.diagnosis.problem import Problem, affected
from musclesim.diagnosis.regimes import regime_table, regimes
from musclesim.diagnosis.selection import (NO_GAP, calibration, calibration_table, candidates,
                                           cross_signal, explained, rank, refine, scanned)
from musclesim.diagnosis.simulate import Failed, residuals, signal_gap, simulate
from musclesim.diagnosis.stats import (HELD_OUT, TRAIN, before_after, deviates, gap, noise_floor,
                                       part_segments)
from musclesim.diagnosis.weigh import (CALIBRATION_ONLY, Weighed, profile_jobs, symmetries,
                                      weigh, with_symmetries)
from musclesim.diagnosis.weigh import section as weigh_section
from musclesim.errors import UserError


@dataclass
class Nominal:
    """An isolation unit's nominal run: its residuals, and whether it deviates."""

    unit: object
    residuals: dict
    deviates: bool


@dataclass
class Calibration:
    """A unit's calibration: its `Free` parameters and their fitted `values`, the residuals
    there, the Jacobian (box coordinates) and the sensor latencies held, the report's table of
    values, the `FitResult` (None: nothing calibrated) and the held-out gap of the nominal
    values."""

    free: list
    values: dict
    residuals: dict
    jac: object
    table: dict
    fit: object
    latency: dict
    nominal_gap: float = None


@dataclass
class Isolation:
    """An isolation unit, calibrated on its own: its held-out gap and noise floor, whether it
    deviates, the nominal values' gap."""

    unit: object
    calibration: Calibration
    gap: float
    floor: float
    deviates: bool
    nominal_gap: float

    def section(self):
        """The report's entry of this unit (``units``)."""
        return {"instances": list(self.unit.instances), "observed": list(self.unit.observed),
                "heldout_gap_nominal": self.nominal_gap, "heldout_gap": self.gap,
                "noise_floor": self.floor, "deviates": self.deviates}


def diagnose(ds, fmu_dir="fmus", pmap=None, progress=None, traces=None):
    """Diagnose measured data set `ds` (a `musclesim.diagnosis.DataSet`); return the report dict.

    `pmap(fn, items)` maps the fits (default: one after the other); `progress(text)` is told
    what runs; a dict given as `traces` receives the runs of `Problem.replayed`, nominal,
    calibrated and with the selected effects, for plots.
    """
    # BLAS on one thread, as beside a Dask cluster (batch.dask_client): a product's reduction
    # order, hence its last bits, depends on the thread count, and the report must not depend
    # on where the fits ran (measured: serial and Dask reports differed in the 13th digit)
    with reuse_fmus(), threadpool_limits(1, user_api="blas"):
        return _diagnose(ds, fmu_dir, pmap or serial_map, progress or (lambda text: None),
                         traces)


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
    res_whole = residuals(whole, sims)
    report = _gap_section(problem, whole, sims, res_whole)
    if not report["gap"]["deviates"] and not any(u.deviates for u in units):
        floor = report["gap"]["noise_floor"]
        report.update(calibration={"parameters": {}}, effects=[], selected=[], stand_ins=[],
                      verdict="none", explanation=NO_GAP, noise_floor=floor, complete=True)
        report.update(_shrinkage(problem, ({}, cut_sims), {}, traces, pmap))
        return report
    res_cut = residuals(cut, cut_sims)
    say(f"2/5 calibrating the model and {len(units)} isolation unit(s) on the training part")
    cal, isolated = _calibrate(problem, (cut, res_cut), units, pmap)
    report["calibration"] = _calibration_section(cut, res_cut, cal)
    say("3/5 isolating components (each unit calibrated)")
    suspects, report["located"] = _locate(problem, isolated)
    report["units"] = [i.section() for i in isolated]
    masks = regimes(problem, whole)
    report["regimes"] = regime_table(cut, cal.residuals, masks)
    values = {}
    if not deviates(cut, cal.residuals) and not any(i.deviates for i in isolated):
        floor = noise_floor(cut)
        report.update(effects=[], selected=[], stand_ins=[], verdict="recalibration",
                      complete=True, noise_floor=floor, explanation=(
                          f"calibration alone takes the held-out gap from "
                          f"{report['calibration']['heldout_gap_before']:.3g} to "
                          f"{report['calibration']['heldout_gap_after']:.3g}, within the noise "
                          f"(floor {floor:.3g}): no unmodelled effect is needed"))
    else:
        unit, unit_cal, suspects = _fit_unit((cut, cal), isolated, suspects)
        report["fit_unit"] = {"instances": list(unit.instances), "observed": list(unit.observed),
                              "latency": unit_cal.latency}
        say("4/5 which effect: candidates fitted with the calibration parameters")
        values, section = _which_effect(problem, (unit, unit_cal, suspects, masks),
                                        report["calibration"]["parameters"], pmap, say)
        report.update(section)
    say("5/5 how far the gap shrinks")
    report.update(_shrinkage(problem, (cal.values, cut_sims), values, traces, pmap))
    return report


def _gap_section(problem, whole, sims, res_whole):
    """The report's head and section 1: the whole model's gap per signal and pooled."""
    ds = problem.ds
    return {
        "data_set": str(ds.path), "scenario": ds.scenario or sorted(
            {e.scenario for e in ds.experiments.values()}), "scalar_only": problem.scalar_only,
        "parts": {"train": list(problem.part_names[0]), "held_out": list(problem.part_names[1])},
        "gap": {"signals": signal_gap(problem, whole, sims),
                "heldout_gap": gap(whole, res_whole, HELD_OUT), "noise_floor": noise_floor(whole),
                "deviates": bool(deviates(whole, res_whole))},
    }


def _same(unit, whole):
    """Whether isolation `unit` simulates what `whole` does: the same observed signals from the
    same instances (those of `whole` that act on an observed signal) fed the same replays."""
    if unit.observed != whole.observed:
        return False
    acting = {i for i in whole.instances if affected(whole, (i,))}
    return acting == set(unit.instances) and all(
        {k for k in a.inputs if split_signal(k)[0] in acting} == set(b.inputs)
        for a, b in zip(whole.runs, unit.runs))


def _nominal_runs(problem, whole, cut, pmap):
    """The nominal runs, mapped together: of the whole model (its failure is the user's
    error), every isolation unit (a `Nominal` each, one whose simulation fails left out) and
    the model with every measured signal replayed `cut` (the whole model's again for scalar
    metrics)."""
    units = problem.isolation_units()
    extra = [] if problem.scalar_only else [cut]
    runs = pmap(simulation_task, [(u, {}, problem.fmu_dir, None) for u in [whole, *extra, *units]])
    if runs[0] is None:  # run again here for the cause
        try:
            simulate(whole, {}, problem.fmu_dir)
        except Failed as exc:
            raise UserError(f"data set {problem.ds.path}: the nominal scenario fails: "
                            f"{exc}") from None
    nominal = []
    for u, r in zip(units, runs[1 + len(extra):]):
        if r is not None:
            res = residuals(u, r)
            nominal.append(Nominal(u, res, deviates(u, res)))
    return runs[0], nominal, runs[1] if extra else runs[0]


def _calibrate(problem, cut, units, pmap):
    """Section 2: the calibration parameters of the model with every measured signal replayed
    (`cut`: that unit and its nominal residuals) and, separately, of every isolation unit
    (`Nominal` each) fitted on the training part from the nominal values (one mapped task
    each): a unit is judged on its own calibration, so that calibrating the whole model around
    a sensor's fault cannot make the plant's unit deviate. Return the model's `Calibration`
    and an `Isolation` per unit."""
    cut, res_cut = cut
    jobs = [(u, calibration(problem, u)) for u in [cut] + [n.unit for n in units]]
    # a unit that is the whole model again (the same instances, signals and replays) is
    # calibrated once
    same = [i for i, (u, _) in enumerate(jobs) if i and _same(u, cut)]
    fits = iter(fit_all([FitJob(u, free, problem.fmu_dir, scan=scanned(free))
                         for i, (u, free) in enumerate(jobs) if free and i not in same], pmap))
    cals = []
    for i, ((u, free), nominal) in enumerate(zip(jobs, [res_cut] + [n.residuals for n in units])):
        f = cals[0].fit if i in same else next(fits) if free else None
        if f is None or f.residuals is None:
            latency = {}
            residuals(u, simulate(u, {}, problem.fmu_dir), latency)
            cal = Calibration([], {}, nominal, None, {}, None, latency)
        else:
            cal = Calibration(free, values_of(free, f.x), f.residuals, f.jac,
                              calibration_table(free, f), f, f.latency)
        cal.nominal_gap = gap(u, nominal, HELD_OUT)
        cals.append(cal)
    isolated = [Isolation(n.unit, c, gap(n.unit, c.residuals, HELD_OUT), noise_floor(n.unit),
                          deviates(n.unit, c.residuals), c.nominal_gap)
                for n, c in zip(units, cals[1:])]
    return cals[0], isolated


def _calibration_section(cut, res_cut, cal):
    """The report's ``calibration``: the calibrated values, the sensors' latencies, and the
    held-out gap before and after, pooled and per signal, of the model with every measured
    signal replayed (`cut`, its nominal residuals `res_cut`)."""
    return {"parameters": cal.table, "latency": cal.latency,
            "heldout_gap_before": gap(cut, res_cut, HELD_OUT),
            "heldout_gap_after": gap(cut, cal.residuals, HELD_OUT),
            "signals": {c: before_after(cut, res_cut, cal.residuals, [c]) for c in cut.observed}}


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


def _fit_unit(whole, isolated, suspects):
    """(unit, its `Calibration`, suspects): the unit the candidates are fitted in, the smallest
    deviating isolation unit holding every suspect, else the model with every measured signal
    replayed (whose every instance is a suspect when none was located). `whole`: (that model,
    its calibration)."""
    whole, cal = whole
    if not suspects:
        return whole, cal, set(whole.instances)
    holders = [u for u in isolated if u.deviates and suspects <= set(u.unit.instances)]
    if holders:
        return holders[0].unit, holders[0].calibration, suspects
    return whole, cal, suspects


def _which_effect(problem, fitting, calibrated, pmap, say):
    """Section 4: every candidate effect of the suspects fitted together with the fit unit's
    calibration parameters (from its calibrated values), then weighed by evidence against
    calibration alone (`weigh`): probabilities, the credible set, symmetries; the pair of the
    two most probable effects when the most probable single leaves a structured gap. Each
    effect's fit is also scored descriptively against calibration on the signals it can change
    (``effects``). `fitting`: (unit, its `Calibration`, suspects, regime masks); `calibrated`:
    the report's table of the model's calibrated values. Return the values of the candidate
    named (or, undecided, the most probable) {(instance, parameter): value}, calibration
    refitted with it, and the report's section."""
    unit, cal, suspects, masks = fitting
    fmu_dir = problem.fmu_dir
    calib, jac = cal.free, cal.jac
    x_cal = [cal.values[(fr.instances[0], fr.name)] for fr in calib]
    base = {"residuals": cal.residuals, "heldout_gap": gap(unit, cal.residuals, HELD_OUT)}
    cands = candidates(problem, unit, suspects)
    say(f"fitting {len(cands)} candidate effect(s), each with {len(calib)} calibration "
        "parameter(s)")
    jobs = [FitJob(unit, c.free + calib, fmu_dir, x0=[fr.start for fr in c.free] + x_cal,
                   scan=len(c.free), known=known_columns(jac, len(c.free)), latency=cal.latency)
            for c in cands]
    fits = refine(unit, cands, fit_all(jobs, pmap), calib, cal.latency, fmu_dir, pmap)
    floor = noise_floor(unit)
    entries, _ = rank(unit, [base] * len(cands), cands, fits, masks, calib)
    calibration_only = Weighed(CALIBRATION_ONLY, cal.fit or _unfitted(unit, cal), calib, 0)
    singles = [Weighed(c.label, f, c.free + calib, len(c.free)) for c, f in zip(cands, fits)
               if f.applicable and f.residuals is not None]
    weighed, disc = weigh(unit, calibration_only, singles)
    effects = [w for w in weighed if w.k]
    top = weighed[0]
    if top.k and len(effects) > 1 and not explained(top.fit.heldout_gap, cal.nominal_gap,
                                                    floor):
        say("a pair: the two most probable effects together")
        w1, w2 = effects[0], effects[1]
        c1, c2 = (next(c for c in cands if c.label == w.name) for w in (w1, w2))
        pair_fit, = fit_all([FitJob(
            unit, c2.free + c1.free + calib, fmu_dir, x0=[f.start for f in c2.free] + w1.fit.x,
            scan=len(c2.free), known=known_columns(jac, len(c2.free) + len(c1.free)),
            latency=cal.latency)], pmap)
        if pair_fit.residuals is not None:
            pair = Weighed(f"{w1.name} + {w2.name}", pair_fit, c2.free + c1.free + calib,
                           len(c2.free) + len(c1.free))
            weighed, disc = weigh(unit, calibration_only, singles, [pair], disc)
    profiles = profile_jobs(unit, singles, calibration_only, disc, fmu_dir)
    say(f"symmetries: {len(profiles)} profile fit(s), each effect moved and the calibration "
        "fitted again")
    fitted = fit_all([job for _, _, job in profiles], pmap)
    symmetric = symmetries(weighed, [(w, length, f) for (w, length, _), f
                                     in zip(profiles, fitted)], disc, problem)
    weighed = with_symmetries(weighed, symmetric)
    section, name, explanation, complete, chosen = weigh_section(
        unit, weighed, symmetric, disc, cal.nominal_gap, floor, explained)
    out = {"effects": entries, "evidence": section,
           "selected": [chosen.name] if chosen.k and name == chosen.name else [],
           "consistency": cross_signal(unit, entries, [e for e in entries
                                                       if e["label"] == chosen.name]),
           "stand_ins": [s["candidates"][0] for s in symmetric], "verdict": name,
           "explanation": explanation, "complete": complete, "noise_floor": floor}
    return (values_of(chosen.free, chosen.fit.x) if chosen.k else {}), out


def _unfitted(unit, cal):
    """A `FitResult` of the nominal values where nothing was calibrated."""
    res = cal.residuals
    return FitResult([], [], res, gap(unit, res, TRAIN), gap(unit, res, HELD_OUT), True, 0, None,
                     cal.latency, np.zeros(0), part_segments(unit, res, TRAIN))


def _shrinkage(problem, calibrated, values, traces, pmap):
    """Section 5, the report's ``shrinkage``: the held-out gap per signal of the model with every
    measured signal replayed (`Problem.replayed`), nominal (``before``), calibrated and with
    the selected effects (``after``, calibration refitted with them), and the latencies found
    there (``aligned_samples``); the traces for the plots. `calibrated`: (the calibrated values,
    the nominal runs of that model)."""
    unit = problem.replayed()
    calibrated, nominal = calibrated
    wanted = [v for v in (calibrated, {**calibrated, **values}) if v]
    wanted = [v for i, v in enumerate(wanted) if v not in wanted[:i]]
    got = pmap(simulation_task, [(unit, v, problem.fmu_dir, None) for v in wanted])
    runs = {"calibrated": nominal}
    for key, v in (("calibrated", calibrated), ("after", {**calibrated, **values})):
        run = got[wanted.index(v)] if v else None
        runs[key] = runs["calibrated"] if run is None else run
    shifts = {}
    before_res, cal_res = residuals(unit, nominal), residuals(unit, runs["calibrated"])
    after_res = residuals(unit, runs["after"], shifts)
    shrinkage = {c: {**before_after(unit, before_res, after_res, [c]),
                     "calibrated": gap(unit, cal_res, HELD_OUT, [c])} for c in unit.observed}
    shrinkage["all"] = {**before_after(unit, before_res, after_res),
                        "calibrated": gap(unit, cal_res, HELD_OUT)}
    if traces is not None:
        traces.update(unit=unit, nominal=nominal, calibrated=runs["calibrated"],
                      selected=runs["after"])
    return {"shrinkage": shrinkage, "aligned_samples": shifts}
