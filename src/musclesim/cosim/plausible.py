"""A scenario's values checked against the values their parameters plausibly take, before any FMU
is loaded: a temperature written in degrees Celsius, a length in mm, a stress in MPa or an absurd
mass is refused in one sentence giving the value likely meant.

The ranges are the components' declarations (`musclesim.fmu.declare`'s ``plausible``, or its
unit's `musclesim.fmu.PLAUSIBLE` range); a value passes inside its range, or at 0 where the
declared default is 0 (a feature off). A variable of unit "1" that carries another's quantity
(``same_unit_as``: a signal source's offset, a controller's reference) takes the unit the
scenario's wiring gives it (`signal_unit`): a reference offset of 75 fed to a controller that
measures a temperature is a temperature. A component outside the catalogue (an FMU of another
tool) and a name its component does not declare are not checked here: the wiring check reports
the latter once the FMUs are read.
"""
from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable, Mapping

from musclesim.components import CATALOGUE, declarations
from musclesim.cosim.address import Signal
from musclesim.fmu import CELSIUS, SLIPS, Declaration, Plausible

# a value in K from this to this may be a temperature in degrees Celsius written as kelvin
_CELSIUS_LIKE = (-50.0, 150.0)


def declared(component: str, name: str) -> Declaration | None:
    """What `component` (a name of the catalogue) declares of its variable `name`, or None for a
    component outside the catalogue or a name it does not declare."""
    if component not in CATALOGUE:
        return None
    return declarations(component).get(name)


def signal_unit(components: Mapping[str, str], connections: Iterable[tuple[Signal, Signal]],
                signal: Signal) -> str:
    """The unit of `signal` in a scenario whose instances are of `components` (instance ->
    component) and wired by `connections` (source, destination): its declared unit, or for one
    of unit "1" the first unit declared along what carries the same quantity (its
    ``same_unit_as``, the variables naming it so, the signals connected to it); "1" if none."""
    links = list(connections)
    seen: set[Signal] = set()
    todo = [signal]
    while todo:
        sig = todo.pop(0)
        component = components.get(sig.instance, "")
        decl = declared(component, sig.variable)
        if sig in seen or decl is None:
            seen.add(sig)
            continue
        seen.add(sig)
        if decl.unit != "1":
            return decl.unit
        alike = [n for n, d in declarations(component).items()
                 if d.same_unit_as == sig.variable or n == decl.same_unit_as]
        todo += [Signal(sig.instance, n) for n in alike]
        todo += [src for src, dst in links if dst == sig]
        todo += [dst for src, dst in links if src == sig]
    return "1"


def problem(component: str, label: str, name: str, value: float, show: bool = True,
            unit: str | None = None) -> str | None:
    """What is implausible in setting variable `name` of `component` to `value`, or None.

    Parameters
    ----------
    component : str
        The component (a name of the catalogue; another is not checked).
    label : str
        How the sentence names the value (``"wire.T_init"``, or with the file it is in).
    name : str
        The variable of the component.
    value : float
        The value, in the variable's SI unit.
    show : bool
        Repeat the value in the sentence; False for a value read from a parameters file, whose
        values are not ours to print (the sentence then says how to convert instead).
    unit : str, optional
        The unit the scenario gives a variable declared of unit "1" (`signal_unit`).

    Returns
    -------
    str or None
        ``"wire.T_init = 45 K is below the plausible 150-1500 K for a temperature; 45 looks like
        degrees Celsius: write 318.15 K"``, or None for a plausible value.

    Examples
    --------
    >>> problem("SmaWire", "wire.T_init", "T_init", 318.15) is None
    True
    >>> said = problem("SmaWire", "wire.length", "length", 58.42)
    >>> said.startswith("wire.length = 58.42 m is above the plausible 0-10 m for a length; ")
    True
    >>> said.endswith("; 58.42 looks like mm: write 0.05842 m")
    True
    """
    decl = declared(component, name)
    if decl is not None and decl.unit == "1" and unit is not None:
        decl = dataclasses.replace(decl, unit=unit)
    rng = decl.plausible_range() if decl is not None else None
    if decl is None or rng is None or rng.lo <= value <= rng.hi or (value == 0
                                                                   and decl.default == 0):
        return None
    unit = "" if decl.unit == "1" else f" {decl.unit}"
    side = "below" if value < rng.lo else "above"
    lo, hi = f"{rng.lo:g}", f"{rng.hi:g}"
    span = f"{lo}-{hi}" if rng.lo >= 0 and "e" not in lo + hi else f"{lo} to {hi}"
    where = f"the plausible {span}{unit} for {rng.what}" if rng.what else \
        f"its plausible {span}{unit}"
    said = f"{label} = {value:.12g}{unit}" if show else f"{label}"
    text = f"{said} is {side} {where}"
    hint = _hint(decl, rng, value, show)
    return f"{text}; {hint}" if hint else text


def _hint(decl: Declaration, rng: Plausible, value: float, show: bool) -> str | None:
    """The value `value` of `decl` likely meant, if a usual slip of unit brings it into `rng`."""
    it = f"{value:.12g}" if show else "it"
    if decl.unit == "K" and _CELSIUS_LIKE[0] <= value <= _CELSIUS_LIKE[1] \
            and rng.lo <= value + CELSIUS <= rng.hi:
        return f"{it} looks like degrees Celsius: " + (
            f"write {value + CELSIUS:.12g} K" if show else f"add {CELSIUS:g} K")
    if not value > 0:
        return None
    fits = [(name, factor) for name, factor in SLIPS.get(decl.unit, ())
            if rng.lo <= value * factor <= rng.hi]
    if not fits:
        return None
    if decl.default > 0:  # the slip that lands nearest the declared default
        fits.sort(key=lambda fit: abs(math.log(value * fit[1] / decl.default)))
    name, factor = fits[0]
    return f"{it} looks like {name}: " + (
        f"write {value * factor:.12g} {decl.unit}" if show else f"multiply it by {factor:g}")
