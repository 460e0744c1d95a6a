"""The data-set's check against the model: the scenarios and their FMUs give each column's and
condition's unit, name the variables a column may be, and the metrics; format-1 sets' old port
names and temperatures in degrees Celsius where the model's unit is K are refused.

Each function appends the problems it finds to a list (see `musclesim.diagnosis.dataset.load`).
"""
from pathlib import Path

import numpy as np

from musclesim.components import renamed
from musclesim.cosim import Master, load_scenario, metric_unit, read_fmu, renamed_signals
from musclesim.diagnosis.measured import DATA, MANIFEST
from musclesim.errors import UserError

# A column or condition in kelvin whose values all lie below this is in degrees Celsius: no bench
# of this library runs colder than -73 C (its wires and chambers live near room temperature and
# up to about 200 C), while 200 C is 473 K.
COLDEST_KELVIN = 200.0


def _same_unit(a, b):
    return (a or "1") == (b or "1")


def check_units(ds, fmu_dir, problems):
    """Without the model check: the units of the columns and conditions from the scenarios' FMUs
    where both can be read (a scenario not found or FMUs not built are --model's problems, not
    this one's), each given unit checked against them, the missing ones filled in."""
    declared = {}
    for e in ds.experiments.values():
        try:
            s = load_scenario(e.scenario_path, ds.overrides(e.name), e.stop_time) \
                if e.scenario_path is not None else None
            old_names(ds, s.instances.values() if s else (), problems)
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


def old_names(ds, instances, problems):
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


def check_kelvin(ds, problems):
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


def check_model(ds, fmu_dir, problems):
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
        old_names(ds, m.instances.values(), problems)
        for column in ds.columns:
            inst, _, var = column.partition(".")
            if inst not in m.instances:
                problems.append(f"{DATA}: column {column!r}: scenario {ref!r} has no instance "
                                f"{inst!r} (instances: {', '.join(m.instances)})")
                continue
            v = m.instances[inst].vars.get(var)
            if v is None:
                now = renamed(m.instances[inst].component, var)
                if not (now and ds.format < 2):  # a format-1 file's old name: old_names said it
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
