"""Monolithic reference simulation of SMA position control (§position-control).

The ten components of ``scenarios/sma-position-control.toml`` (the two reference profiles, the
Preisach inverse, the gain-scheduled temperature PID, the thermocouple, the wire, the load PID,
the electromagnet, the load cell and the laser) stepped in one compiled loop with no
co-simulation in between: each component's compiled kernel (`musclesim.fmu.kernel`) called
directly, the wiring written out as local variables. It is what a hand-written simulation of the
same equations does, and so the limit of speed the co-simulation is measured against
(benchmarks/bench_position.py); the co-simulated scenario must give its bits
(tests/cosim/test_position_monolithic.py).

What the FMU interface asks for and a monolithic model does not: no value buffer, no flags of
which outputs are out of date, no check for NaN or non-finite values, and the inverse's
temperature reference taken by one committing `inversekernel.step` per point instead of a
`peek` on a copy of its memory and a `step` after it. The duty is clamped to [0, 1] as the
electromagnet's input is.

The model starts from the components' kernel arrays as their slaves left them after
initialization (`parts`: `musclesim.cosim.Master.kernels`), so that it and the co-simulation start
from one state; it copies them. Time is counted as the master counts its points, t = k h.
"""
from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from musclesim.components.control.slaves import (pid_advance, pid_evaluate, scheduled_advance,
                                                 scheduled_evaluate)
from musclesim.components.loads.slaves import magnet_advance, magnet_evaluate
from musclesim.components.sensors import sensor
from musclesim.components.sma import inversekernel, wirekernel
from musclesim.components.sources.slaves import loading_evaluate, strain_evaluate
from musclesim.fmu import jit

__all__ = ["INSTANCES", "RECORD", "simulate_position"]

# the scenario's instances, in the order `simulate_position` takes their arrays
INSTANCES = ("strain", "loading", "inverse", "tpid", "thermocouple", "wire", "spid", "magnet",
             "loadcell", "laser")
# the scenario's recorded signals, the columns of `simulate_position`'s rows
RECORD = ("strain.eps_ref", "laser.s_meas", "wire.strain", "loading.sigma_ref", "wire.stress",
          "inverse.T_ref", "thermocouple.T_meas", "tpid.y", "spid.y", "loadcell.f_meas")


def simulate_position(parts: Mapping[str, tuple[np.ndarray, ...]], step: float,
                      n: int) -> tuple[np.ndarray, np.ndarray]:
    """Simulate §position-control for `n` steps of `step` [s] and return (time, rows): the
    `RECORD` signals at the n + 1 points.

    Parameters
    ----------
    parts
        Per instance of `INSTANCES`, its kernel's parameters, state and inputs after
        initialization (``kp``, ``kx`` and `Kernel.inputs` of its slave, as
        `musclesim.cosim.Master.kernels` gives them); copied, not changed. Of the inputs only the
        wire's ambient temperature is read: it is the one no other component sets.
    step : float
        The communication step [s] (the scenario's 0.4 ms).
    n : int
        The number of steps.
    """
    p = [np.asarray(parts[name][0], dtype=float) for name in INSTANCES]
    x = [np.array(parts[name][1], dtype=float) for name in INSTANCES]
    T_amb = float(parts["wire"][2][wirekernel.INPUTS.index("T_amb")])
    times, rows = np.empty(n + 1), np.empty((n + 1, len(RECORD)))
    _simulate(tuple(p), tuple(x), T_amb, step, n, times, rows)
    return times, rows


@jit
def _simulate(p, x, T_amb, h, n, times, rows):
    """`simulate_position` on the instances' parameters `p` and states `x` (tuples in
    `INSTANCES`' order: strain, loading, inverse, tpid, thermocouple, wire, spid, magnet,
    loadcell, laser)."""
    p_s, p_l, p_i, p_t, p_tc, p_w, p_f, p_m, p_lc, p_ls = p
    x_s, x_l, x_i, x_t, x_tc, x_w, x_f, x_m, x_lc, x_ls = x
    ys, yl, yw, ym = np.empty(1), np.empty(2), np.empty(7), np.empty(2)
    yt, yf, y1 = np.empty(2), np.empty(2), np.empty(1)
    ut, uf, u1, uw, um = np.empty(2), np.empty(2), np.empty(1), np.empty(3), np.empty(2)
    block, _ = inversekernel.blocks(x_i)
    none = np.empty(0)
    uw[1] = T_amb
    for k in range(n + 1):
        t = k * h  # t0 + k h, as the master counts its points
        # the outputs at t, in the order of their dependencies
        strain_evaluate(p_s, x_s, none, t, ys)
        loading_evaluate(p_l, x_l, none, t, yl)
        wirekernel.evaluate(p_w, x_w, none, t, yw)
        magnet_evaluate(p_m, x_m, none, t, ym)
        T_ref = inversekernel.step(p_i, x_i, block, ys[0], yl[0], t) + inversekernel.ZERO_C
        u1[0] = yw[0]
        sensor.evaluate(p_tc, x_tc, u1, t, y1)
        T_meas = y1[0]
        u1[0] = ym[0]
        sensor.evaluate(p_lc, x_lc, u1, t, y1)
        f_meas = y1[0]
        u1[0] = yw[2]
        sensor.evaluate(p_ls, x_ls, u1, t, y1)
        s_meas = y1[0]
        ut[0], ut[1] = T_ref, T_meas
        scheduled_evaluate(p_t, x_t, ut, t, yt)
        uf[0], uf[1] = yl[1], f_meas
        pid_evaluate(p_f, x_f, uf, t, yf)
        times[k] = t
        r = rows[k]
        r[0], r[1], r[2], r[3], r[4] = ys[0], s_meas, yw[1], yl[0], yw[3]
        r[5], r[6], r[7], r[8], r[9] = T_ref, T_meas, yt[0], yf[0], f_meas
        if k == n:
            break
        # every state over [t, t + h], the inputs held at their values at t
        scheduled_advance(p_t, x_t, ut, yt, t, h)
        u1[0] = yw[0]
        sensor.advance(p_tc, x_tc, u1, y1, t, h)
        uw[0], uw[2] = yt[0], ym[0]
        wirekernel.advance(p_w, x_w, uw, yw, t, h)
        pid_advance(p_f, x_f, uf, yf, t, h)
        um[0], um[1] = min(max(yf[0], 0.0), 1.0), yw[2]
        magnet_advance(p_m, x_m, um, ym, t, h)
        u1[0] = ym[0]
        sensor.advance(p_lc, x_lc, u1, y1, t, h)
        u1[0] = yw[2]
        sensor.advance(p_ls, x_ls, u1, y1, t, h)
