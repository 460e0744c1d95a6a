"""The data-set format's checks: manifest.toml's tables and data.csv's columns read into a
`musclesim.diagnosis.measured.DataSet`, every mistake of the format reported (`build`).

Each function appends the problems it finds, each naming its file (and key, column or
experiment), to a list, so that `musclesim.diagnosis.dataset.load` reports them all at once.
"""
from __future__ import annotations

import math
import tomllib
from pathlib import Path
from typing import Any

import numpy as np

from musclesim.cosim import ParamRef, Signal, format_problem
from musclesim.diagnosis.measured import (DATA, MANIFEST, PARTS, DataSet, Experiment,
                                          MeasuredMetric, OpenValue, Split, part_mask)

_TOP_KEYS = {"format", "description", "reference", "scenario", "inputs", "outputs", "units",
             "conditions", "experiments", "split", "calibrate"}
_EXPERIMENT_KEYS = {"span", "scenario", "description", "metrics", "stop_time", "conditions"}
_CALIBRATE_KEYS = {"set", "bounds", "why"}
_METRIC_KEYS = {"value", "unit", "uncertainty", "description"}
_SPLIT_KEYS = {"held_out", "train", "held_out_fraction"}


def _number(value: Any) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def find_scenario(reference: str, manifest_dir: str | Path,
                  scenarios_dir: str | Path | None = None) -> Path | None:
    """Resolve `reference`, a manifest's scenario reference, to a file, or None if there is none.

    A reference ending in ``.toml`` is a path relative to the manifest's folder `manifest_dir`;
    a name is looked up as ``<name>.toml`` in `scenarios_dir`, by default the nearest folder
    named ``scenarios`` that holds the manifest, else ``./scenarios``.
    """
    manifest_dir = Path(manifest_dir)
    if reference.endswith(".toml"):
        path = manifest_dir / reference
        return path if path.is_file() else None
    if scenarios_dir is None:
        holders = [p for p in manifest_dir.resolve().parents if p.name == "scenarios"]
        scenarios_dir = holders[0] if holders else Path("scenarios")
    path = Path(scenarios_dir) / f"{reference}.toml"
    return path if path.is_file() else None


def read_manifest(path: Path, problems: list[str]) -> dict[str, Any] | None:
    """The table of manifest file `path`, or None with the reason appended to `problems`."""
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        problems.append(f"{MANIFEST} is missing")
    except (OSError, UnicodeDecodeError) as exc:
        problems.append(f"{MANIFEST} cannot be read: {exc}")
    except tomllib.TOMLDecodeError as exc:
        problems.append(f"{MANIFEST} is not valid TOML: {exc}")
    return None


def _param(text: Any) -> ParamRef | None:
    """The parameter `text` names (``"instance.name"``), None if it is not of that form."""
    try:
        return ParamRef.parse(text)
    except ValueError:
        return None


def _names(value: Any, what: str, problems: list[str]) -> tuple[str, ...]:
    if value is None:
        return ()
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        problems.append(f"{MANIFEST}: '{what}' must be a list of strings")
        return ()
    return tuple(value)


def build(path: Path, m: dict[str, Any], table: tuple | None, has_data: bool,
          scenarios_dir: str | Path | None, problems: list[str]) -> DataSet | None:
    """The `DataSet` in folder `path` from its manifest's table `m` and data.csv's `table`
    ((header, time, data) as `musclesim.cosim.read_time_series` reads it, None if unusable;
    `has_data`: data.csv exists), scenario names looked up in `scenarios_dir`; None, with every
    mistake of the format appended to `problems`, if there is any."""
    for key in sorted(set(m) - _TOP_KEYS):
        problems.append(f"{MANIFEST}: unknown key {key!r} (known: {', '.join(sorted(_TOP_KEYS))})")
    inputs = _names(m.get("inputs"), "inputs", problems)
    outputs = _names(m.get("outputs"), "outputs", problems)
    units = m.get("units", {})
    if not isinstance(units, dict) or not all(isinstance(u, str) for u in units.values()):
        problems.append(f"{MANIFEST}: [units] must map columns to unit strings")
        units = {}
    reference = m.get("scenario", "")
    if not isinstance(reference, str):
        problems.append(f"{MANIFEST}: 'scenario' must be a string")
        reference = ""
    scenario_path = find_scenario(reference, path, scenarios_dir) if reference else None

    header, time, data = table if table is not None else (None, None, None)
    columns = tuple(header[1:]) if header else ()
    _columns(inputs, outputs, units, header, columns, has_data, problems)
    if units.get("time", "s") != "s":
        problems.append(f"{MANIFEST}: time must be in 's', not {units['time']!r}")

    conditions = _conditions(m.get("conditions", {}), columns, problems)
    experiments = _experiments(m.get("experiments"), reference, path, scenarios_dir, time,
                               has_data, problems)
    split = _split(m.get("split"), experiments, time, has_data, problems,
                   fit_all=not has_data and bool(m.get("calibrate")))
    calibrate = _calibrate(m.get("calibrate", []), problems)
    fmt = m.get("format", 1)
    if problem := format_problem(fmt):
        problems.append(f"{MANIFEST}: {problem}")
    if problems:
        return None
    assert split is not None, "no split without a problem said"
    # every name is checked by now (each a column of data.csv, whose header read_time_series
    # checked): data.csv's header and the lists become Signals here, once
    signals = {c: Signal.parse(c) for c in columns}
    return DataSet(path=path, scenario=reference, scenario_path=scenario_path,
                   inputs=tuple(signals[c] for c in inputs),
                   outputs=tuple(signals[c] for c in outputs),
                   units={signals[c]: units.get(c) for c in columns},
                   experiments=experiments, split=split, time=time,
                   columns=tuple(signals.values()), data=data,
                   description=str(m.get("description", "")), reference=str(m.get("reference", "")),
                   conditions=conditions, calibrate=calibrate, format=fmt)


def _columns(inputs: tuple[str, ...], outputs: tuple[str, ...], units: dict[str, str],
             header: list[str] | None, columns: tuple[str, ...], has_data: bool,
             problems: list[str]) -> None:
    """The manifest's `inputs`, `outputs` and `units` against data.csv's `header` (its
    `columns`; `has_data`: data.csv exists): each listed once, each a column, each column
    listed."""
    if not has_data:
        if inputs or outputs or units:
            problems.append(f"{DATA} is missing but {MANIFEST} lists columns (inputs, outputs "
                            "or units)")
        return
    for name in inputs:
        if name in outputs:
            problems.append(f"{MANIFEST}: column {name!r} is both an input and an output")
    listed = set(inputs) | set(outputs)
    if header is not None:
        for name in [*inputs, *outputs]:
            if name not in columns:
                problems.append(f"{MANIFEST}: column {name!r} is missing from {DATA}")
        for name in columns:
            if name not in listed:
                problems.append(f"{DATA}: column {name!r} is in neither inputs nor outputs "
                                f"of {MANIFEST}")
        for name in units:
            if name != "time" and name not in columns:
                problems.append(f"{MANIFEST}: [units] names {name!r}, not a column of {DATA}")
    if not outputs:
        problems.append(f"{MANIFEST}: no 'outputs' (observed columns)")


def _conditions(raw: Any, columns: tuple[str, ...], problems: list[str],
                where: str = MANIFEST) -> dict[ParamRef, float]:
    """``{ParamRef: value}`` of the manifest's [conditions] table `raw` ("instance.variable" =
    value; or an experiment's, `where`), none of them one of data.csv's `columns`."""
    if not isinstance(raw, dict):
        problems.append(f"{where}: [conditions] must map \"instance.variable\" to numbers")
        return {}
    out = {}
    for name, value in raw.items():
        ref = _param(name)
        if ref is None:
            problems.append(f"{where}: [conditions] {name!r} is not of the form "
                            "\"instance.variable\"")
        elif isinstance(value, bool) or not isinstance(value, (int, float)) \
                or not math.isfinite(value):
            problems.append(f"{where}: [conditions] {name!r} must be a finite number")
        elif name in columns:
            problems.append(f"{MANIFEST}: [conditions] {name!r} is also a column of {DATA}: "
                            "state it once")
        else:
            out[ref] = float(value)
    return out


def _experiments(raw: Any, reference: str, path: Path, scenarios_dir: str | Path | None,
                 time: np.ndarray | None, has_data: bool,
                 problems: list[str]) -> dict[str, Experiment]:
    if raw is None:
        raw = {"all": {}} if has_data else {}
    if not isinstance(raw, dict) or (not raw and not has_data):
        problems.append(f"{MANIFEST}: a scalar-only set (no {DATA}) needs [experiments.NAME] "
                        "tables with metrics")
        return {}
    out = {}
    for name, spec in raw.items():
        where = f"{MANIFEST}, experiment {name!r}"
        if not isinstance(spec, dict):
            problems.append(f"{where}: must be a table")
            continue
        if "/" in name:
            problems.append(f"{where}: the name must not contain '/'")
        for key in sorted(set(spec) - _EXPERIMENT_KEYS):
            problems.append(f"{where}: unknown key {key!r} "
                            f"(known: {', '.join(sorted(_EXPERIMENT_KEYS))})")
        ref = spec.get("scenario", reference)
        if not isinstance(ref, str) or not ref:
            problems.append(f"{where}: no scenario (give 'scenario' at the top or in the "
                            "experiment)")
            ref = ""
        metrics = _metrics(spec.get("metrics", {}), where, problems)
        if not has_data and not metrics:
            problems.append(f"{where}: no metrics (the set has no {DATA})")
        span = None
        if has_data:
            span = _span(spec, where, time, problems)
        elif "span" in spec:
            problems.append(f"{where}: 'span' needs {DATA}, which is missing")
        stop = spec.get("stop_time")
        if stop is not None and (has_data or not _number(stop) or stop <= 0):
            problems.append(f"{where}: stop_time {stop!r} " + (
                f"is for scalar-only sets (with {DATA} the span gives the duration)" if has_data
                else "is not a positive number of seconds"))
            stop = None
        out[name] = Experiment(name, span, ref, find_scenario(ref, path, scenarios_dir)
                               if ref else None, metrics, str(spec.get("description", "")),
                               None if stop is None else float(stop),
                               _conditions(spec.get("conditions", {}), (), problems, where))
    spans = sorted((e.span, e.name) for e in out.values() if e.span is not None)
    for (a, na), (b, nb) in zip(spans, spans[1:]):
        if b[0] < a[1]:
            problems.append(f"{MANIFEST}: experiments {na!r} {list(a)} and {nb!r} {list(b)} "
                            "overlap")
    return out


def _calibrate(raw: Any, problems: list[str]) -> tuple[OpenValue, ...]:
    """The manifest's ``[[calibrate]]`` tables as `OpenValue`s."""
    where = f"{MANIFEST}, [[calibrate]]"
    if not isinstance(raw, list) or not all(isinstance(t, dict) for t in raw):
        problems.append(f"{where} must be tables, each with set = [\"instance.parameter\", ...] "
                        "and bounds = [lower, upper]")
        return ()
    out = []
    for k, spec in enumerate(raw, start=1):
        at = f"{where} {k}"
        for key in sorted(set(spec) - _CALIBRATE_KEYS):
            problems.append(f"{at}: unknown key {key!r} "
                            f"(known: {', '.join(sorted(_CALIBRATE_KEYS))})")
        targets = spec.get("set")
        if not (isinstance(targets, list) and targets
                and all(_param(t) is not None for t in targets)):
            problems.append(f"{at}: set must list one or more \"instance.parameter\" names")
            continue
        bounds = spec.get("bounds")
        if not (isinstance(bounds, list) and len(bounds) == 2 and all(_number(b) for b in bounds)
                and bounds[0] < bounds[1]):
            problems.append(f"{at}: bounds {bounds!r} is not [lower, upper] with lower < upper")
            continue
        out.append(OpenValue(tuple(ParamRef.parse(t) for t in targets), float(bounds[0]),
                             float(bounds[1]), str(spec.get("why", ""))))
    taken = [str(t) for v in out for t in v.targets]
    for t in sorted({t for t in taken if taken.count(t) > 1}):
        problems.append(f"{where}: {t!r} is in more than one set")
    return tuple(out)


def _span(spec: dict[str, Any], where: str, time: np.ndarray | None,
          problems: list[str]) -> tuple[float, float] | None:
    if "span" not in spec:
        if time is not None:
            return (float(time[0]), float(time[-1]))
        return (-math.inf, math.inf)
    span = spec["span"]
    if not (isinstance(span, list) and len(span) == 2 and all(_number(x) for x in span)
            and span[0] < span[1]):
        problems.append(f"{where}: span {span!r} is not [t0, t1] with t0 < t1 [s]")
        return None
    t0, t1 = float(span[0]), float(span[1])
    if time is not None:
        if t0 < time[0] or t1 > time[-1]:
            problems.append(f"{where}: span [{t0!r}, {t1!r}] s is outside the data "
                            f"[{float(time[0])!r}, {float(time[-1])!r}] s of {DATA}")
        elif np.count_nonzero((time >= t0) & (time <= t1)) < 2:
            problems.append(f"{where}: span [{t0!r}, {t1!r}] s holds fewer than two samples")
    return (t0, t1)


def _metrics(raw: Any, where: str, problems: list[str]) -> dict[str, MeasuredMetric]:
    if not isinstance(raw, dict):
        problems.append(f"{where}: 'metrics' must be a table")
        return {}
    out = {}
    for name, spec in raw.items():
        at = f"{where}, metric {name!r}"
        if not isinstance(spec, dict) or not _number(spec.get("value")):
            problems.append(f"{at}: needs value = a finite number")
            continue
        for key in sorted(set(spec) - _METRIC_KEYS):
            problems.append(f"{at}: unknown key {key!r} (known: {', '.join(sorted(_METRIC_KEYS))})")
        unit = spec.get("unit", "1")
        if not isinstance(unit, str):
            problems.append(f"{at}: unit must be a string")
            unit = "1"
        u = spec.get("uncertainty")
        if u is not None and not (_number(u) and u >= 0):
            problems.append(f"{at}: uncertainty {u!r} is not a finite number >= 0")
            u = None
        out[name] = MeasuredMetric(float(spec["value"]), unit,
                                   None if u is None else float(u),
                                   str(spec.get("description", "")))
    return out


def _split(raw: Any, experiments: dict[str, Experiment], time: np.ndarray | None,
           has_data: bool, problems: list[str], fit_all: bool = False) -> Split | None:
    """The [split] table; `fit_all`: the set is scalar-only and names open values, so its
    held-out part may be empty (``held_out = []``: `musclesim calibrate` fits every outcome
    and predicts none)."""
    where = f"{MANIFEST}, [split]"
    if not isinstance(raw, dict):
        problems.append(f"{MANIFEST}: no [split] table (held_out = [experiment names], or "
                        "held_out_fraction = a fraction of each experiment, last in time)")
        return None
    for key in sorted(set(raw) - _SPLIT_KEYS):
        problems.append(f"{where}: unknown key {key!r} (known: {', '.join(sorted(_SPLIT_KEYS))})")
    if "held_out_fraction" in raw:
        if "held_out" in raw or "train" in raw:
            problems.append(f"{where}: give either held_out_fraction or held_out/train, not both")
        f = raw["held_out_fraction"]
        if not has_data:
            problems.append(f"{where}: held_out_fraction needs time series ({DATA} is missing)")
            return None
        if not (_number(f) and 0 < f < 1):
            problems.append(f"{where}: held_out_fraction {f!r} is not a number between 0 and 1")
            return None
        if time is not None:
            for e in experiments.values():
                if e.span is None:
                    continue
                for part in PARTS:
                    if np.count_nonzero(part_mask(time, e.span, part, f)) < 2:
                        problems.append(f"{where}: held_out_fraction {f!r} leaves the {part} "
                                        f"part of experiment {e.name!r} with fewer than two "
                                        "samples")
        return Split(fraction=float(f))
    if "held_out" not in raw:
        problems.append(f"{where}: needs held_out = [experiment names] or held_out_fraction")
        return None
    held = _names(raw.get("held_out"), "split.held_out", problems)
    train = _names(raw.get("train"), "split.train", problems) if "train" in raw else \
        tuple(n for n in experiments if n not in held)
    for part, names in (("held_out", held), ("train", train)):
        for n in names:
            if n not in experiments:
                problems.append(f"{where}: {part} names unknown experiment {n!r} "
                                f"(experiments: {', '.join(experiments) or 'none'})")
        if not names and not (part == "held_out" and fit_all):
            problems.append(f"{where}: the {part} part is empty")
    for n in set(held) & set(train):
        problems.append(f"{where}: experiment {n!r} is both in train and held_out")
    return Split(train=train, held_out=held)
