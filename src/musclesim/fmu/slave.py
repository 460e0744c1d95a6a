"""The project's pythonfmu base class: SI units, a complete ModelStructure and real FMU state.

Every component's FMU slave derives from `Slave`; the units it declares are in
`musclesim.fmu.units`, a parameter's declaration in `musclesim.fmu.declaration`, its clock in
`musclesim.fmu.clock`. It fixes, once, what pythonfmu 0.7 leaves out:

- ``ModelStructure/InitialUnknowns`` (pythonfmu writes none, so fmpy's ``validate_fmu`` complains
  about every calculated output) and ``Outputs`` dependencies, which declare direct feedthrough
  so that a master can order the exchange of values at a communication point;
- units: every Real carries an SI unit, declared in ``UnitDefinitions``, and where users read
  another one a display unit (`DISPLAY_UNITS`: C, MPa or kPa, mm);
- FMU state: pythonfmu's default ``_get_fmu_state`` copies registered variables only, losing
  internal state (integrator state, memories, random generators); ours deep-copies all of it,
  and serializes it with pickle (pythonfmu's JSON takes none of those), so that a tool can save a
  state to a file and restore it in another instance (``canSerializeFMUstate``). Restore only
  states you saved yourself: unpickling runs code, as loading any FMU does;
- a default experiment (FMI ``DefaultExperiment``): start 0 and, per component, the stop time and
  step of the study's experiment it comes from (`experiment`), which a tool runs when told
  nothing else.

A slave declares its core's parameters with `parameters_of` (the fields made with
`musclesim.fmu.declare`), its other variables with `parameter`, `input` and `output`;
`Slave.declarations` gives each variable's `Declaration`. It builds its physics core in `setup`,
computes outputs in `evaluate` and advances state in `advance`. This module imports nothing but
the standard library and pythonfmu: it is shipped inside every FMU, which must run where only
Python, numpy and scipy are installed.
"""
from __future__ import annotations

import copy
import dataclasses
import math
import operator
import pickle
import warnings
from typing import Any, Callable, Mapping, Sequence, TypeVar
from xml.etree.ElementTree import Element, SubElement

from pythonfmu import (Boolean, Fmi2Causality, Fmi2Initial, Fmi2Slave, Fmi2Variability, Integer,
                       Real)
from pythonfmu.enums import Fmi2Status

from musclesim.fmu.declaration import Declaration, resolve
from musclesim.fmu.clock import experiment, step_end
from musclesim.fmu.units import UNITS, unit_definitions

T = TypeVar("T")

# attributes that belong to the FMI plumbing, not to the model's state
_NOT_STATE = frozenset({"vars", "log_queue", "_getters", "_setters", "_attrs", "_meta",
                        "_parameters"})


# the FMI 2.0 variable of each type, and the Python value the FMI calls take for it; a slave
# keeps every value as a float, so that its physics reads Integer and Boolean values as numbers
_TYPES: dict[str, tuple[type, type]] = {"Real": (Real, float), "Integer": (Integer, int),
                                        "Boolean": (Boolean, bool)}


def _find(root: Element, tag: str) -> Element:
    """The child `tag` of model description `root`, which pythonfmu always writes."""
    child = root.find(tag)
    if child is None:
        raise ValueError(f"the model description has no {tag}")
    return child


class Slave(Fmi2Slave):
    """Base of every musclesim FMU slave (FMI 2.0 co-simulation through pythonfmu).

    Subclasses declare variables in ``__init__`` and override:

    - `setup()`: check parameters (raise ``ValueError`` with a sentence naming the parameter) and
      build the physics core; runs before outputs are first needed, again if a parameter changes
      during initialization;
    - `initialize()`: set the initial internal state from the parameters and the inputs, leaving
      initialization mode and whenever outputs are read before (so it may run several times);
    - `evaluate()`: set the outputs from the current state, inputs and time, changing nothing
      else: it runs when outputs are read (or a step needs them) after a step or after an input
      was set, not after every step, so it may run any number of times (outputs declared with
      ``depends`` are direct feedthrough; tests/fmu/test_slave.py checks the rule);
    - `advance(t, dt)`: advance the internal state from ``t`` to ``t + dt`` with the current inputs.
    """

    author = "musclesim"
    license = "MIT"
    default_experiment = experiment(10.0, 1e-3)  # components set their study's experiment
    # the display unit of each unit that has one (`DISPLAY_UNITS`): temperatures in C, stresses
    # in MPa, positions in mm; a component whose pascals are air pressures shows them in kPa
    display_units: dict[str, str] = {"K": "degC", "Pa": "MPa", "m": "mm"}

    def __init__(self, **kwargs: Any) -> None:
        """`**kwargs`: pythonfmu's (``instance_name``, ``resources``, ``visible``, ...), passed
        on to it; a subclass declares its variables after calling this."""
        super().__init__(**kwargs)
        self._getters: list[Callable[[], Any]] = []
        self._setters: list[Callable[[Any], None]] = []
        self._attrs: list[str] = []  # attribute holding each variable, by value reference
        self._meta: dict[str, Declaration] = {}
        self._parameters: set[int] = set()  # value references of parameters
        self._configured = False  # setup() has run for the current parameter values
        self._initialized = False  # initialization mode has been left
        self._dirty = True  # an input changed since the outputs were evaluated
        self._clamped: set[str] = set()  # inputs whose clamping has been warned about
        self.time = self.start_time = 0.0

    # ---- declaring variables -------------------------------------------------------------------
    def _declare(self, name: str, value: float, unit: str, description: str,
                 causality: Fmi2Causality, variability: Fmi2Variability,
                 initial: Fmi2Initial | None, depends: tuple[str, ...] | None, type: str = "Real",
                 **role: Any) -> None:
        if unit not in UNITS:
            raise ValueError(f"variable {name}: unit {unit!r} is not in musclesim.fmu.UNITS")
        if type not in _TYPES or (type != "Real" and unit != "1"):
            raise ValueError(f"variable {name}: type {type!r} is not Real, or Integer or Boolean "
                             "of unit 1")
        if type != "Real":  # FMI 2.0 knows no continuous Integer or Boolean
            variability = variability if causality == Fmi2Causality.parameter else \
                Fmi2Variability.discrete
            if value != _TYPES[type][1](value):
                raise ValueError(f"variable {name}: {value!r} is not {type}")
        resolve(role.get("plausible"), unit)  # ValueError for a `plausible` it does not take
        # the FMU's description names the section its value comes from
        source = role.get("source")
        attr = name.replace(".", "_")
        kind, typed = _TYPES[type]
        setattr(self, attr, float(value))  # assign before registering, or pythonfmu makes no setter
        self.register_variable(kind(
            name, causality=causality, variability=variability,
            description=f"{description} ({source})" if source else description,
            initial=initial, getter=(lambda: getattr(self, attr)) if type == "Real" else (
                lambda: typed(getattr(self, attr))),  # a Real's is called at every get_real
            setter=lambda v: setattr(self, attr, float(v))))
        var = self.vars[len(self.vars) - 1]
        self._getters.append(var.getter)
        self._setters.append(var.setter)
        self._attrs.append(attr)
        if causality == Fmi2Causality.parameter:
            self._parameters.add(var.value_reference)
        self._meta[name] = Declaration(name, causality.name, float(value), unit, description,
                                       depends=depends, type=type, **role)

    def parameter(self, name: str, default: float, unit: str, description: str,
                  **role: Any) -> None:
        """Declare a fixed parameter `name` (set before initialization), stored as attribute, with
        its `default`, `unit` and `description`; `**role`: `musclesim.fmu.declare`'s type,
        source, effect, calibrate, plausible or same_unit_as, for a parameter no core dataclass
        holds (another keyword raises TypeError)."""
        self._declare(name, default, unit, description, Fmi2Causality.parameter,
                      Fmi2Variability.fixed, Fmi2Initial.exact, None, **role)

    def parameters_of(self, cls: type, skip: Sequence[str] = (),
                      overrides: Mapping[str, Mapping[str, Any]] | None = None) -> None:
        """Declare as parameters the fields of the core's dataclass `cls` made with `declare`, in
        their order, but not those in `skip`. A core shared by several components (the sensors')
        has per-component units, defaults or roles: `overrides`, ``overrides[name]``, is a dict
        replacing any of the field's declared default, unit, description, source, type, effect,
        calibrate, plausible or same_unit_as (ValueError for a name `cls` does not declare)."""
        overrides = dict(overrides or {})
        for f in dataclasses.fields(cls):
            if "unit" in f.metadata and f.name not in skip:
                m = {**f.metadata, "default": f.default, **overrides.pop(f.name, {})}
                self.parameter(f.name, m["default"], m["unit"], m["description"], type=m["type"],
                               source=m["source"], effect=m["effect"], calibrate=m["calibrate"],
                               plausible=m["plausible"], same_unit_as=m["same_unit_as"])
        if overrides:
            raise ValueError(f"{cls.__name__} declares no {', '.join(overrides)}")

    def input(self, name: str, start: float, unit: str, description: str, **role: Any) -> None:
        """Declare a continuous Real input `name` with its `start` value, `unit` and
        `description` (`**role`: a `Calibration` of an input held constant, such as the ambient
        temperature; `declare`'s source, plausible (the values a scenario may hold it at) or
        same_unit_as; another keyword raises TypeError)."""
        self._declare(name, start, unit, description, Fmi2Causality.input,
                      Fmi2Variability.continuous, None, None, **role)

    def output(self, name: str, unit: str, description: str, depends: Sequence[str] = (),
               type: str = "Real", same_unit_as: str | None = None) -> None:
        """Declare a calculated output `name` of `unit` and `description` (Real unless `type`
        says "Integer" or "Boolean"); `depends` names the inputs it depends on directly;
        `same_unit_as`, for an output of unit "1" that carries another variable's quantity (a
        controller's error, its measurement's), that variable's name (`Declaration`)."""
        self._declare(name, 0.0, unit, description, Fmi2Causality.output,
                      Fmi2Variability.continuous, Fmi2Initial.calculated, tuple(depends), type,
                      same_unit_as=same_unit_as)

    @classmethod
    def declarations(cls) -> dict[str, Declaration]:
        """{name: `Declaration`} of every variable the slave class declares, in order."""
        return dict(cls(instance_name=cls.__name__)._meta)

    def log(self, msg: str, status: Fmi2Status = Fmi2Status.ok, category: str | None = None,
            debug: bool | None = None) -> None:
        """Queue `msg` of `status` and `category` for the FMU log as pythonfmu does, with the
        debug flag pythonfmu3's C layer reads too, always False (an FMI 3.0 face shares this
        queue; a message without it crashed the process); `debug` is pythonfmu's, unused."""
        super().log(msg, status, category)
        self.log_queue[-1].debug = False

    def logged(self, call: Callable[..., T], *args: Any) -> T:
        """`call` (`*args`) with the warnings it raises (a core's one-time range warnings) sent to
        the FMU log as warnings instead of the process's stderr."""
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = call(*args)
        for w in caught:
            self.log(str(w.message), Fmi2Status.warning)
        return result

    def core_params(self, cls: Callable[..., T]) -> T:
        """The core's parameter dataclass `cls` from the parameters of the same names, checked.

        ``cls.check()`` raises ValueError naming a bad parameter; the FMU reports it as the cause.
        """
        params = cls(**{name: getattr(self, name)
                        for name in cls.__dataclass_fields__})  # type: ignore[attr-defined]
        params.check()  # type: ignore[attr-defined]
        return params

    def clamped_input(self, name: str, lo: float, hi: float, t: float) -> float:
        """Input `name` clamped to [`lo`, `hi`] at time `t`; its first clamp is logged as a
        warning, NaN raises ValueError."""
        value = getattr(self, name.replace(".", "_"))
        if math.isnan(value):
            raise ValueError(f"input {name} is NaN at t = {t:g} s")
        if lo <= value <= hi:
            return value
        clamped = min(max(value, lo), hi)
        if name not in self._clamped:
            self._clamped.add(name)
            self.log(f"{name} {value:g} at t = {t:g} s is outside [{lo:g}, {hi:g}]; clamped to "
                     f"{clamped:g} (warned once)", Fmi2Status.warning)
        return clamped

    # ---- hooks for subclasses ------------------------------------------------------------------
    def setup(self) -> None:
        """Check parameters and build the physics core; may run again while initializing."""

    def initialize(self) -> None:
        """Set the initial internal state from parameters and inputs (leaving initialization)."""

    def evaluate(self) -> None:
        """Set the outputs from the state, the current inputs and the time; change nothing
        else."""

    def advance(self, t: float, dt: float) -> None:
        """Advance the internal state from `t` to `t` + `dt`."""

    # ---- FMI calls -----------------------------------------------------------------------------
    def setup_experiment(self, start_time: float, stop_time: float | None = None,
                         tolerance: float | None = None) -> None:
        """FMI setupExperiment: time starts at `start_time`; `stop_time` and `tolerance` are
        not used."""
        self.time = self.start_time = float(start_time)

    def _refresh(self) -> None:
        if not self._configured:
            self.setup()
            self._configured = True
            self._dirty = True
        if self._dirty:
            if not self._initialized:
                # before initialization ends, outputs are those of the initial state for the
                # inputs set so far, so that values passed in initialization mode hold after it
                # (FMPy's container passes none after it)
                self.initialize()
            self.evaluate()
            self._dirty = False

    def exit_initialization_mode(self) -> None:
        """FMI exitInitializationMode: the initial state and outputs from the inputs set."""
        self._dirty = True  # the initial state from the inputs as they are now, then its outputs
        self._refresh()
        self._initialized = True

    def do_step(self, current_time: float, step_size: float) -> bool:
        """FMI doStep: advance from `current_time` by `step_size`; True (pythonfmu's ok)."""
        self._refresh()  # advance may read what evaluate sets (a friction block's contact)
        self.advance(current_time, step_size)
        self.time = step_end(self.start_time, current_time, step_size)
        self._dirty = True  # outputs evaluated when read: a master sets inputs first, mostly
        return True

    def get_real(self, vrs: Sequence[int]) -> list[float]:
        """FMI getReal: the values of the value references `vrs`."""
        self._refresh()
        getters = self._getters
        return [getters[vr]() for vr in vrs]

    def get_integer(self, vrs: Sequence[int]) -> list[int]:
        """FMI getInteger: the values of the value references `vrs`."""
        self._refresh()
        return super().get_integer(vrs)

    def get_boolean(self, vrs: Sequence[int]) -> list[bool]:
        """FMI getBoolean: the values of the value references `vrs`."""
        self._refresh()
        return super().get_boolean(vrs)

    def set_integer(self, vrs: Sequence[int], values: Sequence[int]) -> None:
        """FMI setInteger: set the value references `vrs` to `values` (kept as floats)."""
        self.set_real(vrs, values)  # every value is kept as a float

    def set_boolean(self, vrs: Sequence[int], values: Sequence[bool]) -> None:
        """FMI setBoolean: set the value references `vrs` to `values` (kept as floats)."""
        self.set_real(vrs, values)

    def set_real(self, vrs: Sequence[int], values: Sequence[float]) -> None:
        """FMI setReal: set the value references `vrs` to `values`; a parameter only before
        initialization ends (ValueError after)."""
        setters = self._setters
        for vr, value in zip(vrs, values):
            if vr in self._parameters:
                if self._initialized:
                    raise ValueError(f"parameter {self.vars[vr].name} is fixed: it can only be set "
                                     "before initialization ends")
                self._configured = False
            setters[vr](value)
        self._dirty = True

    # ---- batched calls for a host in this process (musclesim.cosim.direct) ----------------------
    def reader(self, vrs: Sequence[int]) -> Callable[[], tuple[float, ...]]:
        """A function returning the values of `vrs` as a tuple: what ``get_real(vrs)`` returns,
        without a Python call per variable."""
        attrs = [self._attrs[vr] for vr in vrs]
        get: Callable[[Slave], Any] = operator.attrgetter(*attrs)
        refresh = self._refresh
        if len(attrs) == 1:
            return lambda: (refresh(), (get(self),))[1]
        return lambda: (refresh(), get(self))[1]

    def writer(self, vrs: Sequence[int]) -> Callable[[Sequence[float]], None]:
        """A function setting `vrs` to its argument's values: what ``set_real(vrs, values)`` does,
        for inputs (parameters go through `set_real`, which guards them)."""
        if any(vr in self._parameters for vr in vrs):
            raise ValueError("writer() sets inputs; set parameters with set_real")
        attrs = [self._attrs[vr] for vr in vrs]

        def write(values: Sequence[float]) -> None:
            for attr, value in zip(attrs, values):
                setattr(self, attr, float(value))
            self._dirty = True
        return write

    def _get_fmu_state(self) -> dict[str, Any]:
        return copy.deepcopy({k: v for k, v in self.__dict__.items() if k not in _NOT_STATE})

    def _set_fmu_state(self, state: dict[str, Any]) -> None:
        # copy again: the same saved state may be restored several times
        self.__dict__.update(copy.deepcopy(state))

    @staticmethod
    def _fmu_state_to_bytes(state: dict[str, Any]) -> bytes:
        return pickle.dumps(state, protocol=pickle.HIGHEST_PROTOCOL)

    @staticmethod
    def _fmu_state_from_bytes(data: bytes) -> dict[str, Any]:
        return pickle.loads(data)

    # ---- model description ---------------------------------------------------------------------
    def describe_units(self, root: Element,
                       typed: Callable[[Element], Element] = lambda v: v[0]) -> Element:
        """Give each variable of model description `root` its unit, display unit and exact start
        value (on the element `typed` returns for it: FMI 2.0's type child, FMI 3.0's variable
        itself; a variable this slave does not declare, FMI 3.0's time, is in s), add the
        UnitDefinitions after CoSimulation, and return the ModelStructure element, emptied."""
        used = set()
        for v in _find(root, "ModelVariables"):
            declared = self._meta.get(v.get("name", ""))
            unit = declared.unit if declared else "s"
            if declared and declared.type == "Real" and typed(v).get("start") is not None:
                typed(v).set("start", repr(declared.default))  # pythonfmu writes 16 digits
            if unit != "1":
                typed(v).set("unit", unit)
                if unit in self.display_units:
                    typed(v).set("displayUnit", self.display_units[unit])
                used.add(unit)
        root.insert(list(root).index(_find(root, "CoSimulation")) + 1,
                    unit_definitions(used, self.display_units))
        structure = _find(root, "ModelStructure")
        for child in list(structure):
            structure.remove(child)
        return structure

    def feedthrough(self) -> list[tuple[str, tuple[str, ...]]]:
        """[(output name, names of the inputs it depends on directly)], in declaration order."""
        return [(n, d.depends) for n, d in self._meta.items() if d.depends is not None]

    def to_xml(self, model_options: dict[str, str] | None = None) -> Element:
        """The model description, pythonfmu's (`model_options`: its options) with units and a
        complete ModelStructure (outputs' dependencies, initial unknowns)."""
        root = super().to_xml(model_options or {})
        index = {v.get("name"): i for i, v in enumerate(_find(root, "ModelVariables"), start=1)}
        structure = self.describe_units(root)
        outputs = self.feedthrough()
        if outputs:
            node = SubElement(structure, "Outputs")
            for name, deps in outputs:
                SubElement(node, "Unknown", index=str(index[name]),
                           dependencies=" ".join(str(index[d]) for d in deps))
            # outputs are initial="calculated": they are initial unknowns, depending on everything
            node = SubElement(structure, "InitialUnknowns")
            for name, _ in outputs:
                SubElement(node, "Unknown", index=str(index[name]))
        return root
