"""Scenario files: parse and check the TOML that wires FMU instances into an experiment.

A scenario names instances (a component: the name of an FMU in the FMU folder, parameter
values, inline or from a TOML file given as ``parameters_file`` relative to the scenario and
inside its folder, inline values winning, and ``every``: how many communication steps the
instance takes at once), connections ``"a.y" -> "b.u"``, the communication step, start and stop
time, the master algorithm, the signals to record, the metrics to compute and the plot panels.
A file may ``extends = "other.toml"`` (relative to it): its tables merge key by key onto the
other's, its connections, recorded signals and plots are added to the other's, its other values
replace them, so that variants of an experiment state only what differs. ``format = 2``
(`FORMAT`) declares that a file uses the port names of the Modelica Standard Library (e.g. the
PID's ``u_s``, ``u_m`` -> ``y``); a file without it is format 1 and may use none of the names
format 2 changed (`musclesim.components.RENAMED`): the PID's ``y`` was its measurement. Checks
collect every problem and raise once with the whole list. No message repeats a value read from a
parameters file (it may hold what is not ours to print), only its key.

Limits: a step of at least `MIN_STEP`, at most `MAX_STEPS` communication steps, times of at most
`MAX_TIME` in magnitude, ``every`` at most `MAX_EVERY`.
"""
import math
import re
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Mapping, NamedTuple

from musclesim.components import renamed
from musclesim.cosim.address import ParamRef
from musclesim.errors import UserError

ALGORITHMS = ("gauss-seidel", "jacobi")
METRIC_OPS = ("final", "initial", "mean", "min", "max", "max_abs", "rms", "rate", "peak_to_peak",
              "per_period", "frequency", "cycle_peak_to_peak")
_PERIODIC = ("per_period", "cycle_peak_to_peak")  # ops that need a period
_TOP_KEYS = {"format", "name", "description", "reference", "step", "start_time", "stop_time",
             "algorithm", "connections", "record", "instances", "metrics", "plots"}
FORMAT = 2  # the scenario and data-set format written now: the ports' MSL names
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

    signal: str
    op: str
    start: float = -math.inf
    stop: float = math.inf
    scale: float = 1.0
    period: float = None
    over: str = None


@dataclass(frozen=True)
class Instance:
    """One FMU instance: its name, the component (FMU) it instantiates, parameter values and
    ``every``: it steps at every ``every``-th communication point, by ``every`` steps at once
    (multi-rate; 1 = at every point)."""

    name: str
    component: str
    parameters: dict = field(default_factory=dict)
    every: int = 1


@dataclass(frozen=True)
class Scenario:
    """A checked scenario (see the module docstring); signals are ``"instance.variable"``
    strings."""

    name: str
    path: Path
    instances: dict
    connections: tuple  # ((source signal, destination signal), ...)
    step: float
    stop_time: float
    start_time: float = 0.0
    algorithm: str = "gauss-seidel"
    record: tuple = ()
    metrics: dict = field(default_factory=dict)  # name -> Metric
    plots: tuple = ()  # ({"title": str, "signals": [..]}, ...)
    description: str = ""
    reference: str = ""

    @property
    def n_steps(self):
        """Number of communication steps from start to stop time."""
        return int(round((self.stop_time - self.start_time) / self.step))


def split_signal(signal):
    """Split ``"instance.variable"`` (the variable may itself contain dots) into its two parts."""
    inst, _, var = signal.partition(".")
    return inst, var


def _number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def load(path, overrides=(), stop_time=None):
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
    data = _read(path, ())
    problems = []
    scenario = _parse(data, path, problems)
    if scenario is not None:
        scenario = apply_overrides(scenario, overrides, problems)
        if stop_time is not None:
            stop_time = float(stop_time)
            if not math.isfinite(stop_time):
                problems.append(f"--stop-time {stop_time!r} is not a finite number")
            else:
                scenario = replace(scenario, stop_time=stop_time)
        _check_times(scenario, problems)
    if problems:
        raise UserError(f"scenario {path} has {len(problems)} problem(s): " + "; ".join(problems))
    return scenario


def _read(path, chain):
    """The scenario file's table, merged onto the file it ``extends`` (tables merge key by key,
    connections, recorded signals and plots are added, other values replace); `chain` holds the
    files that extend this one."""
    if path in chain:
        loop = " -> ".join(map(str, chain))
        raise UserError(f"scenario {chain[0]} extends itself through {loop}")
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise UserError(f"scenario {chain[-1]} extends {path}, which cannot be read: {exc}") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise UserError(f"scenario file {path} is not valid TOML: {exc}") from None
    base = data.pop("extends", None)
    fmt = data.pop("format", 1)
    if problem := format_problem(fmt):
        raise UserError(f"scenario {path}: {problem}")
    if base is not None and not isinstance(base, str):
        raise UserError(f"scenario {path}: extends must be a file name, not {base!r}")
    merged = data if base is None else _merge(_read(path.parent / base, (*chain, path)), data)
    if fmt < 2:
        _old_names(path, data, merged)
    return merged


def _signals(data):
    """The "instance.variable" strings a scenario file's table names."""
    def strings(items):
        return [s for s in items if isinstance(s, str)] if isinstance(items, list) else []
    out = strings(data.get("record"))
    for pair in data.get("connections", []) if isinstance(data.get("connections"), list) else ():
        out += strings(pair)
    metrics = data.get("metrics")
    for spec in metrics.values() if isinstance(metrics, dict) else ():
        out += strings([spec.get("signal"), spec.get("over")] if isinstance(spec, dict) else [])
    for panel in data.get("plots", []) if isinstance(data.get("plots"), list) else ():
        out += strings(panel.get("signals") if isinstance(panel, dict) else None)
    return out


def format_problem(value):
    """What is wrong with a file's ``format`` = `value` (a whole number from 1 to `FORMAT`), or
    None."""
    if not isinstance(value, int) or isinstance(value, bool) or not 1 <= value <= FORMAT:
        return f"format = {value!r} is not one this musclesim reads (1 to {FORMAT})"
    return None


def renamed_signals(signals, components):
    """{signal: its name since format 2} of the `signals` ("instance.variable") that name a port
    format 2 renamed; `components` maps instance names to their component's."""
    out = {}
    for signal in signals:
        inst, var = split_signal(signal)
        now = renamed(components[inst], var) if inst in components else None
        if now:
            out[signal] = f"{inst}.{now}"
    return out


def _old_names(path, data, merged):
    """Refuse the names format 2 changed in the format-1 file at `path` (its table `data`; the
    instances are those of `merged`, its chain): the PID's y then meant another variable."""
    instances = merged.get("instances")
    components = {name: spec["component"] for name, spec in
                  (instances.items() if isinstance(instances, dict) else ())
                  if isinstance(spec, dict) and isinstance(spec.get("component"), str)}
    problems = [f"{signal!r} is {now} now" for signal, now in
                renamed_signals(dict.fromkeys(_signals(data)), components).items()]
    if problems:
        raise UserError(f"scenario {path} names ports as before format 2 (the Modelica Standard "
                        "Library's port names): " + "; ".join(problems)
                        + "; write the new names and format = 2 at the top of the file")


_ADDED = ("connections", "record", "plots")  # lists an extending file adds to


def _merge(base, data):
    out = dict(base)
    for key, value in data.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = _merge(out[key], value)
        elif key in _ADDED and isinstance(value, list) and isinstance(out.get(key), list):
            out[key] = out[key] + value
        else:
            out[key] = value
    return out


def _parse(data, path, problems):
    for key in sorted(set(data) - _TOP_KEYS):
        problems.append(f"unknown key {key!r} (known: {', '.join(sorted(_TOP_KEYS))})")
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
        params = {**_parameters_file(path, name, spec.get("parameters_file"), problems),
                  **spec.get("parameters", {})}
        for key in sorted(set(spec) - {"component", "parameters", "parameters_file", "every"}):
            problems.append(f"instance {name!r}: unknown key {key!r} "
                            "(known: component, parameters, parameters_file, every)")
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
                                   every)

    connections = []
    for item in data.get("connections", []):
        if (not isinstance(item, list) or len(item) != 2
                or not all(isinstance(s, str) and "." in s for s in item)):
            problems.append(f"connection {item!r} is not a pair [\"src.output\", \"dst.input\"]")
            continue
        connections.append(tuple(item))
    record = data.get("record", [])
    if not isinstance(record, list) or not all(isinstance(s, str) for s in record):
        problems.append("'record' must be a list of \"instance.variable\" strings")
        record = []

    metrics = {}
    for name, spec in data.get("metrics", {}).items():
        keys = {"signal", "op", "from", "to", "scale", "over"} | (
            {"period"} if isinstance(spec, dict) and spec.get("op") in _PERIODIC else set())
        if not isinstance(spec, dict) or spec.get("op") not in METRIC_OPS \
                or not isinstance(spec.get("signal"), str) or set(spec) - keys \
                or not isinstance(spec.get("over", ""), str) \
                or not all(_number(spec.get(k, 1.0)) for k in ("from", "to", "scale", "period")) \
                or (spec["op"] in _PERIODIC and not spec.get("period", 0) > 0):
            problems.append(f"metric {name!r} needs signal = \"inst.var\", op in {METRIC_OPS} "
                            "(per_period with period = a positive time [s], and so "
                            "cycle_peak_to_peak) and "
                            "optionally from / to = the window's start / end time [s], scale = "
                            "a factor and over = \"inst.var\" (the ratio to the op on that signal)")
            continue
        metrics[name] = Metric(spec["signal"], spec["op"], float(spec.get("from", -math.inf)),
                               float(spec.get("to", math.inf)), float(spec.get("scale", 1.0)),
                               spec.get("period"), spec.get("over"))
    plots = data.get("plots", [])
    for panel in plots:
        if not isinstance(panel, dict) or not isinstance(panel.get("signals"), list):
            problems.append(f"plot panel {panel!r} needs a 'signals' list")
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


def _parameters_file(scenario_path, instance, name, problems):
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


def with_values(scenario: "Scenario", values: Mapping[ParamRef, float]) -> "Scenario":
    """`scenario` with parameter `values` applied (the one way values reach a scenario: ``--set``,
    a data set's stated values, a fit's candidates); instances not in `scenario` are skipped."""
    instances = dict(scenario.instances)
    for ref, value in values.items():
        if ref.instance in instances:
            old = instances[ref.instance]
            instances[ref.instance] = replace(old, parameters={**old.parameters,
                                                               ref.name: float(value)})
    return replace(scenario, instances=instances)


def apply_overrides(scenario, overrides, problems):
    """Return `scenario` with ``instance.parameter=value`` overrides applied; problems appended."""
    values = {}
    for text in overrides:
        target, sep, value = text.partition("=")
        inst, var = split_signal(target.strip())
        if not sep or not var:
            problems.append(f"--set {text!r} is not of the form instance.parameter=value")
            continue
        if inst not in scenario.instances:
            problems.append(f"--set {text!r}: no instance {inst!r} "
                            f"(instances: {', '.join(scenario.instances)})")
            continue
        try:
            number = float(value)
        except ValueError:
            problems.append(f"--set {text!r}: {value.strip()!r} is not a number")
            continue
        if not math.isfinite(number):
            problems.append(f"--set {text!r}: the value must be finite")
            continue
        values[ParamRef(inst, var)] = number
    return with_values(scenario, values)


def _check_times(s, problems):
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
