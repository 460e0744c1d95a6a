"""Measured data sets for the sim-to-real gap diagnosis: the format, loading, validation, writing.

A measured data set is a directory holding ``manifest.toml`` and, for time series, ``data.csv``
in the format of a run's ``results.csv``; the manifest names the scenario, the replayed input and
observed output columns, optional units, known bench conditions (``[conditions]``: constant
values of the model's parameters or of inputs nothing in the scenario feeds, such as the ambient
temperature ``"wire.T_amb" = 298.15``), the experiments (named time spans) and the split into
training and held-out parts; a scalar-only set has metrics per experiment instead of data.csv.
A condition that varies is replayed as an input column instead.
The format with examples: the user guide's data-set page (§data-sets).

Validation reports every problem at once in one `musclesim.errors.UserError`, each naming its
file (and line, column or experiment): malformed TOML or CSV, missing or unknown columns,
duplicated or non-increasing time, NaN/inf, spans outside the data or overlapping, a split that
names unknown experiments or leaves a part empty. Wherever the scenario and its FMUs can be read,
every unit given must equal the model's, and a column or condition in kelvin whose values are
degrees Celsius is refused. A scenario reference that is not found is a problem only when
checking against the model (``check_model=True``: the scenarios may not exist yet when the data
are recorded); then every column must also be a variable of the scenario's instances and every
metric a metric of the scenario.

Examples
--------
>>> import tempfile, pathlib
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> _ = (d / "data.csv").write_text("time,a.x\\n0,1\\n1,2\\n2,4\\n3,8\\n")
>>> _ = (d / "manifest.toml").write_text('scenario = "s"\\noutputs = ["a.x"]\\n'
...                                      '[split]\\nheld_out_fraction = 0.5\\n')
>>> ds = load(d)
>>> ds.parts()
(('all/train',), ('all/held_out',))
>>> ds.experiment("all/held_out")[0]
array([2., 3.])
"""
import json
import math
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from musclesim.components import renamed
from musclesim.cosim import (FORMAT, Master, format_problem, load_scenario, metric_unit,
                             read_fmu, read_time_series, renamed_signals)
from musclesim.errors import UserError

MANIFEST = "manifest.toml"
DATA = "data.csv"
_TOP_KEYS = {"format", "description", "reference", "scenario", "inputs", "outputs", "units",
             "conditions", "experiments", "split", "calibrate"}
_EXPERIMENT_KEYS = {"span", "scenario", "description", "metrics", "stop_time", "conditions"}
_CALIBRATE_KEYS = {"set", "bounds", "why"}
_METRIC_KEYS = {"value", "unit", "uncertainty", "description"}
_SPLIT_KEYS = {"held_out", "train", "held_out_fraction"}
_PARTS = ("train", "held_out")
# A column or condition in kelvin whose values all lie below this is in degrees Celsius: no bench
# of this library runs colder than -73 C (its wires and chambers live near room temperature and
# up to about 200 C), while 200 C is 473 K.
COLDEST_KELVIN = 200.0


@dataclass(frozen=True)
class MeasuredMetric:
    """One measured scalar: its value, unit and (optional) standard uncertainty, same unit."""

    value: float
    unit: str = "1"
    uncertainty: float = None
    description: str = ""


@dataclass(frozen=True)
class Experiment:
    """A named experiment: its time span in data.csv (None if scalar-only), scenario, metrics."""

    name: str
    span: tuple = None  # (t0, t1) [s], closed
    scenario: str = ""  # reference as written in the manifest
    scenario_path: Path = None  # the resolved scenario file, None if not found
    metrics: dict = field(default_factory=dict)  # name -> MeasuredMetric
    description: str = ""
    stop_time: float = None  # scalar-only: how long the model runs (None: the scenario's)
    conditions: dict = field(default_factory=dict)  # this experiment's own bench conditions


@dataclass(frozen=True)
class OpenValue:
    """A value the data set asks `musclesim calibrate` to fit: one value for every parameter
    in `targets` ("instance.parameter"), within (`lower`, `upper`), and why it is open."""

    targets: tuple
    lower: float
    upper: float
    why: str = ""


@dataclass(frozen=True)
class Split:
    """Training and held-out parts: by experiment names, or the last `fraction` of each in time."""

    train: tuple = ()
    held_out: tuple = ()
    fraction: float = None  # set for a split blocked in time


@dataclass
class DataSet:
    """A checked measured data set (see the module docstring for the format).

    ``time`` and ``data[i, j]`` (column ``columns[j]``) are None for a scalar-only set. ``units``
    maps every column to its unit: the manifest's, else the model's (read from the scenario's FMUs
    whenever they can be read, and required by the model check), else None (SI assumed);
    ``condition_units`` the model's unit of each condition, where known.
    """

    path: Path
    scenario: str
    scenario_path: Path
    inputs: tuple
    outputs: tuple
    units: dict
    experiments: dict  # name -> Experiment
    split: Split
    time: np.ndarray = None
    columns: tuple = ()
    data: np.ndarray = None
    description: str = ""
    reference: str = ""
    conditions: dict = field(default_factory=dict)  # "instance.variable" -> known constant value
    condition_units: dict = field(default_factory=dict)  # the model's unit of each condition
    calibrate: tuple = ()  # the open values `musclesim calibrate` fits (`OpenValue` each)
    # experiment -> its Scenario, loaded with the conditions (`loaded`): a data set that carries
    # them is diagnosed where the scenario files are not (a Dask worker of another machine)
    scenarios: dict = None
    format: int = FORMAT  # the manifest's format (1: the port names before format 2)

    @property
    def scalar_only(self):
        """True when the set holds metrics but no time series."""
        return self.time is None

    def __getitem__(self, column):
        return self.data[:, self.columns.index(column)]

    def scenario_of(self, experiment):
        """The Scenario experiment `experiment` runs: the one the set carries, else its file
        loaded with the bench conditions and the experiment's stop time."""
        if self.scenarios is not None:
            return self.scenarios[experiment]
        e = self.experiments[experiment]
        return load_scenario(e.scenario_path, self.overrides(experiment), e.stop_time)

    def loaded(self):
        """This data set carrying its experiments' scenarios (`scenario_of`), to be diagnosed
        without their files."""
        return replace(self, scenarios={name: self.scenario_of(name) for name in self.experiments})

    def overrides(self, experiment=None):
        """The bench conditions as scenario overrides (``"instance.variable=value"``), with
        those of the experiment named `experiment` after the set's."""
        own = self.experiments[experiment].conditions if experiment else {}
        return [f"{name}={value!r}" for name, value in {**self.conditions, **own}.items()]

    def parts(self):
        """Names of the training and the held-out parts: two tuples of names for `experiment`."""
        if self.split.fraction is None:
            return self.split.train, self.split.held_out
        return tuple(tuple(f"{e}/{part}" for e in self.experiments) for part in _PARTS)

    def experiment(self, name):
        """Time and ``{column: values}`` of an experiment or a part named by `parts`.

        Raises
        ------
        UserError
            If the name is unknown or the set has no time series.
        """
        if self.scalar_only:
            raise UserError(f"data set {self.path} is scalar-only (no {DATA}); experiment "
                            f"{name!r} has metrics only: {sorted(self.experiments)}")
        base, _, part = name.partition("/")
        known = list(self.experiments)
        if self.split.fraction is not None:
            known += [n for pair in self.parts() for n in pair]
        if base not in self.experiments or (part and (part not in _PARTS
                                                      or self.split.fraction is None)):
            raise UserError(f"data set {self.path} has no experiment {name!r} "
                            f"(known: {', '.join(known)})")
        rows = _part_mask(self.time, self.experiments[base].span, part, self.split.fraction)
        return self.time[rows], {c: self.data[rows, j] for j, c in enumerate(self.columns)}


def _part_mask(time, span, part="", fraction=None):
    """Rows of `time` in `span` (closed), or in its training / held-out part."""
    t0, t1 = span
    rows = (time >= t0) & (time <= t1)
    if part:
        cut = t1 - fraction * (t1 - t0)
        rows &= (time < cut) if part == "train" else (time >= cut)
    return rows


def _number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _same_unit(a, b):
    return (a or "1") == (b or "1")


def find_scenario(reference, manifest_dir, scenarios_dir=None):
    """Resolve a manifest's scenario reference to a file, or None if there is none.

    A reference ending in ``.toml`` is a path relative to the manifest's folder; a name is looked
    up as ``<name>.toml`` in `scenarios_dir`, by default the nearest folder named ``scenarios``
    that holds the manifest, else ``./scenarios``.
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


def load(path, check_model=False, fmu_dir="fmus", scenarios_dir=None, models=None):
    """Read and check the measured data set in directory `path` (or its manifest.toml).

    Parameters
    ----------
    path : str or Path
        The data set's directory (holding manifest.toml and, for time series, data.csv).
    check_model : bool
        Also check against the scenario and its FMUs: the scenario must exist, columns must be
        variables of its instances, metrics must be its metrics, units must equal the model's.
    fmu_dir : str or Path
        Folder of built FMUs, used when `check_model`.
    scenarios_dir : str or Path, optional
        Where scenario names are looked up (see `find_scenario`).
    models : dict, optional
        ``{experiment: scenario}`` replacing the manifest's models, ``"*"`` for every experiment
        (the same data against another model, e.g. the ideal-actuation crawler). A reference
        ending in ``.toml`` is a path from the current folder, else a name in `scenarios_dir`.

    Returns
    -------
    DataSet

    Raises
    ------
    UserError
        Naming the data set and every problem found.
    """
    path = Path(path)
    if path.name == MANIFEST and path.is_file():
        path = path.parent
    manifest_path = path / MANIFEST
    if not path.is_dir():
        raise UserError(f"data set {path} is not a directory")
    problems = []
    manifest = _read_manifest(manifest_path, problems)
    data_path = path / DATA
    table = read_time_series(data_path, problems, DATA) if data_path.is_file() else None
    ds = None
    if manifest is not None:
        ds = _build(path, manifest, table, data_path.is_file(), scenarios_dir, problems)
    if ds is not None and models:
        ds = _with_models(ds, models, scenarios_dir, problems)
    if ds is not None and check_model:
        _check_model(ds, fmu_dir, problems)
    elif ds is not None:
        _check_units(ds, fmu_dir, problems)
    if ds is not None:
        _check_kelvin(ds, problems)
    if problems:
        raise UserError(f"data set {path} has {len(problems)} problem(s): " + "; ".join(problems))
    return ds


def _with_models(ds, models, scenarios_dir, problems):
    """`ds` with the experiments' scenarios replaced by `models` (see `load`)."""
    for name in sorted(set(models) - set(ds.experiments) - {"*"}):
        problems.append(f"model for experiment {name!r}: the data set has no such experiment "
                        f"(experiments: {', '.join(ds.experiments)})")
    experiments = {}
    for name, e in ds.experiments.items():
        ref = models.get(name, models.get("*"))
        if ref is not None:
            path = Path(ref) if ref.endswith(".toml") else find_scenario(ref, ds.path, scenarios_dir)
            e = replace(e, scenario=ref, scenario_path=path if path and path.is_file() else None)
        experiments[name] = e
    return replace(ds, experiments=experiments)


def write(path, time, cols, inputs, outputs, scenario_ref, description="", conditions=None,
          held_out_fraction=0.35):
    """Write a measured data set: data.csv (`time` and the columns `inputs` + `outputs` of
    `cols`) and manifest.toml (scenario `scenario_ref`, the last `held_out_fraction` of the data
    held out; `conditions` ({"instance.variable": value}) its ``[conditions]`` table), the
    format `load` reads."""
    path = Path(path)
    path.mkdir(parents=True, exist_ok=True)
    names = inputs + outputs
    np.savetxt(path / DATA, np.column_stack([time] + [cols[c] for c in names]),
               delimiter=",", header=",".join(["time", *names]), comments="", fmt="%.9g")
    lines = [f"format = {FORMAT}", f"description = {json.dumps(description)}",
             f"scenario = {json.dumps(scenario_ref)}",
             f"inputs = {json.dumps(inputs)}", f"outputs = {json.dumps(outputs)}", "",
             "[split]", f"held_out_fraction = {held_out_fraction}", ""]
    if conditions:
        lines += ["[conditions]"] + [f"{json.dumps(k)} = {float(v)!r}"
                                     for k, v in conditions.items()] + [""]
    (path / MANIFEST).write_text("\n".join(lines))


def _read_manifest(path, problems):
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        problems.append(f"{MANIFEST} is missing")
    except (OSError, UnicodeDecodeError) as exc:
        problems.append(f"{MANIFEST} cannot be read: {exc}")
    except tomllib.TOMLDecodeError as exc:
        problems.append(f"{MANIFEST} is not valid TOML: {exc}")
    return None


def _names(value, what, problems):
    if value is None:
        return ()
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        problems.append(f"{MANIFEST}: '{what}' must be a list of strings")
        return ()
    return tuple(value)


def _build(path, m, table, has_data, scenarios_dir, problems):
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
    if not has_data:
        if inputs or outputs or units:
            problems.append(f"{DATA} is missing but {MANIFEST} lists columns (inputs, outputs "
                            "or units)")
    else:
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
    if units.get("time", "s") != "s":
        problems.append(f"{MANIFEST}: time must be in 's', not {units['time']!r}")

    conditions = _conditions(m.get("conditions", {}), columns, problems)
    experiments = _experiments(m.get("experiments"), reference, path, scenarios_dir, time,
                               has_data, problems)
    split = _split(m.get("split"), experiments, time, has_data, problems)
    calibrate = _calibrate(m.get("calibrate", []), problems)
    fmt = m.get("format", 1)
    if problem := format_problem(fmt):
        problems.append(f"{MANIFEST}: {problem}")
    if problems:
        return None
    return DataSet(path=path, scenario=reference, scenario_path=scenario_path, inputs=inputs,
                   outputs=outputs, units={c: units.get(c) for c in columns},
                   experiments=experiments, split=split, time=time, columns=columns, data=data,
                   description=str(m.get("description", "")), reference=str(m.get("reference", "")),
                   conditions=conditions, calibrate=calibrate, format=fmt)


def _conditions(raw, columns, problems, where=MANIFEST):
    """``{"instance.variable": value}`` of the manifest's [conditions] table (or an
    experiment's, `where`)."""
    if not isinstance(raw, dict):
        problems.append(f"{where}: [conditions] must map \"instance.variable\" to numbers")
        return {}
    out = {}
    for name, value in raw.items():
        inst, _, var = name.partition(".")
        if not inst or not var:
            problems.append(f"{where}: [conditions] {name!r} is not of the form "
                            "\"instance.variable\"")
        elif isinstance(value, bool) or not isinstance(value, (int, float)) \
                or not math.isfinite(value):
            problems.append(f"{where}: [conditions] {name!r} must be a finite number")
        elif name in columns:
            problems.append(f"{MANIFEST}: [conditions] {name!r} is also a column of {DATA}: "
                            "state it once")
        else:
            out[name] = float(value)
    return out


def _experiments(raw, reference, path, scenarios_dir, time, has_data, problems):
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


def _calibrate(raw, problems):
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
        if not (isinstance(targets, list) and targets and all(
                isinstance(t, str) and all(t.partition(".")[::2]) for t in targets)):
            problems.append(f"{at}: set must list one or more \"instance.parameter\" names")
            continue
        bounds = spec.get("bounds")
        if not (isinstance(bounds, list) and len(bounds) == 2 and all(_number(b) for b in bounds)
                and bounds[0] < bounds[1]):
            problems.append(f"{at}: bounds {bounds!r} is not [lower, upper] with lower < upper")
            continue
        out.append(OpenValue(tuple(targets), float(bounds[0]), float(bounds[1]),
                             str(spec.get("why", ""))))
    taken = [t for v in out for t in v.targets]
    for t in sorted({t for t in taken if taken.count(t) > 1}):
        problems.append(f"{where}: {t!r} is in more than one set")
    return tuple(out)


def _span(spec, where, time, problems):
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


def _metrics(raw, where, problems):
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


def _split(raw, experiments, time, has_data, problems):
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
                for part in _PARTS:
                    if np.count_nonzero(_part_mask(time, e.span, part, f)) < 2:
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
        if not names:
            problems.append(f"{where}: the {part} part is empty")
    for n in set(held) & set(train):
        problems.append(f"{where}: experiment {n!r} is both in train and held_out")
    return Split(train=train, held_out=held)


def _check_units(ds, fmu_dir, problems):
    """Without the model check: the units of the columns and conditions from the scenarios' FMUs
    where both can be read (a scenario not found or FMUs not built are --model's problems, not
    this one's), each given unit checked against them, the missing ones filled in."""
    declared = {}
    for e in ds.experiments.values():
        try:
            s = load_scenario(e.scenario_path, ds.overrides(e.name), e.stop_time) \
                if e.scenario_path is not None else None
            _old_names(ds, s.instances.values() if s else (), problems)
            for inst in (s.instances.values() if s else ()):
                fmu = Path(fmu_dir) / f"{inst.component}.fmu"
                if not fmu.is_file():
                    continue
                md = read_fmu(fmu)
                for v in md.modelVariables:
                    declared.setdefault(f"{inst.name}.{v.name}", v.unit or "1")
        except UserError:
            continue
    for column in ds.columns:
        given, unit = ds.units.get(column), declared.get(column)
        if unit is None:
            continue
        if given is None:
            ds.units[column] = unit
        elif not _same_unit(given, unit):
            problems.append(f"{MANIFEST}: [units] {column!r} is {given!r} but the model's "
                            f"unit is {unit!r}")
    ds.condition_units.update({n: declared[n] for n in ds.conditions if n in declared})


def _old_names(ds, instances, problems):
    """A format-1 data set's columns that use a port name format 2 changed in one of a
    scenario's `instances` (the name may now be another variable's: the PID's y); each problem
    is said once, however many experiments' scenarios have the instance."""
    if ds.format >= 2:
        return
    components = {i.name: i.component for i in instances}
    for column, now in renamed_signals(ds.columns, components).items():
        inst, _, var = column.partition(".")
        problem = (f"{DATA}: column {column!r}: {components[inst]}'s {var} is {now} since "
                   "format 2 (the Modelica Standard Library's port names): rename the column and "
                   f"write format = 2 in {MANIFEST}")
        if problem not in problems:
            problems.append(problem)


def _check_kelvin(ds, problems):
    """Temperatures given in degrees Celsius where the model's unit is K: their values say so."""
    for column in ds.columns:
        values = ds[column]
        if ds.units.get(column) == "K" and len(values) and np.max(values) < COLDEST_KELVIN:
            problems.append(f"{DATA}: column {column!r} is in K, but its values "
                            f"({np.min(values):g} to {np.max(values):g}) are degrees Celsius, "
                            "not kelvin: add 273.15")
    for name, value in ds.conditions.items():
        if ds.condition_units.get(name) == "K" and value < COLDEST_KELVIN:
            problems.append(f"{MANIFEST}: [conditions] {name!r} = {value:g} is in K, but that "
                            f"value is degrees Celsius, not kelvin: write {value + 273.15:g}")


def _check_model(ds, fmu_dir, problems):
    """Check columns, metrics and units against the scenarios and their FMUs."""
    refs = {(e.scenario, e.stop_time): e.scenario_path for e in ds.experiments.values()}
    metric_names = {}
    for e in ds.experiments.values():
        metric_names.setdefault((e.scenario, e.stop_time), []).append(e)
    for (ref, stop_time), spath in refs.items():
        if spath is None:
            problems.append(f"{MANIFEST}: scenario {ref!r} not found (a .toml path relative to "
                            "the manifest, or a name in the scenarios folder)")
            continue
        try:
            s = load_scenario(spath, ds.overrides(metric_names[(ref, stop_time)][0].name),
                              stop_time)
            m = Master(s, fmu_dir)
        except UserError as exc:
            problems.append(f"{MANIFEST}: scenario {ref!r} cannot be checked: {exc}")
            continue
        model_units = {}
        _old_names(ds, m.instances.values(), problems)
        for column in ds.columns:
            inst, _, var = column.partition(".")
            if inst not in m.instances:
                problems.append(f"{DATA}: column {column!r}: scenario {ref!r} has no instance "
                                f"{inst!r} (instances: {', '.join(m.instances)})")
                continue
            v = m.instances[inst].vars.get(var)
            if v is None:
                now = renamed(m.instances[inst].component, var)
                if not (now and ds.format < 2):  # a format-1 file's old name: _old_names said it
                    hint = f" (renamed {inst}.{now}: rename the column)" if now else ""
                    problems.append(f"{DATA}: column {column!r}: {m.instances[inst].component} "
                                    f"has no variable {var!r}{hint}")
                continue
            model_units[column] = v.unit or "1"
            given = ds.units.get(column)
            if given is not None and not _same_unit(given, v.unit):
                problems.append(f"{MANIFEST}: [units] {column!r} is {given!r} but the model's "
                                f"unit is {v.unit or '1'!r}")
        for column, unit in model_units.items():
            if ds.units.get(column) is None:
                ds.units[column] = unit
        for name in ds.conditions:
            inst, _, var = name.partition(".")
            v = m.instances[inst].vars.get(var) if inst in m.instances else None
            if v is not None:
                ds.condition_units[name] = v.unit or "1"
        for e in metric_names[(ref, stop_time)]:
            for name, mm in e.metrics.items():
                sm = s.metrics.get(name)
                if sm is None:
                    problems.append(f"{MANIFEST}, experiment {e.name!r}: metric {name!r} is not a "
                                    f"metric of scenario {ref!r} (metrics: "
                                    f"{', '.join(s.metrics) or 'none'})")
                    continue
                inst, _, var = sm.signal.partition(".")
                v = m.instances.get(inst) and m.instances[inst].vars.get(var)
                if v is None:
                    continue  # the scenario itself is at fault, and Master reported it
                unit = metric_unit(v.unit, sm.op, sm.over is not None)
                if not _same_unit(mm.unit, unit):
                    problems.append(f"{MANIFEST}, experiment {e.name!r}: metric {name!r} is in "
                                    f"{mm.unit!r} but the model's is {unit!r}")
