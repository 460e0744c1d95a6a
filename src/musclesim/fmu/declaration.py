"""One declaration per parameter: `declare` makes a field of a physics core's parameter dataclass
that carries the parameter's default, unit, description, source, role for the diagnosis (an
effect's fitting bounds or a `Calibration`) and plausible values; `Declaration` is one variable as
a slave declares it, which `musclesim.fmu.Slave.declarations` gives to the docs, the diagnosis and
the scenario checks.

Shipped inside every FMU with the rest of `musclesim.fmu`: the standard library only.
"""
from __future__ import annotations

import dataclasses
from typing import Any

from musclesim.fmu.units import DIFFERENCES, PLAUSIBLE, QUANTITIES, UNITS, Plausible

# what `declare`'s `plausible` takes: None (its unit's `PLAUSIBLE` range), "difference" (its
# unit's `DIFFERENCES` range), a name of `QUANTITIES` or a (lo, hi) range of its own
PlausibleSpec = tuple[float, float] | str | None


@dataclasses.dataclass(frozen=True)
class Calibration:
    """The role of a nominal value a real bench has differently: the diagnosis calibrates it
    before it tests any effect. The bounds are factors on the scenario's value (`relative`) or
    offsets added to it; `why` says what differs on a bench; a `period` (> 0) makes it periodic
    (a phase)."""

    lower: float
    upper: float
    relative: bool
    why: str
    period: float = 0.0


@dataclasses.dataclass(frozen=True)
class Declaration:
    """One variable as its component declares it. `type`: its FMI 2.0 type, "Real", "Integer"
    (a count, an index, a seed) or "Boolean" (a switch; 0 or 1 where values are numbers);
    `effect`: the (lower, upper) fitting bounds of an effect parameter, whose default is the
    effect off; `calibrate`: its `Calibration`; `source`: the model reference section the value
    comes from (``§label``); `depends`: the inputs an output depends on directly (None for other
    variables); `plausible`: the values it plausibly takes (`declare`'s, read with
    `plausible_range`); `same_unit_as`: for a variable of unit "1" that carries the quantity of
    another of the component (a signal source's offset, its output's; a controller's reference,
    its measurement's), that variable's name: a scenario's wiring gives them their unit."""

    name: str
    causality: str  # "parameter", "input" or "output"
    default: float
    unit: str
    description: str
    source: str = ""
    effect: tuple[float, float] | None = None
    calibrate: Calibration | None = None
    depends: tuple[str, ...] | None = None
    type: str = "Real"
    plausible: PlausibleSpec = None
    same_unit_as: str | None = None

    def plausible_range(self) -> Plausible | None:
        """The `Plausible` values of this variable, or None where neither its declaration nor its
        unit gives a range (a count, a gain, a force)."""
        return resolve(self.plausible, self.unit)


def resolve(plausible: PlausibleSpec, unit: str) -> Plausible | None:
    """The `Plausible` range `declare`'s `plausible` means for a variable of `unit` (ValueError
    for what `declare` does not take)."""
    if plausible is None:
        return PLAUSIBLE.get(unit)
    if plausible == "difference":
        return DIFFERENCES.get(unit)
    if isinstance(plausible, str) and plausible in QUANTITIES:
        return QUANTITIES[plausible]
    if isinstance(plausible, tuple) and len(plausible) == 2 and plausible[0] <= plausible[1]:
        return Plausible(float(plausible[0]), float(plausible[1]))
    raise ValueError(f"plausible {plausible!r} is not None, 'difference', a name of "
                     "musclesim.fmu.units.QUANTITIES or a range (lo, hi)")


def declare(default: float, unit: str, description: str, *, source: str = "",
            effect: tuple[float, float] | None = None, calibrate: Calibration | None = None,
            type: str = "Real", plausible: PlausibleSpec = None,
            same_unit_as: str | None = None) -> Any:
    """A field of a core's parameter dataclass declaring the parameter once: its `default`, SI
    `unit` (a key of `UNITS`), `description`, `source` (a ``§label`` of the model reference),
    FMI `type` ("Real", "Integer" or "Boolean", the last two of unit "1"), role: an effect's
    fitting bounds `effect` = (lower, upper) (the default is the effect off) or a
    `Calibration` (`calibrate`), and `plausible`, the values it plausibly takes, which a
    scenario's value must lie in (besides 0 where the default is 0, a feature off): None for its
    unit's `musclesim.fmu.units.PLAUSIBLE` range (a temperature above 150 K, a positive
    length...), "difference" for a bias, shift or amplitude (its unit's `DIFFERENCES` range),
    a quantity of `musclesim.fmu.units.QUANTITIES` ("gauge pressure", which may be negative;
    "wire stress") or (lo, hi) where its physics says otherwise; where the unit is "1" but the
    value is of the quantity another variable carries, `same_unit_as` names that variable (see
    `Declaration`). `musclesim.fmu.Slave.parameters_of` declares such fields as the FMU's
    parameters. The field (a ``dataclasses.Field``) is typed Any, as ``dataclasses.field`` is, so
    that ``m: float = declare(...)`` type-checks.

    Examples
    --------
    >>> @dataclasses.dataclass(frozen=True)
    ... class Params:
    ...     m: float = declare(0.2, "kg", "Block mass", source="§two-mass")
    >>> Params().m, dataclasses.fields(Params)[0].metadata["unit"]
    (0.2, 'kg')
    """
    if unit not in UNITS:
        raise ValueError(f"unit {unit!r} is not in musclesim.fmu.UNITS")
    resolve(plausible, unit)  # ValueError for a `plausible` it does not take
    return dataclasses.field(default=default, metadata={
        "unit": unit, "description": description, "source": source, "type": type,
        "effect": tuple(effect) if effect is not None else None, "calibrate": calibrate,
        "plausible": plausible, "same_unit_as": same_unit_as})
