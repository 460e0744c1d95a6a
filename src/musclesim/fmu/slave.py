"""The project's pythonfmu base class: SI units, a complete ModelStructure and real FMU state.

Every component's FMU slave derives from `Slave`. It fixes, once, what pythonfmu 0.7 leaves out:

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

A component's parameters are declared once, where its physics core takes them: a field of the
core's parameter dataclass made with `declare` carries its default, unit, description, the docs
section it comes from and its role for the diagnosis (an effect's fitting bounds, a `Calibration`).
The slave declares them with `parameters_of`, its other variables with `parameter`, `input` and
`output`; `Slave.declarations` gives every variable's `Declaration` (the docs' tables and the
diagnosis's effect and calibration catalogues read them). The slave turns parameters into its
physics core in `setup`, computes outputs in `evaluate` and advances state in `advance`.
This module must import nothing but the standard library, numpy and pythonfmu: it is shipped inside
every FMU, which must run where only Python, numpy and scipy are installed.
"""
import copy
import dataclasses
import math
import operator
import pickle
import warnings
from xml.etree.ElementTree import Element, SubElement

from pythonfmu import (Boolean, DefaultExperiment, Fmi2Causality, Fmi2Initial, Fmi2Slave,
                       Fmi2Variability, Integer, Real)
from pythonfmu.enums import Fmi2Status

# SI base-unit exponents of every unit a variable may carry (FMI 2.0 BaseUnit attributes).
UNITS = {
    "m": {"m": 1},
    "m/s": {"m": 1, "s": -1},
    "m/s2": {"m": 1, "s": -2},
    "m2": {"m": 2},
    "m3": {"m": 3},
    "m3/(s.Pa)": {"m": 4, "kg": -1, "s": 1},
    "kg": {"kg": 1},
    "s": {"s": 1},
    "Hz": {"s": -1},
    "rad": {"rad": 1},
    "N": {"kg": 1, "m": 1, "s": -2},
    "N/m": {"kg": 1, "s": -2},
    "N.s/m": {"kg": 1, "s": -1},
    "Pa": {"kg": 1, "m": -1, "s": -2},
    "K": {"K": 1},
    "W": {"kg": 1, "m": 2, "s": -3},
    "V": {"kg": 1, "m": 2, "s": -3, "A": -1},
    "A": {"A": 1},
    "Ohm": {"kg": 1, "m": 2, "s": -3, "A": -2},
    "H": {"kg": 1, "m": 2, "s": -2, "A": -2},
    "N/A": {"kg": 1, "m": 1, "s": -2, "A": -1},
    "1/A": {"A": -1},
    "1/s": {"s": -1},
    "1/rad": {"rad": -1},
    "kg/s": {"kg": 1, "s": -1},
    "kg/m3": {"kg": 1, "m": -3},
    "J/kg": {"m": 2, "s": -2},
    "J/(kg.K)": {"m": 2, "s": -2, "K": -1},
    "W/K": {"kg": 1, "m": 2, "s": -3, "K": -1},
    "W/(m2.K)": {"kg": 1, "s": -3, "K": -1},
    "W/(m.K)": {"kg": 1, "m": 1, "s": -3, "K": -1},
    "Ohm.m": {"kg": 1, "m": 3, "s": -3, "A": -2},
    "1": {},
}

# display units a tool may show a variable in (FMI 2.0 DisplayUnit: shown = factor * value +
# offset): name -> (unit, factor, offset)
DISPLAY_UNITS = {
    "degC": ("K", 1.0, -273.15),
    "MPa": ("Pa", 1e-6, 0.0),
    "kPa": ("Pa", 1e-3, 0.0),
    "mm": ("m", 1e3, 0.0),
}

# attributes that belong to the FMI plumbing, not to the model's state
_NOT_STATE = frozenset({"vars", "log_queue", "_getters", "_setters", "_attrs", "_meta",
                        "_parameters"})


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
    variables)."""

    name: str
    causality: str  # "parameter", "input" or "output"
    default: float
    unit: str
    description: str
    source: str = ""
    effect: tuple = None
    calibrate: Calibration = None
    depends: tuple = None
    type: str = "Real"


# the FMI 2.0 variable of each type, and the Python value the FMI calls take for it; a slave
# keeps every value as a float, so that its physics reads Integer and Boolean values as numbers
_TYPES = {"Real": (Real, float), "Integer": (Integer, int), "Boolean": (Boolean, bool)}


def declare(default, unit, description, *, source="", effect=None, calibrate=None, type="Real"):
    """A field of a core's parameter dataclass declaring the parameter once: its `default`, SI
    `unit` (a key of `UNITS`), `description`, `source` (a ``§label`` of the model reference),
    FMI `type` ("Real", "Integer" or "Boolean", the last two of unit "1") and role: an effect's
    fitting bounds `effect` = (lower, upper) (the default is the effect off) or a
    `Calibration`. `Slave.parameters_of` declares such fields as the FMU's parameters.

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
    return dataclasses.field(default=default, metadata={
        "unit": unit, "description": description, "source": source, "type": type,
        "effect": tuple(effect) if effect is not None else None, "calibrate": calibrate})


def step_end(t0, t, h):
    """The time a step of `h` from `t` ends at: t0 + (k + 1) h where `t` is the point t0 + k h of
    a master counting its points from the start time t0 (musclesim's, FMPy's), so that a
    time-driven output reads the same instant whoever steps it; t + h otherwise.

    Examples
    --------
    >>> step_end(0.0, 9 * 0.001, 0.001), 9 * 0.001 + 0.001
    (0.01, 0.010000000000000002)
    """
    k = round((t - t0) / h) if h > 0 else None
    return t0 + (k + 1) * h if k is not None and t0 + k * h == t else t + h


def experiment(stop_time, step):
    """The FMI default experiment of a component: from 0 to `stop_time` [s] in steps of `step`
    [s]."""
    return DefaultExperiment(start_time=0.0, stop_time=stop_time, step_size=step)


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
      ``depends`` are direct feedthrough; tests/fmu/test_evaluate_contract.py checks the rule);
    - `advance(t, dt)`: advance the internal state from ``t`` to ``t + dt`` with the current inputs.
    """

    author = "musclesim"
    license = "MIT"
    default_experiment = experiment(10.0, 1e-3)  # components set their study's experiment
    # the display unit of each unit that has one (`DISPLAY_UNITS`): temperatures in C, stresses
    # in MPa, positions in mm; a component whose pascals are air pressures shows them in kPa
    display_units = {"K": "degC", "Pa": "MPa", "m": "mm"}

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._getters = []
        self._setters = []
        self._attrs = []  # attribute holding each variable, by value reference
        self._meta = {}
        self._parameters = set()  # value references of parameters
        self._configured = False  # setup() has run for the current parameter values
        self._initialized = False  # initialization mode has been left
        self._dirty = True  # an input changed since the outputs were evaluated
        self._clamped = set()  # inputs whose clamping has been warned about
        self.time = self.start_time = 0.0

    # ---- declaring variables -------------------------------------------------------------------
    def _declare(self, name, value, unit, description, causality, variability, initial, depends,
                 type="Real", **role):
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

    def parameter(self, name, default, unit, description, **role):
        """Declare a fixed parameter (set before initialization), stored as attribute; `role`:
        `declare`'s type, source, effect or calibrate, for a parameter no core dataclass holds."""
        self._declare(name, default, unit, description, Fmi2Causality.parameter,
                      Fmi2Variability.fixed, Fmi2Initial.exact, None, **role)

    def parameters_of(self, cls, skip=(), **overrides):
        """Declare as parameters the fields of the core's dataclass `cls` made with `declare`, in
        their order, but not those in `skip`. A core shared by several components (the sensors')
        has per-component units, defaults or roles: ``overrides[name]`` is a dict replacing any
        of the field's declared default, unit, description, source, type, effect or calibrate."""
        for f in dataclasses.fields(cls):
            if "unit" in f.metadata and f.name not in skip:
                m = {**f.metadata, "default": f.default, **overrides.pop(f.name, {})}
                self.parameter(f.name, m["default"], m["unit"], m["description"], type=m["type"],
                               source=m["source"], effect=m["effect"], calibrate=m["calibrate"])
        if overrides:
            raise ValueError(f"{cls.__name__} declares no {', '.join(overrides)}")

    def input(self, name, start, unit, description, **role):
        """Declare a continuous Real input with its start value (`role`: a `Calibration` of an
        input held constant, such as the ambient temperature; `declare`'s source)."""
        self._declare(name, start, unit, description, Fmi2Causality.input,
                      Fmi2Variability.continuous, None, None, **role)

    def output(self, name, unit, description, depends=(), type="Real"):
        """Declare a calculated output (Real unless `type` says "Integer" or "Boolean");
        ``depends`` names the inputs it depends on directly."""
        self._declare(name, 0.0, unit, description, Fmi2Causality.output,
                      Fmi2Variability.continuous, Fmi2Initial.calculated, tuple(depends), type)

    @classmethod
    def declarations(cls):
        """{name: `Declaration`} of every variable the slave class declares, in order."""
        return dict(cls(instance_name=cls.__name__)._meta)

    def log(self, msg, status=Fmi2Status.ok, category=None, debug=None):
        """Queue `msg` for the FMU log as pythonfmu does, with the debug flag pythonfmu3's C
        layer reads too (an FMI 3.0 face shares this queue; a message without it crashed the
        process)."""
        super().log(msg, status, category)
        self.log_queue[-1].debug = False

    def logged(self, call, *args):
        """call(*args) with the warnings it raises (a core's one-time range warnings) sent to the
        FMU log as warnings instead of the process's stderr."""
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = call(*args)
        for w in caught:
            self.log(str(w.message), Fmi2Status.warning)
        return result

    def core_params(self, cls):
        """The core's parameter dataclass `cls` from the parameters of the same names, checked.

        ``cls.check()`` raises ValueError naming a bad parameter; the FMU reports it as the cause.
        """
        params = cls(**{name: getattr(self, name) for name in cls.__dataclass_fields__})
        params.check()
        return params

    def clamped_input(self, name, lo, hi, t):
        """Input `name` clamped to [lo, hi] at time t; its first clamp is logged as a warning,
        NaN raises ValueError."""
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
    def setup(self):
        """Check parameters and build the physics core; may run again while initializing."""

    def initialize(self):
        """Set the initial internal state from parameters and inputs (leaving initialization)."""

    def evaluate(self):
        """Set the outputs from the state, the current inputs and the time; change nothing
        else."""

    def advance(self, t, dt):
        """Advance the internal state from t to t + dt."""

    # ---- FMI calls -----------------------------------------------------------------------------
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        self.time = self.start_time = float(start_time)

    def _refresh(self):
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

    def exit_initialization_mode(self):
        self._dirty = True  # the initial state from the inputs as they are now, then its outputs
        self._refresh()
        self._initialized = True

    def do_step(self, current_time, step_size):
        self._refresh()  # advance may read what evaluate sets (a friction block's contact)
        self.advance(current_time, step_size)
        self.time = step_end(self.start_time, current_time, step_size)
        self._dirty = True  # outputs evaluated when read: a master sets inputs first, mostly
        return True

    def get_real(self, vrs):
        self._refresh()
        getters = self._getters
        return [getters[vr]() for vr in vrs]

    def get_integer(self, vrs):
        self._refresh()
        return super().get_integer(vrs)

    def get_boolean(self, vrs):
        self._refresh()
        return super().get_boolean(vrs)

    def set_integer(self, vrs, values):
        self.set_real(vrs, values)  # every value is kept as a float

    def set_boolean(self, vrs, values):
        self.set_real(vrs, values)

    def set_real(self, vrs, values):
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
    def reader(self, vrs):
        """A function returning the values of `vrs` as a tuple: what ``get_real(vrs)`` returns,
        without a Python call per variable."""
        attrs = [self._attrs[vr] for vr in vrs]
        get, refresh = operator.attrgetter(*attrs), self._refresh
        if len(attrs) == 1:
            return lambda: (refresh(), (get(self),))[1]
        return lambda: (refresh(), get(self))[1]

    def writer(self, vrs):
        """A function setting `vrs` to its argument's values: what ``set_real(vrs, values)`` does,
        for inputs (parameters go through `set_real`, which guards them)."""
        if any(vr in self._parameters for vr in vrs):
            raise ValueError("writer() sets inputs; set parameters with set_real")
        attrs = [self._attrs[vr] for vr in vrs]

        def write(values):
            for attr, value in zip(attrs, values):
                setattr(self, attr, float(value))
            self._dirty = True
        return write

    def _get_fmu_state(self):
        return copy.deepcopy({k: v for k, v in self.__dict__.items() if k not in _NOT_STATE})

    def _set_fmu_state(self, state):
        # copy again: the same saved state may be restored several times
        self.__dict__.update(copy.deepcopy(state))

    @staticmethod
    def _fmu_state_to_bytes(state):
        return pickle.dumps(state, protocol=pickle.HIGHEST_PROTOCOL)

    @staticmethod
    def _fmu_state_from_bytes(data):
        return pickle.loads(data)

    # ---- model description ---------------------------------------------------------------------
    def describe_units(self, root, typed=lambda v: v[0]):
        """Give each variable of model description `root` its unit, display unit and exact start
        value (on the element `typed` returns for it: FMI 2.0's type child, FMI 3.0's variable
        itself; a variable this slave does not declare, FMI 3.0's time, is in s), add the
        UnitDefinitions after CoSimulation, and return the ModelStructure element, emptied."""
        used = set()
        for v in root.find("ModelVariables"):
            declared = self._meta.get(v.get("name"))
            unit = declared.unit if declared else "s"
            if declared and declared.type == "Real" and typed(v).get("start") is not None:
                typed(v).set("start", repr(declared.default))  # pythonfmu writes 16 digits
            if unit != "1":
                typed(v).set("unit", unit)
                if unit in self.display_units:
                    typed(v).set("displayUnit", self.display_units[unit])
                used.add(unit)
        root.insert(list(root).index(root.find("CoSimulation")) + 1, self._unit_definitions(used))
        structure = root.find("ModelStructure")
        for child in list(structure):
            structure.remove(child)
        return structure

    def _unit_definitions(self, used):
        """The ``UnitDefinitions`` element of the units `used` (FMI 2.0 and 3.0 alike)."""
        units = Element("UnitDefinitions")
        for unit in sorted(used):
            node = SubElement(units, "Unit", name=unit)
            SubElement(node, "BaseUnit", {k: str(e) for k, e in UNITS[unit].items()})
            if unit in self.display_units:
                name = self.display_units[unit]
                base, factor, offset = DISPLAY_UNITS[name]
                if base != unit:
                    raise ValueError(f"display unit {name} is not one of {unit}")
                SubElement(node, "DisplayUnit", name=name, factor=repr(factor),
                           offset=repr(offset))
        return units

    def feedthrough(self):
        """[(output name, names of the inputs it depends on directly)], in declaration order."""
        return [(n, d.depends) for n, d in self._meta.items() if d.depends is not None]

    def to_xml(self, model_options=None):
        root = super().to_xml(model_options or {})
        index = {v.get("name"): i for i, v in enumerate(root.find("ModelVariables"), start=1)}
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
