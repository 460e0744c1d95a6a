"""`musclesim calibrate`: the open values a data set names fitted to its training part, and what
the model then predicts for the part held out (§diagnosis).

A bench that reports a few numbers (a study's published outcomes) cannot pin every nominal
value the diagnosis calibrates, but it can pin the few its author knows to be open: the data
set lists them as ``[[calibrate]]`` tables (`dataset.OpenValue`: one value for every parameter
of its ``set``, within its ``bounds``). They are fitted together by the diagnosis's own
bounded least squares (`fitting.fit`) on the training metrics, each residual divided by its
metric's largest measured magnitude (the diagnosis's range), and their 95 % intervals follow
from the metrics' stated uncertainties through the Jacobian at the fit. Where every uncertainty
is the same fraction of its value, the fit is thereby weighed by the uncertainties; a metric
name several experiments share has one range and one uncertainty (the largest) for all of them. The held-out experiments are never fitted: their metrics, simulated at
the fitted values, are the model's predictions (a set may hold none out and fit every outcome).

A value that ends on its bound, or within 1 % of its range of it (`advice.bound_side`, the rule
of the diagnosis's reports too), is not a fitted value:
the data push it beyond the range its bounds argue is physical, so it soaks up a gap of another
kind. The report keeps it for the record with the status ``"on bound"`` and a model-form warning
(`bound_status`), and the command says so in one sentence at its end (`bound_sentence`).
"""
from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from musclesim.batch import serial_map
from musclesim.cosim import reuse_fmus
from musclesim.diagnosis.advice import WHY, bound_side
from musclesim.diagnosis.box import box_intervals
from musclesim.diagnosis.fitting import FitJob, Free, fit_all, values_of
from musclesim.diagnosis.parameters import nominal, unit_of
from musclesim.diagnosis.problem import Problem
from musclesim.diagnosis.simulate import Failed, simulate
from musclesim.diagnosis.stats import TRAIN, part_segments
from musclesim.errors import UserError

if TYPE_CHECKING:
    from musclesim.diagnosis.dataset import DataSet

ON_BOUND_WARNING = f"on its bound: {WHY}"


def bound_status(value: float, lower: float, upper: float) -> dict[str, Any]:
    """Whether fitted `value` is a fit or sits on one of its `lower`/`upper` bounds (within
    `ON_BOUND` of their range): ``{"status": "fitted" | "on bound", "bound": None | "lower" |
    "upper", "warning": None | ON_BOUND_WARNING}``.

    Examples
    --------
    >>> bound_status(14.9, -5.0, 15.0)["status"], bound_status(14.9, -5.0, 15.0)["bound"]
    ('on bound', 'upper')
    >>> bound_status(10.0, -5.0, 15.0)
    {'status': 'fitted', 'bound': None, 'warning': None}
    """
    side = bound_side(value, lower, upper)
    return {"status": "fitted" if side is None else "on bound", "bound": side,
            "warning": None if side is None else ON_BOUND_WARNING}


def bound_sentence(report: dict[str, Any]) -> str | None:
    """One sentence naming the values of calibration `report` that ended on a bound (None if
    none did)."""
    hits = [f"{', '.join(v['set'])} = {v['value']:.4g} (its {v['bound']} bound "
            f"{v['bounds'][0 if v['bound'] == 'lower' else 1]:.4g})"
            for v in report["open_values"] if v["status"] == "on bound"]
    if not hits:
        return None
    return (f"model-form warning: {'; '.join(hits)} ended on {'its' if len(hits) == 1 else 'their'}"
            " bound: the data push beyond the range, so "
            f"{'it is' if len(hits) == 1 else 'they are'} kept for the record, not a fitted value.")


def open_values(problem):
    """The data set's ``[[calibrate]]`` tables as `Free` parameters: one per table, on the
    instances of its first target's parameter name, the other names as ``also``; the start is
    the first target's value in its scenario (or its FMU's default), held within the bounds.

    Raises
    ------
    UserError
        If a target names no instance or parameter of the data set's scenarios.
    """
    out = []
    for ov in problem.ds.calibrate:
        refs = list(ov.targets)  # ParamRefs, parsed by the data set from its manifest
        for ref in refs:
            if not any(ref.instance in s.instances for s in problem.scenarios.values()):
                raise UserError(f"data set {problem.ds.path}: [[calibrate]] names {ref}, "
                                "but no scenario of the data set has an instance "
                                f"{ref.instance!r}")
        starts = []
        for ref in refs:  # each target must exist
            try:
                starts.append(nominal(problem, ref))
            except KeyError as exc:
                raise UserError(f"data set {problem.ds.path}: [[calibrate]] names "
                                f"{ref}, but {exc.args[0]}") from None
        name = refs[0].name
        start = min(max(starts[0], ov.lower), ov.upper)
        out.append(Free(tuple(r.instance for r in refs if r.name == name), name, ov.lower,
                        ov.upper, start, also=tuple(r for r in refs if r.name != name)))
    return out


def intervals(fit, free, unit):
    """95 % intervals of the fitted values from the training metrics' stated uncertainties
    (`unit.noise`, normalised like the residuals) through the fit's Jacobian (box
    coordinates, `box.box_intervals`): covariance (J^T W J)^-1 with W the inverse
    variances."""
    segments = part_segments(unit, fit.residuals, TRAIN)
    sigma = np.concatenate([np.full(sum(len(a) for a in segments[c]), unit.noise[c])
                            for c in unit.observed])
    return box_intervals(np.asarray(fit.jac) / sigma[:, None], np.asarray(fit.z),
                         [f.lower for f in free], [f.upper - f.lower for f in free])


def metric_table(problem, unit, runs):
    """Per experiment and metric: the measured value, its uncertainty, the part, and each
    model's value with its relative error. `runs`: {label: simulated runs, or None}."""
    table = []
    held = set(problem.part_names[1])
    for run, (ename, e) in zip(unit.runs, problem.ds.experiments.items()):
        for m, mm in e.metrics.items():
            row = {"experiment": ename, "metric": m, "part": "held_out" if ename in held
                   else "train", "measured": mm.value, "uncertainty": mm.uncertainty,
                   "unit": mm.unit}
            for label, sims in runs.items():
                index = list(problem.ds.experiments).index(ename)
                v = None if sims is None else float(sims[index][m][0])
                row[label] = v
                row[f"{label}_error"] = None if v is None or not math.isfinite(v) \
                    or mm.value == 0 else (v - mm.value) / abs(mm.value)
            table.append(row)
    return table


def calibrate(ds: DataSet, fmu_dir: Any = "fmus", pmap: Callable[..., list] | None = None,
              progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """Fit the open values of scalar-only data set `ds` (its FMUs in `fmu_dir`, the fit's runs
    mapped by `pmap`, `progress` told what runs) on its training part; return the report: the
    values with their intervals and, per metric, the nominal and the fitted model against the
    measurement (the held-out ones predictions).

    Raises
    ------
    UserError
        If the set has time series or names no open value.
    """
    if not ds.scalar_only:
        raise UserError(f"data set {ds.path}: musclesim calibrate takes scalar metrics only; "
                        "use musclesim diagnose for time series")
    say = progress or (lambda text: None)
    with reuse_fmus():
        problem = Problem(ds, fmu_dir)
        unit = problem.unit("model")
        free = open_values(problem)
        if not free:
            raise UserError(f"data set {ds.path} names no open value: add [[calibrate]] tables")
        say(f"nominal model: {len(unit.runs)} experiment(s)")
        nominal = _runs(unit, {}, fmu_dir)
        say(f"fitting {len(free)} open value(s) on {', '.join(problem.part_names[0])}")
        fit, = fit_all([FitJob(unit, free, fmu_dir)], pmap or serial_map)
        fitted = _runs(unit, values_of(free, fit.x), fmu_dir)
    spans = intervals(fit, free, unit) if fit.jac is not None and fit.residuals is not None \
        else [(f.lower, f.upper) for f in free]
    values = [{"set": [str(r) for r in f.refs],
               "value": x, **bound_status(x, f.lower, f.upper), "interval95": list(iv),
               "bounds": [f.lower, f.upper], "nominal": f.start,
               "unit": unit_of(unit.components.get(f.instances[0], ""), f.name), "why": ov.why}
              for f, x, iv, ov in zip(free, fit.x, spans, ds.calibrate)]
    return {"data_set": str(ds.path), "reference": ds.reference,
            "parts": {"train": list(problem.part_names[0]),
                      "held_out": list(problem.part_names[1])},
            "open_values": values, "evaluations": fit.evaluations,
            "metrics": metric_table(problem, unit, {"nominal": nominal, "fitted": fitted})}


def _runs(unit, values, fmu_dir):
    try:
        return simulate(unit, values, fmu_dir)
    except Failed:
        return None


def markdown(report: dict[str, Any]) -> str:
    """The calibration `report` (`calibrate`'s) as a readable page."""
    lines = [f"# Calibration of {report['data_set']}", "",
             f"Trained on {', '.join(report['parts']['train'])}; held out (predicted): "
             f"{', '.join(report['parts']['held_out']) or 'none, every outcome trains the fit'}.",
             "",
             "| open value | unit | fitted | 95 % interval | bounds | start |",
             "|---|---|---|---|---|---|"]
    for v in report["open_values"]:
        value = f"{v['value']:.4g}" if v["status"] == "fitted" else \
            f"on its {v['bound']} bound ({v['value']:.4g}, a model-form warning, not a fit)"
        lines.append(f"| {', '.join(v['set'])} | {v.get('unit', '1')} | {value} | "
                     f"[{v['interval95'][0]:.4g}, {v['interval95'][1]:.4g}] | "
                     f"[{v['bounds'][0]:.4g}, {v['bounds'][1]:.4g}] | {v['nominal']:.4g} |")
    lines += ["", "| experiment | metric | part | measured | nominal model | fitted model |",
              "|---|---|---|---|---|---|"]
    for r in report["metrics"]:
        cells = []
        for label in ("nominal", "fitted"):
            v, e = r[label], r[f"{label}_error"]
            cells.append("failed" if v is None else f"{v:.4g} ({100 * e:+.0f} %)"
                         if e is not None else f"{v:.4g}")
        lines.append(f"| {r['experiment']} | {r['metric']} | {r['part']} | {r['measured']:.4g} "
                     f"{r['unit']} | {cells[0]} | {cells[1]} |")
    if sentence := bound_sentence(report):
        lines += ["", sentence]
    return "\n".join(lines) + "\n"
