"""The SmaWire's compiled kernel (`musclesim.fmu.kernel`): `SmaWireCore`'s start and step on
float64 arrays, operation for operation, so that it gives the same bits compiled or as Python.

Parameters (`pack`, slots ``P_*``): the wire's own values, the cold end zones' table, then the
thermal parameters (`thermal.pack`, from ``p[P_THERMAL]``) and the hysteresis surface
(`surface.pack`, from ``p[P_SURFACE]``). State (`state`, slots ``X_*``): temperature, cycles,
fractions, strain, the held stress and power, the last maximum strain's stress and value, the
stress-clamp flag (0 none, 1 clamped; the value and time of the first clamp, which the slave
logs), an error flag of the latent heat's root search (1: no sign change, 2: no convergence),
the root search's context, then the Preisach memories (`preisach.memory`): the core's, one per
cold end zone, and a scratch copy for `preisach.mem_peek`.

Per step (`advance`): the hysteresis stress (f / area, the stress-blend's share, clamped to the
data set's stresses), the thermal submodel (lumped, or with the latent heat coupled implicitly
to the core memory's `mem_peek`: `thermal.step_coupled`'s search with scipy's `brentq`, step for
step), then the memories stepped at their temperatures and the strain, fractions and drift.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from musclesim.components.sma import preisach, surface, thermal
from musclesim.components.sma.drift import (count_cycles_k, strain_scale_k,
                                            temperature_shift_k)
from musclesim.components.sma.preisach import mem_peek, mem_reset, mem_step
from musclesim.components.sma.surface import (S_THI, S_TLO, fmax, fmin, stress_in_range,
                                              surface_F)
from musclesim.components.sma.thermal import (joule_power_k, martensite_fraction_k,
                                              resistance_k, step_k)
from musclesim.fmu import Kernel, jit

__all__ = ["ZERO_C", "INPUTS", "OUTPUTS", "pack", "state", "start", "evaluate", "advance",
           "KERNEL"]

ZERO_C = 273.15  # K; the FMU speaks K, the cores C
MAX_ZONES = 3  # cold end zones (`ends.EDGES`)
INPUTS = ("u", "T_amb", "flange.f")
OUTPUTS = ("T", "strain", "flange.s", "stress", "R", "P", "xi")

# parameter slots
(P_T_INIT, P_CYCLES_START, P_HYSTERESIS_SHIFT, P_STRAIN_SCALE, P_AREA, P_LENGTH, P_BLEND,
 P_SIGMA_SURFACE, P_STRESS_BLEND, P_DRIFT_AMPLITUDE, P_DRIFT_SHIFT, P_DRIFT_SETTLE, P_LATENT,
 P_ZONES, P_CORE_SHARE, P_ZONE_W, P_ZONE_G) = (0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14,
                                               15, 15 + MAX_ZONES)
P_MEMORY = 15 + 2 * MAX_ZONES  # size of one Preisach memory
P_THERMAL = P_MEMORY + 1  # offset of the thermal parameters
P_SURFACE = P_MEMORY + 2  # offset of the surface
P_HEAD = P_MEMORY + 3

# state slots
(X_T, X_CYCLES, X_XI, X_XI_CORE, X_EPS, X_STRESS, X_P, X_EPS_MAX_SIGMA, X_EPS_MAX, X_WARN,
 X_WARN_SIGMA, X_WARN_T, X_ERROR) = range(13)
X_CONTEXT = 13  # the root search's context (C_* slots)
(C_T, C_U, C_T_AMB, C_XI, C_DT, C_SHIFT, C_SIGMA, C_EPS_MAX, C_T0, C_SLOPE) = range(10)
X_MEMORIES = X_CONTEXT + 10  # the core's memory, the zones', the scratch


def pack(params: Any, wire: thermal.ThermalParams, hysteresis: surface.Hypersurface,
         zones: Sequence[tuple[float, float]], memory_size: int) -> np.ndarray:
    """The kernel's parameters of the wire's `params` (`smawire.SmaWireParams`), thermal
    parameters `wire`, `hysteresis` surface, cold end `zones` (`ends.zones`) and Preisach
    memories of `memory_size` floats (layout: the module docstring)."""
    p = params
    if len(zones) > MAX_ZONES:
        raise ValueError(f"at most {MAX_ZONES} cold end zones (got {len(zones)})")
    head = np.zeros(P_HEAD)
    blend = p.sigma_surface > 0 and p.stress_blend > 0
    head[:P_CORE_SHARE] = [
        p.T_init - ZERO_C, p.drift_cycles_start, p.hysteresis_shift,
        p.strain_scale, thermal.cross_section(wire), wire.length,
        1.0 if blend else 0.0, p.sigma_surface, p.stress_blend,
        p.drift_amplitude, p.drift_shift, p.drift_settle_cycles,
        1.0 if wire.latent_heat != 0 else 0.0, float(len(zones))]
    head[P_CORE_SHARE] = 1 - sum(w for w, _ in zones)  # as the ends submodel sums it
    for i, (w, g) in enumerate(zones):
        head[P_ZONE_W + i], head[P_ZONE_G + i] = w, g
    tp = thermal.pack(wire)
    head[P_MEMORY] = memory_size
    head[P_THERMAL] = P_HEAD
    head[P_SURFACE] = P_HEAD + len(tp)
    return np.concatenate([head, tp, surface.packed(hysteresis)])


def state(p: np.ndarray, memory: np.ndarray) -> np.ndarray:
    """A state array for the parameters `p` (`pack`), each Preisach memory a copy of the new
    `memory` (`preisach.memory`); `start` sets it."""
    n = int(p[P_ZONES]) + 2
    x = np.zeros(X_MEMORIES + n * len(memory))
    x[X_MEMORIES:] = np.tile(memory, n)
    x[X_EPS_MAX_SIGMA] = math.nan  # no maximum strain yet
    return x


@jit
def _views(p: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(thermal parameters, surface) of `p`."""
    tp = p[int(p[P_THERMAL]):int(p[P_SURFACE])]
    return tp, p[int(p[P_SURFACE]):]


@jit
def _memory(p: np.ndarray, x: np.ndarray, i: int) -> np.ndarray:
    """Preisach memory `i` of the state `x`: 0 the core's, 1.. the zones', zones + 1 scratch."""
    size = int(p[P_MEMORY])
    return x[X_MEMORIES + i * size:X_MEMORIES + (i + 1) * size]


@jit
def _seen(p: np.ndarray, s: np.ndarray, T: float, shift: float) -> float:
    """`SmaWireCore._seen`: the temperature [C] the hysteresis sees."""
    return fmin(fmax(T - shift - p[P_HYSTERESIS_SHIFT], s[S_TLO]), s[S_THI])


@jit
def _eps_max(p: np.ndarray, x: np.ndarray, s: np.ndarray, sigma: float) -> float:
    """F(a0, b0; `sigma`), evaluated once per new stress."""
    if x[X_EPS_MAX_SIGMA] != sigma:
        x[X_EPS_MAX_SIGMA] = sigma
        x[X_EPS_MAX] = surface_F(s, s[S_THI], s[S_TLO], sigma)
    return x[X_EPS_MAX]


@jit
def stress(p: np.ndarray, x: np.ndarray, f: float, t: float) -> float:
    """The stress [Pa] the hysteresis takes under the load `f` [N] at `t` [s]
    (`SmaWireCore.stress_seen`) of the parameters `p`, clamped to the data set's stresses: the
    first clamp is kept in the state `x` (X_WARN 1, its value and time) for the slave to log."""
    sigma = f / p[P_AREA]
    if p[P_BLEND] != 0.0:
        sigma = p[P_SIGMA_SURFACE] + p[P_STRESS_BLEND] * (sigma - p[P_SIGMA_SURFACE])
    return stress_in_range(p[int(p[P_SURFACE]):], sigma, x, X_WARN, t)


@jit
def _strains(p: np.ndarray, x: np.ndarray, reset: bool, T_core: float, T_amb: float,
             sigma: float, shift: float) -> None:
    """`SmaWireCore._strains`: reset (or step) the memories, the core's at `T_core` [C] and each
    zone's at its own temperature; set the strain and the martensite fractions."""
    tp, s = _views(p, x)
    eps_max = _eps_max(p, x, s, sigma)
    core = _memory(p, x, 0)
    T_seen = _seen(p, s, T_core, shift)
    eps_core = mem_reset(s, core, T_seen, sigma) if reset else mem_step(s, core, T_seen, sigma)
    eps = eps_core
    nz = int(p[P_ZONES])
    if nz > 0:
        acc = 0.0
        for i in range(nz):
            T_zone = T_amb + p[P_ZONE_G + i] * (T_core - T_amb)
            m = _memory(p, x, 1 + i)
            T_seen = _seen(p, s, T_zone, shift)
            e = mem_reset(s, m, T_seen, sigma) if reset else mem_step(s, m, T_seen, sigma)
            acc += p[P_ZONE_W + i] * e
        eps = p[P_CORE_SHARE] * eps_core + acc
    x[X_XI_CORE] = martensite_fraction_k(eps_core, eps_max)
    x[X_XI] = martensite_fraction_k(eps, eps_max)
    x[X_EPS] = p[P_STRAIN_SCALE] * strain_scale_k(x[X_CYCLES], p[P_DRIFT_AMPLITUDE],
                                                  p[P_DRIFT_SETTLE]) * eps


@jit
def start(p: np.ndarray, x: np.ndarray, u: float, T_amb: float, f: float, sigma: float) -> None:
    """`SmaWireCore.start` of the parameters `p` into the state `x`: a new (or
    drift_cycles_start old) wire heated to T_init, under the input `u`, ambient `T_amb` [C], load
    `f` [N] and hysteresis stress `sigma` [Pa]."""
    tp, s = _views(p, x)
    x[X_T] = p[P_T_INIT]
    x[X_CYCLES] = p[P_CYCLES_START]
    _strains(p, x, True, x[X_T], T_amb, sigma, 0.0)
    x[X_STRESS] = f / p[P_AREA]
    x[X_P] = joule_power_k(tp, u, x[X_XI])


@jit
def _xi_end(p: np.ndarray, x: np.ndarray, c: np.ndarray, T_end: float) -> float:
    """The martensite fraction the core's memory would reach at `T_end` [C], clipped (`xi_at`
    and `step_coupled`'s xi_end)."""
    s = p[int(p[P_SURFACE]):]
    nz = int(p[P_ZONES])
    xi = martensite_fraction_k(
        mem_peek(s, _memory(p, x, 0), _memory(p, x, nz + 1),
                 _seen(p, s, T_end, c[C_SHIFT]), c[C_SIGMA]), c[C_EPS_MAX])
    return fmin(1.0, fmax(0.0, xi))


@jit
def _g(mode: int, p: np.ndarray, x: np.ndarray, c: np.ndarray, T_end: float) -> float:
    """The latent heat's root function: mode 0, x - advance(x) (h(T) on); mode 1, its affine
    form x - T0 - slope (xi_end(x) - xi) (`thermal.step_coupled`)."""
    if mode == 0:
        tp = p[int(p[P_THERMAL]):int(p[P_SURFACE])]
        rate = (_xi_end(p, x, c, T_end) - c[C_XI]) / c[C_DT]
        return T_end - step_k(tp, c[C_T], c[C_U], c[C_T_AMB], c[C_XI], rate, c[C_DT])
    return T_end - c[C_T0] - c[C_SLOPE] * (_xi_end(p, x, c, T_end) - c[C_XI])


@jit
def _brentq(mode: int, p: np.ndarray, x: np.ndarray, c: np.ndarray, xa: float,
            xb: float) -> float:
    """scipy's `brentq` of `_g` over [`xa`, `xb`] (xtol 1e-10, rtol 4 eps, 100 iterations): its
    C code step for step. A failure sets X_ERROR (1: f(a), f(b) of one sign; 2: no
    convergence) for the slave to raise, as scipy raises, and gives NaN (a fused loop stops at
    the non-finite temperature)."""
    xtol = 1e-10
    rtol = 4 * 2.220446049250313e-16
    xpre = xa
    xcur = xb
    xblk = 0.0
    fblk = 0.0
    spre = 0.0
    scur = 0.0
    fpre = _g(mode, p, x, c, xpre)
    fcur = _g(mode, p, x, c, xcur)
    if fpre == 0:
        return xpre
    if fcur == 0:
        return xcur
    if (math.copysign(1.0, fpre) < 0) == (math.copysign(1.0, fcur) < 0):
        x[X_ERROR] = 1.0
        return math.nan
    for _ in range(100):
        if fpre != 0 and fcur != 0 and (
                (math.copysign(1.0, fpre) < 0) != (math.copysign(1.0, fcur) < 0)):
            xblk = xpre
            fblk = fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre = xcur
            xcur = xblk
            xblk = xpre
            fpre = fcur
            fcur = fblk
            fblk = fpre
        delta = (xtol + rtol * abs(xcur)) / 2
        sbis = (xblk - xcur) / 2
        if fcur == 0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:  # interpolate
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:  # extrapolate
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            a = abs(spre)
            b = 3 * abs(sbis) - delta
            if 2 * abs(stry) < (a if a < b else b):  # good short step
                spre = scur
                scur = stry
            else:  # bisect
                spre = sbis
                scur = sbis
        else:  # bisect
            spre = sbis
            scur = sbis
        xpre = xcur
        fpre = fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += (delta if sbis > 0 else -delta)
        fcur = _g(mode, p, x, c, xcur)
    x[X_ERROR] = 2.0
    return math.nan


@jit
def _thermal_step(p: np.ndarray, x: np.ndarray, c: np.ndarray, tp: np.ndarray) -> float:
    """The thermal submodel's step from the context `c`: `thermal.step` without latent heat,
    else `thermal.step_coupled`'s temperature."""
    T, u, T_amb, xi, dt = c[C_T], c[C_U], c[C_T_AMB], c[C_XI], c[C_DT]
    if p[P_LATENT] == 0.0:
        return step_k(tp, T, u, T_amb, xi, 0.0, dt)
    T0 = step_k(tp, T, u, T_amb, xi, 0.0, dt)
    xi0 = _xi_end(p, x, c, T0)
    if xi0 == xi:
        return T0
    end = 0.0 if xi0 < xi else 1.0
    other = step_k(tp, T, u, T_amb, xi, (end - xi) / dt, dt)
    lo, hi = (other, T0) if other < T0 else (T0, other)
    if hi - lo < 1e-12:
        return lo
    if tp[thermal.TP_H_EXPONENT] != 0:
        return _brentq(0, p, x, c, lo, hi)
    c[C_T0] = T0
    c[C_SLOPE] = (other - T0) / (end - xi)
    g0 = _g(1, p, x, c, T0)
    x1 = T0 - g0
    g1 = _g(1, p, x, c, x1)
    if g1 == 0 or (g1 < 0) != (g0 < 0):
        lo, hi = (x1, T0) if x1 < T0 else (T0, x1)
    return _brentq(1, p, x, c, lo, hi)


@jit
def step(p: np.ndarray, x: np.ndarray, u: float, T_amb: float, f: float, sigma: float,
         dt: float) -> None:
    """`SmaWireCore.step` of the parameters `p`: advance the state `x` over a step of `dt` [s]
    with the input `u`, ambient `T_amb` [C], load `f` [N] and hysteresis stress `sigma` [Pa]
    held."""
    tp, s = _views(p, x)
    eps_max = _eps_max(p, x, s, sigma)
    shift = temperature_shift_k(x[X_CYCLES], p[P_DRIFT_SHIFT], p[P_DRIFT_SETTLE])
    u_core = u
    if p[P_ZONES] > 0 and tp[thermal.TP_CURRENT] == 0.0:  # ColdEnds.core_drive
        u_core = u * resistance_k(tp, x[X_XI_CORE]) / resistance_k(tp, x[X_XI])
    c = x[X_CONTEXT:X_MEMORIES]
    c[C_T], c[C_U], c[C_T_AMB], c[C_XI], c[C_DT] = x[X_T], u_core, T_amb, x[X_XI_CORE], dt
    c[C_SHIFT], c[C_SIGMA], c[C_EPS_MAX] = shift, sigma, eps_max
    T_new = _thermal_step(p, x, c, tp)
    xi_old = x[X_XI]
    x[X_P] = joule_power_k(tp, u, xi_old)
    _strains(p, x, False, T_new, T_amb, sigma, shift)
    x[X_CYCLES] = count_cycles_k(x[X_CYCLES], xi_old, x[X_XI])
    x[X_STRESS] = f / p[P_AREA]
    x[X_T] = T_new


@jit
def evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """The outputs `y` (`OUTPUTS`) of the state `x` after the last step, parameters `p` (the
    inputs `u` and the time `t` play no part: no direct feedthrough)."""
    tp = p[int(p[P_THERMAL]):int(p[P_SURFACE])]
    y[0] = x[X_T] + ZERO_C
    y[1] = x[X_EPS]
    y[2] = x[X_EPS] * p[P_LENGTH]
    y[3] = x[X_STRESS]
    y[4] = resistance_k(tp, x[X_XI])
    y[5] = x[X_P]
    y[6] = x[X_XI]


@jit
def advance(p: np.ndarray, x: np.ndarray, u: np.ndarray, y: np.ndarray, t: float,
            dt: float) -> None:
    """Step the wire of parameters `p`, state `x`, over [`t`, `t` + `dt`] [s] with the inputs
    `u` (`INPUTS`) held (the outputs `y` play no part)."""
    sigma = stress(p, x, u[2], t)
    step(p, x, u[0], u[1] - ZERO_C, u[2], sigma, dt)


KERNEL = Kernel(evaluate, advance, INPUTS, OUTPUTS)
