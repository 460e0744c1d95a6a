"""The diagnosis's sets calibrated on a pool of family cases, and the sets' scores.

`build` turns a pool (a folder of family cases diagnosed, with its key.json, as ``musclesim
benchmark-diagnosis --bench family`` (or ``crawler-family``) writes it) of one family of bench
forms (a `musclesim.benchmark.family.Family`, `FAMILIES` by name) into a calibration document
(`musclesim.diagnosis.confidence.Confidence`): the pool is split per cause, a third to fit the
conditional logit (its ridge chosen there by cross-validation) and the gate's scale, two thirds
to calibrate the per-cause thresholds and the gate's scores. It also reports leave-one-form-out
coverage (`lofo`: calibrated without every case of one form, scored on those) and a reliability
table. `score` scores diagnosed cases' sets against their key. `fingerprint` is the method's:
the source of everything that makes a case's features (the diagnosis, the family and its bench,
this module), docstrings and comments left out; a calibration made with another is stale (a
test checks the shipped ones).
"""
from __future__ import annotations

import ast
import datetime
import hashlib
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from musclesim import diagnosis
from musclesim.benchmark import family, family_crawler
from musclesim.benchmark.family import Family
from musclesim.diagnosis import (ANOTHER_PAIR, CALIBRATION_ONLY, TWO_EFFECTS, Confidence,
                                 Outlyingness, alternatives, case_features, choose_ridge,
                                 fit_choice, mondrian_thresholds, reliability)

ALPHA = 0.05  # the sets' level: the truth in the set at least 95 % of the time, per cause
GATE_ALPHA = 0.03  # the gate fires on at most 3 % of the family's cases
FIT_SHARE = 1 / 3  # of each cause's pool cases, to fit the logit and the gate's scale
SPLIT_SEED = 57
# the logit's ridges tried, one chosen per calibration by five-fold cross-validation of the log
# loss on the pool's fit part only (`choose_ridge`; the document records each one's loss)
RIDGES = (1e-2, 1e-3, 3e-4, 1e-4, 3e-5)
FAMILIES: dict[str, Family] = {f.bench: f for f in (family.SMA, family_crawler.CRAWLER)}
# the benchmark's modules every family's cases pass through, besides its own `Family.sources`
SHARED = ("family.py", "plan.py", "calibrate.py", "cases.py", "recording.py")


def fingerprint(fam: Family = family.SMA) -> str:
    """sha256 of the method's source for family `fam` (`diagnosis` but its report writer, the
    benchmark's shared modules, the family and its bench), each module's syntax tree without
    docstrings."""
    here = Path(__file__).parent
    files = sorted(p for p in Path(diagnosis.__file__).parent.glob("*.py")
                   if p.name != "report.py")
    files += [here / name for name in dict.fromkeys(SHARED + fam.sources)]
    h = hashlib.sha256()
    for p in files:
        tree = ast.parse(p.read_text())
        for node in ast.walk(tree):
            body = getattr(node, "body", None)
            if (isinstance(body, list) and body and isinstance(body[0], ast.Expr)
                    and isinstance(body[0].value, ast.Constant)
                    and isinstance(body[0].value.value, str)):
                node.body = body[1:] or [ast.Pass()]  # type: ignore[attr-defined]
        h.update(p.name.encode() + ast.dump(tree).encode())
    return h.hexdigest()


def pool(folder: str | Path) -> list[tuple[dict[str, Any], dict[str, Any]]]:
    """(case, report.json document) of every diagnosed case in `folder` (its key.json)."""
    folder = Path(folder)
    key = json.loads((folder / "key.json").read_text())
    out = []
    for case in key["cases"]:
        path = folder / "cases" / case["case"] / "report.json"
        out.append((case, json.loads(path.read_text())))
    return out


def _truth(case: dict[str, Any], names: list[str]) -> str:
    """The name of `case`'s true alternative among `names`."""
    cause = case["cause"]
    if cause == TWO_EFFECTS:
        for n in names:
            if " + " in n and set(n.split(" + ")) == set(case["pair"]):
                return n
        return ANOTHER_PAIR
    return cause


def _arrays(rows: list[tuple[dict, dict]], fam: Family) -> dict[str, Any]:
    """Padded (features, available, truth index, alternatives' causes) of `rows` of `fam`."""
    alts = [alternatives(doc, list(fam.library), fam.signals, fam.regimes) for _, doc in rows]
    width = max(len(a) for a in alts)
    F = np.zeros((len(rows), width, len(alts[0][0][2])))
    avail = np.zeros((len(rows), width), bool)
    truth = np.zeros(len(rows), int)
    for i, ((case, _), a) in enumerate(zip(rows, alts)):
        names = [x[0] for x in a]
        F[i, :len(a)] = [x[2] for x in a]
        avail[i, :len(a)] = True
        truth[i] = names.index(_truth(case, names))
    return {"F": F, "available": avail, "truth": truth, "alternatives": alts}


def _split(rows: list[tuple[dict, dict]],
           fam: Family = family.SMA) -> tuple[list[int], list[int]]:
    """(fit, calibration) indices: `FIT_SHARE` of each of `fam`'s causes' cases to fit, at
    random."""
    rng = np.random.default_rng(SPLIT_SEED)
    fit, cal = [], []
    for cause in fam.causes:
        idx = [i for i, (c, _) in enumerate(rows) if c["cause"] == cause]
        idx = [idx[j] for j in rng.permutation(len(idx))]
        k = int(round(FIT_SHARE * len(idx)))
        fit += idx[:k]
        cal += idx[k:]
    return sorted(fit), sorted(cal)


def calibrate(rows: list[tuple[dict, dict]], fit: list[int], cal: list[int],
              meta: dict[str, Any] | None = None, fam: Family = family.SMA,
              ridges: tuple[float, ...] = RIDGES) -> dict[str, Any]:
    """A calibration document from pool `rows` of family `fam`: the logit (its ridge the
    cross-validated best of `ridges`) and the gate's scale fitted on the rows `fit`, the
    thresholds and the gate's scores on the rows `cal`."""
    singles = list(fam.library)
    a = _arrays([rows[i] for i in fit], fam)
    l2, losses = choose_ridge(a["F"], a["available"], a["truth"], ridges, seed=SPLIT_SEED)
    weights = fit_choice(a["F"], a["available"], a["truth"], l2)
    scale = Outlyingness.fit(np.array([case_features(rows[i][1]) for i in fit]))
    doc: dict[str, Any] = {
        "name": f"{fam.scenario}-{fam.bench}-{fam.version}", "scenario": fam.scenario,
        "alpha": ALPHA, "singles": singles, "causes": list(fam.causes),
        "weights": weights.tolist(),
        "ridge": {"l2": l2, "cross_validated_log_loss": {str(k): v for k, v in losses.items()},
                  "uniform_log_loss": float(np.log(a["available"].sum(axis=1)).mean())},
        "signals": fam.signals, "regimes": fam.regimes,
        "features": diagnosis.confidence_features(singles, fam.signals, fam.regimes),
        "thresholds": {}, "gate": {"alpha": GATE_ALPHA, "outlyingness": scale.to_json(),
                                   "scores": []},
        **(meta or {})}
    cal_rows = [rows[i] for i in cal]
    probe = Confidence({**doc, "thresholds": {}, "gate": {**doc["gate"], "scores": [0.0]}})
    scores = [1 - probe.probabilities(d)[0].get(c["cause"], 0.0) for c, d in cal_rows]
    q = mondrian_thresholds(np.array(scores), np.array([c["cause"] for c, _ in cal_rows]),
                            ALPHA)
    doc["thresholds"] = {k: (v if math.isfinite(v) else 1.0) for k, v in q.items()}
    doc["scores"] = {k: sorted(s for s, (c, _) in zip(scores, cal_rows) if c["cause"] == k)
                     for k in fam.causes}
    doc["gate"]["scores"] = scale.score(
        np.array([case_features(d) for _, d in cal_rows])).tolist()
    return doc


def build(folder: str | Path, fam: Family = family.SMA) -> dict[str, Any]:
    """The calibration document of the diagnosed pool of family `fam` in `folder`, with its
    reliability table and leave-one-form-out coverage (``lofo``)."""
    rows = pool(folder)
    fit, cal = _split(rows, fam)
    key = json.loads((Path(folder) / "key.json").read_text())
    meta = {"fingerprint": fingerprint(fam),
            "family": {"version": fam.version, "seed": key["seed"], "cases": len(rows)},
            "cases": {"fit": len(fit), "calibration": len(cal)},
            "created": datetime.date.today().isoformat()}
    doc = calibrate(rows, fit, cal, meta, fam)
    cal_obj = Confidence(doc)
    doc["reliability"] = _reliability(cal_obj, [rows[i] for i in cal])
    doc["lofo"] = lofo(rows, fit, cal, fam)
    return doc


def _reliability(cal: Confidence, rows: list[tuple[dict, dict]]) -> list[Any]:
    """Stated probability against observed frequency over every cause of every row."""
    probs, hits = [], []
    for case, doc in rows:
        p = cal.probabilities(doc)[0]
        for k in cal.causes:
            probs.append(p.get(k, 0.0))
            hits.append(k == case["cause"])
    return reliability(np.array(probs), np.array(hits))


def lofo(rows: list[tuple[dict, dict]], fit: list[int], cal: list[int],
         fam: Family = family.SMA, ridges: tuple[float, ...] = RIDGES) -> dict[str, Any]:
    """Leave one form out: per subsystem of family `fam` and form, the coverage on the pool's
    cases of that form of a calibration made without any of them (its ridge too chosen
    without them, among `ridges`); and over all forms, per subsystem."""
    out: dict[str, Any] = {}
    for sub, options in fam.forms.items():
        per: dict[str, Any] = {}
        hit_all = n_all = 0
        for form in options:
            keep = lambda idx: [i for i in idx if rows[i][0]["forms"][sub] != form]  # noqa: E731
            test = [rows[i] for i in range(len(rows)) if rows[i][0]["forms"][sub] == form]
            if not test:
                continue
            doc = calibrate(rows, keep(fit), keep(cal), fam=fam, ridges=ridges)
            doc.update(fingerprint="", family={}, cases={}, created="")
            s = score([c for c, _ in test], [d for _, d in test], Confidence(doc), fam)
            per[form] = {"cases": s["cases"], "coverage": s["coverage"],
                         "mean_set_size": s["mean_set_size"]}
            hit_all += round(s["coverage"] * s["cases"])
            n_all += s["cases"]
        out[sub] = {"forms": per, "coverage": hit_all / n_all if n_all else None}
    return out


def score(cases: list[dict[str, Any]], docs: list[dict[str, Any]],
          cal: Confidence | None = None, fam: Family = family.SMA) -> dict[str, Any]:
    """The sets' scores over `cases` of family `fam` and their report.json `docs`: coverage overall
    and per cause, set sizes (mean and distribution), false alarms (no effect hidden, yet
    calibration only left out), the gate's firing rate, a reliability table. With `cal` the
    sets are made here from the documents; without, read from their ``evidence``."""
    rows = []
    for case, doc in zip(cases, docs):
        if cal is not None:
            got = cal.assess(doc)
        else:
            got = doc.get("evidence") or {}
        rows.append({"case": case["case"], "cause": case["cause"], "set": got.get("set", []),
                     "probabilities": got.get("probabilities", {}),
                     "gate": (got.get("gate") or {}).get("outside"),
                     "forms": case.get("forms")})
    n = len(rows)
    covered = [r["cause"] in r["set"] for r in rows]
    sizes = [len(r["set"]) for r in rows]
    per = {k: {"cases": sum(r["cause"] == k for r in rows),
               "coverage": _mean([c for c, r in zip(covered, rows) if r["cause"] == k])}
           for k in fam.causes}
    probs = [r["probabilities"].get(k, 0.0) for r in rows for k in fam.causes]
    hits = [r["cause"] == k for r in rows for k in fam.causes]
    none = [r for r in rows if r["cause"] == CALIBRATION_ONLY]
    return {"cases": n, "coverage": _mean(covered), "per_cause": per,
            "mean_set_size": _mean(sizes),
            "set_sizes": {str(s): sizes.count(s) for s in sorted(set(sizes))},
            "false_alarm_rate": _mean([CALIBRATION_ONLY not in r["set"] for r in none]),
            "gate_rate": _mean([bool(r["gate"]) for r in rows]),
            "reliability": reliability(np.array(probs), np.array(hits)) if n else [],
            "per_case": rows}


def _mean(values: list[Any]) -> float | None:
    return sum(map(float, values)) / len(values) if values else None


def write(path: str | Path, doc: dict[str, Any]) -> None:
    """Write calibration document `doc` to `path` (JSON)."""
    Path(path).write_text(json.dumps(doc, indent=1) + "\n")


__all__ = ["build", "calibrate", "lofo", "score", "fingerprint", "pool", "write", "ALPHA",
           "GATE_ALPHA", "RIDGES", "FAMILIES"]
