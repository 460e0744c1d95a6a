"""The wiring of a scenario checked against its FMUs' model descriptions, before a run.

Every problem is collected (unknown instance or variable, answered with the nearest declared
name, a port renamed by format 2, wrong
causality, types or units that do not join, an input connected twice or also replayed, a value
a parameter cannot take, a recorded signal that does not exist) and returned as sentences for
`musclesim.cosim.master.Master` to raise once. `Loaded` is an instance of the scenario with the
model description of its FMU, and later the tables of the master's loop.
"""
from __future__ import annotations

import difflib
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from musclesim.components import renamed
from musclesim.cosim.address import Signal
from musclesim.cosim.adapters import KINDS
from musclesim.cosim.scenario import Scenario, unknown_instance

Call = Callable[[], None]  # a get or set of the master's loop, made once


class Loaded:
    """An instance of the scenario, its FMU's model description `md` read; once the master has
    planned and instantiated it, the value-reference and buffer-slot tables of its loop."""

    def __init__(self, name: str, component: str, md: Any) -> None:
        """Instance `name` of `component`, whose FMU's model description is `md`."""
        self.name, self.component, self.md = name, component, md
        self.vars: dict[str, Any] = {v.name: v for v in md.modelVariables}
        self.feedthrough: dict[str, bool] = {}  # input -> True if an output depends on it at once
        for out in md.outputs:
            deps = out.dependencies
            for v in md.modelVariables:
                if v.causality == "input" and (deps is None or v in deps):
                    self.feedthrough[v.name] = True
        self.slave: Any = None  # a DirectSlave or an fmpy adapter, while the run goes
        self.log: list[tuple[int, str]] = []  # (FMI status, message) the FMU logged
        # planned (`Master._plan`): the signals read from it, at buffer slots first, first + 1..
        self.reads: list[Signal] = []
        self.first = 0
        self.read_vrs: list[int] = []
        self.read_kinds: list[str] = []
        # (value references, buffer slots, kinds) of the inputs set early, late and all
        self.transfers: list[tuple[list[int], np.ndarray, list[str]]] = []
        # instantiated (`Master._instantiate`): the calls of the loop
        self.get: Call | None = None
        self.set_early: Call | None = None
        self.set_late: Call | None = None
        self.set_all: Call | None = None
        self.before_step: Call | None = None
        self.after_step: Call | None = None
        self.step: Callable[[float, float], None] = _not_instantiated
        self.every = 1


def _not_instantiated(t: float, h: float) -> None:
    """The step of an instance not instantiated yet."""
    raise RuntimeError("an instance steps only once the master has instantiated it")


def _a(word: str) -> str:
    """`word` with its indefinite article ("an output", "a parameter")."""
    return ("an " if word[0].lower() in "aeiou" else "a ") + word


def variable(instances: Mapping[str, Loaded], signal: Signal, problems: list[str],
             what: str) -> Any:
    """The model variable `signal` names among `instances`, or None with the reason appended to
    `problems` (the signal called `what`: "connection source", "parameter", ...)."""
    inst, var = signal.instance, signal.variable
    if inst not in instances:
        problems.append(f"{what} {str(signal)!r}: "
                        f"{unknown_instance(inst, instances, 'the scenario declares')}")
        return None
    v = instances[inst].vars.get(var)
    now = renamed(instances[inst].component, var)
    if v is None and now:
        problems.append(f"{what} {str(signal)!r}: {instances[inst].component}'s {var} has "
                        f"been renamed {now} (the Modelica Standard Library's port names)")
    elif v is None:
        near = difflib.get_close_matches(var, instances[inst].vars, n=1)
        problems.append(f"{what} {str(signal)!r}: {instances[inst].component} has no variable "
                        f"{var!r}" + (f"; it declares {near[0]!r}" if near else
                                      f" (variables: {', '.join(instances[inst].vars)})"))
    elif v.type not in KINDS:
        problems.append(f"{what} {str(signal)!r}: only Real, Integer and Boolean (FMI 2.0) and "
                        f"Float64, Int32 and Boolean (FMI 3.0) variables are supported, not "
                        f"{v.type}")
        return None
    return v


def check(s: Scenario, instances: Mapping[str, Loaded], inputs: Mapping[Signal, np.ndarray],
          problems: list[str]) -> None:
    """Append to `problems` what is wrong in scenario `s` against its `instances`' model
    descriptions, with `inputs` replayed (one value per communication point each)."""
    targets: dict[Signal, Signal] = {}
    for src, dst in s.connections:
        vs = variable(instances, src, problems, "connection source")
        vd = variable(instances, dst, problems, "connection destination")
        if vs is None or vd is None:
            continue
        if vs.causality != "output":
            problems.append(f"connection {src} -> {dst}: {src} is {_a(vs.causality)}, "
                            "not an output")
        if vd.causality != "input":
            problems.append(f"connection {src} -> {dst}: {dst} is {_a(vd.causality)}, "
                            "not an input")
        if KINDS[vs.type] != KINDS[vd.type]:
            problems.append(f"connection {src} -> {dst} joins {_a(vs.type)} output to "
                            f"{_a(vd.type)} input; FMI connects variables of one type")
        if vs.unit and vd.unit and vs.unit != vd.unit:  # a unitless port takes any signal
            problems.append(f"connection {src} -> {dst} joins incompatible units "
                            f"{vs.unit!r} and {vd.unit!r}")
        if dst in targets:
            problems.append(f"input {dst} is connected twice (from {targets[dst]} and {src})")
        targets[dst] = src
    for dst, values in inputs.items():
        v = variable(instances, dst, problems, "replayed input")
        if v is not None and v.causality != "input":
            problems.append(f"replayed input {dst} is {_a(v.causality)}, not an input")
        if dst in targets:
            problems.append(f"replayed input {dst} is also connected (from {targets[dst]})")
        if values.shape != (s.n_steps + 1,):
            problems.append(f"replayed input {dst} has {values.size} values, not one per "
                            f"communication point ({s.n_steps + 1})")
    for name, spec in s.instances.items():
        for par, value in spec.parameters.items():
            _check_value(instances, Signal(name, par), value, targets, inputs, problems)
    for sig in s.recorded():
        variable(instances, sig, problems, "recorded signal")


def _check_value(instances: Mapping[str, Loaded], signal: Signal, value: float,
                 targets: Mapping[Signal, Signal], inputs: Mapping[Signal, object],
                 problems: list[str]) -> None:
    """A value a scenario sets: a parameter, or an input nothing feeds (a bench condition
    such as the ambient temperature, held constant); an Integer's a whole number, a
    Boolean's 0 or 1."""
    v = variable(instances, signal, problems, "parameter")
    if v is not None and KINDS[v.type] == "Integer" and not float(value).is_integer():
        problems.append(f"{signal} is an Integer: {value!r} is not a whole number")
    if v is not None and KINDS[v.type] == "Boolean" and value not in (0, 1):
        problems.append(f"{signal} is a Boolean: {value!r} is neither 0 (false) nor 1 (true)")
    if v is None or v.causality == "parameter":
        return
    if v.causality != "input":
        problems.append(f"{signal} is {_a(v.causality)}, not a parameter or an input")
    elif signal in targets:
        problems.append(f"{signal} is an input connected from {targets[signal]}: a value set "
                        "on it would be overwritten at every step")
    elif signal in inputs:
        problems.append(f"{signal} is an input replayed from data: it cannot also be set")
