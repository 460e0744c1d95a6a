"""The FMPy adapters: an FMI 2.0 or FMI 3.0 co-simulation FMU instantiated by fmpy, seen by the
master through the same calls as `musclesim.cosim.direct.DirectSlave` (set parameters, a reader,
a writer and a stepper made once, called in the loop).

The loop's calls go straight to the FMU's C functions on preallocated ctypes arrays (fmpy's
wrapper costs a Python call each); a status above fmi2Warning raises `FMICallException` as fmpy
would. The master's values are floats: Integer and Boolean variables are read and set through
their own functions and converted (`KINDS` names a variable's kind).
"""
from __future__ import annotations

import ctypes
from collections.abc import Callable, Iterable, Sequence
from typing import Any

import numpy as np
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

__all__ = ["KINDS", "FmpySlave", "Fmpy3Slave"]

Call = Callable[[], None]  # a get or set of the master's loop, made once


def _check(status: int, function: str) -> None:
    """Raise like fmpy does for a status above fmi2Warning."""
    if status > 1:
        raise FMICallException(function=function, status=status)


# a variable's type as the master moves it: the FMI 2.0 name of FMI 2.0 and FMI 3.0 types
KINDS = {"Real": "Real", "Float64": "Real", "Integer": "Integer", "Int32": "Integer",
         "Boolean": "Boolean"}


def _groups(kinds: Sequence[str]) -> list[tuple[str, list[int]]]:
    """[(kind, [positions in `kinds` of that kind])] for each kind present, Real first."""
    return [(k, [i for i, x in enumerate(kinds) if x == k]) for k in ("Real", "Integer", "Boolean")
            if k in kinds]


class FmpySlave:
    """An FMU instantiated by fmpy, with the calls of the master's loop made on preallocated
    ctypes arrays straight to the FMU's functions (fmpy's wrapper costs a Python call each);
    a status above fmi2Warning raises as fmpy would. `reader` and `writer` give None where there
    is nothing to get or set, as `direct.DirectSlave`'s do. The master's values are floats:
    Integer and Boolean variables (`kinds`) are read and set through their own functions and
    converted."""

    sized = False  # FMI 2.0's get and set take the number of value references only
    # per kind: the FMU's get and set functions and the C type of a value
    functions: dict[str, tuple[str, str, Any]] = {
                 "Real": ("fmi2GetReal", "fmi2SetReal", ctypes.c_double),
                 "Integer": ("fmi2GetInteger", "fmi2SetInteger", ctypes.c_int),
                 "Boolean": ("fmi2GetBoolean", "fmi2SetBoolean", ctypes.c_int)}

    def __init__(self, md: Any, unzipped: str, name: str, fmi_callbacks: Any) -> None:
        """Instantiate the FMU of model description `md` extracted in `unzipped` as instance
        `name`, its log going through `fmi_callbacks` (`musclesim.cosim.host.callbacks`)."""
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=unzipped, instanceName=name,
                             modelIdentifier=md.coSimulation.modelIdentifier)
        self.fmu.instantiate(callbacks=fmi_callbacks, loggingOn=True)
        self._bind("fmi2GetReal", "fmi2SetReal", "fmi2DoStep")

    def _bind(self, *names: str) -> None:
        """The FMU's get, set and step functions, called straight (fmpy's checks bypassed)."""
        self.c, self.names = self.fmu.component, names
        self.get, self.set, self.do_step = (self.fmu._functions[f] for f in names)

    def setup_experiment(self, start_time: float, stop_time: float) -> None:
        """Declare the run's `start_time` and `stop_time` [s]."""
        self.fmu.setupExperiment(startTime=start_time, stopTime=stop_time)

    def enter_initialization_mode(self) -> None:
        """Enter initialization mode."""
        self.fmu.enterInitializationMode()

    def exit_initialization_mode(self) -> None:
        """Leave initialization mode."""
        self.fmu.exitInitializationMode()

    def terminate(self) -> None:
        """Terminate and free the instance (if it was instantiated)."""
        if self.fmu.component is not None:
            self.fmu.terminate()
            self.fmu.freeInstance()

    def set_real(self, vrs: Iterable[int], values: Iterable[float],
                 kinds: Sequence[str] | None = None) -> None:
        """Set the value references `vrs` to `values` (numbers), each through the function of
        its kind in `kinds` (default: all Real)."""
        vrs, values = list(vrs), [float(v) for v in values]
        for kind, at in _groups(kinds or ["Real"] * len(vrs)):
            _, name, ctype = self.functions[kind]
            refs = (ctypes.c_uint * len(at))(*[vrs[i] for i in at])
            cast = {"Real": float, "Integer": int, "Boolean": bool}[kind]
            vals = (ctype * len(at))(*[cast(values[i]) for i in at])
            sized = (len(at),) if self.sized else ()
            _check(self.fmu._functions[name](self.c, refs, len(at), vals, *sized), name)

    def reader(self, vrs: Sequence[int], out: np.ndarray, kinds: Sequence[str] | None = None
               ) -> Call | None:
        """A function reading the value references `vrs` (of `kinds`, default Real) into the
        buffer `out`; None if there is nothing to read."""
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

    def _reader(self, vrs: list[int], kind: str, out: np.ndarray, at: np.ndarray) -> Call:
        """A function reading `vrs` of one kind into ``out[at]``."""
        name, _, ctype = self.functions[kind]
        n, vr, vals = len(vrs), (ctypes.c_uint * len(vrs))(*vrs), (ctype * len(vrs))()
        get, c, view = self.fmu._functions[name], self.c, np.ctypeslib.as_array(vals)
        sized = (n,) if self.sized else ()

        def read():
            _check(get(c, vr, n, vals, *sized), name)
            out[at] = view
        return read

    def writer(self, vrs: Sequence[int], slots: np.ndarray, values: np.ndarray,
               kinds: Sequence[str] | None = None) -> Call | None:
        """A function setting the value references `vrs` (of `kinds`, default Real) to
        ``values[slots]``; None if there is nothing to set."""
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

    def stepper(self) -> Callable[[float, float], None]:
        """A function ``step(t, h)``: one step of `h` [s] from time `t`."""
        do_step, c, name = self.do_step, self.c, self.names[2]

        def step(t: float, h: float) -> None:
            _check(do_step(c, t, h, 1), name)
        return step


class Fmpy3Slave(FmpySlave):
    """An FMI 3.0 co-simulation FMU instantiated by fmpy, with the same calls as `FmpySlave`:
    FMI 3.0's Float64, Int32 and Boolean functions, the start and stop time given when
    initialization mode is entered, log messages (formatted by the FMU) appended to `log` as
    (status, message)."""

    sized = True  # FMI 3.0's get and set take the number of values too
    functions: dict[str, tuple[str, str, Any]] = {
                 "Real": ("fmi3GetFloat64", "fmi3SetFloat64", ctypes.c_double),
                 "Integer": ("fmi3GetInt32", "fmi3SetInt32", ctypes.c_int32),
                 "Boolean": ("fmi3GetBoolean", "fmi3SetBoolean", ctypes.c_bool)}

    def __init__(self, md: Any, unzipped: str, name: str,
                 log: list[tuple[int, str]]) -> None:
        """Instantiate the FMU of model description `md` extracted in `unzipped` as instance
        `name`, its log messages appended to `log`."""
        def route(env: Any, status: int, category: Any, message: bytes) -> None:
            log.append((status, message.decode("utf-8", "replace").strip()))

        self.fmu = FMU3Slave(guid=md.guid, unzipDirectory=unzipped, instanceName=name,
                             modelIdentifier=md.coSimulation.modelIdentifier)
        self.fmu.instantiate(loggingOn=True, logMessage=route)
        self._bind("fmi3GetFloat64", "fmi3SetFloat64", "fmi3DoStep")
        self.span: tuple[float, float | None] = (0.0, None)

    def setup_experiment(self, start_time: float, stop_time: float) -> None:
        """Keep the run's `start_time` and `stop_time` [s] for initialization mode."""
        self.span = (start_time, stop_time)

    def enter_initialization_mode(self) -> None:
        """Enter initialization mode with the run's start and stop time."""
        self.fmu.enterInitializationMode(startTime=self.span[0], stopTime=self.span[1])

    def stepper(self) -> Callable[[float, float], None]:
        """A function ``step(t, h)``: one step of `h` [s] from time `t`."""
        do_step, c, name = self.do_step, self.c, self.names[2]
        flags, last = [ctypes.c_bool() for _ in range(3)], ctypes.c_double()
        refs = [ctypes.byref(f) for f in flags] + [ctypes.byref(last)]

        def step(t: float, h: float) -> None:
            _check(do_step(c, t, h, True, *refs), name)
        return step
