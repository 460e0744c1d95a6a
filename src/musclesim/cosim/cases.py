"""Many cases of one scenario in one pass: `run_cases` steps the parameter sets of a scenario
(masters of `with_values` copies) in one compiled call, one thread per case, where all of them
fuse into arrays of one shape (`musclesim.cosim.fused`); each case gives its own run's bits.
"""
from __future__ import annotations

import contextlib
from collections.abc import Sequence

import numpy as np

from musclesim.cosim import fused
from musclesim.cosim.master import Master, Run
from musclesim.cosim.results import Results

__all__ = ["run_cases"]


def run_cases(masters: Sequence[Master]) -> list[Results]:
    """`Results` of every run of the `masters` (of one scenario with other parameter values, as
    `with_values` makes them): where all of them fuse into arrays of one shape, in one compiled
    call, the cases on threads (the generated ``run_cases``), each case the bits of its own run;
    else one after the other."""
    with contextlib.ExitStack() as stack:
        runs = [stack.enter_context(m.session(None)) for m in masters]
        plans = [fused.Fused.plan(m) if r.ready and m.fuse else None
                 for m, r in zip(masters, runs)]
        if len(masters) > 1 and fused.Fused.batchable(plans):
            _run_batch(masters, runs, [p for p in plans if p is not None])
        else:
            for m, r in zip(masters, runs):
                if r.ready:
                    r.error = m.steps(r)
    return [r.results for r in runs if r.results is not None]


def _run_batch(masters: Sequence[Master], runs: list[Run], plans: list[fused.Fused]) -> None:
    """Step the initialized `masters` in one compiled call (their `plans` batchable)."""
    s = masters[0].scenario
    stack = {k: np.stack([p.arrays[k] for p in plans]) for k in fused.PER_CASE}
    values = np.stack([m.values for m in masters])
    time, data = np.stack([r.time for r in runs]), np.stack([r.data for r in runs])
    rows, ends, faults = (np.zeros(len(masters), dtype=np.intp) for _ in range(3))
    ts = np.zeros(len(masters))
    plans[0].module.run_cases(*stack.values(), values,
                              np.stack([m.replay_rows() for m in masters]), time, data,
                              s.n_steps, s.start_time, s.step, rows, ts, ends, faults)
    for c, (m, r, plan) in enumerate(zip(masters, runs, plans)):
        for k in fused.PER_CASE:
            plan.arrays[k][...] = stack[k][c]
        m.values[:], r.time[:], r.data[:] = values[c], time[c], data[c]
        m.fused, m.row, m.t = True, int(rows[c]), float(ts[c])
        plan.finish()
        r.error = m.fused_error(plan, int(ends[c]), int(faults[c]), r.data, m.row, m.t)
