"""The fused step: a scenario whose instances are all compiled kernels runs in one compiled loop.

Where every instance of a scenario is one of ours on the direct host and its slave is a
`musclesim.fmu.kernel.KernelSlave` whose kernel `musclesim.components.kernels` knows, and numba is
installed (`musclesim.fmu.compiled.COMPILED`), the master hands its loop to `run_rows` once the
instances are initialized: the exchange (inputs set from the value buffer, outputs evaluated and
read into it), the steps (multi-rate and Gauss-Seidel included), the recording and the check for
non-finite values, for many communication steps per call. It calls the same compiled kernels in
the order the master would call the slaves: the results are the unfused run's bits.

`Fused.plan` lays the instances' arrays end to end (parameters, state, inputs, outputs) and turns
the master's plan into index arrays; `Fused.finish` writes the state, the clocks and the inputs
back into the slaves and logs the clamps the kernels met as the slaves would have. `run_cases`
runs many parameter sets of one scenario in one call, one thread per case, each case the bits of
its own run.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from musclesim.components import kernels
from musclesim.fmu.compiled import COMPILED, jit, parallel_jit, range_over_cases
from musclesim.fmu.kernel import KernelSlave

__all__ = ["Fused", "run_rows", "run_cases", "DONE", "PAUSED", "NOT_FINITE", "NAN_INPUT",
           "PER_CASE"]

DONE, PAUSED, NOT_FINITE, NAN_INPUT = 0, 1, 2, 3  # how `run_rows` ended
# the arrays of a plan that differ from case to case of one scenario (`run_cases`)
PER_CASE = ("P", "X", "U", "Y", "clock", "cl_t", "cl_v")


@jit
def _step_end(t0, t, h):
    """`musclesim.fmu.step_end` (rint rounds half to even, as Python's round)."""
    if h > 0:
        k = np.rint((t - t0) / h)
        if t0 + k * h == t:
            return t0 + (k + 1.0) * h
    return t + h


@jit
def _inputs(i, U, uoff, cl_ptr, cl_u, cl_lo, cl_hi, cl_t, cl_v, t):
    """Instance `i`'s inputs, those with a range clamped (the first clamp and its time noted);
    None if one of those is NaN."""
    u = U[uoff[i]:uoff[i + 1]]
    if cl_ptr[i] == cl_ptr[i + 1]:
        return u
    u = u.copy()
    for j in range(cl_ptr[i], cl_ptr[i + 1]):
        k = cl_u[j] - uoff[i]
        v = u[k]
        if math.isnan(v):
            cl_t[j], cl_v[j] = t, v
            return None
        if v < cl_lo[j] or v > cl_hi[j]:
            if math.isnan(cl_t[j]):
                cl_t[j], cl_v[j] = t, v
            u[k] = min(max(v, cl_lo[j]), cl_hi[j])
    return u


@jit
def _set(i, which, values, U, tr_ptr, tr_u, tr_slot):
    for j in range(tr_ptr[which, i], tr_ptr[which, i + 1]):
        U[tr_u[j]] = values[tr_slot[j]]


@jit
def _get(i, kind, P, poff, X, xoff, U, uoff, Y, yoff, clock, rd_ptr, rd_y, rd_slot, values,
         cl_ptr, cl_u, cl_lo, cl_hi, cl_t, cl_v):
    """Evaluate instance `i` and read its outputs into `values`; False if an input was NaN."""
    u = _inputs(i, U, uoff, cl_ptr, cl_u, cl_lo, cl_hi, cl_t, cl_v, clock[i])
    if u is None:
        return False
    kernels.evaluate(kind[i], P[poff[i]:poff[i + 1]], X[xoff[i]:xoff[i + 1]], u, clock[i],
                     Y[yoff[i]:yoff[i + 1]])
    for j in range(rd_ptr[i], rd_ptr[i + 1]):
        values[rd_slot[j]] = Y[rd_y[j]]
    return True


@jit
def run_rows(kind, P, poff, X, xoff, U, uoff, Y, yoff, every, start, clock, ex_order, st_order,
             rd_ptr, rd_y, rd_slot, tr_ptr, tr_u, tr_slot, cl_ptr, cl_u, cl_lo, cl_hi, cl_t, cl_v,
             gauss_seidel, values, replay_slots, replay_table, rec_slots, time, data, row, t,
             row_stop, n, t0, h):
    """Record, step and exchange from row `row` at time `t` (the master's `_loop`, line by line)
    until the stop time or row `row_stop`; return (row, t, how it ended, instance at fault)."""
    while True:
        if row >= row_stop:
            return row, t, PAUSED, -1
        time[row] = t
        for c in range(rec_slots.shape[0]):
            data[row, c] = values[rec_slots[c]]
        row += 1
        for c in range(rec_slots.shape[0]):
            if not math.isfinite(data[row - 1, c]):
                return row, t, NOT_FINITE, -1
        if row > n:
            return row, t, DONE, -1
        k = row - 1
        for i in st_order:
            h_every = every[i] * h
            if every[i] > 1:
                if k % every[i]:
                    continue
                if k + every[i] > n:  # its last step ends at the stop time
                    h_every = (n - k) * h
            _set(i, 2 if gauss_seidel else 1, values, U, tr_ptr, tr_u, tr_slot)
            u = _inputs(i, U, uoff, cl_ptr, cl_u, cl_lo, cl_hi, cl_t, cl_v, clock[i])
            if u is None:
                return row, t, NAN_INPUT, i
            p, x, y = P[poff[i]:poff[i + 1]], X[xoff[i]:xoff[i + 1]], Y[yoff[i]:yoff[i + 1]]
            kernels.evaluate(kind[i], p, x, u, clock[i], y)  # do_step: outputs, then the step
            u = _inputs(i, U, uoff, cl_ptr, cl_u, cl_lo, cl_hi, cl_t, cl_v, t)
            kernels.advance(kind[i], p, x, u, y, t, h_every)
            clock[i] = _step_end(start[i], t, h_every)
            if gauss_seidel and every[i] == 1:
                if not _get(i, kind, P, poff, X, xoff, U, uoff, Y, yoff, clock, rd_ptr, rd_y,
                            rd_slot, values, cl_ptr, cl_u, cl_lo, cl_hi, cl_t, cl_v):
                    return row, t, NAN_INPUT, i
        t = t0 + row * h  # t0 + k h, as FMPy and the FMUs count it
        for j in range(replay_slots.shape[0]):
            values[replay_slots[j]] = replay_table[row, j]
        for i in ex_order:
            if every[i] > 1 and row % every[i] and row != n:
                continue  # between its own points: its outputs held, its inputs not taken
            _set(i, 0, values, U, tr_ptr, tr_u, tr_slot)
            if not _get(i, kind, P, poff, X, xoff, U, uoff, Y, yoff, clock, rd_ptr, rd_y, rd_slot,
                        values, cl_ptr, cl_u, cl_lo, cl_hi, cl_t, cl_v):
                return row, t, NAN_INPUT, i


@parallel_jit
def run_cases(kind, P, poff, X, xoff, U, uoff, Y, yoff, every, start, clock, ex_order, st_order,
              rd_ptr, rd_y, rd_slot, tr_ptr, tr_u, tr_slot, cl_ptr, cl_u, cl_lo, cl_hi, cl_t,
              cl_v, gauss_seidel, values, replay_slots, replay_table, rec_slots, time, data, n, t0,
              h, rows, ts, ends, faults):
    """`run_rows` to the stop time for every case c: its arrays are row c of `P`, `X`, `U`, `Y`,
    `clock`, `cl_t`, `cl_v`, `values`, `replay_table`, `time` and `data`; its last row, its time,
    how it ended and the instance at fault go to ``rows[c]``, ``ts[c]``, ``ends[c]``,
    ``faults[c]``."""
    for c in range_over_cases(P.shape[0]):
        rows[c], ts[c], ends[c], faults[c] = run_rows(
            kind, P[c], poff, X[c], xoff, U[c], uoff, Y[c], yoff, every, start, clock[c],
            ex_order, st_order, rd_ptr, rd_y, rd_slot, tr_ptr, tr_u, tr_slot, cl_ptr, cl_u, cl_lo,
            cl_hi, cl_t[c], cl_v[c], gauss_seidel, values[c], replay_slots, replay_table[c],
            rec_slots, time[c], data[c], 0, t0, n + 1, n, t0, h)


def _offsets(sizes: list[int]) -> np.ndarray:
    return np.concatenate([[0], np.cumsum(sizes)]).astype(np.intp)


def _csr(lists: list[list[Any]], width: int) -> tuple[np.ndarray, list[np.ndarray]]:
    """Row pointers and the columns of `lists` (one list of `width`-tuples per instance)."""
    ptr = _offsets([len(x) for x in lists])
    flat = [e for x in lists for e in x]
    return ptr, [np.array([e[w] for e in flat]) for w in range(width)]


@dataclass
class Fused:
    """One scenario's instances as the arrays `run_rows` takes (`plan`); `arrays` in its
    argument order up to `gauss_seidel`, `slaves` in the master's instance order."""

    slaves: list[KernelSlave]
    names: list[str]
    arrays: dict[str, Any]
    clamps: list[tuple[int, str, float, float]]  # (instance, input, lower, upper) per clamp

    @classmethod
    def plan(cls, master: Any) -> Fused | None:
        """The fused plan of `master` (a `Master` whose instances are initialized), or None where
        an instance cannot join (not ours on the direct host, no kernel) or numba is missing."""
        if not COMPILED:
            return None
        insts = list(master.instances.values())
        found = [getattr(i.slave, "slave", None) for i in insts]
        slaves = [s for s in found if isinstance(s, KernelSlave) and s.kernel in kernels.KINDS]
        if len(slaves) < len(insts):
            return None
        index = {inst.name: k for k, inst in enumerate(insts)}
        ks = [s.kernel for s in slaves]
        yoff = _offsets([len(k.outputs) for k in ks])
        uoff = _offsets([len(k.inputs) for k in ks])
        reads: list[list[tuple[int, int]]] = []
        transfers: list[list[list[tuple[int, int]]]] = [[], [], []]
        for k, (inst, kern) in enumerate(zip(insts, ks)):
            name_of = {v.valueReference: name for name, v in inst.vars.items()
                       if v.causality == "input"}
            reads.append([(yoff[k] + kern.outputs.index(sig.variable), inst.first + j)
                          for j, sig in enumerate(inst.reads) if sig.variable in kern.outputs])
            for which, (vrs, slots, _) in enumerate(inst.transfers):
                names = [name_of.get(vr) for vr in vrs]
                if any(n not in kern.inputs for n in names):
                    return None  # an input the kernel does not take
                transfers[which].append([(uoff[k] + kern.inputs.index(str(n)), int(slot))
                                         for n, slot in zip(names, slots)])
        clamps = [(k, name, lo, hi) for k, kern in enumerate(ks) for name, lo, hi in kern.clamps]
        rd_ptr, (rd_y, rd_slot) = _csr(reads, 2)
        tr = [_csr(t, 2) for t in transfers]
        cl_ptr = _offsets([len(k.clamps) for k in ks])
        every = np.array([i.every for i in insts], dtype=np.intp)
        arrays = dict(
            kind=np.array([kernels.KINDS[k] for k in ks], dtype=np.intp),
            P=np.concatenate([np.asarray(s.kp, dtype=float) for s in slaves] + [np.zeros(0)]),
            poff=_offsets([len(s.kp) for s in slaves]),
            X=np.concatenate([np.asarray(s.kx, dtype=float) for s in slaves] + [np.zeros(0)]),
            xoff=_offsets([len(s.kx) for s in slaves]),
            U=np.array([v for s in slaves for v in s.kernel_inputs()], dtype=float),
            uoff=uoff, Y=np.zeros(yoff[-1]), yoff=yoff, every=every,
            start=np.array([s.start_time for s in slaves], dtype=float),
            clock=np.array([s.time for s in slaves], dtype=float),
            ex_order=np.array([index[n] for n in master.exchange_order], dtype=np.intp),
            st_order=np.array([index[n] for n in master.step_order], dtype=np.intp),
            rd_ptr=rd_ptr, rd_y=rd_y.astype(np.intp), rd_slot=rd_slot.astype(np.intp),
            tr_ptr=np.stack([p for p, _ in tr]),
            tr_u=np.concatenate([c[0] for _, c in tr]).astype(np.intp),
            tr_slot=np.concatenate([c[1] for _, c in tr]).astype(np.intp),
            cl_ptr=cl_ptr, cl_u=np.array([uoff[k] + ks[k].inputs.index(n)
                                          for k, n, _, _ in clamps], dtype=np.intp),
            cl_lo=np.array([c[2] for c in clamps], dtype=float),
            cl_hi=np.array([c[3] for c in clamps], dtype=float),
            cl_t=np.full(len(clamps), math.nan), cl_v=np.zeros(len(clamps)),
            gauss_seidel=master.scenario.algorithm == "gauss-seidel")
        # tr_ptr's rows are offsets into each kind's own columns: shift them into the flat ones
        shift = np.cumsum([0] + [len(c[0]) for _, c in tr[:-1]])
        arrays["tr_ptr"] = arrays["tr_ptr"] + shift[:, None]
        return cls(slaves, [i.name for i in insts], arrays, clamps)

    @staticmethod
    def batchable(plans: list[Fused | None]) -> bool:
        """Whether the `plans` (one per case) run as one `run_cases` call: all fused, with the
        same layout (index arrays) and arrays of the same shapes."""
        if not plans or any(p is None for p in plans):
            return False
        first = plans[0].arrays  # type: ignore[union-attr]
        return all(
            all(np.shape(p.arrays[k]) == np.shape(v) if k in PER_CASE
                else np.array_equal(p.arrays[k], v) for k, v in first.items())
            for p in plans[1:] if p is not None)

    def finish(self) -> None:
        """Write the state, the clocks and the last inputs back into the slaves; log each clamp
        the kernels met as the slave's first clamp (`Slave.clamped_input`) would have."""
        a = self.arrays
        for k, s in enumerate(self.slaves):
            s.kx[:] = a["X"][a["xoff"][k]:a["xoff"][k + 1]]
            s.time = float(a["clock"][k])
            s.set_kernel_inputs(a["U"][a["uoff"][k]:a["uoff"][k + 1]])
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
