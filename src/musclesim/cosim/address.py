"""Typed addresses: a signal (instance, variable) and a parameter reference (instance, name).

Strings hold them only at the edges: scenario files, data sets, results.csv and report.json
write ``"instance.variable"``; everything inside musclesim passes these frozen types, parsed once
with `Signal.parse` / `ParamRef.parse` and printed with ``str()``. The variable's or parameter's
name may itself contain dots (FMI structured names such as ``flange.s``): the instance is
everything before the first dot.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Self


def _split(text: str, what: str) -> tuple[str, str]:
    if not isinstance(text, str):
        raise ValueError(f"{what} {text!r} is not a string \"instance.name\"")
    inst, sep, name = text.partition(".")
    if not sep or not inst or not name:
        raise ValueError(f"{what} {text!r} is not of the form \"instance.name\"")
    return inst, name


@dataclass(frozen=True, order=True)
class Signal:
    """The variable `variable` of the instance `instance`: an input, output or recorded signal.

    Examples
    --------
    >>> s = Signal.parse("body.flange_a.s")
    >>> s.instance, s.variable, str(s)
    ('body', 'flange_a.s', 'body.flange_a.s')
    """

    instance: str
    variable: str

    @classmethod
    def parse(cls, text: str) -> Self:
        """The signal ``"instance.variable"`` names; ValueError if `text` is not of that form."""
        return cls(*_split(text, "signal"))

    def __str__(self) -> str:
        return f"{self.instance}.{self.variable}"


@dataclass(frozen=True, order=True)
class ParamRef:
    """The parameter `name` of the instance `instance`, as ``--set`` and a data set's
    ``[calibrate]`` name it.

    Examples
    --------
    >>> p = ParamRef.parse("wire.T_amb")
    >>> p.instance, p.name, str(p)
    ('wire', 'T_amb', 'wire.T_amb')
    """

    instance: str
    name: str

    @classmethod
    def parse(cls, text: str) -> Self:
        """The parameter ``"instance.name"`` names; ValueError if `text` is not of that form."""
        return cls(*_split(text, "parameter"))

    def __str__(self) -> str:
        return f"{self.instance}.{self.name}"
