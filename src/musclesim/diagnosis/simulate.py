"""Simulating a unit against its data: parameter values applied, the runs, residuals, the gap table.

`simulate` runs every experiment of a `musclesim.diagnosis.problem.Unit` with the master (its
measured signals replayed) and samples the model at the data's times; `residuals` compares it
with the data, normalised by each signal's range; `signal_gap` is the report's section 1.

Downstream restarts: a fit's runs often differ only in the values of instances that feed no
other fitted instance (a sensor's lag beside the wire's calibration, a Jacobian's column for
it). `simulate` keeps the outputs that the other instances passed them in its last `RESTARTS`
runs (`Unit.restarts`) and, when a run's values upstream are those of a kept run, simulates only
the instances downstream, those outputs replayed into them: under the Jacobi algorithm, where
every instance reads the others' outputs of the same communication point, the same bits as the
whole run (tests/diagnosis/test_simulate.py).
"""
from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from musclesim.cosim import Master, ParamRef, Results, compute_metrics, run_cases, with_values
from musclesim.diagnosis.stats import HELD_OUT, TRAIN, Part, advance, gap, lag
from musclesim.diagnosis.thresholds import MAX_ALIGN

if TYPE_CHECKING:
    from musclesim.diagnosis.problem import Unit


RESTARTS = 16  # upstream runs a unit keeps for downstream restarts (a few signals each)


class Failed(Exception):
    """A simulation of candidate values failed (reported, not raised to the user)."""


@dataclass(frozen=True)
class Simulated:
    """A simulation task's outcome (`musclesim.diagnosis.fitting.simulation_task`): the `runs`
    `simulate` gives ([{column: array}] per run), or, when a run failed, None and the
    failure's message (`error`): a failure is a value that says why, not a None."""

    runs: list[dict[Any, np.ndarray]] | None
    error: str | None = None

    @property
    def failed(self) -> bool:
        """Whether the simulation failed (`error` says why)."""
        return self.runs is None


def simulate(unit: Unit, values: Mapping[ParamRef, float], fmu_dir: Any,
             part: Part | None = None, done: Mapping[int, Results] | None = None
             ) -> list[dict[Any, np.ndarray]]:
    """Model values of every run of `unit` with parameter `values` ({ParamRef: value}, applied
    by `musclesim.cosim.with_values`), the FMUs in `fmu_dir`: [{column: array}] per run.

    With `part` ``TRAIN`` it simulates only what the training part needs, as a fit's every step does: each
    run up to its last training row (the model is causal, so those rows are the same to the
    bit), the rows after it NaN; a run without training rows is not run.
    Raises `Failed` when a run fails (the effect's values are then not viable). `done` gives
    runs already made ({run index: `Results`}, as `simulate_many` makes them).
    """
    out = []
    for index, run in enumerate(unit.runs):
        s, inputs, rows = _stepped(run, values, part)
        if s is None:
            out.append({c: np.full(run.part.shape, np.nan) for c in unit.observed})
            continue
        res = _checked(done[index]) if done and index in done else None
        if run.time is None:  # scalar-only: the scenario's metrics
            res = res or _ran(s, fmu_dir, inputs)
            metrics: dict[Any, float] = compute_metrics(res, s.metrics)  # by metric name
            # a metric of another experiment's scenario: no comparison here (NaN, as measured)
            out.append({m: np.array([metrics.get(m, math.nan)]) for m in unit.observed})
        else:
            time, cols = (res.time, {c: res[c] for c in s.record}) if res else \
                _run(unit, (index, part), s, inputs, values, fmu_dir)
            sim = {c: np.interp(run.time, time, cols[c]) for c in unit.observed}
            if rows is not None:
                for v in sim.values():
                    v[rows[-1] + 1:] = np.nan
            out.append(sim)
    return out


def simulate_many(unit: Unit, values: Sequence[Mapping[ParamRef, float]], fmu_dir: Any,
                  part: Part | None = None) -> list[Simulated]:
    """`simulate` of each of the parameter `values`, a `Simulated` each: the runs that go whole
    (no downstream restart) of one experiment in one pass over the cases (`run_cases`)."""
    done: list[dict[int, Results]] = [{} for _ in values]
    for index, run in enumerate(unit.runs):
        jobs = []
        for case, v in enumerate(values):
            s, inputs, _ = _stepped(run, v, part)
            if s is not None and (run.time is None or _downstream(s, v) is None):
                jobs.append((case, Master(s, fmu_dir, inputs)))
        if len(jobs) > 1:
            for (case, _), res in zip(jobs, run_cases([m for _, m in jobs])):
                done[case][index] = res
    out = []
    for v, ran in zip(values, done):
        try:
            out.append(Simulated(simulate(unit, v, fmu_dir, part, ran)))
        except Failed as exc:
            out.append(Simulated(None, str(exc)))
    return out


def _stepped(run, values, part):
    """(scenario, replayed inputs, rows of `part`) that `simulate` runs for `run` with `values`;
    the scenario None where the run has no rows of `part`."""
    (s, inputs), rows = run.stepped(with_values(run.scenario, values)), None
    if part is not None:
        rows = np.flatnonzero(run.part == part)
        if not rows.size:
            return None, inputs, rows
        if run.time is not None:
            # a step beyond it: the sample is interpolated between the same points
            n = min(s.n_steps, math.floor(run.time[rows[-1]] / s.step) + 2)
            s = replace(s, stop_time=s.start_time + n * s.step)
            inputs = {k: v[:s.n_steps + 1] for k, v in inputs.items()}
    return s, inputs, rows


def _checked(res):
    """`res`, or `Failed` raised with its error."""
    if res.error:
        raise Failed(res.error)
    return res


def _ran(s, fmu_dir, inputs):
    """The master's `Results` of scenario `s` with replayed `inputs`; raises `Failed`."""
    return _checked(Master(s, fmu_dir, inputs).run())


def _downstream(s, values):
    """(graph, instances, links into them) of scenario `s` that a run with `values` may
    simulate alone: those downstream of the fitted instances that feed no other fitted instance,
    and the links from the others; None where there is nothing upstream, or under Gauss-Seidel
    (a reader stepped after its source takes the source's output after its step)."""
    if s.algorithm != "jacobi":
        return None
    graph = s.graph
    fitted = {ref.instance for ref in values if ref.instance in s.instances}
    kept = graph.downstream({x for x in fitted if graph.downstream({x}) & fitted == {x}})
    if not kept or kept == set(s.instances):
        return None
    return graph, kept, [k for k in graph.links if k.target in kept and k.source not in kept]


def _run(unit, which, s, inputs, values, fmu_dir):
    """(time, {recorded column: values}) of scenario `s` with replayed `inputs`: restarted
    downstream from a kept run (see the module's docstring) where `unit.restarts` holds one with
    the same values upstream, else run whole and its upstream outputs kept. `which` names the run
    and its part. Raises `Failed`."""
    split = _downstream(s, values)
    if split is None:
        res = _ran(s, fmu_dir, inputs)
        return res.time, {c: res[c] for c in s.record}
    graph, kept, cut = split
    key = (which, frozenset(kept),
           tuple(sorted((k, v) for k, v in values.items() if k.instance not in kept)))
    if key not in unit.restarts:
        # the cut links' sources are read at every exchange anyway: recording them changes nothing
        record = tuple(dict.fromkeys((*s.record, *(k.src for k in cut))))
        res = _ran(replace(s, record=record), fmu_dir, inputs)
        unit.restarts[key] = ({k.dst: res[k.src] for k in cut},
                              {c: res[c] for c in s.record if c.instance not in kept})
        while len(unit.restarts) > RESTARTS:
            del unit.restarts[next(iter(unit.restarts))]
        return res.time, {c: res[c] for c in s.record}
    fed, upstream = unit.restarts[key]
    alone = graph.restrict(kept, fed, [c for c in s.record if c.instance in kept])
    res = _ran(alone, fmu_dir, {**{k: v for k, v in inputs.items()
                                   if k.instance in kept}, **fed})
    return res.time, {**upstream, **{c: res[c] for c in alone.record}}


def residuals(unit: Unit, sims: list[dict[Any, np.ndarray]],
              shifts: dict[Any, int] | None = None,
              align: dict[Any, int] | None = None) -> dict[Any, list[np.ndarray]]:
    """Normalised residuals (model `sims` - measured) / range of `unit`: ``{column: [array per
    run]}``.

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
        assert best is not None  # one shift at least
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
