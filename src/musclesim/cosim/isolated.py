"""An FMU instance hosted in a child process of its own: the choice for FMUs one does not trust.

An FMU's native code runs in the process that loads it: a crash there (a segmentation fault in
its library, an abort) takes the host with it, and the run's results with it. `IsolatedSlave`
runs the instance through fmpy in a child process instead and answers the master's calls (the
same as `musclesim.cosim.adapters.FmpySlave`'s: set parameters, a reader, a writer and a
stepper) over a pipe. If the child dies, the call that finds it dead raises the FMI error the
master already turns into one sentence naming the instance, the phase and the time, with the
rows recorded so far kept; the message the instance "logged" says how its process ended (the
signal). The design follows libcosim's proxy FMUs (proxyfmu: each FMU in a process of its own,
called over a remote interface).

Costs: a process per instance (about a second to start, with numpy and fmpy imported) and a
round trip over the pipe per read and per step (tens of microseconds); writes travel without
waiting for an answer, their errors reported by the next call that waits. Bits: the child calls
the same FMU functions with the same values, so an isolated run equals an unisolated run on
fmpy (``--host fmpy``) bit for bit.
"""
from __future__ import annotations

import multiprocessing
import os
import signal
from collections.abc import Callable, Iterable, Sequence
from typing import Any

import numpy as np
from fmpy.fmi1 import FMICallException

__all__ = ["IsolatedSlave"]

Call = Callable[[], None]


def _ended(exitcode: int | None) -> str:
    """How a child process ended, from its `exitcode` (a signal's negative number)."""
    if exitcode is not None and exitcode < 0:
        try:
            sig = signal.Signals(-exitcode)
            return f"its process ended by signal {sig.name} ({signal.strsignal(sig) or ''})"
        except ValueError:
            return f"its process ended by signal {-exitcode}"
    return f"its process ended (exit status {exitcode})"


class IsolatedSlave:
    """Instance `name` of the FMU extracted in `unzipped` (FMI 2.0 or 3.0, `fmi3`), run by fmpy
    in a child process; its log messages appended to `log` as (FMI status, message) when a
    call returns."""

    def __init__(self, unzipped: str, name: str, log: list[tuple[int, str]],
                 fmi3: bool = False) -> None:
        ctx = multiprocessing.get_context("spawn")  # no copy of this process's FMUs or threads
        self.conn, child = ctx.Pipe()
        self.log, self.name, self.failed = log, name, False
        self.proc = ctx.Process(target=_serve, args=(child, unzipped, name, fmi3), daemon=True,
                                name=f"musclesim FMU {name}")
        self.proc.start()
        child.close()
        try:
            self._ask("instantiate", "fmi2Instantiate")
        except FMICallException:
            self.close()
            raise

    def _ask(self, what: str, function: str, *args: Any) -> Any:
        """Send `what` with `args`, wait for the answer and return its value; an FMU error or a
        dead child raises `FMICallException` as `function` would."""
        try:
            self.conn.send((what, *args))
            status, value, logged = self.conn.recv()
        except (EOFError, OSError, BrokenPipeError):
            self.proc.join(5)
            self.failed = True
            self.log.append((4, _ended(self.proc.exitcode)))
            raise FMICallException(function=function, status=4) from None
        self.log.extend(logged)
        if status == "error":
            self.failed = True
            raise FMICallException(function=value[0], status=value[1])
        return value

    def _tell(self, what: str, *args: Any) -> None:
        """Send `what` with `args` without waiting (a write): an error comes with the next
        answer; a dead child is found by the next call that waits."""
        try:
            self.conn.send((what, *args))
        except (OSError, BrokenPipeError):
            pass

    def setup_experiment(self, start_time: float, stop_time: float) -> None:
        """Declare the run's `start_time` and `stop_time` [s]."""
        self._ask("setup", "fmi2SetupExperiment", start_time, stop_time)

    def enter_initialization_mode(self) -> None:
        """Enter initialization mode."""
        self._ask("enter", "fmi2EnterInitializationMode")

    def exit_initialization_mode(self) -> None:
        """Leave initialization mode."""
        self._ask("exit", "fmi2ExitInitializationMode")

    def terminate(self) -> None:
        """Terminate and free the instance (unless it failed), then end the child process."""
        if self.proc.is_alive() and not self.failed:
            try:
                self._ask("terminate", "fmi2Terminate")
            except FMICallException:
                pass
        self.close()

    def close(self) -> None:
        """End the child process (killed if it does not end by itself within a second)."""
        if not self.conn.closed:
            self._tell("quit")
            self.conn.close()
        self.proc.join(1)
        if self.proc.is_alive():
            self.proc.kill()
            self.proc.join()

    def set_real(self, vrs: Iterable[int], values: Iterable[float],
                 kinds: Sequence[str] | None = None) -> None:
        """Set the value references `vrs` to `values`, each of its kind in `kinds` (default
        Real)."""
        self._ask("set", "fmi2SetReal", list(vrs), [float(v) for v in values],
                  list(kinds) if kinds else None)

    def reader(self, vrs: Sequence[int], out: np.ndarray, kinds: Sequence[str] | None = None
               ) -> Call | None:
        """A function reading `vrs` (of `kinds`) into the buffer `out`; None if there is
        nothing to read."""
        if not vrs:
            return None
        key = self._ask("reader", "fmi2GetReal", list(vrs), list(kinds) if kinds else None)

        def read() -> None:
            out[:] = self._ask("read", "fmi2GetReal", key)
        return read

    def writer(self, vrs: Sequence[int], slots: np.ndarray, values: np.ndarray,
               kinds: Sequence[str] | None = None) -> Call | None:
        """A function setting `vrs` (of `kinds`) to ``values[slots]``; None if there is nothing
        to set."""
        if not vrs:
            return None
        key = self._ask("writer", "fmi2SetReal", list(vrs), list(kinds) if kinds else None)

        def write() -> None:
            self._tell("write", key, values[slots])
        return write

    def stepper(self) -> Callable[[float, float], None]:
        """A function ``step(t, h)``: one step of `h` [s] from time `t`."""
        def step(t: float, h: float) -> None:
            self._ask("step", "fmi2DoStep", t, h)
        return step


class _Sink:
    """Where the child's FMU logs (`musclesim.cosim.host.LOG_SINKS` wants objects with a
    ``log``)."""

    def __init__(self) -> None:
        self.log: list[tuple[int, str]] = []


def _serve(conn: Any, unzipped: str, name: str, fmi3: bool) -> None:
    """The child process: instantiate the FMU in `unzipped` as `name` on fmpy and answer the
    parent's calls on `conn` until it says quit or goes away."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the parent stops the run, not a Ctrl-C here
    from fmpy import read_model_description

    from musclesim.cosim.adapters import Fmpy3Slave, FmpySlave
    from musclesim.cosim.host import LOG_SINKS, callbacks

    sink = _Sink()
    slave: Any = None
    step: Callable[[float, float], None] | None = None
    calls: list[Any] = []  # readers (with their buffers) and writers (with theirs), by key
    pending: tuple[str, int] | None = None  # a write's error, for the next answer

    def answer(status: str, value: Any) -> None:
        conn.send((status, value, sink.log[:]))
        sink.log.clear()

    while True:
        try:
            what, *args = conn.recv()
        except (EOFError, OSError):
            break
        if what == "quit":
            break
        try:
            if what == "write":
                if pending is None:
                    key, values = args
                    calls[key][1][:] = values
                    calls[key][0]()
                continue
            if pending is not None:
                answer("error", pending)
                pending = None
                continue
            if what == "instantiate":
                md = read_model_description(os.path.join(unzipped, "modelDescription.xml"))
                if fmi3:
                    slave = Fmpy3Slave(md, unzipped, name, sink.log)
                else:
                    LOG_SINKS[id(sink)] = {name: sink}
                    slave = FmpySlave(md, unzipped, name, callbacks(id(sink)))
                answer("ok", None)
            elif what == "setup":
                answer("ok", slave.setup_experiment(*args))
            elif what == "enter":
                answer("ok", slave.enter_initialization_mode())
            elif what == "exit":
                answer("ok", slave.exit_initialization_mode())
            elif what == "terminate":
                answer("ok", slave.terminate())
            elif what == "set":
                answer("ok", slave.set_real(*args))
            elif what == "reader":
                vrs, kinds = args
                buf = np.empty(len(vrs))
                calls.append((slave.reader(vrs, buf, kinds), buf))
                answer("ok", len(calls) - 1)
            elif what == "read":
                read, buf = calls[args[0]]
                read()
                answer("ok", buf.copy())
            elif what == "writer":
                vrs, kinds = args
                buf = np.empty(len(vrs))
                calls.append((slave.writer(vrs, np.arange(len(vrs)), buf, kinds), buf))
                answer("ok", len(calls) - 1)
            elif what == "step":
                step = step or slave.stepper()
                answer("ok", step(*args))
        except FMICallException as exc:
            if what == "write":
                pending = (exc.function, exc.status)
            else:
                answer("error", (exc.function, exc.status))
        except Exception as exc:  # an fmpy failure outside the FMU's calls (a missing library)
            sink.log.append((4, str(exc)))
            answer("error", (what, 4))
    conn.close()
