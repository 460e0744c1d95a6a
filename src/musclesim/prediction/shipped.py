"""The shipped predictions (scenarios/predictions/*.json) as a run's summary.json carries them:
`summary_entry` gives a scenario's predictions when the run is the one they were made for, else
why they do not apply; `made_for` is what a run must equal.

This module imports nothing above `musclesim.cosim`: `musclesim run` reads the predictions
through it without importing the diagnosis.
"""
from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

from musclesim.cosim import Scenario, shipped_scenarios

SUMMARY_KEY = "predictions"  # the key of summary.json that holds them


def folder() -> Path:
    """The folder of the shipped predictions: scenarios/predictions."""
    return shipped_scenarios() / "predictions"


def made_for(scenario: Scenario) -> dict[str, Any]:
    """What a run of `scenario` must equal for predictions made on it to apply: its times, step
    and every parameter value it sets."""
    return {"start_time": scenario.start_time, "stop_time": scenario.stop_time,
            "step": scenario.step,
            "parameters": {n: dict(sorted(i.parameters.items()))
                           for n, i in sorted(scenario.instances.items())}}


def _differences(run: dict[str, Any], made: dict[str, Any]) -> list[str]:
    """What differs between `run` and `made` (two `made_for`), in words."""
    out = [f"{k} {run[k]:g} s instead of {made[k]:g} s" for k in ("start_time", "stop_time")
           if run[k] != made[k]]
    if run["step"] != made["step"]:
        out.append(f"step {run['step']:g} s instead of {made['step']:g} s")
    names = sorted(set(run["parameters"]) | set(made["parameters"]))
    for n in names:
        a, b = run["parameters"].get(n), made["parameters"].get(n)
        if a is None or b is None:
            out.append(f"instance {n} {'added' if b is None else 'missing'}")
            continue
        for p in sorted(set(a) | set(b)):
            if a.get(p) != b.get(p):
                here = "its default" if a.get(p) is None else f"{a[p]:g}"
                there = "its default" if b.get(p) is None else f"{b[p]:g}"
                out.append(f"{n}.{p} = {here} instead of {there}")
    return out


def summary_entry(scenario: Scenario) -> dict[str, Any]:
    """``{SUMMARY_KEY: ...}`` for a run of `scenario` (as loaded with the run's ``--set`` and
    stop time) whose name has shipped predictions, else ``{}``.

    When the run is the one the predictions were made for (`made_for`), the entry holds, per
    metric, the prediction, its 90 % interval and the study's value (or null); otherwise it says
    ``"applies": false`` and why: a value or a time of their run changed, so their intervals
    would be wrong.
    """
    for path in sorted(folder().glob("*.json")):
        doc = json.loads(path.read_text())
        entry = doc["scenarios"].get(scenario.name)
        if entry is None:
            continue
        where = f"scenarios/predictions/{path.name}"
        differences = _differences(made_for(scenario), entry["made_for"])
        if differences:
            return {SUMMARY_KEY: {"applies": False, "file": where, "why": (
                "the predictions were made for the shipped scenario, and this run differs: "
                + "; ".join(differences))}}
        return {SUMMARY_KEY: {
            "applies": True, "file": where, "level": doc["level"], "created": doc["created"],
            "outcomes": {m: {k: o[k] for k in ("value", "interval90", "study", "unit")}
                         for m, o in entry["outcomes"].items()}}}
    return {}


def describe(entry: dict[str, Any]) -> list[str]:
    """Lines a user reads of `entry`, the value `summary_entry` gives under `SUMMARY_KEY`."""
    if not entry["applies"]:
        return [f"predictions ({entry['file']}) do not apply: {entry['why']}"]
    lines = [f"predictions with {100 * entry['level']:.0f} % intervals ({entry['file']}):"]
    for m, o in entry["outcomes"].items():
        value = "no value" if o["value"] is None else f"{o['value']:.4g}"
        lo, hi = o["interval90"] or (math.nan, math.nan)
        study = "" if o["study"] is None else f"; the study: {o['study']:.4g}"
        lines.append(f"  {m} = {value} [{lo:.4g}, {hi:.4g}] {o['unit']}{study}")
    return lines
