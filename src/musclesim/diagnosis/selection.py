"""Choosing the effect: candidates, their recalibrated rivals, scores, the signature, the verdict.

An effect counts when it shrinks the held-out gap by `MIN_SHRINKAGE`, leaves at most
`BEAT_RECALIBRATED` of the gap of the nominal model with as many nominal parameters recalibrated,
and gains at least `SIGNATURE_MIN` of its average per sample in the regime it predicts
(`musclesim.diagnosis.thresholds`). The best counting effect is selected; a second one is added
greedily when it shrinks the remaining gap by `MIN_SHRINKAGE` again. `verdict` names the outcome.

>>> explained(0.02, 1.0, 0.01)  # within STRUCTURED (3) noise floors
True
>>> explained(0.05, 1.0, 0.01), explained(0.05, 0.5, 0.01)  # ... or RESIDUAL_SHARE (0.1) of before
(True, True)
>>> explained(0.2, 1.0, 0.01)
False
"""
from dataclasses import dataclass

import numpy as np

from musclesim.diagnosis.effects import CALIBRATION, by_component
from musclesim.diagnosis.fitting import Free, fit, fit_task
from musclesim.diagnosis.stats import (before_after, bootstrap, gap, interval95, part_rows,
                                       row_squares)
from musclesim.diagnosis.thresholds import (BEAT_RECALIBRATED, MIN_SHRINKAGE, MOST,
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


def candidates(problem, unit, suspects):
    """The `Candidate` effects of the `suspects`' components and the nominal parameters they may
    recalibrate (`Free`, absolute bounds from `effects.CALIBRATION`'s factors): (candidates,
    calibration)."""
    out = []
    by_comp = {}
    for inst in suspects:
        if inst in unit.components:
            by_comp.setdefault(unit.components[inst], []).append(inst)
    for comp, insts in by_comp.items():
        for e in by_component(comp):
            groups = [(i,) for i in insts] if e.per_instance else [tuple(insts)]
            for g in groups:
                free = [Free(g, p.name, p.lower, p.upper, _nominal(problem, unit, g[0], p.name))
                        for p in e.parameters]
                out.append(Candidate(e, g, free))
    calib = []
    for comp, insts in by_comp.items():
        for p in CALIBRATION.get(comp, ()):
            nom = _nominal(problem, unit, insts[0], p.name)
            calib.append(Free(tuple(insts), p.name, p.lower * nom, p.upper * nom, nom))
    return out, calib


def recalibrated(unit, res_nom, calib, calib_fits, k_max, fmu_dir):
    """The nominal model's competitors: {k: held-out gap with k nominal parameters refitted} and
    their table. k = 1 is the best single parameter on held-out data (the strictest rival);
    k = 2 refits the two best on training data together."""
    recal, table = {0: gap(unit, res_nom, 1)}, []
    if not calib_fits:
        return recal, table
    recal[1] = min(f["heldout_gap"] for f in calib_fits)
    table = [{"parameters": {f"{','.join(c.instances)}.{c.name}": f["x"][0]},
              "heldout_gap": f["heldout_gap"]} for c, f in zip(calib, calib_fits)]
    if len(calib) > 1 and k_max > 1:
        pair = [calib[i] for i in np.argsort([f["train_gap"] for f in calib_fits])[:2]]
        f2 = fit(unit, pair, fmu_dir)
        recal[2] = f2["heldout_gap"]
        table.append({"parameters": {f"{','.join(c.instances)}.{c.name}": x
                                     for c, x in zip(pair, f2["x"])},
                      "heldout_gap": f2["heldout_gap"]})
    return recal, table


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


def signature(unit, res_nominal, res_effect, regime_masks):
    """Gain of an effect per held-out sample in its regime vs overall: (ratio, consistent)."""
    rows = part_rows(unit, 1)
    gain = np.concatenate([a - b for a, b in zip(row_squares(unit, res_nominal, 1),
                                                 row_squares(unit, res_effect, 1))])
    mask = None if regime_masks is None else \
        np.concatenate([m[r] for m, r in zip(regime_masks, rows)])
    return gain_signature(gain, mask)


def score(unit, res_nom, cand, f, recal, masks):
    """The report's entry of candidate `cand` fitted as `f` (a `fit` result) in `unit`: held-out
    gaps, shrinkage, its rival ``recal[k]`` (k its free parameters), signature, ``counts``."""
    before = gap(unit, res_nom, 1)
    after = f["heldout_gap"]
    res = f["residuals"]
    recal_gap = recal.get(len(cand.free), recal.get(max(recal)))
    regime = cand.effect.regime
    ratio, consistent = (None, False) if res is None else \
        signature(unit, res_nom, res, masks.get(regime) if regime != "all" else None)
    entry = {"name": cand.effect.name, "label": cand.label, "component": cand.effect.component,
             "instances": list(cand.instances), "spec": cand.effect.spec,
             "parameters": {fr.name: {"value": x, "interval": list(iv), "lower": fr.lower,
                                      "upper": fr.upper, "off": fr.start}
                            for fr, x, iv in zip(cand.free, f["x"], f["interval"])},
             "applicable": f["applicable"], "heldout_gap_before": before,
             "heldout_gap_after": after, "shrinkage": 1 - after / before if before else 0.0,
             "recalibrated_gap": recal_gap,
             "beats_recalibrated": bool(after <= BEAT_RECALIBRATED * recal_gap),
             "signature": {"regime": regime, "gain_ratio": ratio, "consistent": bool(consistent)}}
    if res is not None:
        boot = bootstrap(unit, [res_nom, res])
        entry["interval"] = interval95(1 - boot[:, 1] / boot[:, 0])
        entry["per_signal"] = {c: before_after(unit, res_nom, res, [c]) for c in unit.observed}
    else:
        entry["interval"] = [0.0, 0.0]
    entry["counts"] = bool(f["applicable"] and res is not None
                           and entry["shrinkage"] >= MIN_SHRINKAGE
                           and entry["beats_recalibrated"] and consistent)
    return entry


def rank(unit, res_nom, cands, fits, recal, masks):
    """Score and rank the candidates (counting ones first, then by held-out gap after), each
    entry's ``margin`` to the next: (entries, [(entry, candidate, fit) that count])."""
    scored = sorted(((score(unit, res_nom, c, f, recal, masks), c, f)
                     for c, f in zip(cands, fits)),
                    key=lambda t: (not t[0]["counts"], t[0]["heldout_gap_after"]))
    entries = [e for e, _, _ in scored]
    for a, b in zip(entries, entries[1:] + [None]):
        a["margin"] = None if b is None else (b["heldout_gap_after"] - a["heldout_gap_after"]) \
            / a["heldout_gap_before"]
    return entries, [t for t in scored if t[0]["counts"]]


def select(unit, counting, floor, masks, pmap, fmu_dir, say):
    """The selected entries and the final fit: the best counting effect, and greedily a second
    one (of the next three, refitted jointly) when the first leaves a structured gap and the pair
    shrinks it by MIN_SHRINKAGE again, with the second's signature."""
    if not counting:
        return [], None
    e1, c1, f1 = counting[0]
    selected, final = [e1], f1
    if explained(f1["heldout_gap"], e1["heldout_gap_before"], floor) or len(counting) < 2:
        return selected, final
    say("greedy: a second effect")
    pairs = counting[1:4]
    pair_fits = pmap(fit_task, [(unit, c1.free + c.free, fmu_dir, None,
                                 f1["x"] + [fr.start for fr in c.free])
                                for _, c, _ in pairs])
    (e2, c2, _), f12 = min(zip(pairs, pair_fits), key=lambda t: t[1]["heldout_gap"])
    regime = c2.effect.regime
    _, ok = signature(unit, f1["residuals"], f12["residuals"],
                      None if regime == "all" else masks.get(regime))
    if ok and f12["heldout_gap"] <= (1 - MIN_SHRINKAGE) * f1["heldout_gap"]:
        selected.append(e2)
        e2["joint_values"] = dict(zip([f"{fr.name}" for fr in c1.free + c2.free], f12["x"]))
        final = f12
    return selected, final


def explained(after, before, floor):
    """Whether a held-out gap left `after` is unstructured: within STRUCTURED noise floors, or
    at most RESIDUAL_SHARE of the gap `before`."""
    return after <= STRUCTURED * floor or after <= RESIDUAL_SHARE * before


def complete(selected, final, floor):
    """Whether the selected effects leave an unstructured gap (the report's ``complete``)."""
    return bool(selected) and explained(final["heldout_gap"], selected[0]["heldout_gap_before"],
                                        floor)


def verdict(selected, final, recal, recal_table, floor, deviates=True):
    """(verdict, explanation): ``none`` when nothing `deviates`; else from the selected effects
    (entries of `score`), the final fit and the recalibrated rivals (`recalibrated`)."""
    if not deviates:
        return "none", NO_GAP
    best_recal = min(recal_table, key=lambda r: r["heldout_gap"], default=None)
    if not selected and best_recal and explained(best_recal["heldout_gap"], recal[0], floor):
        values = ", ".join(f"{k} = {v:.4g}" for k, v in best_recal["parameters"].items())
        return "recalibration", (f"no unmodelled effect is needed: the nominal model with {values} "
                                 f"recalibrated leaves a held-out gap of "
                                 f"{best_recal['heldout_gap']:.3g} (noise floor {floor:.3g})")
    if not selected:
        return "unexplained", ("no candidate effect of the located component(s) shrinks the "
                               "held-out gap enough, beats the recalibrated nominal model and "
                               "shows in its regime")
    first, labels = selected[0], " + ".join(e["label"] for e in selected)
    before, after = first["heldout_gap_before"], final["heldout_gap"]
    if explained(after, before, floor):
        return first["name"], (f"{labels} shrinks the held-out gap from {before:.3g} to "
                               f"{after:.3g} (noise floor {floor:.3g})")
    if after <= (1 - MOST) * before:
        return first["name"], (f"{labels} explains {1 - after / before:.0%} of the held-out gap "
                               f"({before:.3g} -> {after:.3g}); the rest, {after / floor:.1f} "
                               "noise floors, stays structured: a further difference the "
                               "library does not hold")
    return "unexplained", (f"the best candidate ({labels}) leaves a structured held-out gap of "
                           f"{after:.3g}, {after / floor:.1f} noise floors, of {before:.3g}")


def selected_values(entries, selected):
    """``{(instance, parameter): value}`` of the selected effects (joint values when refitted)."""
    out = {}
    for e in entries:
        if e["name"] in selected:
            for name, spec in e["parameters"].items():
                out.update({(inst, name): spec["value"] for inst in e["instances"]})
    joint = next((e.get("joint_values") for e in entries if e.get("joint_values")), None)
    if joint:
        for e in entries:
            if e["name"] in selected:
                out.update({(inst, name): joint[name] for name in e["parameters"] if name in joint
                            for inst in e["instances"]})
    return out
