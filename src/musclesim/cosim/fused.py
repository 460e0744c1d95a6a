"""The fused step: a scenario whose instances are all compiled kernels runs in one compiled loop.

Where every instance of a scenario is one of ours on the direct host, its slave a
`musclesim.fmu.kernel.KernelSlave` whose kernel is compiled, and numba is installed
(`musclesim.fmu.compiled.COMPILED`), the master hands its loop to a function written for that
scenario's layout once its instances are initialized (`Fused.plan`): the exchange (inputs set
from the value buffer, outputs evaluated and read into it), the steps (multi-rate and
Gauss-Seidel included), the recording and the check for non-finite values, for many
communication steps per call, each kernel called directly with constant indices. It calls the
kernels in the order the master calls the slaves, and evaluates where a slave would (after an
input was set or a step taken: `Slave._refresh`): the results are the unfused run's bits.

The function's source is a function of the layout only (no parameter value): it is written to
the compiled-code cache (`musclesim.fmu.compiled.CACHE`) under its digest and compiled once per
layout and source version. `Fused.finish` writes the state, the clocks and the inputs back into
the slaves and logs the clamps the kernels met as the slaves would have. The generated
``run_cases`` runs many parameter sets of one scenario in one call, one thread per case, each case
the bits of its own run.
"""
from __future__ import annotations

import hashlib
import importlib.util
import math
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from musclesim.fmu.compiled import CACHE, COMPILED
from musclesim.fmu.kernel import Kernel, KernelSlave

__all__ = ["Fused", "DONE", "PAUSED", "NOT_FINITE", "NAN_INPUT", "PER_CASE"]

DONE, PAUSED, NOT_FINITE, NAN_INPUT = 0, 1, 2, 3  # how a fused loop ended
# a plan's arrays that differ from case to case of one scenario (`run_cases`)
PER_CASE = ("P", "X", "U", "Y", "clock", "dirty", "cl_t", "cl_v")
_MODULES: dict[str, ModuleType] = {}  # digest of a layout's source -> its compiled module


def _literal(x: float) -> str:
    """`x` as Python source (an infinity as math.inf)."""
    return repr(float(x)) if math.isfinite(x) else ("-" if x < 0 else "") + "math.inf"


def _function(fn: Any) -> tuple[str, str] | None:
    """(module, name) under which the compiled kernel function `fn` is importable, else None."""
    py = getattr(fn, "py_func", None)
    if py is None:
        return None
    module = sys.modules.get(py.__module__)
    return (py.__module__, py.__name__) if getattr(module, py.__name__, None) is fn else None


@dataclass
class _Layout:
    """What the generated source says: per instance its kernel's functions, array slices,
    transfers, reads, clamps and rate; the orders; the algorithm; the recorded slots."""

    funcs: list[tuple[tuple[str, str], tuple[str, str]]]
    sizes: dict[str, list[int]]  # "P", "X", "U", "Y" -> size per instance
    early: list[list[tuple[int, int]]]  # (input index, value slot) per instance
    late: list[list[tuple[int, int]]]
    every_set: list[list[tuple[int, int]]]  # all inputs (Gauss-Seidel sets them before a step)
    reads: list[list[tuple[int, int]]]  # (output index, value slot)
    clamps: list[list[tuple[int, int, float, float]]]  # (clamp number, input index, lo, hi)
    every: list[int]
    start: list[float]
    ex_order: list[int]
    st_order: list[int]
    gauss_seidel: bool
    record: list[int]
    replay: list[int]
    lines: list[str] = field(default_factory=list)

    def source(self) -> str:
        """The module's source: ``run_rows`` and ``run_cases`` for this layout."""
        imports = sorted({f for pair in self.funcs for f in pair})
        self.lines = ["import math", "import numpy as np",
                      "from musclesim.fmu.compiled import jit, parallel_jit, range_over_cases"]
        self.lines += [f"from {m} import {n} as {self._alias(m, n)}" for m, n in imports]
        self.lines += ["", "", "@jit", "def run_rows(P, X, U, Y, clock, dirty, cl_t, cl_v, values, "
                       "replay_table, time, data, row, t, row_stop, n, t0, h):"]
        for i in range(len(self.funcs)):
            for a in "PXUY":
                o = sum(self.sizes[a][:i])
                self._emit(1, f"{a.lower()}{i} = {a}[{o}:{o + self.sizes[a][i]}]")
            if self.clamps[i]:
                self._emit(1, f"c{i} = np.empty({self.sizes['U'][i]})")
        self._emit(1, "while True:")
        self._emit(2, "if row >= row_stop:")
        self._emit(3, f"return row, t, {PAUSED}, -1")
        self._emit(2, "time[row] = t")
        for c, slot in enumerate(self.record):
            self._emit(2, f"data[row, {c}] = values[{slot}]")
        self._emit(2, "row += 1")
        if self.record:
            self._emit(2, f"for c in range({len(self.record)}):")
            self._emit(3, "if not math.isfinite(data[row - 1, c]):")
            self._emit(4, f"return row, t, {NOT_FINITE}, -1")
        self._emit(2, "if row > n:")
        self._emit(3, f"return row, t, {DONE}, -1")
        self._emit(2, "k = row - 1")
        for i in self.st_order:
            self._step(i)
        self._emit(2, "t = t0 + row * h  # t0 + k h, as FMPy and the FMUs count it")
        for j, slot in enumerate(self.replay):
            self._emit(2, f"values[{slot}] = replay_table[row, {j}]")
        for i in self.ex_order:
            depth = 2
            if self.every[i] > 1:  # between its own points: outputs held, inputs not taken
                self._emit(2, f"if row % {self.every[i]} == 0 or row == n:")
                depth = 3
            self._set(depth, i, self.early[i])
            self._get(depth, i)
        self._emit(1, "")
        self.lines += ["", "@parallel_jit",
                       "def run_cases(P, X, U, Y, clock, dirty, cl_t, cl_v, values, replay_table, "
                       "time, data, n, t0, h, rows, ts, ends, faults):",
                       "    for c in range_over_cases(P.shape[0]):",
                       "        rows[c], ts[c], ends[c], faults[c] = run_rows(",
                       "            P[c], X[c], U[c], Y[c], clock[c], dirty[c], cl_t[c], cl_v[c], "
                       "values[c], replay_table[c], time[c], data[c], 0, t0, n + 1, n, t0, h)", ""]
        return "\n".join(self.lines)

    @staticmethod
    def _alias(module: str, name: str) -> str:
        return "k_" + hashlib.sha256(f"{module}:{name}".encode()).hexdigest()[:10] + "_" + name

    def _emit(self, depth: int, line: str) -> None:
        self.lines.append("    " * depth + line)

    def _set(self, depth: int, i: int, pairs: list[tuple[int, int]]) -> None:
        for index, slot in pairs:
            self._emit(depth, f"u{i}[{index}] = values[{slot}]")
        if pairs:
            self._emit(depth, f"dirty[{i}] = True")

    def _inputs(self, depth: int, i: int, t: str) -> str:
        """Emit instance `i`'s clamps at time `t` (a NaN returns); the inputs' array name."""
        if not self.clamps[i]:
            return f"u{i}"
        self._emit(depth, f"c{i}[:] = u{i}")
        for j, index, lo, hi in self.clamps[i]:
            v = f"c{i}[{index}]"
            self._emit(depth, f"if math.isnan({v}):")
            self._emit(depth + 1, f"cl_t[{j}], cl_v[{j}] = {t}, {v}")
            self._emit(depth + 1, f"return row, t, {NAN_INPUT}, {i}")
            self._emit(depth, f"if {v} < {_literal(lo)} or {v} > {_literal(hi)}:")
            self._emit(depth + 1, f"if math.isnan(cl_t[{j}]):")
            self._emit(depth + 2, f"cl_t[{j}], cl_v[{j}] = {t}, {v}")
            self._emit(depth + 1, f"{v} = min(max({v}, {_literal(lo)}), {_literal(hi)})")
        return f"c{i}"

    def _evaluate(self, depth: int, i: int) -> None:
        """Emit `Slave._refresh`: evaluate instance `i` if an input was set or it stepped."""
        self._emit(depth, f"if dirty[{i}]:")
        u = self._inputs(depth + 1, i, f"clock[{i}]")
        self._emit(depth + 1, f"{self._alias(*self.funcs[i][0])}(p{i}, x{i}, {u}, clock[{i}], y{i})")
        self._emit(depth + 1, f"dirty[{i}] = False")

    def _get(self, depth: int, i: int) -> None:
        self._evaluate(depth, i)
        for index, slot in self.reads[i]:
            self._emit(depth, f"values[{slot}] = y{i}[{index}]")

    def _step(self, i: int) -> None:
        every, depth = self.every[i], 2
        if every > 1:
            self._emit(2, f"if k % {every} == 0:")
            self._emit(3, f"h{i} = (n - k) * h if k + {every} > n else {every} * h")
            depth = 3
        else:
            self._emit(2, f"h{i} = h")
        self._set(depth, i, self.every_set[i] if self.gauss_seidel else self.late[i])
        self._evaluate(depth, i)  # do_step: the outputs first (advance may read them)
        u = self._inputs(depth, i, "t")
        self._emit(depth, f"{self._alias(*self.funcs[i][1])}(p{i}, x{i}, {u}, y{i}, t, h{i})")
        self._emit(depth, f"dirty[{i}] = True")
        # step_end: t0 + (k + 1) h where t is the point t0 + k h (musclesim.fmu.step_end)
        self._emit(depth, f"q = np.rint((t - {self.start[i]!r}) / h{i})")
        self._emit(depth, f"clock[{i}] = {self.start[i]!r} + (q + 1.0) * h{i} if "
                          f"{self.start[i]!r} + q * h{i} == t else t + h{i}")
        if self.gauss_seidel and every == 1:
            self._get(depth, i)


def _compiled(source: str) -> ModuleType:
    """The module of `source`, written to the compiled-code cache and imported (once)."""
    digest = hashlib.sha256(source.encode()).hexdigest()[:20]
    if digest not in _MODULES:
        folder = CACHE if CACHE is not None else Path(tempfile.mkdtemp(prefix="musclesim_fused_"))
        path = folder / f"fused_{digest}.py"
        if not path.exists() or path.read_text() != source:
            tmp = path.with_suffix(f".{id(source)}.tmp")
            tmp.write_text(source)
            tmp.replace(path)  # atomic: another process may be writing the same file
        spec = importlib.util.spec_from_file_location(f"musclesim_fused_{digest}", path)
        assert spec is not None and spec.loader is not None  # a .py file has both
        module = importlib.util.module_from_spec(spec)
        sys.modules[spec.name] = module  # numba's cache finds the module of a function by name
        spec.loader.exec_module(module)
        _MODULES[digest] = module
    return _MODULES[digest]


@dataclass
class Fused:
    """One scenario's initialized instances as the arrays of its generated loop (`plan`):
    `module` holds ``run_rows`` and ``run_cases``; `arrays` are the per-case ones (`PER_CASE`)."""

    slaves: list[KernelSlave]
    names: list[str]
    module: ModuleType
    arrays: dict[str, np.ndarray]
    clamps: list[tuple[int, str, float, float]]  # (instance, input, lower, upper) per clamp
    offsets: dict[str, np.ndarray]

    @classmethod
    def plan(cls, master: Any) -> Fused | None:
        """The fused plan of `master` (a `Master` whose instances are initialized), or None where
        an instance cannot join (not ours on the direct host, no compiled kernel) or numba is
        missing."""
        if not COMPILED:
            return None
        insts = list(master.instances.values())
        found = [getattr(i.slave, "slave", None) for i in insts]
        slaves = [s for s in found if isinstance(s, KernelSlave)]
        ks: list[Kernel] = [s.kernel for s in slaves]
        funcs = [(_function(k.evaluate), _function(k.advance)) for k in ks]
        if len(slaves) < len(insts) or any(e is None or a is None for e, a in funcs):
            return None
        index = {inst.name: k for k, inst in enumerate(insts)}
        transfers: list[list[list[tuple[int, int]]]] = [[], [], []]
        for inst, kern in zip(insts, ks):
            name_of = {v.valueReference: name for name, v in inst.vars.items()}
            for which, (vrs, slots, _) in enumerate(inst.transfers):
                names = [name_of[vr] for vr in vrs]
                if any(n not in kern.inputs for n in names):
                    return None  # an input the kernel does not take
                transfers[which].append([(kern.inputs.index(n), int(slot))
                                         for n, slot in zip(names, slots)])
        clamps = [(k, name, lo, hi) for k, kern in enumerate(ks) for name, lo, hi in kern.clamps]
        numbered = [[(j, ks[k].inputs.index(name), lo, hi)
                     for j, (k, name, lo, hi) in enumerate(clamps) if k == i]
                    for i in range(len(ks))]
        layout = _Layout(
            funcs=funcs,  # type: ignore[arg-type]  # no None left (checked above)
            sizes={"P": [len(s.kp) for s in slaves], "X": [len(s.kx) for s in slaves],
                   "U": [len(k.inputs) for k in ks], "Y": [len(k.outputs) for k in ks]},
            early=transfers[0], late=transfers[1], every_set=transfers[2],
            reads=[[(k.outputs.index(sig.variable), inst.first + j)
                    for j, sig in enumerate(inst.reads) if sig.variable in k.outputs]
                   for inst, k in zip(insts, ks)],
            clamps=numbered, every=[i.every for i in insts],
            start=[float(s.start_time) for s in slaves],
            ex_order=[index[n] for n in master.exchange_order],
            st_order=[index[n] for n in master.step_order],
            gauss_seidel=master.scenario.algorithm == "gauss-seidel",
            record=[int(x) for x in master.record_slots],
            replay=[int(x) for x in master.replay_slots])
        arrays = {
            "P": np.concatenate([np.asarray(s.kp, dtype=float) for s in slaves] + [np.zeros(0)]),
            "X": np.concatenate([np.asarray(s.kx, dtype=float) for s in slaves] + [np.zeros(0)]),
            "U": np.array([v for s in slaves for v in s.kernel_inputs()], dtype=float),
            "Y": np.concatenate([np.asarray(s.ky, dtype=float) for s in slaves] + [np.zeros(0)]),
            "clock": np.array([s.time for s in slaves], dtype=float),
            "dirty": np.array([s.kernel_dirty() for s in slaves], dtype=np.bool_),
            "cl_t": np.full(len(clamps), math.nan), "cl_v": np.zeros(len(clamps))}
        offsets = {a: np.concatenate([[0], np.cumsum(layout.sizes[a])]).astype(int)
                   for a in "PXUY"}
        return cls(slaves, [i.name for i in insts], _compiled(layout.source()), arrays, clamps,
                   offsets)

    @staticmethod
    def batchable(plans: list[Fused | None]) -> bool:
        """Whether the `plans` (one per case) run as one ``run_cases`` call: all fused by one
        generated module, with arrays of the same shapes."""
        if not plans or any(p is None for p in plans):
            return False
        first = plans[0]
        assert first is not None
        return all(p.module is first.module and all(
            p.arrays[k].shape == v.shape for k, v in first.arrays.items())
            for p in plans[1:] if p is not None)

    def finish(self) -> None:
        """Write the state, the clocks and the last inputs and outputs back into the slaves; log
        each clamp the kernels met as the slave's first clamp (`Slave.clamped_input`) would
        have."""
        a, o = self.arrays, self.offsets
        for k, s in enumerate(self.slaves):
            x, u, y = (a[v][o[v][k]:o[v][k + 1]] for v in "XUY")
            s.restore_kernel(x, u, y, float(a["clock"][k]), bool(a["dirty"][k]))
        for j, (k, name, lo, hi) in enumerate(self.clamps):
            if not math.isnan(a["cl_t"][j]) and not math.isnan(a["cl_v"][j]):
                self.slaves[k].note_clamp(name, float(a["cl_v"][j]), lo, hi, float(a["cl_t"][j]))

    def nan_input(self, k: int) -> str:
        """The sentence of instance `k`'s NaN input, as `Slave.clamped_input` raises it."""
        a = self.arrays
        for j, (inst, name, _, _) in enumerate(self.clamps):
            if inst == k and math.isnan(a["cl_v"][j]):
                return f"input {name} is NaN at t = {a['cl_t'][j]:g} s"
        return "an input is NaN"
