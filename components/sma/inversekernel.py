"""The PreisachInverse FMU's compiled kernel (`musclesim.fmu.kernel`): `inverse.PreisachInverse`'s
clear, peek and step on float64 arrays, operation for operation, so that it gives the same bits
compiled or as Python.

Parameters (`pack`, slots ``I_*``): the grid's ends, the bases' spacing and size, the F axis's
scale, the largest strain, then the offsets of the packed surface (`surface.pack`) and of the
bases' four tables (`inverse.InverseBases`). State (`state`, slots ``X_*``): the first clamp of
the reference strain and of the stress (flag 0 none, 1 clamped; value; time: the slave logs
them), then the memory block (the last reference, then a `preisach.memory`) and a scratch block
of the same size for `peek`.
"""
from __future__ import annotations

import math

import numpy as np

from musclesim.components.sma import preisach, surface
from musclesim.components.sma.inverse import InverseBases
from musclesim.components.sma.preisach import (M_CAP, M_HEAD, M_K, M_N, M_RISING, M_SIG,
                                               M_SIGMA, M_TOL, M_W, M_X, M_XSIG, M_XTERM,
                                               mem_all_off, mem_record, mem_set_stress)
from musclesim.components.sma.surface import (S_MSHI, S_MSLO, S_NC, cell_eval, fmax, fmin,
                                              stress_weights_k)
from musclesim.fmu import Kernel, jit

__all__ = ["ZERO_C", "INPUTS", "OUTPUTS", "pack", "state", "clear", "peek", "step", "evaluate",
           "advance", "KERNEL", "InverseState", "blocks", "new_state"]

ZERO_C = 273.15  # K; the FMU speaks K, the cores C
INPUTS = ("eps_ref", "sigma_ref")
OUTPUTS = ("T_ref",)

(I_TLO, I_THI, I_INVH, I_N, I_XSCALE, I_EPS_HI, I_SURFACE, I_AFMAX, I_ATABLE, I_BFMAX,
 I_BTABLE) = range(11)
I_HEAD = 11

(X_WARN_EPS, X_WARN_EPS_VALUE, X_WARN_EPS_T, X_WARN_SIGMA, X_WARN_SIGMA_VALUE,
 X_WARN_SIGMA_T) = range(6)
X_BLOCK = 6  # the memory block: [last reference, preisach memory]


def pack(hysteresis: surface.Hypersurface, bases: InverseBases) -> np.ndarray:
    """The kernel's parameters of the inverse on `hysteresis` with its `bases` (layout: the
    module docstring)."""
    s = surface.packed(hysteresis)
    tables = [np.asarray(t, dtype=float) for t in (bases.a_fmax, bases.a_table, bases.b_fmax,
                                                    bases.b_table)]
    head = np.zeros(I_HEAD)
    head[:I_SURFACE] = [hysteresis.t_lo, hysteresis.t_hi, bases.inv_h, bases.n,
                        (bases.n - 1) / math.pi, float(hysteresis.table[:, -1, 0].max())]
    offset = I_HEAD + len(s)
    head[I_SURFACE] = I_HEAD
    for slot, table in zip((I_AFMAX, I_ATABLE, I_BFMAX, I_BTABLE), tables):
        head[slot] = offset
        offset += len(table)
    return np.concatenate([head, s, *tables])


def state(memory: np.ndarray) -> np.ndarray:
    """A state array with the new `memory` (`preisach.memory`) in its block and scratch block;
    `clear` sets it."""
    block = np.concatenate([[0.0], memory])
    return np.concatenate([np.zeros(X_BLOCK), block, block])


@jit
def blocks(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(memory block, scratch block) of the state `x`."""
    size = (len(x) - X_BLOCK) // 2
    return x[X_BLOCK:X_BLOCK + size], x[X_BLOCK + size:]


@jit
def _new_stress(p: np.ndarray, x: np.ndarray, m: np.ndarray, sigma: float, t: float) -> None:
    """`_set_stress`, its first clamp kept in the state for the slave to log."""
    s = p[int(p[I_SURFACE]):int(p[I_AFMAX])]
    if not s[S_MSLO] <= sigma <= s[S_MSHI] and x[X_WARN_SIGMA] == 0.0:
        x[X_WARN_SIGMA], x[X_WARN_SIGMA_VALUE], x[X_WARN_SIGMA_T] = 1.0, sigma, t
    mem_set_stress(s, m, sigma)


@jit
def _invert(p: np.ndarray, m: np.ndarray, b_table: bool, x0: float, target: float) -> float:
    """`PreisachInverse._invert`: the a-basis (`_heat`) or the b-basis (`_cool`, `b_table`)."""
    fo = int(p[I_BFMAX]) if b_table else int(p[I_AFMAX])
    to = int(p[I_BTABLE]) if b_table else int(p[I_ATABLE])
    limit = p[I_TLO] if b_table else p[I_THI]
    n = int(p[I_N])
    k = int(m[M_K])
    w = m[M_W]
    y = (x0 - p[I_TLO]) * p[I_INVH]
    j = int(y)
    if j >= n - 1:
        j = n - 2
    v = y - j
    q = fo + k * n + j
    f0 = p[q] + v * (p[q + 1] - p[q])
    f1 = p[q + n] + v * (p[q + n + 1] - p[q + n])
    fm = f0 + w * (f1 - f0)
    if target <= 0.0 or fm <= 0.0:
        return x0
    if target >= fm:
        return limit
    xx = math.acos(1.0 - 2.0 * target / fm) * p[I_XSCALE]
    # _bilinear
    l = int(xx)  # noqa: E741
    h = xx - l
    q = to + k * n * n + j * n + l
    a = p[q] + h * (p[q + 1] - p[q])
    b = p[q + n] + h * (p[q + n + 1] - p[q + n])
    lower = a + v * (b - a)
    q += n * n
    a = p[q] + h * (p[q + 1] - p[q])
    b = p[q + n] + h * (p[q + n + 1] - p[q + n])
    T = lower + w * (a + v * (b - a) - lower)
    return T if (T > x0) == (not b_table) else x0


@jit
def _rise(p: np.ndarray, m: np.ndarray, eps_r: float) -> float:
    """`PreisachInverse._rise`: T on the ascending branch, wiping out smaller maxima."""
    cap = int(m[M_CAP])
    n = int(m[M_N])
    T = _invert(p, m, False, m[M_HEAD + n - 1], eps_r - m[M_HEAD + cap + n - 1])
    while n > 2 and T >= m[M_HEAD + n - 2]:
        top = m[M_HEAD + n - 2]
        n -= 2
        m[M_N] = n
        T = fmax(_invert(p, m, False, m[M_HEAD + n - 1], eps_r - m[M_HEAD + cap + n - 1]), top)
    return T


@jit
def _fall(p: np.ndarray, m: np.ndarray, eps_r: float) -> float:
    """`PreisachInverse._fall`: T on the descending branch, wiping out larger minima."""
    cap = int(m[M_CAP])
    n = int(m[M_N])
    T = _invert(p, m, True, m[M_HEAD + n - 1], m[M_HEAD + cap + n - 1] - eps_r)
    while T <= m[M_HEAD + n - 2]:
        if n == 2:
            mem_all_off(p[int(p[I_SURFACE]):int(p[I_AFMAX])], m)
            return p[I_TLO]
        bottom = m[M_HEAD + n - 2]
        n -= 2
        m[M_N] = n
        T = fmin(_invert(p, m, True, m[M_HEAD + n - 1], m[M_HEAD + cap + n - 1] - eps_r), bottom)
    return T


@jit
def _reverse(p: np.ndarray, m: np.ndarray, eps_r: float) -> float:
    """`PreisachInverse._reverse`: turn at X, unless the branch at X does not lie across eps_r
    or the turn is within tol (then hold at X)."""
    s = p[int(p[I_SURFACE]):int(p[I_AFMAX])]
    cap = int(m[M_CAP])
    n = int(m[M_N])
    X = m[M_X]
    last = m[M_HEAD + n - 1]
    tol = m[M_TOL]
    k, w = stress_weights_k(s, m[M_XSIG])
    nc = int(s[S_NC])
    if m[M_RISING] != 0.0:
        term = cell_eval(s, k * nc * nc, X, last, w)
        if _invert(p, m, True, X, m[M_HEAD + cap + n - 1] + term - eps_r) >= X - tol:
            return X
    else:
        term = -cell_eval(s, k * nc * nc, last, X, w)
        if _invert(p, m, False, X, eps_r - m[M_HEAD + cap + n - 1] - term) <= X + tol:
            return X
    m[M_XTERM] = term  # push_extremum's term
    mem_record(s, m)
    if m[M_RISING] != 0.0:
        return fmax(_rise(p, m, eps_r), np.nextafter(X + tol, np.inf))
    return fmin(_fall(p, m, eps_r), np.nextafter(X - tol, -np.inf))


@jit
def step(p: np.ndarray, x: np.ndarray, block: np.ndarray, eps_r: float, sigma: float,
         t: float) -> float:
    """`PreisachInverse.step` of the parameters `p` on the memory `block` (the last reference,
    then the memory): take `eps_r` [-] and `sigma` [Pa] at `t` [s], return T_out [C]; clamps
    kept in the state `x`."""
    m = block[1:]
    eps_hi = p[I_EPS_HI]
    if not 0.0 <= eps_r <= eps_hi:
        if x[X_WARN_EPS] == 0.0:
            x[X_WARN_EPS], x[X_WARN_EPS_VALUE], x[X_WARN_EPS_T] = 1.0, eps_r, t
        eps_r = fmin(fmax(eps_r, 0.0), eps_hi)
    if sigma != m[M_SIGMA]:
        _new_stress(p, x, m, sigma, t)
    X = m[M_X]
    last = block[0]
    block[0] = eps_r
    if m[M_RISING] != 0.0:
        T = _reverse(p, m, eps_r) if eps_r < last else fmax(_rise(p, m, eps_r), X)
    else:
        T = _reverse(p, m, eps_r) if eps_r > last else fmin(_fall(p, m, eps_r), X)
    m[M_X] = T
    m[M_XSIG] = m[M_SIG]
    return T


@jit
def peek(p: np.ndarray, x: np.ndarray, eps_r: float, sigma: float, t: float) -> float:
    """`PreisachInverse.peek` of the parameters `p`: `step` of `eps_r` [-], `sigma` [Pa] at `t`
    [s] on a copy of the state `x`'s memory block (a new array: the state is left as it was but
    for a clamp's first warning, as evaluate's rule asks)."""
    block, _ = blocks(x)
    return step(p, x, block.copy(), eps_r, sigma, t)


@jit
def clear(p: np.ndarray, x: np.ndarray, sigma: float, t: float) -> None:
    """`PreisachInverse.clear` of the parameters `p`: the state `x`'s memory all off at b0
    under `sigma` [Pa] at `t` [s]."""
    block, _ = blocks(x)
    m = block[1:]
    _new_stress(p, x, m, sigma, t)
    mem_all_off(p[int(p[I_SURFACE]):int(p[I_AFMAX])], m)
    block[0] = 0.0


@jit
def evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """T_ref [K] into `y`: `peek` of the parameters `p`, state `x` at the present inputs `u`
    (eps_ref, sigma_ref) and time `t`, the memory untouched."""
    y[0] = peek(p, x, u[0], u[1], t) + ZERO_C


@jit
def advance(p: np.ndarray, x: np.ndarray, u: np.ndarray, y: np.ndarray, t: float,
            dt: float) -> None:
    """Commit the inputs `u` at `t` [s] to the state `x` with `step`, parameters `p` (the
    outputs `y` and `dt` play no part: no dynamics)."""
    block, _ = blocks(x)
    step(p, x, block, u[0], u[1], t)


KERNEL = Kernel(evaluate, advance, INPUTS, OUTPUTS)


class InverseState:
    """The slave's view of its kernel's memory: the `bases` it inverts with, the state `kx`, and
    the memory's stack as `PreisachInverse` names it (`extrema`, `prefix`, `stresses`)."""

    def __init__(self, bases: InverseBases, kx: np.ndarray) -> None:
        self.bases, self.kx = bases, kx

    def _stack(self, which: int) -> list[float]:
        m = self.kx[X_BLOCK + 1:]
        n, cap = int(m[M_N]), int(m[M_CAP])
        return list(m[M_HEAD + which * cap:M_HEAD + which * cap + n].tolist())

    @property
    def extrema(self) -> list[float]:
        """The stack [m_0 = b0, M_1, m_1, ...] [C]."""
        return self._stack(0)

    @property
    def prefix(self) -> list[float]:
        """The completed terms' running sums."""
        return self._stack(1)

    @property
    def stresses(self) -> list[float]:
        """Each extremum's stress [Pa]."""
        return self._stack(2)


def new_state(params: preisach.MemoryParams | None = None) -> np.ndarray:
    """`state` with a new memory of `params`."""
    return state(preisach.memory(params))
