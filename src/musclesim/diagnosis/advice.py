"""What a report tells its reader to look at and to do next, read from report.json's document
(`musclesim.diagnosis.sections.Report.to_json` adds it; report.md says the same): the fitted
values on their bounds (`on_bound`, named in `warnings`) and the verdict's `next_step`, one
sentence per kind of verdict (none, a recalibration, an effect, a set of several, unexplained,
incomplete, outside the calibrated family). Nothing here changes a number of the diagnosis.
"""
from __future__ import annotations

from typing import Any

from musclesim.diagnosis.confidence import OUTSIDE_LIBRARY, TWO_EFFECTS
from musclesim.diagnosis.thresholds import ON_BOUND
from musclesim.diagnosis.weigh import CALIBRATION_ONLY

__all__ = ["on_bound", "bound_side", "with_bounds", "warnings", "next_step", "quantity", "WHY"]

Doc = dict[str, Any]  # a report.json document
WHY = "the data push beyond the range; a model-form warning"


def quantity(value: Any, unit: str | None, fmt: str = ".6g") -> str:
    """`value` written in format `fmt` with its `unit` (none written for "1"; "-" for no
    number).

    >>> quantity(285.15004, "K"), quantity(0.99250012, "1"), quantity(None, "s")
    ('285.15 K', '0.9925', '-')
    """
    if not isinstance(value, (int, float)) or value != value:
        return "-"
    return format(value, fmt) + ("" if unit in (None, "", "1") else f" {unit}")


def bound_side(x: Any, lo: Any, hi: Any) -> str | None:
    """"lower" or "upper": the bound a fitted value `x` between `lo` and `hi` sits on, within
    `ON_BOUND` of their range; None when it sits inside or there is no range (the rule of the
    diagnosis's reports and of `musclesim calibrate`'s alike).

    >>> bound_side(14.9, -5.0, 15.0), bound_side(10.0, -5.0, 15.0)
    ('upper', None)
    """
    if not (isinstance(x, (int, float)) and isinstance(lo, (int, float))
            and isinstance(hi, (int, float)) and hi > lo):
        return None
    near = ON_BOUND * (hi - lo)
    return "lower" if x <= lo + near else "upper" if x >= hi - near else None


def _side(entry: Doc) -> str | None:
    """`bound_side` of a report table's entry (value, lower, upper)."""
    return bound_side(entry.get("value"), entry.get("lower"), entry.get("upper"))


def on_bound(entry: Doc) -> bool:
    """Whether the fitted value `entry` (a report table's value, lower, upper) is on, or within
    `ON_BOUND` of its range from, a bound.

    >>> on_bound({"value": 0.99250012, "lower": 0.9925, "upper": 1.0075})
    True
    >>> on_bound({"value": 1.0, "lower": 0.9925, "upper": 1.0075})
    False
    """
    return _side(entry) is not None


def with_bounds(parameters: Doc) -> Doc:
    """The report table `parameters` ({name: value, lower, upper, ...}) with each entry's
    ``on_bound``."""
    return {k: {**p, "on_bound": on_bound(p)} for k, p in parameters.items()}


def _warning(name: str, entry: Doc) -> str:
    """The warning of value `name`'s `entry`, on its bound."""
    side = _side(entry) or "lower"
    unit = entry.get("unit")
    return (f"{name} = {quantity(entry['value'], unit)} is on its {side} bound "
            f"{quantity(entry[side], unit)} (within {ON_BOUND * 100:g} % of its range "
            f"{quantity(entry['lower'], unit)} to {quantity(entry['upper'], unit)}): {WHY}")


def _selected_effects(doc: Doc) -> list[Doc]:
    """The effects' entries the verdict selected."""
    chosen = set(doc.get("selected") or [])
    return [e for e in doc.get("effects") or [] if e["name"] in chosen or e["label"] in chosen]


def warnings(doc: Doc) -> list[str]:
    """One sentence per value of report.json document `doc` on its bound: the calibrated values
    and those of the effects the verdict selected.

    >>> warnings({"calibration": {"parameters": {"thermocouple.gain": {
    ...     "value": 0.99250012, "lower": 0.9925, "upper": 1.0075, "unit": "1"}}}})[0]
    'thermocouple.gain = 0.9925 is on its lower bound 0.9925 (within 1 % of its range 0.9925 to 1.0075): the data push beyond the range; a model-form warning'
    """
    out = [_warning(k, p) for k, p in doc.get("calibration", {}).get("parameters", {}).items()
           if on_bound(p)]
    for e in _selected_effects(doc):
        out += [f"{e['label']}: " + _warning(f"{','.join(e['instances'])}.{n}", p)
                for n, p in e["parameters"].items() if on_bound(p)]
    return out


def _sets(pairs: list[tuple[str, float]]) -> str:
    """``--set`` options of the (instance(s).parameter, value) `pairs`."""
    out = []
    for key, value in pairs:
        # "inst1,inst2.name": instance names hold no dot, a parameter's name may
        instances, name = key.split(".", 1) if "." in key else ("", key)
        out += [f"{inst}.{name}={value:.6g}" for inst in instances.split(",") if inst]
    return " ".join(f"--set {s}" for s in out)


def _worst(doc: Doc) -> str:
    """Where the calibrated gap is largest: the worst window, else the worst regime."""
    reg = doc.get("regimes") or {}
    windows = reg.get("worst_windows") or []
    if windows:
        w = windows[0]
        return f"{w['experiment']} {w['t0']:.2f}-{w['t1']:.2f} s"
    regimes = {k: r for k, r in (reg.get("by_regime") or {}).items()
               if isinstance(r.get("gap"), (int, float))}
    if regimes:
        return "the " + max(regimes, key=lambda k: regimes[k]["gap"]) + " regime"
    return "the held-out part"


def _farthest(doc: Doc) -> list[str]:
    """The calibrated values on their bounds, else the one farthest from its nominal value
    (as a share of its range)."""
    params = doc.get("calibration", {}).get("parameters", {})
    flagged = [k for k, p in params.items() if on_bound(p)]
    if flagged or not params:
        return flagged

    def moved(p: Doc) -> float:
        span = p["upper"] - p["lower"]
        return abs(p["value"] - p.get("nominal", p["value"])) / span if span > 0 else 0.0
    return [max(params, key=lambda k: moved(params[k]))]


def _outside_interval(entry: Doc) -> bool:
    """Whether calibrated value `entry`'s 95 % interval leaves out its nominal value."""
    iv, nominal = entry.get("interval") or [None, None], entry.get("nominal")
    numbers = [v for v in (*iv, nominal) if isinstance(v, (int, float))]
    return len(numbers) == 3 and not iv[0] <= nominal <= iv[1]


def _members(doc: Doc) -> list[str]:
    """The causes the report cannot tell apart: the calibrated set where the report has one,
    else the verdict's credible set (``A or B``)."""
    ev = doc.get("evidence") or {}
    if "gate" in ev:
        return list(ev.get("set") or [])
    return doc["verdict"].split(" or ")


def next_step(doc: Doc) -> str:
    """What to do next, one sentence, from report.json document `doc`: for no gap, where to test
    further; for a recalibration, the values to set; for an effect, how to add it (or, where
    calibration mimics it, what separates them); for a set of several, the experiment or
    condition that separates them; for unexplained and incomplete verdicts, where the gap left
    lies; outside the calibrated family, where the model must first come closer."""
    ev = doc.get("evidence") or {}
    if (ev.get("gate") or {}).get("outside"):
        where = ", ".join(_farthest(doc)) or "its calibration"
        return (f"bring the model closer to this bench first (where it differs most: {where}), "
                "then diagnose again: outside the calibrated family the set is only a hint")
    verdict = doc["verdict"]
    if verdict == "none":
        return (f"keep the model as it is (its held-out gap "
                f"{quantity(doc.get('gap', {}).get('heldout_gap'), '1', '.3g')} of the range is "
                f"within the noise floor {quantity(doc.get('noise_floor'), '1', '.3g')}), and test "
                "it again on a recording of conditions these data do not cover")
    if verdict == "unexplained":
        return (f"look for a difference the library does not hold where the calibrated gap is "
                f"largest ({_worst(doc)}), model it, and diagnose again")
    members = _members(doc)
    syms = [s for s in ev.get("symmetries") or []
            if set(s["candidates"]) & set(members + list(doc.get("selected") or []))]
    if len(members) > 1:
        if syms:
            s = syms[0]
            return (f"to tell {' from '.join(s['candidates'])}, {s['breaks_with'][0]}, and "
                    "diagnose again")
        effects = [m for m in members if m not in (CALIBRATION_ONLY, TWO_EFFECTS,
                                                   OUTSIDE_LIBRARY)]
        return (f"record longer, or an experiment that excites "
                f"{' and '.join(effects) or 'the suspects'} differently, and diagnose again")
    left = ("" if doc.get("complete", True) else
            f", then look for the further difference the library does not hold where the gap "
            f"left is largest ({_worst(doc)})")
    chosen = _selected_effects(doc)
    if chosen:
        if syms:
            s = syms[0]
            return (f"to tell {s['candidates'][0]} from a recalibration of "
                    f"{', '.join(s['with']) or 'nothing'}, {s['breaks_with'][0]}, and diagnose "
                    f"again{left}")
        sets = _sets([(f"{','.join(e['instances'])}.{n}", p["value"])
                      for e in chosen for n, p in e["parameters"].items()])
        return (f"add {' and '.join(e['label'] for e in chosen)} to the model (`{sets}` or the "
                f"scenario's parameters) and check it on a new recording{left}")
    params = doc.get("calibration", {}).get("parameters", {})
    moved = {k: p for k, p in params.items() if _outside_interval(p)} or params
    sets = _sets([(k, p["value"]) for k, p in moved.items()])
    return (f"set the calibrated values in the scenario's parameters (`{sets}`) and check them on "
            f"a new recording{left}" if sets else
            f"keep the nominal values and check them on a new recording{left}")
