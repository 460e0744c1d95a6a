"""The calibration parameters of a unit: the nominal values a real bench has differently
(`effects.CALIBRATION`), as `Free` parameters (`calibration`), how many of them a calibration
scans (`scanned`), the report's table of their fitted values (`calibration_table`), and the one
place a parameter's nominal value (`nominal`) and its unit (`unit_of`) are read.
"""
from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from musclesim.components import CATALOGUE, declarations
from musclesim.cosim import ParamRef, read_fmu
from musclesim.diagnosis.effects import calibration_of
from musclesim.diagnosis.fitting import FitResult, Free
from musclesim.diagnosis.problem import Problem, Unit, affected
from musclesim.diagnosis.stats import TRAIN, part_rows
from musclesim.diagnosis.thresholds import MIN_VALUES_PER_PARAMETER

__all__ = ["nominal", "unit_of", "components_of", "calibration", "scanned", "calibration_table"]


def nominal(problem: Problem, ref: ParamRef) -> float:
    """The nominal value of parameter `ref` (a `ParamRef`) in `problem`: the value the first of
    its scenarios holding the instance gives, else its FMU's start value.

    Raises
    ------
    KeyError
        If the instance's component has no parameter `name` with a start value (its message:
        "<component> has no parameter '<name>'").
    """
    inst, name = ref.instance, ref.name
    for s in problem.scenarios.values():
        if inst in s.instances:
            if name in s.instances[inst].parameters:
                return float(s.instances[inst].parameters[name])
            component = s.instances[inst].component
            break
    var = problem.vars.get(inst, {}).get(name)
    if var is None:  # an instance only a later experiment's scenario has
        md = read_fmu(Path(problem.fmu_dir) / f"{component}.fmu")
        var = next((v for v in md.modelVariables if v.name == name), None)
    if var is None or var.start is None:
        raise KeyError(f"{component} has no parameter {name!r}")
    return float(var.start)


def unit_of(component: str, name: str) -> str:
    """The unit of parameter `name` of `component` as the component declares it; "1" for a
    component outside the catalogue (whose parameters are neither calibrated nor an effect's)
    or a name it does not declare. For the report only: no number of the diagnosis depends on
    it.

    >>> unit_of("Thermocouple", "tau"), unit_of("SmaWire", "T_amb"), unit_of("Other", "k")
    ('s', 'K', '1')
    """
    decl = declarations(component).get(name) if component in CATALOGUE else None
    return decl.unit if decl is not None else "1"


def components_of(unit: Unit, instances: Iterable[str]) -> dict[str, list[str]]:
    """{component: [its instances]} of `instances` (sorted) that are in `unit`."""
    out: dict[str, list[str]] = {}
    for inst in sorted(instances):
        if inst in unit.components:
            out.setdefault(unit.components[inst], []).append(inst)
    return out


def calibration(problem: Problem, unit: Unit,
                instances: Iterable[str] | None = None) -> list[Free]:
    """The calibration parameters (`Free`, absolute bounds) in `problem` of the components of
    `instances` (default: all of `unit`'s) that act on an observed signal, one per component and parameter
    for all its instances together, the periodic ones first.
    A value the data set states as a bench condition (``[conditions]``) is fixed, not
    calibrated, and so is an input the scenario connects or the data set replays. Nothing is
    calibrated when the training part holds fewer than MIN_VALUES_PER_PARAMETER values per
    parameter (scalar metrics)."""
    rows = sum(int(np.count_nonzero(m)) for m in part_rows(unit, TRAIN)) * len(unit.observed)
    s = unit.runs[0].scenario
    # the stated values, and the inputs connected or replayed (a Signal names an input as a
    # ParamRef names a parameter: the same instance and variable)
    taken = set(problem.ds.values()) | {ParamRef(dst.instance, dst.variable) for dst in set(
        dst for _, dst in s.connections).union(*(run.inputs for run in unit.runs))}
    out = []
    acting = [i for i in instances or unit.instances if affected(unit, (i,))]
    for comp, insts in components_of(unit, acting).items():
        for c in calibration_of(comp):
            free = tuple(i for i in insts if ParamRef(i, c.name) not in taken)
            if free:
                value = nominal(problem, ParamRef(free[0], c.name))
                lower, upper = c.bounds(value)
                out.append(Free(free, c.name, lower, upper, value, c.period))
    out.sort(key=lambda f: not f.period)  # the periodic first: `fit` scans them (`scanned`)
    # a handful of metrics cannot pin several nominal values: too few training values, none
    return out if rows >= MIN_VALUES_PER_PARAMETER * len(out) else []


def scanned(free: Sequence[Free]) -> int:
    """How many of the calibration parameters `free` (`calibration`'s, the periodic first) a
    calibration from the nominal values scans: the periodic ones, whose nominal value may lie
    in any of their cost's wells."""
    return sum(1 for f in free if f.period)


def calibration_table(free: Sequence[Free], f: FitResult, components: Mapping[str, str]
                      ) -> dict[str, dict[str, Any]]:
    """The report's calibrated values: {instance(s).parameter: value, 95 % interval, nominal,
    bounds, unit} of `free` fitted as `f`, the units those its instances' `components`
    (instance -> component) declare (`unit_of`)."""
    return {fr.key: {
        "value": x, "interval": list(iv), "nominal": fr.start, "lower": fr.lower,
        "upper": fr.upper, "unit": unit_of(components.get(fr.instances[0], ""), fr.name)}
        for fr, x, iv in zip(free, f.x, f.interval)}
