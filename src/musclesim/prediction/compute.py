"""Computing a set of predictions (`predict`): the shipped fit's covariance, the alternative
models, and every outcome of the declared scenarios with its 90 % interval (§predictions).

The steps, each with the library's own code:

1. The fit's covariance. The fit's data set (`musclesim.diagnosis.load_dataset`) is simulated
   on its training part at the values the scenarios ship (`musclesim.diagnosis.simulate_unit`)
   and compared with its metrics by the diagnosis's `residuals`, each divided by its metric's
   stated uncertainty as `musclesim calibrate` divides them. Its Jacobian is taken by central
   differences of `propagate.STEP` of each range, not by the fit's forward differences of a
   thousandth of it, which a relay's stepping metrics make unreliable (§study-outcomes);
   covariance ``(J^T J)^-1`` (`propagate.covariance`).
2. The alternative models: each data set with its opened values fitted by
   `musclesim.diagnosis.calibrate`, its chi-square on the data set's stated uncertainties; those
   within `propagate.ADMIT` of the first alternative's (the reference: nothing opened) are
   admitted.
3. Each scenario: run as shipped (the prediction), with each fitted value it carries stepped
   by its standard deviation either side (its slopes, so its standard deviation through the
   covariance: the delta method), and with each
   admitted model's values (their spread); the interval by `propagate.interval`.
"""
from __future__ import annotations

import datetime
import math
from collections.abc import Callable, Mapping
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from musclesim.cosim import (Master, ParamRef, Scenario, compute_metrics, load_scenario,
                             locate_scenario, metric_unit, read_fmu, run_cases, signal_units,
                             with_values)
from musclesim.errors import UserError
from musclesim.prediction import propagate
from musclesim.prediction.declaration import Declaration, data_set_dir, fingerprint
from musclesim.prediction.shipped import made_for

if TYPE_CHECKING:
    from musclesim.diagnosis import DataSet

# metrics of these operations are never negative: their intervals stop at 0
_NONNEGATIVE = {"peak_to_peak", "cycle_peak_to_peak", "rms", "frequency", "max_abs"}


def predict(declaration: Declaration, fmu_dir: Any = "fmus",
            pmap: Callable[..., list] | None = None,
            progress: Callable[[str], None] | None = None) -> dict[str, Any]:
    """The predictions of `declaration` as the shipped JSON holds them (see the module
    docstring), on the FMUs in `fmu_dir`, the alternatives' fits mapped by `pmap`, `progress`
    told what runs.

    Raises
    ------
    UserError
        If the fit's residuals do not pin its values, or a scenario's run fails.
    """
    say = progress or (lambda text: None)
    fit = fit_covariance(declaration, fmu_dir, say)
    models = alternatives(declaration, fmu_dir, pmap, say)
    admitted = [m for m in models if m["admitted"]]
    scenarios = {}
    for name in declaration.scenarios:
        say(f"scenario {name}")
        scenarios[name] = scenario_predictions(load_scenario(locate_scenario(name)), fit,
                                               admitted, declaration.study.get(name, {}),
                                               fmu_dir)
    return {"name": declaration.name, "description": declaration.description,
            "reference": declaration.reference, "level": propagate.LEVEL,
            "created": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "fingerprint": fingerprint(declaration), "fit": fit, "alternatives": models,
            "scenarios": scenarios}


def _load(name: str, fmu_dir: Any) -> DataSet:
    """The shipped data set `name`, checked against its scenarios."""
    from musclesim.diagnosis import load_dataset  # here: see `fit_covariance`

    return load_dataset(data_set_dir(name), check_model=True, fmu_dir=fmu_dir)


def fit_covariance(declaration: Declaration, fmu_dir: Any,
                   say: Callable[[str], None]) -> dict[str, Any]:
    """The shipped fit of `declaration`: its tables (each ``{"set", "value", "bounds", "sd"}``,
    the value shipped) and the covariance of their values, from the Jacobian of the fit's
    training residuals at the shipped values by central differences (module docstring)."""
    # the diagnosis is imported in the functions that need it, not at the module's top:
    # `musclesim run` reads the shipped predictions through this package and should not pay
    # for importing the diagnosis (a second or more)
    from musclesim.diagnosis import TRAIN, Problem, residuals, simulate_unit

    ds = _load(declaration.fit_data_set, fmu_dir)
    tables = list(ds.calibrate)
    if len(tables) != len(declaration.shipped):
        raise UserError(f"predictions declaration {declaration.path}: [fit] shipped has "
                        f"{len(declaration.shipped)} values, data set {ds.path} "
                        f"{len(tables)} [[calibrate]] tables")
    problem = Problem(ds, fmu_dir)
    unit = problem.unit("model")
    rows = [(c, i) for c in unit.observed for i, run in enumerate(unit.runs)
            if run.part[0] == TRAIN and math.isfinite(run.measured[c][0])]
    sd = np.array([unit.noise[c] for c, _ in rows])  # stated uncertainty / range, as residuals

    def weighted(values: list[float]) -> np.ndarray:
        point = {ref: v for t, v in zip(tables, values) for ref in t.targets}
        res = residuals(unit, simulate_unit(unit, point, fmu_dir, part=TRAIN))
        return np.array([res[c][i][0] for c, i in rows]) / sd

    base = list(declaration.shipped)
    say(f"the fit's Jacobian at the shipped values: {1 + 2 * len(tables)} runs of "
        f"{', '.join(problem.part_names[0])}")
    J = np.empty((len(rows), len(tables)))
    for k, t in enumerate(tables):
        lo, hi = propagate.points(base[k], t.lower, t.upper, propagate.STEP * (t.upper - t.lower))
        J[:, k] = (weighted(base[:k] + [hi] + base[k + 1:])
                   - weighted(base[:k] + [lo] + base[k + 1:])) / (hi - lo)
    try:
        cov = propagate.covariance(J)
    except np.linalg.LinAlgError:
        raise UserError(f"data set {ds.path}: its training metrics do not pin every open value "
                        "at the shipped values (a singular Jacobian); no covariance") from None
    return {"data_set": declaration.fit_data_set, "residuals": len(rows),
            "weighted_residuals": [float(v) for v in weighted(base)],
            "values": [{"set": [str(r) for r in t.targets], "value": v,
                        "bounds": [t.lower, t.upper], "sd": math.sqrt(cov[k, k])}
                       for k, (t, v) in enumerate(zip(tables, base))],
            "covariance": cov.tolist()}


def alternatives(declaration: Declaration, fmu_dir: Any, pmap: Callable[..., list] | None,
                 say: Callable[[str], None]) -> list[dict[str, Any]]:
    """Each alternative model of `declaration` fitted (`musclesim.diagnosis.calibrate`): its
    name, values (``{"inst.param": value}``), the values on a bound, its chi-square on the
    data set's stated uncertainties and whether it is admitted to the spread."""
    from musclesim.diagnosis import calibrate  # here: see `fit_covariance`

    out = []
    for alt in declaration.alternatives:
        ds = _load(alt.data_set, fmu_dir)
        if alt.opened:  # the data set's own type of open value, with these targets and bounds
            template = ds.calibrate[0]
            ds = replace(ds, calibrate=(*ds.calibrate, *(
                replace(template, targets=o.targets, lower=o.lower, upper=o.upper, why=o.why)
                for o in alt.opened)))
        say(f"alternative model {alt.name!r}: musclesim calibrate on {alt.data_set}")
        report = calibrate(ds, fmu_dir, pmap)
        chi2 = sum(((m["fitted"] - m["measured"]) / m["uncertainty"]) ** 2
                   if m["fitted"] is not None and m["uncertainty"] else math.inf
                   for m in report["metrics"])
        out.append({"name": alt.name, "data_set": alt.data_set,
                    "values": {ref: v["value"] for v in report["open_values"] for ref in v["set"]},
                    "on_bound": [r for v in report["open_values"] if v["status"] != "fitted"
                                 for r in v["set"]],
                    "chi2": chi2, "evaluations": report["evaluations"]})
    reference = out[0]["chi2"] if out else math.nan
    for m in out:
        m["admitted"] = propagate.admitted(m["chi2"], reference)
    return out


def _carried(s: Scenario, fit: Mapping[str, Any], fmu_dir: Any) -> list[list[ParamRef]]:
    """Per table of the shipped fit, the parameters of scenario `s` that carry its shipped value,
    set by the scenario or as its component's default (the bending actuator's series
    resistance): a scenario takes a fitted value where it holds it."""
    out = []
    for t in fit["values"]:
        refs = [ParamRef.parse(r) for r in t["set"]]
        out.append([r for r in refs if r.instance in s.instances
                    and math.isclose(_value(s, r, fmu_dir), t["value"], rel_tol=1e-12)])
    return out


def _value(s: Scenario, ref: ParamRef, fmu_dir: Any) -> float:
    """The value of parameter `ref` in scenario `s`: the scenario's, else its FMU's default
    (NaN where it has neither)."""
    inst = s.instances[ref.instance]
    if ref.name in inst.parameters:
        return inst.parameters[ref.name]
    md = read_fmu(Path(fmu_dir) / f"{inst.component}.fmu")
    start = next((v.start for v in md.modelVariables if v.name == ref.name), None)
    return math.nan if start is None else float(start)


def _model_values(s: Scenario, carried: list[list[ParamRef]], fit: Mapping[str, Any],
                  model: Mapping[str, Any]) -> dict[ParamRef, float]:
    """The values of alternative `model` that reach scenario `s`: those of the shipped fit's
    parameters that `s` carries, and those of parameters the shipped fit does not hold (the
    values and effects it opens) where `s` has their instance."""
    fitted = {r for t in fit["values"] for r in t["set"]}
    carry = {str(r) for refs in carried for r in refs}
    out = {}
    for name, v in model["values"].items():
        ref = ParamRef.parse(name)
        if name in carry or (name not in fitted and ref.instance in s.instances):
            out[ref] = v
    return out


def _runs(s: Scenario, cases: list[dict[ParamRef, float]], fmu_dir: Any
          ) -> tuple[list[dict[str, float]], dict[str, str]]:
    """(the metrics of scenario `s` run with each of `cases` (values), the same cases run once;
    the metrics' units)."""
    def key(case: dict[ParamRef, float]) -> tuple[tuple[str, float], ...]:
        return tuple(sorted((str(r), v) for r, v in case.items()))

    unique = {key(c): c for c in cases}
    masters = [Master(with_values(s, c), fmu_dir) for c in unique.values()]
    metrics = {}
    for k, res in zip(unique, run_cases(masters)):
        if res.error:
            raise UserError(f"scenario {s.name} with "
                            f"{', '.join(f'{r}={v:g}' for r, v in k) or 'its values'}: {res.error}")
        metrics[k] = compute_metrics(res, s.metrics)
    units = signal_units(masters[0])
    return [metrics[key(c)] for c in cases], {
        n: metric_unit(units.get(m.signal), m.op, m.over is not None)
        for n, m in s.metrics.items()}


def scenario_predictions(s: Scenario, fit: Mapping[str, Any], models: list[dict[str, Any]],
                         study: Mapping[str, float], fmu_dir: Any) -> dict[str, Any]:
    """The predictions of every metric of scenario `s` (as shipped): its value, the fit's
    standard deviation through `fit`'s covariance, each admitted model's value (`models`), the
    90 % interval and the study's value (`study`, or None)."""
    carried = _carried(s, fit, fmu_dir)
    cases: list[dict[ParamRef, float]] = [{}]
    steps = []
    for k, refs in enumerate(carried):
        if refs:
            t = fit["values"][k]
            lower, upper = t["bounds"]
            lo, hi = propagate.points(t["value"], lower, upper, t["sd"])
            cases += [dict.fromkeys(refs, lo), dict.fromkeys(refs, hi)]
            steps.append((k, hi - lo))
    reach = [_model_values(s, carried, fit, m) for m in models]
    runs, units = _runs(s, cases + reach, fmu_dir)
    nominal, stepped, modelled = runs[0], runs[1:len(cases)], runs[len(cases):]
    cov = np.array(fit["covariance"])
    outcomes = {}
    for name, metric in s.metrics.items():
        g = np.zeros(len(carried))
        for j, (k, h) in enumerate(steps):
            g[k] = (stepped[2 * j + 1][name] - stepped[2 * j][name]) / h
        value, sd = nominal[name], propagate.outcome_sd(g, cov) if np.isfinite(g).all() \
            else math.nan
        ys = {m["name"]: r[name] for m, r in zip(models, modelled)}
        finite = math.isfinite(value) and math.isfinite(sd) and all(map(math.isfinite,
                                                                        ys.values()))
        iv = propagate.interval(value, sd, list(ys.values()), metric.op in _NONNEGATIVE) \
            if finite else None
        outcomes[name] = {
            "value": value if math.isfinite(value) else None,
            "interval90": list(iv) if iv else None, "fit_sd": sd if math.isfinite(sd) else None,
            "slopes": {str(carried[k][0]): float(g[k]) for k, _ in steps},
            "models": {n: (y if math.isfinite(y) else None) for n, y in ys.items()},
            "study": study.get(name), "unit": units[name]}
    return {"made_for": made_for(s),
            "carried": [str(r) for refs in carried for r in refs],
            "models_reach": {m["name"]: {str(r): v for r, v in values.items()}
                             for m, values in zip(models, reach)},
            "outcomes": outcomes}
