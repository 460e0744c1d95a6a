"""Scenario files: parse and check the TOML that wires FMU instances into an experiment.

A scenario names instances (a component: the name of an FMU in the FMU folder, parameter
values, inline or from a TOML file given as ``parameters_file`` relative to the scenario and
inside its folder, inline values winning, ``every``: how many communication steps the
instance takes at once, and ``isolate``: whether it runs in a child process of its own),
connections ``"a.y" -> "b.u"``, the communication step, start and stop
time, the master algorithm, the signals to record, the metrics to compute and the plot panels.
A file may ``extends = "other.toml"``, and declares its ``format`` (`musclesim.cosim.FORMAT`):
how its files are read and merged is `musclesim.cosim.scenario_files`'s. Each signal is parsed
once, here, into a `Signal`; the scenario's data flow is its `Scenario.graph`. Checks collect
every problem and raise once with the whole list: among them an instance no table declares
(named once, with the declared name nearest it: `unknown_instance`) and a value its component
declares implausible (`implausible`: a temperature in Celsius, a length in mm), before any FMU
is read. No message repeats a value read from a parameters file (it may hold what is not ours to
print), only its key.

Limits: a step of at least `MIN_STEP`, at most `MAX_STEPS` communication steps, times of at most
`MAX_TIME` in magnitude, ``every`` at most `MAX_EVERY`.
"""
from __future__ import annotations

import difflib
import math
import re
import tomllib
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import Any, NamedTuple

from musclesim.cosim import plausible
from musclesim.cosim.address import ParamRef, Signal
from musclesim.cosim.graph import Graph
from musclesim.cosim.scenario_files import read
from musclesim.errors import UserError

ALGORITHMS = ("gauss-seidel", "jacobi")
METRIC_OPS = ("final", "initial", "mean", "min", "max", "max_abs", "rms", "rate", "peak_to_peak",
              "per_period", "frequency", "cycle_peak_to_peak")
_PERIODIC = ("per_period", "cycle_peak_to_peak")  # ops that need a period
_TOP_KEYS = {"format", "name", "description", "reference", "step", "start_time", "stop_time",
             "algorithm", "connections", "record", "instances", "metrics", "plots"}
MIN_STEP = 1e-7  # s: a communication step shorter than any physics here needs
MAX_STEPS = 100_000_000  # communication steps of one run (hours of compute at the fastest)
MAX_TIME = 1e9  # s: start and stop times (about 30 years)
MAX_EVERY = 1_000_000  # communication steps an instance may take at once (multi-rate)
_COMPONENT = re.compile(r"[A-Za-z_][A-Za-z0-9_-]*")  # an FMU's file name, never a path


class Metric(NamedTuple):
    """A number computed from one signal: ``op`` over the samples from time ``start`` to ``stop``,
    times ``scale`` (e.g. -1 to count a backward run's distance along its direction of travel).
    ``period`` [s] is the period of ops ``per_period`` (mean change per period, e.g. per stride)
    and ``cycle_peak_to_peak`` (mean peak-to-peak per period). ``over``: another signal; the
    metric is then the op on ``signal`` divided by the op on ``over`` (a ratio, unit 1).
    """

    signal: Signal
    op: str
    start: float = -math.inf
    stop: float = math.inf
    scale: float = 1.0
    period: float | None = None
    over: Signal | None = None


@dataclass(frozen=True)
class Panel:
    """One panel of a run's plot: its `title` and the `signals` drawn in it."""

    title: str
    signals: tuple[Signal, ...]


@dataclass(frozen=True)
class Instance:
    """One FMU instance: its `name`, the `component` (FMU) it instantiates, its `parameters`'
    values and `every`: it steps at every ``every``-th communication point, by ``every`` steps at
    once (multi-rate; 1 = at every point); `isolate`: it runs in a child process of its own (an
    FMU one does not trust: `musclesim.cosim.isolated`)."""

    name: str
    component: str
    parameters: dict[str, float] = field(default_factory=dict)
    every: int = 1
    isolate: bool = False


@dataclass(frozen=True)
class Scenario:
    """A checked scenario (see the module docstring); each signal a `Signal`.

    Its `name`, the file at `path` it was read from (None for one made in code), the `instances`
    by name, the `connections` (output, input), the communication `step` [s] from `start_time`
    to `stop_time` [s], the master's `algorithm` (`ALGORITHMS`), the signals to `record`, the
    `metrics` by name, the `plots`' panels, and the `description` and `reference` (where the
    experiment comes from) it states.
    """

    name: str
    path: Path | None
    instances: dict[str, Instance]
    connections: tuple[tuple[Signal, Signal], ...]  # ((source, destination), ...)
    step: float
    stop_time: float
    start_time: float = 0.0
    algorithm: str = "gauss-seidel"
    record: tuple[Signal, ...] = ()
    metrics: dict[str, Metric] = field(default_factory=dict)
    plots: tuple[Panel, ...] = ()
    description: str = ""
    reference: str = ""

    @property
    def n_steps(self) -> int:
        """Number of communication steps from start to stop time."""
        return int(round((self.stop_time - self.start_time) / self.step))

    @cached_property
    def graph(self) -> Graph[Scenario]:
        """The scenario's data flow (instances and links), built once per scenario object."""
        return Graph(self)

    def recorded(self) -> list[Signal]:
        """The signals the scenario records, plots or computes metrics of, each once, in
        order."""
        return list(dict.fromkeys([*self.record, *(m.signal for m in self.metrics.values()),
                                   *(m.over for m in self.metrics.values() if m.over),
                                   *(sig for panel in self.plots for sig in panel.signals)]))


def _number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def load(path: str | Path, overrides: Iterable[str] = (), stop_time: float | None = None
         ) -> Scenario:
    """Read and check the scenario file at `path`.

    Parameters
    ----------
    path : str or Path
        The scenario TOML file.
    overrides : sequence of str
        ``"instance.parameter=value"`` assignments applied on top of the file (``--set``).
    stop_time : float, optional
        Replaces the file's stop time.

    Raises
    ------
    UserError
        Naming the file and every problem found.
    """
    path = Path(path)
    if path.is_dir():
        raise UserError(f"scenario {path} is a folder, not a scenario file")
    if not path.is_file():
        raise UserError(f"scenario file {path} does not exist")
    data = read(path)
    problems: list[str] = []
    from_files: dict[ParamRef, Path] = {}  # values read from a parameters file, and which
    scenario = _parse(data, path, problems, from_files)
    if scenario is not None:
        values = _overrides(scenario, overrides, problems)
        for name, spec in scenario.instances.items():
            for par, value in spec.parameters.items():
                ref = ParamRef(name, par)
                if ref not in values:  # an override replaces it (and is checked itself)
                    where = from_files.get(ref)
                    problem = implausible(scenario, ref, value, where=where)
                    problems += [problem] if problem else []
        scenario = with_values(scenario, values)
        if stop_time is not None:
            stop_time = float(stop_time)
            if not math.isfinite(stop_time):
                problems.append(f"--stop-time {stop_time!r} is not a finite number")
            else:
                scenario = replace(scenario, stop_time=stop_time)
        _check_times(scenario, problems)
    if problems or scenario is None:
        raise UserError(f"scenario {path} has {len(problems)} problem(s): " + "; ".join(problems))
    return scenario


def _signal(text: object) -> Signal | None:
    """The signal `text` names, or None if it is not a string ``"instance.variable"``."""
    try:
        return Signal.parse(text)  # type: ignore[arg-type]  # parse refuses a non-string
    except ValueError:
        return None


def _signals(items: object) -> list[Signal] | None:
    """The signals of the list `items`, or None if it is not a list of signal names."""
    signals = [_signal(s) for s in items] if isinstance(items, list) else [None]
    return [s for s in signals if s is not None] if None not in signals else None


def _parse(data: dict[str, Any], path: Path, problems: list[str],
           from_files: dict[ParamRef, Path]) -> Scenario | None:
    """The scenario of the merged table `data` read from `path`, or None with `problems`;
    `from_files` gets the values read from a parameters file, each with that file."""
    for key in sorted(set(data) - _TOP_KEYS):
        problems.append(f"unknown key {key!r} (known: {', '.join(sorted(_TOP_KEYS))})")
    instances = _instances(data, path, problems, from_files)
    connections = []
    for item in data.get("connections", []):
        src, dst = map(_signal, item) if isinstance(item, list) and len(item) == 2 else (None, None)
        if src is None or dst is None:
            problems.append(f"connection {item!r} is not a pair [\"src.output\", \"dst.input\"]")
            continue
        connections.append((src, dst))
    raw = data.get("record", [])
    record = _signals(raw)
    if record is None:
        problems.append("'record' must be a list of \"instance.variable\" strings")
        record = []
    metrics = _metrics(data, problems)
    plots = []
    for panel in data.get("plots", []):
        parsed = _signals(panel.get("signals") if isinstance(panel, dict) else None)
        if parsed is None:
            problems.append(f"plot panel {panel!r} needs a 'signals' list")
            continue
        plots.append(Panel(str(panel.get("title", "")), tuple(parsed)))
    declared = data.get("instances")
    if isinstance(declared, dict) and declared:
        _unknown_instances(list(declared), {
            "connections": [sig for pair in connections for sig in pair], "record": record,
            "metrics": [sig for m in metrics.values() for sig in (m.signal, m.over) if sig],
            "plots": [sig for panel in plots for sig in panel.signals]}, problems)
    algorithm = data.get("algorithm", "gauss-seidel")
    if algorithm not in ALGORITHMS:
        problems.append(f"algorithm {algorithm!r} is not one of {ALGORITHMS}")
    for key in ("step", "stop_time"):
        if key not in data:
            problems.append(f"missing '{key}'")
    for key in ("step", "stop_time", "start_time"):
        if key in data and not _number(data[key]):
            problems.append(f"'{key}' = {data[key]!r} is not a finite number")
    if problems:
        return None
    return Scenario(
        name=str(data.get("name", path.stem)), path=path, instances=instances,
        connections=tuple(connections), step=float(data["step"]),
        stop_time=float(data["stop_time"]), start_time=float(data.get("start_time", 0.0)),
        algorithm=algorithm, record=tuple(record), metrics=metrics, plots=tuple(plots),
        description=str(data.get("description", "")), reference=str(data.get("reference", "")))


def unknown_instance(name: str, names: Iterable[str], declares: str = "the file declares"
                     ) -> str:
    """The sentence for an instance `name` that is not one of `names`: the declared name
    nearest it, where one is near (a typo), after `declares` (who declares it: "the file
    declares"), else them all.

    Examples
    --------
    >>> unknown_instance("friction2", ["body", "fricton2"])
    "no instance 'friction2'; the file declares 'fricton2'"
    >>> unknown_instance("robot", ["body", "inputs"])
    "no instance 'robot' (instances: body, inputs)"
    """
    names = list(names)
    near = difflib.get_close_matches(name, names, n=1)
    if near:
        return f"no instance {name!r}; {declares} {near[0]!r}"
    return f"no instance {name!r} (instances: {', '.join(names)})"


def _unknown_instances(names: list[str], signals: Mapping[str, Iterable[Signal]],
                       problems: list[str]) -> None:
    """One problem per instance the `signals` (by the part of the file naming them) name that is
    not one of the declared `names`, however often it is named."""
    where: dict[str, list[str]] = {}
    for part, sigs in signals.items():
        for sig in sigs:
            if sig.instance not in names and part not in where.setdefault(sig.instance, []):
                where[sig.instance].append(part)
    for name, parts in where.items():
        problems.append(f"{', '.join(parts)}: {unknown_instance(name, names)}")


def _instances(data: dict[str, Any], path: Path, problems: list[str],
               from_files: dict[ParamRef, Path]) -> dict[str, Instance]:
    """The scenario's ``[instances.NAME]`` tables, checked; `from_files` gets the values read
    from a parameters file (and not set inline), each with that file."""
    instances = {}
    raw = data.get("instances")
    if not isinstance(raw, dict) or not raw:
        problems.append("no [instances.NAME] tables")
        raw = {}
    for name, spec in raw.items():
        if not isinstance(spec, dict) or not isinstance(spec.get("component"), str):
            problems.append(f"instance {name!r} needs a 'component' name")
            continue
        if "." in name:
            problems.append(f"instance name {name!r} must not contain '.'")
        if not _COMPONENT.fullmatch(spec["component"]):
            problems.append(f"instance {name!r}: component {spec['component']!r} must be the name "
                            "of an FMU in the FMU folder (letters, digits, '_', '-'), not a path")
            continue
        in_file = _parameters_file(path, name, spec.get("parameters_file"), problems)
        params = {**in_file, **spec.get("parameters", {})}
        file = spec.get("parameters_file")
        from_files.update({ParamRef(name, k): path.parent / str(file) for k in in_file
                           if k not in spec.get("parameters", {})})
        known = ("component", "parameters", "parameters_file", "every", "isolate")
        for key in sorted(set(spec) - set(known)):
            problems.append(f"instance {name!r}: unknown key {key!r} (known: "
                            f"{', '.join(known)})")
        isolate = spec.get("isolate", False)
        if not isinstance(isolate, bool):
            problems.append(f"instance {name!r}: isolate = {isolate!r} must be true or false")
            isolate = False
        every = spec.get("every", 1)
        if not isinstance(every, int) or isinstance(every, bool) or not 1 <= every <= MAX_EVERY:
            problems.append(f"instance {name!r}: every = {every!r} must be a whole number of "
                            f"communication steps from 1 to {MAX_EVERY:,}")
            every = 1
        bad = [k for k, v in params.items() if not _number(v)]
        for k in bad:
            problems.append(f"parameter {name}.{k} is not a finite number (a "
                            f"{type(params[k]).__name__})")
        instances[name] = Instance(name, spec["component"],
                                   {k: float(v) for k, v in params.items() if k not in bad},
                                   every, isolate)
    return instances


def _metrics(data: dict[str, Any], problems: list[str]) -> dict[str, Metric]:
    """The scenario's ``[metrics.NAME]`` tables, checked."""
    metrics = {}
    for name, spec in data.get("metrics", {}).items():
        keys = {"signal", "op", "from", "to", "scale", "over"} | (
            {"period"} if isinstance(spec, dict) and spec.get("op") in _PERIODIC else set())
        if not isinstance(spec, dict) or spec.get("op") not in METRIC_OPS \
                or _signal(spec.get("signal")) is None or set(spec) - keys \
                or ("over" in spec and _signal(spec["over"]) is None) \
                or not all(_number(spec.get(k, 1.0)) for k in ("from", "to", "scale", "period")) \
                or (spec["op"] in _PERIODIC and not spec.get("period", 0) > 0):
            problems.append(f"metric {name!r} needs signal = \"inst.var\", op in {METRIC_OPS} "
                            "(per_period with period = a positive time [s], and so "
                            "cycle_peak_to_peak) and "
                            "optionally from / to = the window's start / end time [s], scale = "
                            "a factor and over = \"inst.var\" (the ratio to the op on that signal)")
            continue
        over = spec.get("over")
        metrics[name] = Metric(Signal.parse(spec["signal"]), spec["op"],
                               float(spec.get("from", -math.inf)),
                               float(spec.get("to", math.inf)), float(spec.get("scale", 1.0)),
                               spec.get("period"), None if over is None else Signal.parse(over))
    return metrics


def _parameters_file(scenario_path: Path, instance: str, name: object, problems: list[str]
                     ) -> dict[str, Any]:
    """Parameter values from an instance's ``parameters_file`` (relative to the scenario, inside
    its folder tree); a problem names the file and the key, never a value read from it."""
    if name is None:
        return {}
    folder = scenario_path.parent.resolve()
    path = (folder / str(name)).resolve()
    if not path.is_relative_to(folder):
        problems.append(f"instance {instance!r}: parameters_file {name!r} lies outside the "
                        f"scenario's folder {folder}")
        return {}
    try:
        values = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        problems.append(f"instance {instance!r}: parameters_file {path} cannot be read "
                        f"({exc.strerror or type(exc).__name__})")
        return {}
    except UnicodeDecodeError:
        problems.append(f"instance {instance!r}: parameters_file {path} is not UTF-8 text")
        return {}
    except tomllib.TOMLDecodeError as exc:  # its message gives the position, not the text
        problems.append(f"instance {instance!r}: parameters_file {path} is not valid TOML: {exc}")
        return {}
    bad = [k for k, v in values.items() if not _number(v)]
    for k in bad:
        problems.append(f"instance {instance!r}: {path} sets {k} to something that is not a "
                        "finite number")
    return {k: v for k, v in values.items() if k not in bad}


def with_values(scenario: Scenario, values: Mapping[ParamRef, float]) -> Scenario:
    """`scenario` with parameter `values` applied (the one way values reach a scenario: ``--set``,
    a data set's stated values, a fit's candidates); instances not in `scenario` are skipped."""
    instances = dict(scenario.instances)
    for ref, value in values.items():
        if ref.instance in instances:
            old = instances[ref.instance]
            instances[ref.instance] = replace(old, parameters={**old.parameters,
                                                               ref.name: float(value)})
    return replace(scenario, instances=instances)


def implausible(scenario: Scenario, ref: ParamRef, value: float, label: str | None = None,
                where: Path | None = None) -> str | None:
    """Why `value` is implausible for parameter (or held input) `ref` of `scenario`, as its
    component declares it (`musclesim.cosim.plausible`), or None (also for an instance or a name
    it does not know, which other checks report). The sentence names it `label` (default: `ref`);
    a value read from the parameters file `where` is not repeated, the file is named instead."""
    inst = scenario.instances.get(ref.instance)
    if inst is None:
        return None
    label = label or str(ref)
    if where is not None:
        label = f"{label} in {where}"
    unit = plausible.signal_unit({n: i.component for n, i in scenario.instances.items()},
                                 scenario.connections, Signal(ref.instance, ref.name))
    return plausible.problem(inst.component, label, ref.name, value, show=where is None,
                             unit=unit)


def apply_overrides(scenario: Scenario, overrides: Iterable[str], problems: list[str]
                    ) -> Scenario:
    """Return `scenario` with `overrides`, ``instance.parameter=value`` strings (``--set``),
    parsed with `ParamRef.parse`, checked (`implausible`) and applied with `with_values`; what is
    wrong with one is appended to `problems`."""
    return with_values(scenario, _overrides(scenario, overrides, problems))


def _overrides(scenario: Scenario, overrides: Iterable[str], problems: list[str]
               ) -> dict[ParamRef, float]:
    """The values `overrides` (``--set``) give `scenario`'s parameters; what is wrong with one is
    appended to `problems` (it is left out)."""
    values = {}
    for text in overrides:
        target, sep, value = text.partition("=")
        try:
            ref = ParamRef.parse(target.strip()) if sep else None
        except ValueError:
            ref = None
        if ref is None:
            problems.append(f"--set {text!r} is not of the form instance.parameter=value")
            continue
        if ref.instance not in scenario.instances:
            problems.append(f"--set {text!r}: "
                            f"{unknown_instance(ref.instance, scenario.instances)}")
            continue
        try:
            number = float(value)
        except ValueError:
            problems.append(f"--set {text!r}: {value.strip()!r} is not a number")
            continue
        if not math.isfinite(number):
            problems.append(f"--set {text!r}: the value must be finite")
            continue
        if problem := implausible(scenario, ref, number):
            problems.append(f"--set {text!r}: {problem}")
            continue
        values[ref] = number
    return values


def _check_times(s: Scenario, problems: list[str]) -> None:
    if not s.step > 0:
        problems.append(f"step must be positive (got {s.step!r})")
    elif s.step < MIN_STEP:
        problems.append(f"step {s.step!r} s is shorter than the smallest allowed, {MIN_STEP:g} s")
    elif max(abs(s.start_time), abs(s.stop_time)) > MAX_TIME:
        problems.append(f"start and stop time must lie within +-{MAX_TIME:g} s")
    elif (s.stop_time - s.start_time) / s.step > MAX_STEPS:
        problems.append(f"{s.stop_time - s.start_time:g} s in steps of {s.step:g} s are "
                        f"{(s.stop_time - s.start_time) / s.step:.3g} steps, more than the "
                        f"{MAX_STEPS:,} a run may take")
    elif not s.stop_time > s.start_time:
        problems.append(f"stop_time {s.stop_time!r} must be after start_time {s.start_time!r}")
    elif abs(s.n_steps * s.step - (s.stop_time - s.start_time)) > 1e-9 * max(1.0, s.stop_time):
        problems.append(f"stop_time - start_time = {s.stop_time - s.start_time!r} s is not a whole "
                        f"number of steps of {s.step!r} s")
