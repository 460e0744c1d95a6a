"""The co-simulation master: fixed communication step over FMI 2.0 and 3.0 co-simulation FMUs.

At every communication point t_k the master first *exchanges* values: it visits the instances in
the order of direct feedthrough (an output that depends on an input at the same instant, declared
in ModelStructure/Outputs), sets each one's inputs and reads its outputs, so that every value in a
row of results belongs to t_k. A cycle of feedthrough is an algebraic loop this master cannot
order: it is refused with the instances named. Then it *steps*:

- ``jacobi``: every instance steps from t_k with its inputs at t_k (all inputs are sampled and held,
  as in a zero-order-hold discrete model);
- ``gauss-seidel``: instances step one after the other in data-flow order (sources before their
  consumers; a feedback cycle is entered at the instance declared first in the scenario), and
  each refreshes its inputs right before its step from the instances already stepped, i.e. with
  their values at t_k+1.

Multi-rate: an instance declared with ``every = m`` steps only at its own points t_k, k a multiple
of m, from t_k to t_k+m at once (its last step ends at the stop time); it is exchanged only there
(and at the stop time), so between its points the values read from it are held and its inputs are
not taken. This is libcosim's decimation factor wherever the two ends of a connection step at
rates that divide one another (libcosim passes a value only where both are at one of their points;
here the later end takes the newest value it finds).

Values move through one preallocated float64 buffer: one batched get and one batched set per
instance and phase. Two hosts make those calls: the FMUs musclesim built from the installed
sources are called directly in this process (`musclesim.cosim.direct`, the default), every other
FMU through fmpy with preallocated ctypes arrays (``host="fmpy"`` sends ours that way too). Both
call the same slave code in the same order: the results agree to the bit.
"""
import ctypes
import math
import os
import re
import shutil
import tempfile
import time as clock
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

from musclesim.cosim import direct, interrupt
from musclesim.cosim.build import built_here
from musclesim.cosim.host import (LOG_SINKS, callbacks, extract_fmu, extracted_fmu,
                                  forget_fmu_resource_paths, read_fmu)
from musclesim.cosim.graph import Graph
from musclesim.components import renamed
from musclesim.cosim.scenario import split_signal
from musclesim.errors import UserError

MAX_VALUES = 100_000_000  # recorded values a run keeps in memory (800 MB): rows x columns
FLUSH_SECONDS = 2.0  # wall time between two hand-overs of new rows to a run's `on_rows`
HOSTS = ("direct", "fmpy")  # who calls the FMUs musclesim built: see the module's docstring


@dataclass
class Results:
    """Recorded signals: ``time[i]`` and ``data[i, j]`` for column ``names[j]``, rows 0..n-1.

    ``error`` is None for a complete run, else the sentence saying which instance failed, when
    and why; the rows before the failure are kept. ``warnings`` holds what the FMUs logged as
    warnings (e.g. an input clamped to a model's valid range), each prefixed with its instance.
    """

    time: np.ndarray
    names: list
    data: np.ndarray
    error: str = None
    warnings: list = field(default_factory=list)

    def __getitem__(self, name):
        return self.data[:, self.names.index(name)]


def _a(word):
    """`word` with its indefinite article ("an output", "a parameter")."""
    return ("an " if word[0].lower() in "aeiou" else "a ") + word


def _remove_orphans():
    """Remove the temporary folders of runs whose process is gone (killed with SIGKILL, which no
    ``finally`` survives): the next run cleans up after them."""
    for folder in Path(tempfile.gettempdir()).glob("musclesim_run_*_*"):
        pid = folder.name.split("_")[2]
        if not pid.isdigit():
            continue
        try:
            os.kill(int(pid), 0)
        except ProcessLookupError:
            shutil.rmtree(folder, ignore_errors=True)
        except OSError:  # alive, another user's
            continue


def _check(status, function):
    """Raise like fmpy does for a status above fmi2Warning."""
    if status > 1:
        raise FMICallException(function=function, status=status)


def _recorded(s):
    """The signals a scenario records, plots or computes metrics of, each once, in order."""
    return list(dict.fromkeys([*s.record, *(m.signal for m in s.metrics.values()),
                               *(m.over for m in s.metrics.values() if m.over),
                               *(sig for panel in s.plots for sig in panel["signals"])]))


# a variable's type as the master moves it: the FMI 2.0 name of FMI 2.0 and FMI 3.0 types
KINDS = {"Real": "Real", "Float64": "Real", "Integer": "Integer", "Int32": "Integer",
         "Boolean": "Boolean"}


def _groups(kinds):
    """[(kind, [positions in `kinds` of that kind])] for each kind present, Real first."""
    return [(k, [i for i, x in enumerate(kinds) if x == k]) for k in ("Real", "Integer", "Boolean")
            if k in kinds]


class _FmpySlave:
    """An FMU instantiated by fmpy, with the calls of the master's loop made on preallocated
    ctypes arrays straight to the FMU's functions (fmpy's wrapper costs a Python call each);
    a status above fmi2Warning raises as fmpy would. `reader` and `writer` give None where there
    is nothing to get or set, as `direct.DirectSlave`'s do. The master's values are floats:
    Integer and Boolean variables (`kinds`) are read and set through their own functions and
    converted."""

    sized = False  # FMI 2.0's get and set take the number of value references only
    # per kind: the FMU's get and set functions and the C type of a value
    functions = {"Real": ("fmi2GetReal", "fmi2SetReal", ctypes.c_double),
                 "Integer": ("fmi2GetInteger", "fmi2SetInteger", ctypes.c_int),
                 "Boolean": ("fmi2GetBoolean", "fmi2SetBoolean", ctypes.c_int)}

    def __init__(self, md, unzipped, name, fmi_callbacks):
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, instanceName=name,
                             modelIdentifier=md.coSimulation.modelIdentifier)
        self.fmu.instantiate(callbacks=fmi_callbacks, loggingOn=True)
        self._bind("fmi2GetReal", "fmi2SetReal", "fmi2DoStep")

    def _bind(self, *names):
        """The FMU's get, set and step functions, called straight (fmpy's checks bypassed)."""
        self.c, self.names = self.fmu.component, names
        self.get, self.set, self.do_step = (self.fmu._functions[f] for f in names)

    def setup_experiment(self, start_time, stop_time):
        self.fmu.setupExperiment(startTime=start_time, stopTime=stop_time)

    def enter_initialization_mode(self):
        self.fmu.enterInitializationMode()

    def exit_initialization_mode(self):
        self.fmu.exitInitializationMode()

    def terminate(self):
        if self.fmu.component is not None:
            self.fmu.terminate()
            self.fmu.freeInstance()

    def set_real(self, vrs, values, kinds=None):
        """Set `vrs` to `values` (numbers), each through the function of its kind."""
        vrs, values = list(vrs), [float(v) for v in values]
        for kind, at in _groups(kinds or ["Real"] * len(vrs)):
            _, name, ctype = self.functions[kind]
            refs = (ctypes.c_uint * len(at))(*[vrs[i] for i in at])
            cast = {"Real": float, "Integer": int, "Boolean": bool}[kind]
            vals = (ctype * len(at))(*[cast(values[i]) for i in at])
            sized = (len(at),) if self.sized else ()
            _check(self.fmu._functions[name](self.c, refs, len(at), vals, *sized), name)

    def reader(self, vrs, out, kinds=None):
        if not vrs:
            return None
        kinds = kinds or ["Real"] * len(vrs)
        if set(kinds) == {"Real"}:  # straight into the buffer
            n, vr = len(vrs), (ctypes.c_uint * len(vrs))(*vrs)
            ptr, get, c = out.ctypes.data_as(ctypes.POINTER(ctypes.c_double)), self.get, self.c
            sized, name = (n,) if self.sized else (), self.names[0]

            def read():
                _check(get(c, vr, n, ptr, *sized), name)
            return read
        reads = [self._reader([vrs[i] for i in at], kind, out, np.array(at))
                 for kind, at in _groups(kinds)]

        def read_all():
            for read in reads:
                read()
        return read_all

    def _reader(self, vrs, kind, out, at):
        """A function reading `vrs` of one kind into ``out[at]``."""
        name, _, ctype = self.functions[kind]
        n, vr, vals = len(vrs), (ctypes.c_uint * len(vrs))(*vrs), (ctype * len(vrs))()
        get, c, view = self.fmu._functions[name], self.c, np.ctypeslib.as_array(vals)
        sized = (n,) if self.sized else ()

        def read():
            _check(get(c, vr, n, vals, *sized), name)
            out[at] = view
        return read

    def writer(self, vrs, slots, values, kinds=None):
        if not vrs:
            return None
        kinds = kinds or ["Real"] * len(vrs)
        if set(kinds) == {"Real"}:  # one call, from a buffer taken in place
            n, vr, vals = len(vrs), (ctypes.c_uint * len(vrs))(*vrs), (ctypes.c_double * len(vrs))()
            view, set_, c = np.ctypeslib.as_array(vals), self.set, self.c
            sized, name = (n,) if self.sized else (), self.names[1]

            def write_reals():
                values.take(slots, out=view)
                _check(set_(c, vr, n, vals, *sized), name)
            return write_reals
        writes = []
        for kind, at in _groups(kinds):
            _, name, ctype = self.functions[kind]
            n, vr = len(at), (ctypes.c_uint * len(at))(*[vrs[i] for i in at])
            vals, chosen = (ctype * n)(), slots[at]
            view, set_ = np.ctypeslib.as_array(vals), self.fmu._functions[name]
            writes.append((view, chosen, set_, vr, n, vals, (n,) if self.sized else (), name))

        def write():
            for view, chosen, set_, vr, n, vals, sized, name in writes:
                view[:] = values[chosen]
                _check(set_(self.c, vr, n, vals, *sized), name)
        return write

    def stepper(self):
        do_step, c, name = self.do_step, self.c, self.names[2]

        def step(t, h):
            _check(do_step(c, t, h, 1), name)
        return step


class _Fmpy3Slave(_FmpySlave):
    """An FMI 3.0 co-simulation FMU instantiated by fmpy, with the same calls as `_FmpySlave`:
    FMI 3.0's Float64, Int32 and Boolean functions, the start and stop time given when
    initialization mode is entered, log messages (formatted by the FMU) appended to `log` as
    (status, message)."""

    sized = True  # FMI 3.0's get and set take the number of values too
    functions = {"Real": ("fmi3GetFloat64", "fmi3SetFloat64", ctypes.c_double),
                 "Integer": ("fmi3GetInt32", "fmi3SetInt32", ctypes.c_int32),
                 "Boolean": ("fmi3GetBoolean", "fmi3SetBoolean", ctypes.c_bool)}

    def __init__(self, md, unzipped, name, log):
        def route(env, status, category, message):
            log.append((status, message.decode("utf-8", "replace").strip()))

        self.fmu = FMU3Slave(guid=md.guid, unzipDirectory=unzipped, instanceName=name,
                             modelIdentifier=md.coSimulation.modelIdentifier)
        self.fmu.instantiate(loggingOn=True, logMessage=route)
        self._bind("fmi3GetFloat64", "fmi3SetFloat64", "fmi3DoStep")
        self.span = (0.0, None)

    def setup_experiment(self, start_time, stop_time):
        self.span = (start_time, stop_time)

    def enter_initialization_mode(self):
        self.fmu.enterInitializationMode(startTime=self.span[0], stopTime=self.span[1])

    def stepper(self):
        do_step, c, name = self.do_step, self.c, self.names[2]
        flags, last = [ctypes.c_bool() for _ in range(3)], ctypes.c_double()
        refs = [ctypes.byref(f) for f in flags] + [ctypes.byref(last)]

        def step(t, h):
            _check(do_step(c, t, h, True, *refs), name)
        return step


class _Instance:
    """An instantiated FMU with the value-reference and buffer-slot tables the loop uses."""

    def __init__(self, name, component, md):
        self.name, self.component, self.md = name, component, md
        self.vars = {v.name: v for v in md.modelVariables}
        self.feedthrough = {}  # input name -> True if some output depends on it directly
        for out in md.outputs:
            deps = out.dependencies
            for v in md.modelVariables:
                if v.causality == "input" and (deps is None or v in deps):
                    self.feedthrough[v.name] = True
        self.slave = None
        self.log = []


class Master:
    """Load a scenario's FMUs, check the wiring against their model descriptions, run it.

    Parameters
    ----------
    scenario : musclesim.cosim.Scenario
    fmu_dir : str or Path
        Folder with ``<component>.fmu`` files (output of ``musclesim build``).
    inputs : dict, optional
        Replayed inputs: ``{"instance.input": values}`` with one value per communication point
        (``scenario.n_steps + 1``), set at every exchange in place of a connection, the way an
        upstream FMU swapped for a measured signal would set them (sampled and held over the
        step). The diagnosis re-simulates components alone this way.
    host : {"direct", "fmpy"}
        Who calls the FMUs musclesim built from the installed sources: this process directly
        (default, `musclesim.cosim.direct`) or fmpy. Other FMUs always run through fmpy.

    Raises
    ------
    UserError
        Listing every wiring problem (unknown instance or variable, wrong causality, unit
        mismatch, input connected twice, algebraic loop, replayed input not an unconnected input
        or of the wrong length).
    """

    def __init__(self, scenario, fmu_dir="fmus", inputs=None, host="direct"):
        if host not in HOSTS:
            raise UserError(f"host {host!r} is not one of {', '.join(HOSTS)}")
        self.scenario, self.host = scenario, host
        self.hosts = {}  # instance -> the host that ran it ("direct" or "fmpy"), once loaded
        self.fmu_dir = Path(fmu_dir)
        self.inputs = {k: np.asarray(v, dtype=float) for k, v in (inputs or {}).items()}
        problems = []
        mds = {}
        for comp in sorted({i.component for i in scenario.instances.values()}):
            path = self.fmu_dir / f"{comp}.fmu"
            if path.is_file():
                mds[comp] = read_fmu(path)
            else:
                known = sorted(p.stem for p in self.fmu_dir.glob("*.fmu"))
                problems.append(f"component {comp!r} has no FMU {path} (found: "
                                f"{', '.join(known) or 'none'}; `musclesim build` builds them)")
        self.instances = {n: _Instance(n, i.component, mds[i.component])
                          for n, i in scenario.instances.items() if i.component in mds}
        if problems:
            raise UserError("; ".join(problems))
        self._check(problems)
        if problems:
            raise UserError(f"scenario {scenario.path}: " + "; ".join(problems))
        self._plan(problems)
        if problems:
            raise UserError(f"scenario {scenario.path}: " + "; ".join(problems))
        values = (scenario.n_steps + 1) * (len(self.columns) + 1)
        if values > MAX_VALUES:
            raise UserError(f"scenario {scenario.path}: {scenario.n_steps + 1} rows of "
                            f"{len(self.columns)} recorded signals are {values:.3g} values, more "
                            f"than the {MAX_VALUES:,} a run keeps; record fewer signals, take a "
                            "longer step or a shorter stop time")

    # ---- checks --------------------------------------------------------------------------------
    def _variable(self, signal, problems, what):
        inst, var = split_signal(signal)
        if inst not in self.instances:
            problems.append(f"{what} {signal!r}: no instance {inst!r}")
            return None
        v = self.instances[inst].vars.get(var)
        now = renamed(self.instances[inst].component, var)
        if v is None and now:
            problems.append(f"{what} {signal!r}: {self.instances[inst].component}'s {var} has "
                            f"been renamed {now} (the Modelica Standard Library's port names)")
        elif v is None:
            problems.append(f"{what} {signal!r}: {self.instances[inst].component} has no variable "
                            f"{var!r} (variables: {', '.join(self.instances[inst].vars)})")
        elif v.type not in KINDS:
            problems.append(f"{what} {signal!r}: only Real, Integer and Boolean (FMI 2.0) and "
                            f"Float64, Int32 and Boolean (FMI 3.0) variables are supported, not "
                            f"{v.type}")
            return None
        return v

    def _check(self, problems):
        s = self.scenario
        targets = {}
        for src, dst in s.connections:
            vs = self._variable(src, problems, "connection source")
            vd = self._variable(dst, problems, "connection destination")
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
        for dst, values in self.inputs.items():
            v = self._variable(dst, problems, "replayed input")
            if v is not None and v.causality != "input":
                problems.append(f"replayed input {dst} is {_a(v.causality)}, not an input")
            if dst in targets:
                problems.append(f"replayed input {dst} is also connected (from {targets[dst]})")
            if values.shape != (s.n_steps + 1,):
                problems.append(f"replayed input {dst} has {values.size} values, not one per "
                                f"communication point ({s.n_steps + 1})")
        for name, spec in s.instances.items():
            for par, value in spec.parameters.items():
                self._check_value(f"{name}.{par}", value, targets, problems)
        for sig in _recorded(s):
            self._variable(sig, problems, "recorded signal")

    def _check_value(self, signal, value, targets, problems):
        """A value a scenario sets: a parameter, or an input nothing feeds (a bench condition
        such as the ambient temperature, held constant); an Integer's a whole number, a
        Boolean's 0 or 1."""
        v = self._variable(signal, problems, "parameter")
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
        elif signal in self.inputs:
            problems.append(f"{signal} is an input replayed from data: it cannot also be set")

    # ---- planning ------------------------------------------------------------------------------
    def _plan(self, problems):
        s = self.scenario
        names = list(self.instances)
        graph = Graph(s)
        ft_edges = graph.edges(lambda inst, var: self.instances[inst].feedthrough.get(var))

        def algebraic_loop(remaining):
            loop = [n for n in remaining if any((m, n) in ft_edges for m in remaining)]
            problems.append("algebraic loop: outputs of " + ", ".join(loop) + " depend on each "
                            "other's inputs at the same instant (direct feedthrough in a cycle)")
            return remaining[0]

        self.exchange_order = graph.order(ft_edges, algebraic_loop)
        self.step_order = graph.order(graph.edges(), lambda remaining: remaining[0])
        if problems:
            return

        # One buffer slot per signal read from an instance, each instance's slots contiguous so
        # that fmi2GetReal writes straight into the buffer.
        source_of = {dst: src for src, dst in s.connections}
        replayed = {dst: f"{dst} (replayed)" for dst in self.inputs}
        self.columns = _recorded(s)
        reads = {n: [] for n in names}
        for sig in [src for src, _ in s.connections] + [c for c in self.columns if c not in source_of]:
            reads[split_signal(sig)[0]].append(sig)
        slots = {}
        for name in names:
            inst = self.instances[name]
            inst.reads = list(dict.fromkeys(reads[name]))
            inst.first = len(slots)
            slots.update((sig, len(slots)) for sig in inst.reads)
        self.replay_slots = np.arange(len(slots), len(slots) + len(replayed))
        self.replay_table = np.column_stack([self.inputs[d] for d in replayed]) if replayed \
            else None
        slots.update((sig, len(slots)) for sig in replayed.values())
        source_of.update(replayed)
        self.values = np.zeros(max(1, len(slots)))
        position = {n: i for i, n in enumerate(self.exchange_order)}
        for name, inst in self.instances.items():
            inst.read_vrs = [inst.vars[split_signal(x)[1]].valueReference for x in inst.reads]
            inst.read_kinds = [KINDS[inst.vars[split_signal(x)[1]].type] for x in inst.reads]
            ins = [(dst, src) for dst, src in source_of.items() if split_signal(dst)[0] == name]
            # replayed inputs, and inputs from instances exchanged earlier if they feed through,
            # are set during the exchange; all others are set just before the step
            early = [(d, x) for d, x in ins if d in replayed or (
                inst.feedthrough.get(split_signal(d)[1])
                and position[split_signal(x)[0]] < position[name])]
            late = [pair for pair in ins if pair not in early]
            inst.transfers = [  # (value references, buffer slots, kinds) set early, late, all
                ([inst.vars[split_signal(d)[1]].valueReference for d, _ in pairs],
                 np.array([slots[x] for _, x in pairs], dtype=np.intp),
                 [KINDS[inst.vars[split_signal(d)[1]].type] for d, _ in pairs])
                for pairs in (early, late, ins)]
        self.record_slots = np.array([slots[source_of.get(c, c)] for c in self.columns], dtype=np.intp)

    # ---- running -------------------------------------------------------------------------------
    def _exchange(self, row):
        """Values at communication point `row`: replayed inputs, then every instance's."""
        if self.replay_table is not None:
            self.values[self.replay_slots] = self.replay_table[row]
        for inst, every, calls in self.exchange_calls:
            if every > 1 and row % every and row != self.scenario.n_steps:
                continue  # between its own points: its outputs held, its inputs not taken
            self.current = inst
            for call in calls:
                call()

    def _failure(self, inst, t):
        lines = [ln for _, msg in inst.log for ln in msg.splitlines() if ln.strip()]
        cause = lines[-1] if lines else "the FMU reported an error"
        # pythonfmu reports an exception as its repr, e.g. ValueError('m1 must be positive')
        cause = re.sub(r"^\w+(?:Error|Exception)\((['\"])(.*)\1\)$", r"\2", cause)
        return (f"instance {inst.name!r} ({inst.component}) failed {self.phase} "
                f"at t = {t:.6g} s: {cause}")

    def run(self, on_rows=None):
        """Run the scenario; return `Results` (with ``error`` set if an instance failed).

        `on_rows(time, data)`, if given, receives the rows recorded since its last call about
        every `FLUSH_SECONDS` of wall time and once at the end, so that a caller can write them
        as the run goes. A signal caught by `interrupt.interruptible` stops the run at its next
        step: `interrupt.Interrupted` is raised with the `Results` so far (rows handed over too).
        """
        s = self.scenario
        time = np.empty(s.n_steps + 1)
        data = np.empty((s.n_steps + 1, len(self.columns)))
        self.on_rows, self.flushed = on_rows, 0
        self.callbacks = callbacks(id(self))
        LOG_SINKS[id(self)] = self.instances
        self.current, self.phase, self.row, self.t = None, "while loading", 0, s.start_time
        failed, error, stopped = None, None, None
        _remove_orphans()
        tmp = Path(tempfile.mkdtemp(prefix=f"musclesim_run_{os.getpid()}_"))
        try:
            with interrupt.polled():
                self._instantiate(tmp)
                if interrupt.requested() is None:
                    self.phase = "during initialization"
                    self._initialize()
                if interrupt.requested() is None:
                    self.phase = "in a step"
                    error = self._loop(time, data)
                stopped = interrupt.requested()
        except FMICallException:
            failed = self.current
            error = self._failure(failed, self.t)
        finally:
            for inst in self.instances.values():
                # An instance that failed is left alone: pythonfmu 0.7 has already released its
                # Python objects without forgetting them, and freeing it would release them again.
                if inst.slave is not None and inst is not failed:
                    inst.slave.terminate()
                inst.slave = None
            shutil.rmtree(tmp, ignore_errors=True)
            del LOG_SINKS[id(self)]
        warnings = [f"{i.name}: {msg}" for i in self.instances.values()
                    for status, msg in i.log if status == 1]  # fmi2Warning
        self._flush(time, data)
        if stopped is not None:
            error = f"{interrupt.Interrupted(stopped)} at t = {self.t:.6g} s"
        res = Results(time[:self.row].copy(), list(self.columns), data[:self.row].copy(), error,
                      warnings)
        if stopped is not None:
            raise interrupt.Interrupted(stopped, res)
        return res

    def _flush(self, time, data):
        """Hand the rows recorded since the last call to `on_rows`."""
        if self.on_rows is not None and self.row > self.flushed:
            self.on_rows(time[self.flushed:self.row], data[self.flushed:self.row])
            self.flushed = self.row

    def _instantiate(self, tmp):
        s = self.scenario
        gauss_seidel = s.algorithm == "gauss-seidel"
        unzipped = {}
        for inst in self.instances.values():
            self.current = inst
            path = self.fmu_dir / f"{inst.component}.fmu"
            if inst.component not in unzipped:
                unzipped[inst.component] = extracted_fmu(path) or extract_fmu(
                    path, tmp / inst.component)
            inst.slave = self._load(inst, path, unzipped[inst.component])
            inst.get = inst.slave.reader(inst.read_vrs,
                                         self.values[inst.first:inst.first + len(inst.reads)],
                                         inst.read_kinds)
            inst.set_early, inst.set_late, inst.set_all = (
                inst.slave.writer(vrs, slots, self.values, kinds)
                for vrs, slots, kinds in inst.transfers)
            inst.step = inst.slave.stepper()
            inst.every = s.instances[inst.name].every
            inst.before_step = inst.set_all if gauss_seidel else inst.set_late
            # an instance stepping several points at once is read at its own points only
            inst.after_step = inst.get if gauss_seidel and inst.every == 1 else None
            inst.slave.setup_experiment(s.start_time, s.stop_time)
            params = s.instances[inst.name].parameters
            if params:
                inst.slave.set_real([inst.vars[p].valueReference for p in params],
                                    params.values(), [KINDS[inst.vars[p].type] for p in params])
        forget_fmu_resource_paths()
        self.exchange_calls = [
            (inst, inst.every, [c for c in (inst.set_early, inst.get) if c is not None])
            for inst in (self.instances[n] for n in self.exchange_order)]

    def _load(self, inst, path, unzipped):
        """Instantiate `inst` from the FMU at `path` extracted in `unzipped`, on its host."""
        try:  # fmpy raises bare Exceptions for a missing or broken library, a failed instance
            if inst.md.fmiVersion.startswith("3"):  # through the FMI 3.0 C API, always
                self.hosts[inst.name] = "fmpy"
                return _Fmpy3Slave(inst.md, unzipped, inst.name, inst.log)
            if self.host == "direct" and built_here(path):
                cls = direct.slave_class(unzipped, inst.md.coSimulation.modelIdentifier)
                self.hosts[inst.name] = "direct"
                return direct.DirectSlave(cls, inst.name, unzipped, inst.log)
            self.hosts[inst.name] = "fmpy"
            return _FmpySlave(inst.md, unzipped, inst.name, self.callbacks)
        except FMICallException:
            raise
        except Exception as exc:
            raise UserError(f"FMU {path} cannot be loaded as instance {inst.name!r}: "
                            f"{exc}") from None

    def _initialize(self):
        """Initialization mode: propagate start values in feedthrough order, then leave it."""
        for inst in self.instances.values():
            self.current = inst
            inst.slave.enter_initialization_mode()
        self._exchange(0)
        for inst in self.instances.values():
            self.current = inst
            if inst.set_late is not None:
                inst.set_late()
            inst.slave.exit_initialization_mode()
        self._exchange(0)

    def _loop(self, time, data):
        """Record, step, exchange until the stop time; return an error sentence or None."""
        s = self.scenario
        n, h, t, row = s.n_steps, s.step, self.t, 0
        order = [(inst, inst.every, inst.every * h)
                 for inst in (self.instances[x] for x in self.step_order)]
        take, rec = self.values.take, self.record_slots
        state, due = interrupt.STATE, clock.monotonic() + FLUSH_SECONDS
        try:
            while True:
                time[row] = t
                take(rec, out=data[row])
                row += 1
                if not np.isfinite(data[row - 1]).all():
                    col = next(j for j, x in enumerate(data[row - 1]) if not math.isfinite(x))
                    return f"signal {self.columns[col]} became {data[row - 1, col]} at t = {t:.6g} s"
                if row > n or state["signum"] is not None:
                    return None
                if not row & 1023 and self.on_rows is not None and clock.monotonic() > due:
                    self.row = row
                    self._flush(time, data)
                    due = clock.monotonic() + FLUSH_SECONDS
                k = row - 1
                for inst, every, h_every in order:
                    if every > 1:
                        if k % every:
                            continue
                        if k + every > n:  # its last step ends at the stop time
                            h_every = (n - k) * h
                    self.current = inst
                    if inst.before_step is not None:
                        inst.before_step()
                    inst.step(t, h_every)
                    if inst.after_step is not None:
                        inst.after_step()
                t = s.start_time + row * h  # t0 + k h, as FMPy and the FMUs count it
                self._exchange(row)
        finally:
            self.row, self.t = row, t
