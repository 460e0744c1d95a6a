"""The diagnosis's sets and probabilities calibrated on a family of benches, and a gate for
benches unlike any of them.

When every candidate is wrong in form, Bayes factors grow with the record and the verdict goes to
whichever wrong candidate bends furthest toward the bench (Yang & Zhu, PNAS 2018; Oelrich et
al. 2020): the evidence's own probabilities cannot be trusted. Here they are recalibrated on a
pool of diagnosed cases whose truth is known, drawn from a family of bench forms
(`musclesim.benchmark.family`), and the set of possible causes gets a finite-sample guarantee:

- Each case's *alternatives* (`alternatives`): calibration only, every single effect the
  pipeline considered, every pair it fitted, another pair it did not fit, a change outside the
  library; each described by what the pipeline computed (`FEATURES`: its log evidence to the
  best, its posterior, the held-out gap it leaves, its parameters on their bounds, whether the
  calibration can mimic it, how far the pipeline got). A conditional logit over them
  (`conformal.fit_choice`, fitted by log loss on one part of the pool) gives calibrated
  probabilities; a cause's probability is the sum over its alternatives (the *causes*: calibration
  only, each single effect, ``two effects``, ``outside the library``).
- The set: per-cause (Mondrian) split conformal prediction on the pool's other part (Vovk et
  al. 2005; Romano, Sesia & Candès 2020): a cause is in the set when 1 - its probability is at
  most its cause's threshold. For a new case exchangeable with the family's cases, the truth is
  in the set with probability at least 1 - alpha *for every cause*, ``calibration only`` (no
  effect) included, so false alarms are bounded too.
- The gate: a conformal outlier test (Bates et al., Ann. Statist. 2023) on case-level features
  (`case_features`: the gaps in noise units before and after calibration and after the best
  candidate, the calibration's parameters on their bounds, the regimes' spread, the
  discrepancy's innovations against the noise): a p-value at
  most ``gate_alpha`` says the bench is outside the calibrated family; the set is then the
  nearest one, without its guarantee.

A calibration (`Confidence`) is data shipped with the package (``calibrations/<scenario>.json``,
made by ``musclesim benchmark-diagnosis --bench family --calibrate``); `assess` applies it to a
report.json document. User guide: docs/user/diagnosis-confidence.md.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass
from importlib import resources
from collections.abc import Sequence
from typing import Any

import numpy as np

from musclesim.diagnosis.conformal import (Outlyingness, choice_probabilities,
                                           conformal_p_value)
from musclesim.diagnosis.weigh import CALIBRATION_ONLY

TWO_EFFECTS = "two effects"  # a set's member: two of the library's effects at once
OUTSIDE_LIBRARY = "outside the library"  # a set's member: a change the library does not hold
ANOTHER_PAIR = "another pair"  # the alternative of a pair the pipeline did not fit
FEATURES = ("calibration only", "single", "pair", "outside", "fitted", "log evidence to best",
            "posterior", "most probable", "held-out gain", "on a bound",
            "mimicked by calibration", "effect's gain", "gains clearly", "signature holds",
            "stopped early", "calibrated gap", "gap left", "structured gap left")
CASE_FEATURES = ("nominal gap", "calibrated gap", "gap left", "calibration on bounds",
                 "regime spread", "innovation scale")
BOUND = 1e-3  # share of a parameter's range within which a value sits on its bound


def _log_ratio(a: Any, b: Any) -> float:
    """log(a / b), 0 where either is missing or not positive."""
    try:
        return math.log(float(a) / float(b)) if a and b and a > 0 and b > 0 else 0.0
    except (TypeError, ValueError):
        return 0.0


def _on_bounds(parameters: dict[str, Any]) -> float:
    """Share of `parameters` (report tables: value, lower, upper) within `BOUND` of a bound."""
    hits = [min(abs(p["value"] - p["lower"]), abs(p["upper"] - p["value"]))
            <= BOUND * (p["upper"] - p["lower"]) for p in parameters.values()
            if p.get("lower") is not None and p.get("upper") is not None
            and p["upper"] > p["lower"]]
    return sum(hits) / len(hits) if hits else 0.0


def _floor(doc: dict[str, Any]) -> float:
    return float(doc.get("noise_floor") or doc.get("gap", {}).get("noise_floor") or 0.0)


def _left(doc: dict[str, Any]) -> float | None:
    """The held-out gap left by the report's selected explanation (or calibration)."""
    all_ = doc.get("shrinkage", {}).get("all", {})
    return all_.get("after")


INTERACTED = ("log evidence to best", "held-out gain", "effect's gain")


def features(singles: list[str], signals: list[str], regimes: Sequence[str] = ()) -> list[str]:
    """The names of an alternative's features in a calibration knowing the single effects
    `singles`, the observed `signals` and the operating `regimes`: `FEATURES`; the held-out
    gain on each signal; per cause an intercept (how often the family has that cause, the rest
    given); and per cause each of `INTERACTED`, the gains per signal, the calibrated gap per
    signal and in each regime against the whole (how far each cause's evidence is to be
    trusted, which signals its signature is on, where the gap calibration leaves lies)."""
    gains = [f"gain on {s}" for s in signals]
    where = [f"calibrated gap on {s}" for s in signals] + [f"gap {r}" for r in regimes]
    return [*FEATURES, *gains, *(f"is {k}" for k in causes_of(singles)),
            *(f"{x} if {k}" for k in causes_of(singles) for x in (*INTERACTED, *gains, *where))]


def _where(doc: dict[str, Any], signals: Sequence[str], regimes: Sequence[str]) -> list[float]:
    """Where the calibrated gap of report.json document `doc` lies: per signal, its held-out
    gap against the signal's noise; per regime, its gap against the whole's (logs; 0 where the
    report has none)."""
    cal = doc.get("calibration", {}).get("signals", {})
    noise = doc.get("gap", {}).get("signals", {})
    table = doc.get("regimes", {}).get("by_regime", {})
    whole = table.get("all", {}).get("gap")
    return ([_log_ratio(cal.get(s, {}).get("after"), noise.get(s, {}).get("noise"))
             for s in signals]
            + [_log_ratio(table.get(r, {}).get("gap"), whole) for r in regimes])


def causes_of(singles: list[str]) -> list[str]:
    """The causes of a calibration knowing the single effects `singles`, in order."""
    return [CALIBRATION_ONLY, *singles, TWO_EFFECTS, OUTSIDE_LIBRARY]


def _gains(name: str, cands: dict[str, Any], effect: Any, signals: list[str]) -> list[float]:
    """The held-out gain (log of the gap before over after) of alternative `name` on each of
    `signals`: from its candidate's fit against calibration only's, else its effect's own fit."""
    c, base = cands.get(name), cands.get(CALIBRATION_ONLY)
    if c is not None and base is not None and name != CALIBRATION_ONLY:
        before, after = base.get("heldout_gap", {}), c.get("heldout_gap", {})
        return [_log_ratio(before.get(s), after.get(s)) for s in signals]
    per = (effect or {}).get("per_signal") or {}
    return [_log_ratio(per.get(s, {}).get("before"), per.get(s, {}).get("after"))
            for s in signals]


def alternatives(doc: dict[str, Any], singles: list[str], signals: Sequence[str] = (),
                 regimes: Sequence[str] = ()) -> list[tuple[str, str, list[float]]]:
    """The alternatives of a report.json document `doc`: (name, cause, features) with
    `features`(`singles`, `signals`) in order; `singles` the single effects the calibration
    knows (others the pipeline considered come as their own causes, without a cause's
    features), `signals` the observed signals its gains are on, `regimes` the operating regimes
    where its gap is read."""
    ev = doc.get("evidence") or {}
    cands = {c["name"]: c for c in ev.get("candidates", [])}
    best = max((c["log_evidence"] for c in cands.values()), default=0.0)
    base = cands.get(CALIBRATION_ONLY, {}).get("heldout_gap_all")
    base = base or doc.get("calibration", {}).get("heldout_gap_after")
    mimic = {n for s in ev.get("symmetries", []) if CALIBRATION_ONLY in s["candidates"]
             for n in s["candidates"]}
    early = doc.get("verdict") in ("none", "recalibration")
    floor = _floor(doc)
    calibrated = _log_ratio(doc.get("calibration", {}).get("heldout_gap_after"), floor)
    left = _log_ratio(_left(doc), floor)
    structured = float(doc.get("complete") is False)
    # by label: an effect fitted per instance is one candidate per instance, "anchoring slip
    # (friction1)", its label; elsewhere the label is the name
    effects = {e.get("label", e["name"]): e for e in doc.get("effects", [])}
    considered = list(effects)
    top = max(cands, key=lambda n: cands[n]["probability"]) if cands else CALIBRATION_ONLY
    causes = causes_of(singles)
    where = _where(doc, signals, regimes)
    names = [CALIBRATION_ONLY] + list(dict.fromkeys(singles + considered))
    names += [n for n in cands if " + " in n] + [ANOTHER_PAIR, OUTSIDE_LIBRARY]
    out = []
    for name in names:
        kind = ("calibration only" if name == CALIBRATION_ONLY else "outside"
                if name == OUTSIDE_LIBRARY else "pair" if " + " in name or name == ANOTHER_PAIR
                else "single")
        cause = {"pair": TWO_EFFECTS, "outside": OUTSIDE_LIBRARY, "single": name,
                 "calibration only": name}[kind]
        c = cands.get(name)
        f = dict.fromkeys(FEATURES, 0.0)
        f[kind] = 1.0
        if c is not None:
            f["fitted"] = 1.0
            f["log evidence to best"] = -math.log1p(max(best - c["log_evidence"], 0.0))
            f["posterior"] = float(c["probability"])
            f["held-out gain"] = _log_ratio(base, c.get("heldout_gap_all"))
            f["on a bound"] = _on_bounds({k: v for k, v in c.get("parameters", {}).items()
                                          if k not in doc.get("calibration", {}).get(
                                              "parameters", {})})
            f["mimicked by calibration"] = float(name in mimic and name != CALIBRATION_ONLY)
        f["most probable"] = float(name == top)
        e = effects.get(name)
        if e is not None:
            judged = e.get("judged") or {}
            # a fit whose run failed leaves an infinite gap: it says nothing of the effect
            gain = float(e.get("shrinkage") or 0.0)
            f["effect's gain"] = gain if math.isfinite(gain) else 0.0
            f["gains clearly"] = float(bool(judged.get("significant")))
            f["signature holds"] = float(bool((e.get("signature") or {}).get("consistent")))
        if kind == "calibration only":
            f["stopped early"] = float(early)
            f["calibrated gap"] = calibrated
        if kind == "outside":
            f["gap left"] = left
            f["structured gap left"] = structured
        gains = _gains(name, cands, e, list(signals))
        onehot = [float(cause == k) for k in causes]
        inter = [f[k] for k in INTERACTED] + gains + where
        out.append((name, cause, [f[k] for k in FEATURES] + gains + onehot
                    + [x * v for x in onehot for v in inter]))
    return out


def case_features(doc: dict[str, Any]) -> list[float]:
    """`CASE_FEATURES` of a report.json document `doc`, the gate's description of its bench."""
    floor = _floor(doc)
    cal = doc.get("calibration", {})
    gaps = [r["gap"] for r in doc.get("regimes", {}).get("by_regime", {}).values()
            if r.get("gap")]
    spread = math.log(max(gaps) / min(gaps)) if len(gaps) > 1 and min(gaps) > 0 else 0.0
    signals = doc.get("gap", {}).get("signals", {})
    disc = (doc.get("evidence") or {}).get("discrepancy", {})
    scales = [_log_ratio(d.get("sigma"), signals.get(s, {}).get("noise"))
              for s, d in disc.items()]
    return [_log_ratio(doc.get("gap", {}).get("heldout_gap"), floor),
            _log_ratio(cal.get("heldout_gap_after"), floor), _log_ratio(_left(doc), floor),
            _on_bounds(cal.get("parameters", {})), spread,
            sum(scales) / len(scales) if scales else 0.0]


@dataclass(frozen=True)
class Confidence:
    """A calibration of the sets for one scenario's diagnosis (its JSON document `data`)."""

    data: dict[str, Any]

    @property
    def causes(self) -> list[str]:
        """The causes the sets range over, in order."""
        return list(self.data["causes"])

    def probabilities(self, doc: dict[str, Any]) -> tuple[dict[str, float], dict[str, float]]:
        """({cause: calibrated probability}, {alternative: calibrated probability}) of
        report.json document `doc`."""
        alts = alternatives(doc, self.data["singles"], self.data["signals"],
                            self.data["regimes"])
        F = np.array([[a[2] for a in alts]], float)
        p = choice_probabilities(F, np.ones(F.shape[:2], bool),
                                 np.array(self.data["weights"], float))[0]
        by_cause: dict[str, float] = {}
        for (_, cause, _), pi in zip(alts, p):
            by_cause[cause] = by_cause.get(cause, 0.0) + float(pi)
        return by_cause, {a[0]: float(pi) for a, pi in zip(alts, p)}

    def assess(self, doc: dict[str, Any]) -> dict[str, Any]:
        """The calibrated part of report.json's ``evidence`` for document `doc`: ``set``,
        ``level``, ``probabilities`` (per cause), ``calibrated`` (per alternative), ``gate``,
        ``calibration``."""
        by_cause, by_alt = self.probabilities(doc)
        q = self.data["thresholds"]
        chosen = [k for k in self.causes if 1 - by_cause.get(k, 0.0) <= q.get(k, math.inf)]
        x = np.array([case_features(doc)], float)
        gate = self.data["gate"]
        score = float(Outlyingness.from_json(gate["outlyingness"]).score(x)[0])
        p = conformal_p_value(np.array(gate["scores"], float), score)
        return {"set": chosen, "level": 1 - self.data["alpha"],
                "probabilities": {k: by_cause.get(k, 0.0) for k in self.causes},
                "calibrated": by_alt,
                "gate": {"outside": bool(p <= gate["alpha"]), "p_value": p,
                         "alpha": gate["alpha"]},
                "calibration": {k: self.data[k] for k in ("name", "fingerprint", "family",
                                                          "cases", "created")}}


def load(scenario: str) -> Confidence | None:
    """The calibration shipped for scenario `scenario` (its name), or None."""
    try:
        text = (resources.files("musclesim.diagnosis") / "calibrations"
                / f"{scenario}.json").read_text()
    except (FileNotFoundError, OSError):
        return None
    return Confidence(json.loads(text))
