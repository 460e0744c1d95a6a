"""The candidates and their fits: calibration parameters, candidate effects, each fit described.

The nominal values a real bench has differently (`effects.CALIBRATION`) are calibrated first
(`calibration` gives their `Free` parameters); every candidate effect of the located components
(`candidates`) is then fitted together with them, the best two fitted again with every Jacobian
column fresh (`refine`). Each fit is described for the report against calibration alone on the
observed signals it can change (`musclesim.diagnosis.problem.affected`; `score`, `judge`): its
held-out gain with a block-bootstrap interval, where it gains (its regime), how far the
calibration makes its signature too (`aliasing`); `cross_signal` says whether two signals that
share a state place the gap in a sensor or in the plant. Which cause the data favour is weighed
by evidence (`musclesim.diagnosis.weigh`); `explained` says whether a gap left is unstructured.

>>> explained(0.02, 1.0, 0.01)  # within STRUCTURED (3) noise floors
True
>>> explained(0.05, 1.0, 0.01), explained(0.05, 0.5, 0.01)  # ... or RESIDUAL_SHARE (0.1) of before
(True, True)
>>> explained(0.2, 1.0, 0.01)
False
"""
import math
from dataclasses import dataclass, replace

import numpy as np

from musclesim.diagnosis.effects import by_component, calibration_of
from musclesim.diagnosis.fitting import Free, FitJob, FitResult, fit_all
from musclesim.diagnosis.problem import affected, downstream
from musclesim.diagnosis.stats import (HELD_OUT, TRAIN, before_after, bootstrap, gap, interval95,
                                       part_rows,
                                       row_squares)
from musclesim.diagnosis.thresholds import (DEVIATES, MIN_SHRINKAGE,
                                            MIN_VALUES_PER_PARAMETER, REFINED,
                                            RESIDUAL_SHARE, SIGNATURE_MIN, STRUCTURED)

NO_GAP = ("the model matches the data within the noise on the held-out part: there is no gap to "
          "explain")


@dataclass
class Candidate:
    """An effect placed on instances of its component, with its free parameters."""

    effect: object  # effects.Effect
    instances: tuple
    free: list

    @property
    def label(self):
        """The effect's name, with the instance for a per-instance effect."""
        return self.effect.name + (f" ({self.instances[0]})" if self.effect.per_instance else "")


def _nominal(problem, unit, inst, name):
    s = unit.runs[0].scenario
    if name in s.instances[inst].parameters:
        return float(s.instances[inst].parameters[name])
    return float(problem.vars[inst][name].start)


def _by_component(unit, instances):
    out = {}
    for inst in sorted(instances):
        if inst in unit.components:
            out.setdefault(unit.components[inst], []).append(inst)
    return out


def calibration(problem, unit, instances=None):
    """The calibration parameters (`Free`, absolute bounds) of the components of `instances`
    (default: all of `unit`'s) that act on an observed signal, one per component and parameter
    for all its instances together, the periodic ones first.
    A value the data set states as a bench condition (``[conditions]``) is fixed, not
    calibrated, and so is an input the scenario connects or the data set replays. Nothing is
    calibrated when the training part holds fewer than MIN_VALUES_PER_PARAMETER values per
    parameter (scalar metrics)."""
    rows = sum(int(np.count_nonzero(m)) for m in part_rows(unit, TRAIN)) * len(unit.observed)
    s = unit.runs[0].scenario
    taken = set(problem.ds.conditions) | {dst for _, dst in s.connections}
    taken |= set().union(*(run.inputs for run in unit.runs))
    out = []
    acting = [i for i in instances or unit.instances if affected(unit, (i,))]
    for comp, insts in _by_component(unit, acting).items():
        for c in calibration_of(comp):
            free = tuple(i for i in insts if f"{i}.{c.name}" not in taken)
            if free:
                nominal = _nominal(problem, unit, free[0], c.name)
                out.append(Free(free, c.name, *c.bounds(nominal), nominal, c.period))
    out.sort(key=lambda f: not f.period)  # the periodic first: `fit` scans them (`scanned`)
    # a handful of metrics cannot pin several nominal values: too few training values, none
    return out if rows >= MIN_VALUES_PER_PARAMETER * len(out) else []


def scanned(free):
    """How many of the calibration parameters `free` (`calibration`'s, the periodic first) a
    calibration from the nominal values scans: the periodic ones, whose nominal value may lie
    in any of their cost's wells."""
    return sum(1 for f in free if f.period)


def candidates(problem, unit, suspects):
    """The `Candidate` effects of the `suspects`' components in `unit`."""
    out = []
    for comp, insts in _by_component(unit, suspects).items():
        for e in by_component(comp):
            groups = [(i,) for i in insts] if e.per_instance else [tuple(insts)]
            for g in groups:
                free = [Free(g, p.name, p.lower, p.upper, _nominal(problem, unit, g[0], p.name))
                        for p in e.parameters]
                out.append(Candidate(e, g, free))
    return out


def refine(unit, cands, fits, calib, latency, fmu_dir, pmap):
    """`fits` with the REFINED candidates that fit the training part best fitted again from
    their values with every Jacobian column fresh (a refit replaces a fit only when it lowers
    the training cost). The first fits reuse the calibration's columns, taken at the calibrated
    values without the effect: quasi-Newton steps that can stop short of the joint optimum.
    Without calibration parameters every column was fresh already: `fits` as they are."""
    if not calib:
        return fits
    order = sorted((i for i, f in enumerate(fits) if f.residuals is not None and f.applicable),
                   key=lambda i: fits[i].train_gap)[:REFINED]
    again = fit_all([FitJob(unit, cands[i].free + calib, fmu_dir, x0=fits[i].x, scan=0,
                            latency=latency) for i in order], pmap)
    out = list(fits)
    for i, f in zip(order, again):
        if f.residuals is not None and f.train_gap < fits[i].train_gap:
            out[i] = replace(f, applicable=fits[i].applicable)
    return out


def aliasing(jac, k, names):
    """How far the calibration parameters can stand in for an effect on these data, to first
    order: {"share", "index", "with"} from a fit's Jacobian `jac` (training residuals, the
    effect's `k` columns first, then the calibration parameters `names`), or None (no
    Jacobian, no calibration, an effect that changes nothing).

    ``share`` is the squared cosine of the largest principal angle between the effect's columns
    and the calibration's (for one parameter: the R^2 of its column regressed on theirs): the
    part of the effect's least aliased signature calibration makes too. ``index`` is
    1 / sqrt(1 - share), read as Brun et al.'s (2001) collinearity index is: the change of the
    outputs the effect makes can be compensated by the calibration parameters down to 1 / index
    of it (its norm). ``with`` names the two calibration parameters that carry most of that
    compensation.

    >>> J = np.array([[1.0, 1.0, 0.0], [1.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    >>> a = aliasing(J, 1, ["T_amb", "shift"])  # (1, 1, 0) projects to (1, .5, .5): 1.5 of 2
    >>> round(a["share"], 3), a["with"]
    (0.75, ['T_amb', 'shift'])
    >>> J[:, 0] = J[:, 1] - J[:, 2]  # a bias that an ambient and a shift make together
    >>> round(aliasing(J, 1, ["T_amb", "shift"])["share"], 6)
    1.0
    """
    if jac is None or jac.shape[1] <= k:
        return None
    E, C = jac[:, :k], jac[:, k:]
    if not np.any(E):
        return None

    def basis(A):
        u, sv, _ = np.linalg.svd(A, full_matrices=False)
        return u[:, sv > sv[0] * 1e-9]

    qe = basis(E)
    cosines = np.linalg.svd(basis(C).T @ qe, compute_uv=False)
    share = float(min(cosines) ** 2) if len(cosines) == qe.shape[1] else 0.0
    beta = np.linalg.lstsq(C, E, rcond=None)[0]
    carried = np.abs(beta).sum(axis=1) * np.linalg.norm(C, axis=0)
    order = np.argsort(-carried)[:2]
    return {"share": share, "index": 1 / math.sqrt(max(1 - share, 1e-12)),
            "with": [names[i] for i in order if carried[i] > 0]}


def _aliasing_in(f, k, calib):
    """`aliasing` of fit `f`'s first `k` parameters by the calibration parameters `calib` that
    ended inside their bounds: one at a bound cannot move on (the thermocouple's gain at its
    tolerance cannot stand in for a larger bias)."""
    inside = [i for i, (fr, x) in enumerate(zip(calib, f.x[k:]))
              if fr.lower + 1e-3 * (fr.upper - fr.lower) < x
              < fr.upper - 1e-3 * (fr.upper - fr.lower)]
    jac = f.jac
    return aliasing(None if jac is None else jac[:, list(range(k)) + [k + i for i in inside]],
                    k, [f"{','.join(calib[i].instances)}.{calib[i].name}" for i in inside])


def calibration_table(free, f):
    """The report's calibrated values: {instance(s).parameter: value, 95 % interval, nominal,
    bounds} of `free` fitted as `f`."""
    return {f"{','.join(fr.instances)}.{fr.name}": {
        "value": x, "interval": list(iv), "nominal": fr.start, "lower": fr.lower,
        "upper": fr.upper} for fr, x, iv in zip(free, f.x, f.interval)}


def gain_signature(gain, mask):
    """(ratio, consistent) from per-sample gains (squared residual before - after) and the
    regime's mask of the same samples (None: the effect predicts no regime, it is consistent when
    it gains at all). The ratio is the mean gain in the regime over the mean gain overall."""
    if mask is None:
        return None, gain.sum() > 0
    if not mask.any() or gain.sum() <= 0:
        return None, False
    ratio = float(gain[mask].mean() / gain.mean())
    return ratio, ratio >= SIGNATURE_MIN


def signature(unit, res_before, res_after, regime_masks, columns=None):
    """Gain per held-out sample (of `columns`) in the effect's regime vs overall: (ratio,
    consistent)."""
    rows = part_rows(unit, HELD_OUT)
    gain = np.concatenate([a - b for a, b in zip(row_squares(unit, res_before, HELD_OUT, columns),
                                                 row_squares(unit, res_after, HELD_OUT, columns))])
    mask = None if regime_masks is None else \
        np.concatenate([m[r] for m, r in zip(regime_masks, rows)])
    return gain_signature(gain, mask)


def judge(unit, res_before, res_after, columns, regime, masks):
    """An effect's held-out gain over `res_before` on the signals it can change (`columns`): the
    gap there before and after, the gain 1 - after / before with its 95 % block-bootstrap
    interval, its signature in `regime`, and whether it counts: the gap there is material (one
    of those signals deviates, above DEVIATES times its own noise), the gain is at least
    MIN_SHRINKAGE,
    its interval lies above zero and it shows in the regime."""
    before = gap(unit, res_before, HELD_OUT, columns)
    after = gap(unit, res_after, HELD_OUT, columns)
    boot = bootstrap(unit, [res_before, res_after], columns)
    interval = interval95(1 - boot[:, 1] / boot[:, 0])
    ratio, consistent = signature(unit, res_before, res_after,
                                  masks.get(regime) if regime != "all" else None, columns)
    gain = 1 - after / before if before else 0.0
    material = any(gap(unit, res_before, HELD_OUT, [c]) > DEVIATES * unit.noise[c] for c in columns)
    return {"signals": list(columns), "before": before, "after": after, "gain": gain,
            "interval": interval, "significant": bool(interval[0] > 0),
            "material": bool(material),
            "signature": {"regime": regime, "gain_ratio": ratio, "consistent": bool(consistent)},
            "counts": bool(material and gain >= MIN_SHRINKAGE and interval[0] > 0
                           and consistent)}


def score(unit, base, cand, f, masks, calib=()):
    """The report's entry of candidate `cand` fitted with the calibration parameters as `f` (a
    `fit` result, the effect's parameters first) in `unit`, against its `baseline` `base`:
    its values, the pooled held-out gaps, the per-signal before/after and the judgement on the
    signals it can change (`judge`), ``counts``; ``baseline`` says which it was."""
    k = len(cand.free)
    res = f.residuals
    entry = {"name": cand.effect.name, "label": cand.label, "component": cand.effect.component,
             "instances": list(cand.instances), "reference": cand.effect.reference,
             "parameters": {fr.name: {"value": x, "interval": list(iv), "lower": fr.lower,
                                      "upper": fr.upper, "off": fr.start}
                            for fr, x, iv in zip(cand.free, f.x[:k], f.interval[:k])},
             "calibration": {f"{','.join(fr.instances)}.{fr.name}": x
                             for fr, x in zip(calib, f.x[k:])},
             "applicable": f.applicable, "heldout_gap_before": base["heldout_gap"],
             "baseline": "its own fit with the effect off" if base.get("effect_off")
             else "calibration",
             "heldout_gap_after": f.heldout_gap, "aliasing": _aliasing_in(f, k, calib)}
    entry["shrinkage"] = 1 - entry["heldout_gap_after"] / entry["heldout_gap_before"] \
        if entry["heldout_gap_before"] else 0.0
    if res is None:
        entry.update(judged=None, per_signal={}, interval=[0.0, 0.0], counts=False,
                     signature={"regime": cand.effect.regime, "gain_ratio": None,
                                "consistent": False})
        return entry
    j = judge(unit, base["residuals"], res, affected(unit, cand.instances), cand.effect.regime,
              masks)
    entry.update(judged=j, interval=j["interval"], signature=j["signature"],
                 per_signal={c: before_after(unit, base["residuals"], res, [c])
                             for c in unit.observed},
                 counts=bool(f.applicable and j["counts"]))
    return entry


@dataclass(frozen=True)
class Scored:
    """A candidate's report `entry` (`score`) with the `candidate` and its `fit`."""

    entry: dict
    candidate: Candidate
    fit: FitResult


def rank(unit, bases, cands, fits, masks, calib=()):
    """Score and rank the candidates `cands` fitted as `fits` in `unit`, each against its
    baseline in `bases` (counting ones first, then by pooled held-out gap after), each entry's
    ``margin`` to the next, with the regime `masks` and the calibration parameters `calib`
    (`score`): a `Scored` each, ranked."""
    scored = sorted((Scored(score(unit, b, c, f, masks, calib), c, f)
                     for b, c, f in zip(bases, cands, fits)),
                    key=lambda t: (not t.entry["counts"], t.entry["heldout_gap_after"]))
    entries = [t.entry for t in scored]
    for a, b in zip(entries, entries[1:] + [None]):
        a["margin"] = None if b is None else (b["heldout_gap_after"] - a["heldout_gap_after"]) \
            / a["heldout_gap_before"]
    return scored


def explained(after, before, floor):
    """Whether a held-out gap left `after` is unstructured: within STRUCTURED noise floors, or
    at most RESIDUAL_SHARE of the gap `before`."""
    return after <= STRUCTURED * floor or after <= RESIDUAL_SHARE * before


def cross_signal(unit, entries, selected):
    """Where the gap lies, from the observed signals' consistency: the report's
    ``consistency`` sentence, or None when no two observed signals share an upstream state.

    Signals that depend on one unobserved state (the thermocouple and the strain on the wire's
    temperature) locate a difference: an effect that changes only its sensor's channel, the
    other signals agreeing with the calibrated plant, places the gap in the sensor; an effect of
    the plant must improve every signal downstream of it together.
    """
    shared = {inst: affected(unit, (inst,)) for inst in unit.instances}
    shared = {i: cols for i, cols in shared.items() if len(cols) > 1}
    if not shared or not entries:
        return None
    # the nearest common source: of those feeding the most signals, the one feeding fewest
    # instances (the wire, not the load that pulls on it)
    most = max(len(cols) for cols in shared.values())
    source = min((i for i in shared if len(shared[i]) == most),
                 key=lambda i: len(downstream(unit, (i,))))
    e = selected[0] if selected else entries[0]
    j = e.get("judged")
    if not j:
        return None
    ps = e.get("per_signal", {})

    def change(cols):
        return ", ".join(f"{c} {ps[c]['before']:.3g} -> {ps[c]['after']:.3g}" for c in cols
                         if c in ps)

    others = [c for c in shared[source] if c not in j["signals"] and c in ps]
    what = "The selected" if selected else "The best-ranked (not counting)"
    unsure = "" if e["counts"] else " (it does not count, so nothing is placed)"
    if others:
        agree = [c for c in others if ps[c]["after"] <= DEVIATES * unit.noise[c]]
        tail = (f"with it (the calibration refitted) {', '.join(others)} agree with the model of "
                f"{source} within the noise ({change(others)}): the gap is placed in the sensor, "
                f"not in {source}" if len(agree) == len(others) else
                f"{', '.join(c for c in others if c not in agree)} still deviate "
                f"({change(others)}): {source} differs from its model too")
        return (f"{', '.join(shared[source])} all depend on the state of {source}. {what} "
                f"{e['label']} can change only {', '.join(j['signals'])} "
                f"({change(j['signals'])}); {tail}{unsure}.")
    return (f"{', '.join(shared[source])} all depend on the state of {source}; {what.lower()} "
            f"{e['label']} acts on it and changes them together ({change(j['signals'])}): the gap "
            f"is placed in {source}, where the signals agree, not in one sensor{unsure}.")
