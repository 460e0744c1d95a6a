"""Modified Preisach forward model of §preisach: temperature in, strain out, stress a correction."""
from __future__ import annotations

import math

from bisect import bisect_right
from collections.abc import Callable, Sequence
from typing import Any
from dataclasses import dataclass

import numpy as np

from musclesim.components.checks import require
from musclesim.fmu import jit

from .surface import (GRID_TEMPS, S_HEAD, S_MSHI, S_MSLO, S_NC, S_NLEV, S_THI, S_TLO, STRESSES,
                      Hypersurface, RangeWarning, cell_eval, clamp, clip, fmax, fmin,
                      stress_grid, stress_weights_k)

__all__ = ["GRID_TEMPS", "STRESSES", "Hypersurface", "MemoryParams", "PreisachModel",
           "RangeWarning", "stack_strain", "strain_falling", "strain_rising"]


@dataclass(frozen=True)
class MemoryParams:
    """Numerics of the input memory (the extrema stack); §preisach leaves them open."""

    tol: float = 0.01  # C, reversals smaller than this make no stack entry (real-time noise guard)
    max_extrema: int = 64  # stack bound incl. b0; beyond it the least important pair is forgotten

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, non_negative=("tol",))
        if not (isinstance(self.max_extrema, int) and self.max_extrema >= 4):
            raise ValueError(f"max_extrema must be an integer >= 4 (got {self.max_extrema!r})")


class StressInput:
    """What the forward and inverse models share: stress handling (clamp, warn once, interpolate)
    and the bookkeeping of the extrema stack.

    After `_set_stress`: ``_sig`` is the clamped stress, ``_k`` and ``_w`` its interval and
    weight, ``_k_base = _k * stride`` the offset of the interval in the caller's tables. The stack
    lives in ``extrema`` (from b0), ``prefix`` (completed terms summed) and ``stresses`` (at which
    each extremum was recorded); ``X`` is the running extremum, ``rising`` its direction.
    The model that shares it sets its surface, its memory's numerics and the grid's lower end.
    """

    surface: Hypersurface
    params: MemoryParams
    _t_lo: float

    def _clear_memory(self):
        """The all-off memory at b0 under the current stress."""
        b0 = self._t_lo
        self.extrema, self.prefix, self.stresses = [b0], [0.0], [self._sig]
        self.rising, self.X, self.X_sigma = True, b0, self._sig

    def _wipe_pair(self):
        """Drop the innermost maximum-minimum pair (wiping-out)."""
        del self.extrema[-2:]
        del self.prefix[-2:]
        del self.stresses[-2:]

    def _init_stress(self, surface, stride):
        self._s_lo, self._s_hi, self._levels, self._inv_ds, self._k_max = stress_grid(surface)
        self._stride = stride
        self._warned = set()
        self._sigma = None

    def _set_stress(self, sigma, t):
        """Interpolation weights of a new stress (a single-level surface ignores stress)."""
        self._sigma = sigma
        if not self._s_lo <= sigma <= self._s_hi:
            sigma = clamp(self._warned, "stress", sigma, self._s_lo, self._s_hi, "Pa", t)
        levels = self._levels
        k = bisect_right(levels, sigma) - 1
        if k > self._k_max:
            k = self._k_max
        elif k < 0:
            k = 0
        self._sig = sigma
        self._k = k
        self._w = (sigma - levels[k]) * self._inv_ds[k]
        self._k_base = k * self._stride


class PreisachModel(StressInput):
    """Forward model of §preisach on a `Hypersurface`, stepped sample by sample in O(1).

    The memory is the alternating stack ``extrema = [m_0 = b0, M_1, m_1, M_2, ...]`` with wiping-out
    on every input. Each completed term (F(M_k, m_k-1) when M_k is recorded, -F(M_k, m_k) when m_k
    is) is frozen at the stress of the last step spent at that extremum and kept as a running
    prefix sum, so that a step evaluates F once: strain = prefix[-1] + the running term at the
    current stress.

    Memory rules (`MemoryParams`): a reversal is recorded only once the input has moved back more
    than ``tol`` from the running extremum X; until then the input counts as X (the strain holds).
    When a new extremum makes the stack longer than ``max_extrema``, the two consecutive entries
    whose loss changes the strain least are forgotten (`forget_least_pair`, O(stack) F
    evaluations, only then); the strain changes by that amount. Reaching b0 while cooling
    empties the stack (all hysterons off, strain 0).

    State: plain attributes (lists, floats, a bool), so ``copy.deepcopy`` saves it; the surface is
    shared, not copied. Out-of-range policy: that of `Hypersurface` (clamp, warn once per model).
    With time-varying stress the strain can leave [0, F(a0, b0)], since frozen terms keep their
    stresses (§preisach).

    Parameters
    ----------
    surface : Hypersurface
    params : MemoryParams, optional

    Examples
    --------
    >>> h = Hypersurface.from_function(lambda a, b, s: (a - b) ** 2 / 2e5, stresses=[1e8])
    >>> m = PreisachModel(h, MemoryParams(tol=0.0))
    >>> [round(m.step(T, 1e8) * 1e5, 6) for T in (90.0, 50.0, 70.0, 60.0, 95.0)]
    [1800.0, 1000.0, 1200.0, 1150.0, 2112.5]
    """

    def __init__(self, surface: Hypersurface, params: MemoryParams | None = None) -> None:
        self.params = params or MemoryParams()
        self.params.check()
        self.surface = surface
        self._tol = float(self.params.tol)
        self._t_lo, self._t_hi = surface.t_lo, surface.t_hi
        self._nc, self._inv_h = surface.n_cells, surface.inv_h
        self._init_stress(surface, self._nc * self._nc)
        self.reset(surface.t_lo, surface.s_lo)

    def reset(self, T: float, sigma: float, t: float | None = None) -> float:
        """Start from the all-off state at b0 (fully martensitic), then take input `T` [C],
        `sigma` [Pa] (at time `t` [s], used only in warnings); return the strain."""
        self._set_stress(sigma, t)
        self._all_off()
        return self.step(T, sigma, t)

    def step(self, T: float, sigma: float, t: float | None = None) -> float:
        """Take temperature `T` [C] and stress `sigma` [Pa] (at time `t` [s], used only in
        warnings); return the strain [-]."""
        if not self._t_lo <= T <= self._t_hi:
            T = clamp(self._warned, "temperature", T, self._t_lo, self._t_hi, "C", t)
        if sigma != self._sigma:
            self._set_stress(sigma, t)
        X = self.X
        if self.rising:
            if T < X - self._tol:
                self._record()
        elif T > X + self._tol:
            self._record()
        E = self.extrema
        if self.rising:
            if T >= X:
                X = T
                while len(E) > 2 and T >= E[-2]:  # wiping-out: a larger maximum (§preisach)
                    self._wipe_pair()
            a, b = X, E[-1]
        else:
            if T <= X:
                X = T
                while T <= E[-2]:  # wiping-out: a smaller minimum (§preisach)
                    if len(E) == 2:
                        return self._all_off()
                    self._wipe_pair()
            a, b = E[-1], X
        f = self._term(a, b)
        if not self.rising:
            f = -f
        self.X, self.X_sigma, self.X_term = X, self._sig, f
        return self.prefix[-1] + f

    def _term(self, a, b):
        """F(a, b) at the current stress, bilinear in the grid cell holding (a, b)."""
        nc = self._nc
        x = (a - self._t_lo) * self._inv_h
        i = int(x)
        if i >= nc:
            i = nc - 1
        y = (b - self._t_lo) * self._inv_h
        j = int(y)
        if j >= nc:
            j = nc - 1
        u = x - i
        v = y - j
        c0, c1, c2, c3, d0, d1, d2, d3 = self.surface.cells[self._k_base + i * nc + j]
        return c0 + c1 * u + (c2 + c3 * u) * v + self._w * (d0 + d1 * u + (d2 + d3 * u) * v)

    def peek(self, T: float, sigma: float, t: float | None = None) -> float:
        """The strain `step` would return for `T` [C], `sigma` [Pa] at `t` [s], leaving the memory
        unchanged:
        what an implicit coupling (the latent heat of ``thermal.step_coupled``) asks of the model
        while it searches the end of a step. Out-of-range warnings count as given.

        Examples
        --------
        >>> h = Hypersurface.from_function(lambda a, b, s: (a - b) ** 2 / 2e5, stresses=[1e8])
        >>> m = PreisachModel(h)
        >>> round(m.step(90.0, 1e8) * 1e5, 6), round(m.peek(50.0, 1e8) * 1e5, 6), m.extrema
        (1800.0, 1000.0, [30.0])
        """
        if sigma == self._sigma and self._t_lo <= T <= self._t_hi:
            # the running term moves and nothing is recorded or wiped out (the implicit search's
            # usual trial, a fraction of a kelvin on): `step`'s arithmetic without its bookkeeping
            X, E = self.X, self.extrema
            if self.rising:
                if T >= X - self._tol and (T < X or len(E) <= 2 or T < E[-2]):
                    return self.prefix[-1] + self._term(max(X, T), E[-1])
            elif T <= X + self._tol and (T > X or T > E[-2]):
                return self.prefix[-1] - self._term(E[-1], min(X, T))
        # else a shallow copy (floats and flags are rebound by step), its lists copied (they
        # change in place); built directly, as copy.copy's generic path costs as much as the step
        trial = object.__new__(type(self))
        trial.__dict__.update(self.__dict__)
        trial.extrema, trial.prefix, trial.stresses = self.extrema[:], self.prefix[:], self.stresses[:]
        return trial.step(T, sigma, t)

    def direct_strain(self) -> float:
        """The strain of the current state summed term by term over the stack (O(stack))."""
        return stack_strain(self.surface, self.extrema, self.stresses, self.X, self.X_sigma)

    def _record(self):
        """Push the running extremum X with its frozen term and turn round."""
        push_extremum(self, self.X_term)

    def _all_off(self):
        """Cooling reached b0: every hysteron is off, the memory is empty; strain 0."""
        self._clear_memory()
        self.X_term = 0.0
        return 0.0


def push_extremum(model: StressInput, term: float) -> None:
    """Record `model`.X (stress model.X_sigma, frozen term `term`), bound the stack, turn
    round."""
    E, P, S = model.extrema, model.prefix, model.stresses
    E.append(model.X)
    P.append(P[-1] + term)
    S.append(model.X_sigma)
    if len(E) > model.params.max_extrema:
        forget_least_pair(model.surface, E, P, S)
    model.rising = not model.rising


def forget_least_pair(surface: Hypersurface, extrema: list[float], prefix: list[float],
                      stresses: list[float]) -> None:
    """Drop the two consecutive entries of the stack (`extrema`, their `prefix` sums and
    `stresses` on `surface`) whose loss changes the strain least.

    Neither b0 nor the newest entry is dropped. Dropping entries p, p+1 joins p-1 to p+2 with
    the new term +-F(E[p+2], E[p-1]) at the stress of E[p+2]; the strain changes by the
    Preisach mass of the rectangle the two corners enclosed (at constant stress). Costs one F
    evaluation per entry; the prefix sums above p shift by that change.
    """
    E, P, S = extrema, prefix, stresses
    best = None
    for p in range(1, len(E) - 2):
        q = p + 2
        k, w = surface.stress_weights(S[q])
        term = surface.eval(E[q], E[p - 1], k, w) if q % 2 else -surface.eval(E[p - 1], E[q], k, w)
        change = P[q] - P[p - 1] - term
        if best is None or abs(change) < abs(best[1]):
            best = (p, change)
    assert best is not None  # the stack holds a pair to drop whenever this is called
    p, change = best
    del E[p:p + 2], P[p:p + 2], S[p:p + 2]
    for q in range(p, len(P)):
        P[q] -= change


def stack_strain(surface: Hypersurface, extrema: Sequence[float], stresses: Sequence[float],
                 T: float, sigma: float) -> float:
    """Strain of an extrema stack summed term by term (the O(stack) form of §preisach).

    Parameters
    ----------
    surface : Hypersurface
    extrema : sequence of float
        [m_0 = b0, M_1, m_1, ...] [C]; an odd length means the input is rising from the last
        minimum, an even length that it is falling from the last maximum.
    stresses : sequence of float
        Stress [Pa] at which each extremum was recorded (each term's stress).
    T, sigma : float
        Current input [C] and stress [Pa] (the running term).
    """
    eps = 0.0
    for p in range(1, len(extrema)):
        if p % 2:
            eps += surface.F(extrema[p], extrema[p - 1], stresses[p])
        else:
            eps -= surface.F(extrema[p - 1], extrema[p], stresses[p])
    if len(extrema) % 2:
        return eps + surface.F(T, extrema[-1], sigma)
    return eps - surface.F(extrema[-1], T, sigma)


def strain_rising(F: Callable[[float, float], float], maxima: Sequence[float],
                  minima: Sequence[float]) -> float:
    """§preisach, temperature rising (T = M_n, the last of `maxima`, with `minima` m_0..), at
    one stress (`F` (a, b) its FORC increment):

    eps = sum_{k=1}^{n-1} [F(M_k, m_{k-1}) - F(M_k, m_k)] + F(M_n, m_{n-1})

    with maxima = [M_1, ..., M_n], minima = [m_0 = b0, ..., m_{n-1}] and F(a, b) a callable.

    Examples
    --------
    >>> strain_rising(lambda a, b: (a - b) ** 2 / 2, [90.0, 70.0], [30.0, 50.0])
    1200.0
    """
    n = len(maxima)
    if len(minima) != n:
        raise ValueError(f"rising needs as many minima as maxima (m_0..m_n-1), got "
                         f"{len(minima)} and {n}")
    M: list[Any] = [None, *maxima]
    return sum(F(M[k], minima[k - 1]) - F(M[k], minima[k]) for k in range(1, n)) + \
        F(M[n], minima[n - 1])


def strain_falling(F: Callable[[float, float], float], maxima: Sequence[float],
                   minima: Sequence[float]) -> float:
    """§preisach, temperature falling (T = m_n, the last of `minima`, with `maxima` M_1..), at
    one stress (`F` (a, b) its FORC increment):

    eps = sum_{k=1}^{n} [F(M_k, m_{k-1}) - F(M_k, m_k)]

    with maxima = [M_1, ..., M_n], minima = [m_0 = b0, ..., m_n] and F(a, b) a callable.

    Examples
    --------
    >>> strain_falling(lambda a, b: (a - b) ** 2 / 2, [90.0, 70.0], [30.0, 50.0, 60.0])
    1150.0
    """
    n = len(maxima)
    if len(minima) != n + 1:
        raise ValueError(f"falling needs one more minimum than maxima (m_0..m_n), got "
                         f"{len(minima)} and {n}")
    M: list[Any] = [None, *maxima]
    return sum(F(M[k], minima[k - 1]) - F(M[k], minima[k]) for k in range(1, n + 1))


# --- the memory as a float64 array, for the compiled cores (`musclesim.fmu.compiled`) ---------
# A `PreisachModel`'s state in one array (`memory`): the header slots below, then the stack's
# extrema, prefix sums and stresses, `capacity` slots each. The stack never holds more than
# max_extrema + 1 entries (`push_extremum` forgets a pair as soon as it exceeds max_extrema), so
# capacity = max_extrema + 1 always suffices. The functions below are `PreisachModel`'s
# reset/step/peek, operation for operation, on a packed surface (`surface.pack`); they clamp
# out-of-range inputs without warning (the caller warns).
M_N, M_RISING, M_X, M_XSIG, M_XTERM, M_SIGMA, M_SIG, M_K, M_W, M_CAP, M_TOL = range(11)
M_HEAD = 11


def memory(params: MemoryParams | None = None) -> np.ndarray:
    """A new memory array of `params` (default `MemoryParams()`): header, then 3 x capacity
    slots (capacity = max_extrema + 1); call `mem_reset` before stepping it."""
    params = params or MemoryParams()
    params.check()
    cap = params.max_extrema + 1
    m = np.zeros(M_HEAD + 3 * cap)
    m[M_CAP], m[M_TOL], m[M_SIGMA] = cap, params.tol, math.nan
    return m


@jit
def mem_set_stress(s: np.ndarray, m: np.ndarray, sigma: float) -> None:
    """`StressInput._set_stress` of the memory `m` on the packed surface `s`: the
    interpolation weights of the new stress `sigma` [Pa]."""
    m[M_SIGMA] = sigma
    sigma = clip(sigma, s[S_MSLO], s[S_MSHI])
    nlev = int(s[S_NLEV])
    k = 0
    while k < nlev and s[S_HEAD + k] <= sigma:  # bisect_right
        k += 1
    k -= 1
    if k > nlev - 2:
        k = nlev - 2
    elif k < 0:
        k = 0
    m[M_SIG] = sigma
    m[M_K] = k
    m[M_W] = (sigma - s[S_HEAD + k]) * s[S_HEAD + nlev + k]


@jit
def mem_term(s: np.ndarray, m: np.ndarray, a: float, b: float) -> float:
    """F(`a`, `b`) at the memory `m`'s current stress on the packed surface `s` (`_term`)."""
    nc = int(s[S_NC])
    return cell_eval(s, int(m[M_K]) * nc * nc, a, b, m[M_W])


@jit
def mem_all_off(s: np.ndarray, m: np.ndarray) -> float:
    """Cooling reached b0: the memory `m` all off at its current stress on the packed surface
    `s`; strain 0."""
    cap = int(m[M_CAP])
    b0 = s[S_TLO]
    m[M_N] = 1.0
    m[M_HEAD] = b0
    m[M_HEAD + cap] = 0.0
    m[M_HEAD + 2 * cap] = m[M_SIG]
    m[M_RISING] = 1.0
    m[M_X] = b0
    m[M_XSIG] = m[M_SIG]
    m[M_XTERM] = 0.0
    return 0.0


@jit
def mem_forget_least_pair(s: np.ndarray, m: np.ndarray) -> None:
    """`forget_least_pair` on the stack of the memory `m`, packed surface `s`."""
    cap = int(m[M_CAP])
    n = int(m[M_N])
    e, pr, st = M_HEAD, M_HEAD + cap, M_HEAD + 2 * cap
    nc = int(s[S_NC])
    best_p = -1
    best = 0.0
    for p in range(1, n - 2):
        q = p + 2
        k, w = stress_weights_k(s, m[st + q])
        if q % 2:
            term = cell_eval(s, k * nc * nc, m[e + q], m[e + p - 1], w)
        else:
            term = -cell_eval(s, k * nc * nc, m[e + p - 1], m[e + q], w)
        change = m[pr + q] - m[pr + p - 1] - term
        if best_p < 0 or abs(change) < abs(best):
            best_p = p
            best = change
    p = best_p
    for q in range(p, n - 2):
        m[e + q] = m[e + q + 2]
        m[pr + q] = m[pr + q + 2]
        m[st + q] = m[st + q + 2]
    n -= 2
    for q in range(p, n):
        m[pr + q] -= best
    m[M_N] = n


@jit
def mem_record(s: np.ndarray, m: np.ndarray) -> None:
    """`push_extremum` on the memory `m`, packed surface `s`: record X with its frozen term
    (``m[M_XTERM]``), bound the stack, turn round."""
    cap = int(m[M_CAP])
    n = int(m[M_N])
    m[M_HEAD + n] = m[M_X]
    m[M_HEAD + cap + n] = m[M_HEAD + cap + n - 1] + m[M_XTERM]
    m[M_HEAD + 2 * cap + n] = m[M_XSIG]
    m[M_N] = n + 1
    if n + 1 > cap - 1:
        mem_forget_least_pair(s, m)
    m[M_RISING] = 0.0 if m[M_RISING] != 0.0 else 1.0


@jit
def mem_step(s: np.ndarray, m: np.ndarray, T: float, sigma: float) -> float:
    """`PreisachModel.step` of the memory `m` on the packed surface `s`: take `T` [C] and
    `sigma` [Pa] (clamped without warning), return the strain."""
    T = clip(T, s[S_TLO], s[S_THI])
    if sigma != m[M_SIGMA]:
        mem_set_stress(s, m, sigma)
    tol = m[M_TOL]
    cap = int(m[M_CAP])
    X = m[M_X]
    if m[M_RISING] != 0.0:
        if T < X - tol:
            mem_record(s, m)
    elif T > X + tol:
        mem_record(s, m)
    n = int(m[M_N])
    if m[M_RISING] != 0.0:
        if T >= X:
            X = T
            while n > 2 and T >= m[M_HEAD + n - 2]:  # wiping-out: a larger maximum
                n -= 2
            m[M_N] = n
        a, b = X, m[M_HEAD + n - 1]
    else:
        if T <= X:
            X = T
            while T <= m[M_HEAD + n - 2]:  # wiping-out: a smaller minimum
                if n == 2:
                    return mem_all_off(s, m)
                n -= 2
            m[M_N] = n
        a, b = m[M_HEAD + n - 1], X
    f = mem_term(s, m, a, b)
    if m[M_RISING] == 0.0:
        f = -f
    m[M_X] = X
    m[M_XSIG] = m[M_SIG]
    m[M_XTERM] = f
    return m[M_HEAD + cap + n - 1] + f


@jit
def mem_reset(s: np.ndarray, m: np.ndarray, T: float, sigma: float) -> float:
    """`PreisachModel.reset`: the all-off memory, then `T` [C], `sigma` [Pa]; the strain."""
    mem_set_stress(s, m, sigma)
    mem_all_off(s, m)
    return mem_step(s, m, T, sigma)


@jit
def mem_peek(s: np.ndarray, m: np.ndarray, trial: np.ndarray, T: float, sigma: float) -> float:
    """`PreisachModel.peek`: the strain `mem_step` would return, `m` unchanged (`trial`, an array
    of `m`'s size, is overwritten where the step needs a copy)."""
    if sigma == m[M_SIGMA] and s[S_TLO] <= T <= s[S_THI]:
        X = m[M_X]
        n = int(m[M_N])
        cap = int(m[M_CAP])
        if m[M_RISING] != 0.0:
            if T >= X - m[M_TOL] and (T < X or n <= 2 or T < m[M_HEAD + n - 2]):
                return m[M_HEAD + cap + n - 1] + mem_term(s, m, fmax(X, T), m[M_HEAD + n - 1])
        elif T <= X + m[M_TOL] and (T > X or T > m[M_HEAD + n - 2]):
            return m[M_HEAD + cap + n - 1] - mem_term(s, m, m[M_HEAD + n - 1], fmin(X, T))
    trial[:] = m
    return mem_step(s, trial, T, sigma)
