"""The co-simulation master: fixed communication step over FMI 2.0 and 3.0 co-simulation FMUs.

Before a run the scenario's wiring is checked against the FMUs' model descriptions, every problem
at once (`musclesim.cosim.wiring`); the order of exchange and of steps is asked of the scenario's
graph (`Scenario.graph`), and each signal read or set is a `Signal` parsed once with the file.

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
FMU through fmpy with preallocated ctypes arrays (`musclesim.cosim.adapters`; ``host="fmpy"``
sends ours that way too). Both
call the same slave code in the same order: the results agree to the bit. An instance the
scenario isolates (``isolate = true``), or every one with ``isolate=True``, runs on fmpy in a
child process of its own (`musclesim.cosim.isolated`): its crash ends the run with one sentence,
the rows so far kept; its results are fmpy's bits.
"""
from __future__ import annotations

import contextlib
import math
import os
import re
import shutil
import tempfile
import time as clock
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from fmpy.fmi1 import FMICallException

from musclesim.cosim import direct, fused, interrupt, plausible, wiring
from musclesim.cosim.adapters import KINDS, Fmpy3Slave, FmpySlave
from musclesim.cosim.address import Signal
from musclesim.cosim.build import built_here
from musclesim.cosim.isolated import IsolatedSlave
from musclesim.cosim.host import (LOG_SINKS, callbacks, extract_fmu, extracted_fmu,
                                  forget_fmu_resource_paths, read_fmu, remove_orphan_runs)
from musclesim.cosim.results import Results
from musclesim.cosim.scenario import Scenario
from musclesim.cosim.wiring import Loaded
from musclesim.errors import UserError
from musclesim.fmu import KernelSlave

__all__ = ["Master", "Run", "Results", "signal_units", "HOSTS", "MAX_VALUES", "FLUSH_SECONDS"]

MAX_VALUES = 100_000_000  # recorded values a run keeps in memory (800 MB): rows x columns
FLUSH_SECONDS = 2.0  # wall time between two hand-overs of new rows to a run's `on_rows`
FUSED_ROWS = 4096  # rows a fused loop runs between two looks at signals and `on_rows`
HOSTS = ("direct", "fmpy")  # who calls the FMUs musclesim built: see the module's docstring
Rows = Callable[[np.ndarray, np.ndarray], None]  # on_rows(time, data): rows recorded so far


@dataclass
class Run:
    """One run's recording (`time`, `data`), its `error`, whether its instances are ready to
    step, and its `results` once it ended (`Master.session`)."""

    time: np.ndarray
    data: np.ndarray
    error: str | None = None
    ready: bool = False
    results: Results | None = None


class Master:
    """Load a scenario's FMUs, check the wiring against their model descriptions, run it.

    Parameters
    ----------
    scenario : musclesim.cosim.Scenario
    fmu_dir : str or Path
        Folder with ``<component>.fmu`` files (output of ``musclesim build``).
    inputs : dict of Signal to array, optional
        Replayed inputs: ``{Signal("instance", "input"): values}`` with one value per
        communication point (``scenario.n_steps + 1``), set at every exchange in place of a connection, the way an
        upstream FMU swapped for a measured signal would set them (sampled and held over the
        step). The diagnosis re-simulates components alone this way.
    host : {"direct", "fmpy"}
        Who calls the FMUs musclesim built from the installed sources: this process directly
        (default, `musclesim.cosim.direct`) or fmpy. Other FMUs always run through fmpy.
    fuse : bool
        Where every instance is a compiled kernel on the direct host, run the steps in one
        compiled loop (`musclesim.cosim.fused`; default): the same bits, without Python per step.
    isolate : bool
        Run every instance on fmpy in a child process of its own (`musclesim.cosim.isolated`:
        a crash ends the run with an error sentence, the rows so far kept); without it, only the
        instances the scenario isolates (``isolate = true``) run so.

    Raises
    ------
    UserError
        Listing every wiring problem (unknown instance or variable, wrong causality, unit
        mismatch, input connected twice, algebraic loop, replayed input not an unconnected input
        or of the wrong length).
    """

    def __init__(self, scenario: Scenario, fmu_dir: str | os.PathLike[str] = "fmus",
                 inputs: Mapping[Signal, Any] | None = None, host: str = "direct",
                 fuse: bool = True, isolate: bool = False) -> None:
        """Read the FMUs of `scenario` from `fmu_dir`, check the wiring (with the replayed
        `inputs`), plan the run on `host`, fused or not, every instance in a child process of
        its own if `isolate` (else those the scenario isolates; see the class docstring)."""
        if host not in HOSTS:
            raise UserError(f"host {host!r} is not one of {', '.join(HOSTS)}")
        self.scenario, self.host, self.fuse, self.isolate = scenario, host, fuse, isolate
        self.fused: bool | None = None  # whether the last run's steps ran fused
        self.current: Any = None  # the Loaded instance being called, named if it fails
        self.hosts: dict[str, str] = {}  # instance -> the host that ran it, once loaded
        self.fmu_dir = Path(fmu_dir)
        self.inputs: dict[Signal, np.ndarray] = {
            k: np.asarray(v, dtype=float) for k, v in (inputs or {}).items()}
        problems: list[str] = []
        mds = {}
        for comp in sorted({i.component for i in scenario.instances.values()}):
            path = self.fmu_dir / f"{comp}.fmu"
            if path.is_file():
                mds[comp] = read_fmu(path)
            else:
                known = sorted(p.stem for p in self.fmu_dir.glob("*.fmu"))
                problems.append(f"component {comp!r} has no FMU {path} (found: "
                                f"{', '.join(known) or 'none'}; `musclesim build` builds them)")
        self.instances = {n: Loaded(n, i.component, mds[i.component])
                          for n, i in scenario.instances.items() if i.component in mds}
        if problems:
            raise UserError("; ".join(problems))
        wiring.check(scenario, self.instances, self.inputs, problems)
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

    # ---- planning ------------------------------------------------------------------------------
    def _plan(self, problems: list[str]) -> None:
        s = self.scenario
        names = list(self.instances)
        graph = s.graph
        ft_edges = graph.edges(lambda inst, var: self.instances[inst].feedthrough.get(var))

        def algebraic_loop(remaining: list[str]) -> str:
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
        source_of: dict[Signal, Signal | str] = dict(graph.source_of())
        replayed = {dst: f"{dst} (replayed)" for dst in self.inputs}
        self.columns: list[Signal] = s.recorded()
        reads: dict[str, list[Signal]] = {n: [] for n in names}
        for sig in [k.src for k in graph.links] + [c for c in self.columns if c not in source_of]:
            reads[sig.instance].append(sig)
        slots: dict[Signal | str, int] = {}
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
            inst.read_vrs = [inst.vars[x.variable].valueReference for x in inst.reads]
            inst.read_kinds = [KINDS[inst.vars[x.variable].type] for x in inst.reads]
            ins = [(dst, src) for dst, src in source_of.items() if dst.instance == name]
            # replayed inputs, and inputs from instances exchanged earlier if they feed through,
            # are set during the exchange; all others are set just before the step
            early = [(d, x) for d, x in ins if d in replayed or (
                inst.feedthrough.get(d.variable) and isinstance(x, Signal)
                and position[x.instance] < position[name])]
            late = [pair for pair in ins if pair not in early]
            inst.transfers = [  # (value references, buffer slots, kinds) set early, late, all
                ([inst.vars[d.variable].valueReference for d, _ in pairs],
                 np.array([slots[x] for _, x in pairs], dtype=np.intp),
                 [KINDS[inst.vars[d.variable].type] for d, _ in pairs])
                for pairs in (early, late, ins)]
        self.record_slots = np.array([slots[source_of.get(c, c)] for c in self.columns], dtype=np.intp)

    # ---- running -------------------------------------------------------------------------------
    def _exchange(self, row: int) -> None:
        """Values at communication point `row`: replayed inputs, then every instance's."""
        if self.replay_table is not None:
            self.values[self.replay_slots] = self.replay_table[row]
        for inst, every, calls in self.exchange_calls:
            if every > 1 and row % every and row != self.scenario.n_steps:
                continue  # between its own points: its outputs held, its inputs not taken
            self.current = inst
            for call in calls:
                call()

    def _failure(self, inst: Loaded, t: float) -> str:
        lines = [ln for _, msg in inst.log for ln in msg.splitlines() if ln.strip()]
        cause = lines[-1] if lines else "the FMU reported an error"
        # pythonfmu reports an exception as its repr, e.g. ValueError('m1 must be positive')
        cause = re.sub(r"^\w+(?:Error|Exception)\((['\"])(.*)\1\)$", r"\2", cause)
        return (f"instance {inst.name!r} ({inst.component}) failed {self.phase} "
                f"at t = {t:.6g} s: {cause}")

    def run(self, on_rows: Rows | None = None) -> Results:
        """Run the scenario; return `Results` (with ``error`` set if an instance failed).

        `on_rows`, if given, called as ``on_rows(time, data)``, receives the rows recorded since its last call about
        every `FLUSH_SECONDS` of wall time and once at the end, so that a caller can write them
        as the run goes. A signal caught by `interrupt.interruptible` stops the run at its next
        step: `interrupt.Interrupted` is raised with the `Results` so far (rows handed over too).
        """
        with self.session(on_rows) as run:
            if run.ready:
                run.error = self.steps(run)
        assert run.results is not None  # set when the session ends
        return run.results

    def steps(self, run: Run) -> str | None:
        """Step the initialized instances of `run` (a `session`'s, ready) to the stop time,
        fused where they can be; return an error sentence or None."""
        plan = fused.Fused.plan(self) if self.fuse else None
        self.fused = plan is not None
        if plan is None:
            return self._loop(run.time, run.data)
        return self._loop_fused(plan, run.time, run.data)

    @contextlib.contextmanager
    def session(self, on_rows: Rows | None) -> Iterator[Run]:
        """Load and initialize the instances, yield the `Run` (``ready`` unless a signal or a
        failure came first: the caller then steps it, `steps` or `musclesim.cosim.cases`),
        release everything and set its `Results` (raising `interrupt.Interrupted` with them if a
        signal stopped it); `on_rows` as `run` takes it."""
        s = self.scenario
        run = Run(np.empty(s.n_steps + 1), np.empty((s.n_steps + 1, len(self.columns))))
        self.on_rows, self.flushed = on_rows, 0
        self.callbacks = callbacks(id(self))
        LOG_SINKS[id(self)] = self.instances
        self.current, self.phase, self.row, self.t = None, "while loading", 0, s.start_time
        failed: Loaded | None = None
        stopped: int | None = None
        remove_orphan_runs()
        tmp = Path(tempfile.mkdtemp(prefix=f"musclesim_run_{os.getpid()}_"))
        try:
            with interrupt.polled():
                try:
                    self._instantiate(tmp)
                    if interrupt.requested() is None:
                        self.phase = "during initialization"
                        self._initialize()
                    if interrupt.requested() is None:
                        self.phase = "in a step"
                        run.ready = True
                except FMICallException:
                    failed = self.current
                    run.error = self._failure(failed, self.t)
                try:
                    yield run  # the caller steps it if ready
                except FMICallException:
                    failed = self.current
                    run.error = self._failure(failed, self.t)
                finally:
                    run.ready = False
                stopped = interrupt.requested()
        finally:
            for inst in self.instances.values():
                # An instance that failed is left alone: pythonfmu 0.7 has already released its
                # Python objects without forgetting them, and freeing it would release them again.
                if inst.slave is not None and inst is not failed:
                    inst.slave.terminate()
                elif isinstance(inst.slave, IsolatedSlave):
                    inst.slave.close()  # its child process, alive or not, is ended
                inst.slave = None
            shutil.rmtree(tmp, ignore_errors=True)
            del LOG_SINKS[id(self)]
        warnings = [f"{i.name}: {msg}" for i in self.instances.values()
                    for status, msg in i.log if status == 1]  # fmi2Warning
        self._flush(run.time, run.data)
        if stopped is not None:
            run.error = f"{interrupt.Interrupted(stopped)} at t = {self.t:.6g} s"
        run.results = Results(run.time[:self.row].copy(), tuple(self.columns),
                              run.data[:self.row].copy(), run.error, warnings)
        if stopped is not None:
            raise interrupt.Interrupted(stopped, run.results)

    def kernels(self) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Copies of the parameters, state and inputs (``kp``, ``kx``, `Kernel.inputs` as set)
        of each loaded instance whose slave is a compiled kernel (`musclesim.fmu.KernelSlave`)
        on the direct host, as they are now: within a `session`, after initialization, what a
        model stepping the same kernels by hand starts from."""
        slaves = {name: getattr(inst.slave, "slave", None) for name, inst in self.instances.items()}
        return {name: (s.kp.copy(), s.kx.copy(), np.array(s.kernel_inputs(), dtype=float))
                for name, s in slaves.items() if isinstance(s, KernelSlave)}

    def _flush(self, time: np.ndarray, data: np.ndarray) -> None:
        """Hand the rows recorded since the last call to `on_rows`."""
        if self.on_rows is not None and self.row > self.flushed:
            self.on_rows(time[self.flushed:self.row], data[self.flushed:self.row])
            self.flushed = self.row

    def _instantiate(self, tmp: Path) -> None:
        s = self.scenario
        gauss_seidel = s.algorithm == "gauss-seidel"
        unzipped: dict[str, str] = {}

        def unpacked(inst: Loaded, path: Path) -> str:
            """The folder the FMU at `path` is extracted in (extracted the first time)."""
            if inst.component not in unzipped:
                unzipped[inst.component] = extracted_fmu(path) or extract_fmu(
                    path, tmp / inst.component)
            return unzipped[inst.component]

        for inst in self.instances.values():
            self.current = inst
            path = self.fmu_dir / f"{inst.component}.fmu"
            inst.slave = self._load(inst, path, unpacked)
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
        self.exchange_calls: list[tuple[Loaded, int, list[Callable[[], None]]]] = [
            (inst, inst.every, [c for c in (inst.set_early, inst.get) if c is not None])
            for inst in (self.instances[n] for n in self.exchange_order)]

    def _load(self, inst: Loaded, path: Path, unpacked: Callable[[Loaded, Path], str]) -> Any:
        """Instantiate `inst` from the FMU at `path` on its host (`unpacked` extracts it where
        the host needs its files: all but the direct host)."""
        try:  # fmpy raises bare Exceptions for a missing or broken library, a failed instance
            if self.isolate or self.scenario.instances[inst.name].isolate:
                self.hosts[inst.name] = "isolated"
                return IsolatedSlave(unpacked(inst, path), inst.name, inst.log,
                                     inst.md.fmiVersion.startswith("3"))
            if inst.md.fmiVersion.startswith("3"):  # through the FMI 3.0 C API, always
                self.hosts[inst.name] = "fmpy"
                return Fmpy3Slave(inst.md, unpacked(inst, path), inst.name, inst.log)
            if self.host == "direct" and built_here(path):
                cls = direct.slave_class(path, inst.md.coSimulation.modelIdentifier)
                self.hosts[inst.name] = "direct"
                return direct.DirectSlave(cls, inst.name, inst.log)
            self.hosts[inst.name] = "fmpy"
            return FmpySlave(inst.md, unpacked(inst, path), inst.name, self.callbacks)
        except FMICallException:
            raise
        except Exception as exc:
            raise UserError(f"FMU {path} cannot be loaded as instance {inst.name!r}: "
                            f"{exc}") from None

    def _initialize(self) -> None:
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

    def _not_finite(self, data: np.ndarray, row: int, t: float) -> str:
        col = next(j for j, x in enumerate(data[row - 1]) if not math.isfinite(x))
        return f"signal {self.columns[col]} became {data[row - 1, col]} at t = {t:.6g} s"

    def replay_rows(self) -> np.ndarray:
        """The replayed inputs' values, a row per communication point (none: no column)."""
        if self.replay_table is None:
            return np.zeros((self.scenario.n_steps + 1, 0))
        return self.replay_table

    def fused_error(self, plan: fused.Fused, end: int, fault: int, data: np.ndarray, row: int,
                    t: float) -> str | None:
        """The error sentence of a fused loop of `plan` that ended `end` (`fused.DONE`, ...) at
        row `row`, time `t` [s], with instance number `fault` at fault and `data` recorded: the
        unfused loop's words (None when it ran to the stop time)."""
        if end == fused.NOT_FINITE:
            return self._not_finite(data, row, t)
        if end == fused.NAN_INPUT:
            inst = self.instances[plan.names[fault]]
            inst.log.append((3, plan.nan_input(fault)))  # as the slave would log it
            return self._failure(inst, t)
        return None

    def _loop_fused(self, plan: fused.Fused, time: np.ndarray, data: np.ndarray) -> str | None:
        """`_loop` in compiled chunks of `FUSED_ROWS` rows (`musclesim.cosim.fused`)."""
        s = self.scenario
        n, row, t = s.n_steps, 0, self.t
        state, due = interrupt.STATE, clock.monotonic() + FLUSH_SECONDS
        try:
            while True:
                row, t, end, fault = plan.module.run_rows(
                    *(plan.arrays[k] for k in fused.PER_CASE), self.values, self.replay_rows(),
                    time, data, row, t, min(n + 1, row + FUSED_ROWS), n, s.start_time, s.step)
                if end != fused.PAUSED:
                    return self.fused_error(plan, end, fault, data, row, t)
                if state["signum"] is not None:  # the row the unfused loop records, then stop
                    time[row] = t
                    self.values.take(self.record_slots, out=data[row])
                    row += 1
                    return None
                if self.on_rows is not None and clock.monotonic() > due:
                    self.row = row
                    self._flush(time, data)
                    due = clock.monotonic() + FLUSH_SECONDS
        finally:
            self.row, self.t = row, t
            plan.finish()

    def _loop(self, time: np.ndarray, data: np.ndarray) -> str | None:
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
                    return self._not_finite(data, row, t)
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


def signal_units(master: Master) -> dict[Signal, str]:
    """Unit of every recorded column of `master`: its FMU's, or for one of unit "1" (a
    generic output: a controller's error, a signal source's output) the unit the scenario's
    wiring gives it (`plausible.signal_unit`: a PID's error of a kelvin measurement is in K);
    "1" for a truly unitless one. The one place a recorded signal's unit is resolved: the
    summary's metric units, the printout and the plots read it."""
    s = master.scenario
    components = {n: i.component for n, i in s.instances.items()}
    units = {}
    for sig in master.columns:
        unit = master.instances[sig.instance].vars[sig.variable].unit or "1"
        units[sig] = unit if unit != "1" else plausible.signal_unit(components, s.connections,
                                                                    sig)
    return units
