"""Simulating a unit against its data: parameter values applied, the runs, residuals, the gap table.

`simulate` runs every experiment of a `musclesim.diagnosis.problem.Unit` with the master (its
measured signals replayed) and samples the model at the data's times; `residuals` compares it
with the data, normalised by each signal's range; `signal_gap` is the report's section 1.
"""
import math
from dataclasses import replace

import numpy as np

from musclesim.cosim import Master, compute_metrics
from musclesim.diagnosis.stats import HELD_OUT, TRAIN, advance, gap, lag
from musclesim.diagnosis.thresholds import MAX_ALIGN


class Failed(Exception):
    """A simulation of candidate values failed (reported, not raised to the user)."""


def with_values(s, values):
    """Scenario `s` with ``{(instance, parameter): value}`` applied (instances not in `s`
    skipped)."""
    instances = dict(s.instances)
    for (inst, par), v in values.items():
        if inst in instances:
            old = instances[inst]
            instances[inst] = replace(old, parameters={**old.parameters, par: float(v)})
    return replace(s, instances=instances)


def simulate(unit, values, fmu_dir, part=None):
    """Model values of every run of `unit` with parameter `values`: [{column: array}] per run.

    ``part=TRAIN`` simulates only what the training part needs, as a fit's every step does: each
    run up to its last training row (the model is causal, so those rows are the same to the
    bit), the rows after it NaN; a run without training rows is not run.
    Raises `Failed` when a run fails (the effect's values are then not viable).
    """
    out = []
    for run in unit.runs:
        (s, inputs), rows = run.stepped(with_values(run.scenario, values)), None
        if part is not None:
            rows = np.flatnonzero(run.part == part)
            if not rows.size:
                out.append({c: np.full(run.part.shape, np.nan) for c in unit.observed})
                continue
            if run.time is not None:
                # a step beyond it: the sample is interpolated between the same points
                n = min(s.n_steps, math.floor(run.time[rows[-1]] / s.step) + 2)
                s = replace(s, stop_time=s.start_time + n * s.step)
                inputs = {k: v[:s.n_steps + 1] for k, v in inputs.items()}
        res = Master(s, fmu_dir, inputs).run()
        if res.error:
            raise Failed(res.error)
        if run.time is None:  # scalar-only: the scenario's metrics
            metrics = compute_metrics(res, s.metrics)
            out.append({m: np.array([metrics[m]]) for m in unit.observed})
        else:
            sim = {c: np.interp(run.time, res.time, res[c]) for c in unit.observed}
            if rows is not None:
                for v in sim.values():
                    v[rows[-1] + 1:] = np.nan
            out.append(sim)
    return out


def residuals(unit, sims, shifts=None, align=None):
    """Normalised residuals (model - measured) / range: ``{column: [array per run]}``.

    An alignable column (a sensor channel nothing simulated in the unit reads) is compared
    shifted back by the whole number of samples, 0..MAX_ALIGN, that fits the training part
    best: its acquisition latency, a nuisance; `align` ({column: samples}) imposes the shifts
    instead. `shifts`, a dict, receives the samples chosen.
    """
    out = {}
    for c in unit.observed:
        best = None
        choices = range(MAX_ALIGN + 1 if c in unit.alignable else 1)
        for d in ([align[c]] if align and c in align else choices):
            res = [(sim[c] - advance(run.measured[c], d)) / unit.scale[c]
                   for run, sim in zip(unit.runs, sims)]
            cost = sum(float(np.nansum(np.square(r[run.part == TRAIN])))
                       for r, run in zip(res, unit.runs))
            if best is None or cost < best[0]:
                best = (cost, d, res)
        out[c] = best[2]
        if shifts is not None and c in unit.alignable:
            shifts[c] = best[1]
    return out


def signal_gap(problem, unit, sims):
    """Per observed signal: NRMSE (all, held-out), bias and lag of the model against the data."""
    out = {}
    res = residuals(unit, sims)
    for c in unit.observed:
        meas = np.concatenate([r.measured[c] for r in unit.runs])
        model = np.concatenate([s[c] for s in sims])
        entry = {"nrmse": float(np.sqrt(np.nanmean(np.square(np.concatenate(res[c]))))),
                 "nrmse_heldout": gap(unit, res, HELD_OUT, [c]),
                 "bias": float(np.nanmean(meas - model)),
                 "unit": problem.units_of.get(c, "1"), "range": unit.scale[c],
                 "noise": unit.noise[c]}
        if not problem.scalar_only:
            entry["lag"] = lag(unit.runs[0].time, unit.runs[0].measured[c], sims[0][c])
        else:
            entry["relative_error"] = [float((s[c][0] - r.measured[c][0]) / r.measured[c][0])
                                       if r.measured[c][0] else math.nan
                                       for r, s in zip(unit.runs, sims)]
        out[c] = entry
    return out
