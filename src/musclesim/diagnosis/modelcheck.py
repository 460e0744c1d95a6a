"""The data-set's check against the model: the scenarios and their FMUs give each column's and
condition's unit, name the variables a column may be, and the metrics; format-1 sets' old port
names and temperatures in degrees Celsius where the model's unit is K are refused.

Each function appends the problems it finds to a list (see `musclesim.diagnosis.dataset.load`).
"""
from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np

from musclesim.components import renamed
from musclesim.cosim import (Master, Scenario, Signal, load_scenario, metric_unit,
                             read_fmu, with_values)
from musclesim.diagnosis.measured import DATA, MANIFEST, DataSet
from musclesim.errors import UserError

# A column or condition in kelvin whose values all lie below this is in degrees Celsius: no bench
# of this library runs colder than -73 C (its wires and chambers live near room temperature and
# up to about 200 C), while 200 C is 473 K.
COLDEST_KELVIN = 200.0


def _same_unit(a: str | None, b: str | None) -> bool:
    return (a or "1") == (b or "1")


def _scenario(ds: DataSet, experiment: str, path: Path, stop_time: float | None) -> Scenario:
    """The scenario file `path` of `ds`'s `experiment`, run for `stop_time`, with the bench
    conditions the set states for it (`DataSet.values`)."""
    return with_values(load_scenario(path, (), stop_time), ds.values(experiment))


def check_units(ds: DataSet, fmu_dir: str | Path, problems: list[str]) -> None:
    """Without the model check: the units of `ds`'s columns and conditions from the scenarios'
    FMUs in `fmu_dir` where both can be read (a scenario not found or FMUs not built are
    --model's problems, not this one's), each given unit checked against them (mistakes appended
    to `problems`), the missing ones filled in."""
    declared: dict[Signal, str] = {}
    for e in ds.experiments.values():
        try:
            s = _scenario(ds, e.name, e.scenario_path, e.stop_time) \
                if e.scenario_path is not None else None
            old_names(ds, {n: i.component for n, i in s.instances.items()} if s else {}, problems)
            for inst in (s.instances.values() if s else ()):
                fmu = Path(fmu_dir) / f"{inst.component}.fmu"
                if not fmu.is_file():
                    continue
                md = read_fmu(fmu)
                for v in md.modelVariables:
                    declared.setdefault(Signal(inst.name, v.name), v.unit or "1")
        except UserError:
            continue
    for column in ds.columns:
        given, unit = ds.units.get(column), declared.get(column)
        if unit is None:
            continue
        if given is None:
            ds.units[column] = unit
        elif not _same_unit(given, unit):
            problems.append(f"{MANIFEST}: [units] {str(column)!r} is {given!r} but the model's "
                            f"unit is {unit!r}")
    for ref in ds.conditions:
        if (unit := declared.get(Signal(ref.instance, ref.name))) is not None:
            ds.condition_units[ref] = unit


def old_names(ds: DataSet, components: Mapping[str, str], problems: list[str]) -> None:
    """A format-1 data set `ds`'s columns that use a port name format 2 changed in one of a
    scenario's instances (`components`: instance name -> its component; the name may now be
    another variable's: the PID's y), appended to `problems`; each is said once, however many
    experiments' scenarios have the instance."""
    if ds.format >= 2:
        return
    for column in ds.columns:
        component = components.get(column.instance)
        now = renamed(component, column.variable) if component is not None else None
        if not now:
            continue
        problem = (f"{DATA}: column {str(column)!r}: {component}'s {column.variable} is "
                   f"{Signal(column.instance, now)} since format 2 (the Modelica Standard Library's "
                   f"port names): rename the column and write format = 2 in {MANIFEST}")
        if problem not in problems:
            problems.append(problem)


def check_kelvin(ds: DataSet, problems: list[str]) -> None:
    """Temperatures of `ds` given in degrees Celsius where the model's unit is K: their values
    say so (appended to `problems`)."""
    for column in ds.columns:
        values = ds[column]
        if ds.units.get(column) == "K" and len(values) and np.max(values) < COLDEST_KELVIN:
            problems.append(f"{DATA}: column {str(column)!r} is in K, but its values "
                            f"({np.min(values):g} to {np.max(values):g}) are degrees Celsius, "
                            "not kelvin: add 273.15")
    for ref, value in ds.conditions.items():
        if ds.condition_units.get(ref) == "K" and value < COLDEST_KELVIN:
            problems.append(f"{MANIFEST}: [conditions] {str(ref)!r} = {value:g} is in K, but "
                            f"that value is degrees Celsius, not kelvin: write "
                            f"{value + 273.15:g}")


def check_model(ds: DataSet, fmu_dir: str | Path, problems: list[str]) -> None:
    """Check `ds`'s columns, conditions, metrics and units against its scenarios and their FMUs
    in `fmu_dir`; mistakes appended to `problems`, the model's units filled in."""
    refs = {(e.scenario, e.stop_time): e.scenario_path for e in ds.experiments.values()}
    metric_names: dict[tuple[str, float | None], list] = {}
    for e in ds.experiments.values():
        metric_names.setdefault((e.scenario, e.stop_time), []).append(e)
    for (ref, stop_time), spath in refs.items():
        if spath is None:
            problems.append(f"{MANIFEST}: scenario {ref!r} not found (a .toml path relative to "
                            "the manifest, or a name in the scenarios folder)")
            continue
        first = metric_names[(ref, stop_time)][0].name
        try:
            s = _scenario(ds, first, spath, stop_time)
            m = Master(s, fmu_dir)
        except UserError as exc:
            problems.append(f"{MANIFEST}: scenario {ref!r} cannot be checked: {exc}")
            continue
        for name in ds.values(first):  # with_values skips them: said here
            if name.instance not in m.instances:
                problems.append(f"{MANIFEST}: [conditions] {str(name)!r}: scenario {ref!r} has "
                                f"no instance {name.instance!r} (instances: "
                                f"{', '.join(m.instances)})")
        old_names(ds, {n: i.component for n, i in m.instances.items()}, problems)
        _check_columns(ds, m, ref, problems)
        for name in ds.conditions:
            inst = m.instances.get(name.instance)
            v = inst.vars.get(name.name) if inst is not None else None
            if v is not None:
                ds.condition_units[name] = v.unit or "1"
        _check_metrics(ds, s, m, ref, metric_names[(ref, stop_time)], problems)


def _check_columns(ds: DataSet, m: Master, ref: str, problems: list[str]) -> None:
    """`ds`'s columns against the instances of `m` (scenario `ref`): each a variable, in its
    unit; the model's units filled in where the manifest gives none."""
    model_units = {}
    for column in ds.columns:
        inst, var = column.instance, column.variable
        if inst not in m.instances:
            problems.append(f"{DATA}: column {str(column)!r}: scenario {ref!r} has no instance "
                            f"{inst!r} (instances: {', '.join(m.instances)})")
            continue
        v = m.instances[inst].vars.get(var)
        if v is None:
            now = renamed(m.instances[inst].component, var)
            if not (now and ds.format < 2):  # a format-1 file's old name: old_names said it
                hint = f" (renamed {inst}.{now}: rename the column)" if now else ""
                problems.append(f"{DATA}: column {str(column)!r}: "
                                f"{m.instances[inst].component} has no variable {var!r}{hint}")
            continue
        model_units[column] = v.unit or "1"
        given = ds.units.get(column)
        if given is not None and not _same_unit(given, v.unit):
            problems.append(f"{MANIFEST}: [units] {str(column)!r} is {given!r} but the model's "
                            f"unit is {v.unit or '1'!r}")
    for column, unit in model_units.items():
        if ds.units.get(column) is None:
            ds.units[column] = unit


def _check_metrics(ds: DataSet, s: Scenario, m: Master, ref: str, experiments: list,
                   problems: list[str]) -> None:
    """The metrics of `experiments` (of `ds`, run on scenario `s` named `ref`, its master `m`):
    each a metric of the scenario, in the model's unit."""
    for e in experiments:
        for name, mm in e.metrics.items():
            sm = s.metrics.get(name)
            if sm is None:
                problems.append(f"{MANIFEST}, experiment {e.name!r}: metric {name!r} is not a "
                                f"metric of scenario {ref!r} (metrics: "
                                f"{', '.join(s.metrics) or 'none'})")
                continue
            signal = sm.signal
            inst = m.instances.get(signal.instance)
            v = inst.vars.get(signal.variable) if inst is not None else None
            if v is None:
                continue  # the scenario itself is at fault, and Master reported it
            unit = metric_unit(v.unit, sm.op, sm.over is not None)
            if not _same_unit(mm.unit, unit):
                problems.append(f"{MANIFEST}, experiment {e.name!r}: metric {name!r} is in "
                                f"{mm.unit!r} but the model's is {unit!r}")
