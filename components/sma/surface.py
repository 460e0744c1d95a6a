"""The Preisach hypersurface of §preisach: FORC increments F(a, b; stress) on a grid."""
from __future__ import annotations

import bisect
import math
import sys
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from musclesim.fmu import jit

from . import forcfile

GRID_TEMPS = tuple(30.0 + 5.0 * i for i in range(21))  # C, the Preisach triangle grid (§preisach)
STRESSES = (105e6, 115e6, 125e6, 135e6, 145e6)  # Pa, the identified constant stresses (§preisach)
_ATOL = 1e-12  # strain; round-off allowed in the monotonicity and zero-diagonal checks


class RangeWarning(UserWarning):
    """An input outside the identified range was clamped to it (make it an error with
    ``warnings.simplefilter("error", RangeWarning)``)."""


class Hypersurface:
    """FORC-increment surfaces F(a, b; stress) at several constant stresses (§preisach).

    Inside a grid cell of the Preisach triangle F is bilinear in (a, b); a cell on the diagonal is
    half a square, and its missing corner (a = t_i, b = t_i+1) is taken as -F(t_i+1, t_i), which
    makes F vanish on the diagonal and the half cell linear. Between stress levels F is linear in
    stress; a single level means stress is ignored.

    Out-of-range policy: a temperature outside [temps[0], temps[-1]] or a stress outside
    [stresses[0], stresses[-1]] is clamped to the grid and a `RangeWarning` naming the variable,
    the value, the range and (when the caller gives it) the time is issued once per variable and
    object; NaN raises ValueError. The object is immutable apart from those warning flags, so
    copies share it (``copy.deepcopy`` returns it unchanged).

    Parameters
    ----------
    temps : sequence of float
        Uniform, increasing temperature grid [C] (§preisach: 30..130 C at 5 C).
    stresses : sequence of float
        Increasing stresses [Pa] of the surfaces.
    F : array_like, shape (len(stresses), len(temps), len(temps))
        F[s, i, j] = F(a=temps[i], b=temps[j]; stresses[s]) for i >= j; entries above the
        diagonal are ignored.

    Raises
    ------
    ValueError
        Bad grid, wrong shape, or an entry that is not finite, negative, off zero on the diagonal,
        decreasing in a or increasing in b; the message names the entry.

    Examples
    --------
    >>> h = Hypersurface.from_function(lambda a, b, s: (a - b) * s / 1e9, [30, 80, 130], [1e8])
    >>> round(h.F(130.0, 30.0, 1e8), 12), round(h.F(105.0, 55.0, 1e8), 12)
    (10.0, 5.0)
    """

    def __init__(self, temps: ArrayLike, stresses: ArrayLike, F: ArrayLike) -> None:
        # `temps`, `stresses` and `F` (see the class's Parameters) made read-only arrays here
        temps = np.array(temps, dtype=float)
        stresses = np.array(stresses, dtype=float)
        table = np.array(F, dtype=float)
        _check_grid(temps, stresses, table.shape)
        _check_table(temps, stresses, table)
        table = np.tril(table, -1)  # the diagonal is 0 up to round-off, above it is ignored
        for arr in (temps, stresses, table):
            arr.flags.writeable = False
        self.temps, self.stresses, self.table = temps, stresses, table
        self.t_lo, self.t_hi = float(temps[0]), float(temps[-1])
        self.s_lo, self.s_hi = float(stresses[0]), float(stresses[-1])
        self.n_cells = len(temps) - 1
        self.inv_h = self.n_cells / (self.t_hi - self.t_lo)
        self.cells = _cell_coefficients(table)
        self._levels = [float(s) for s in stresses]
        self._warned: set[str] = set()

    @classmethod
    def from_function(cls, f: Callable[[float, float, float], float],
                      temps: Sequence[float] = GRID_TEMPS,
                      stresses: Sequence[float] = STRESSES) -> Hypersurface:
        """Tabulate `f` (a, b, sigma) [strain] on the grid `temps` [C] x `stresses` [Pa]
        (defaults: §preisach) and validate it."""
        temps = [float(t) for t in temps]
        table = np.zeros((len(stresses), len(temps), len(temps)))
        for s, sigma in enumerate(stresses):
            for i, a in enumerate(temps):
                for j in range(i + 1):
                    table[s, i, j] = f(a, temps[j], float(sigma))
        return cls(temps, stresses, table)

    @classmethod
    def load(cls, path: str | Path) -> Hypersurface:
        """Read the FORC data file `path` (format: `musclesim.components.sma.forcfile`).

        Raises ValueError naming the file and the line of a malformed or non-monotonic entry.
        """
        temps, stresses, table, lines = forcfile.read(path)
        try:
            return cls(temps, stresses, table)
        except forcfile.TableError as exc:
            where = " and ".join(str(lines[k]) for k in exc.entries)
            plural = "s" if len(exc.entries) > 1 else ""
            raise ValueError(f"{path} line{plural} {where}: {exc}") from None
        except ValueError as exc:
            raise ValueError(f"{path}: {exc}") from None

    def save(self, path: str | Path) -> None:
        """Write the surface as the FORC data file `path` (format:
        `musclesim.components.sma.forcfile`)."""
        forcfile.write(path, self.temps, self.stresses, self.table)

    def at_stress(self, sigma: float) -> Hypersurface:
        """The single constant-stress surface at `sigma` [Pa]: a model on it ignores stress (the
        comparison case of §position-control)."""
        k, w = self.stress_weights(self.clamp_stress(sigma))
        upper = min(k + 1, len(self.stresses) - 1)
        G = (1 - w) * self.table[k] + w * self.table[upper]
        return Hypersurface(self.temps, [float(sigma)], G[None])

    def F(self, a: float, b: float, sigma: float, t: float | None = None) -> float:
        """FORC increment F(`a`, `b`; `sigma`) [strain]; 0 for a <= b; out-of-range inputs
        clamped.

        `t` [s], if given, only dates the out-of-range warning.
        """
        a = self.clamp_temperature(a, t)
        b = self.clamp_temperature(b, t)
        if a <= b:
            return 0.0
        k, w = self.stress_weights(self.clamp_stress(sigma, t))
        return self.eval(a, b, k, w)

    def eval(self, a: float, b: float, k: int, w: float) -> float:
        """F at in-range `a` >= `b` [C], stress interval `k`, weight `w` (see `stress_weights`);
        no checks."""
        nc = self.n_cells
        x = (a - self.t_lo) * self.inv_h
        y = (b - self.t_lo) * self.inv_h
        i, j = min(int(x), nc - 1), min(int(y), nc - 1)
        u, v = x - i, y - j
        c0, c1, c2, c3, d0, d1, d2, d3 = self.cells[(k * nc + i) * nc + j]
        return c0 + c1 * u + (c2 + c3 * u) * v + w * (d0 + d1 * u + (d2 + d3 * u) * v)

    def stress_weights(self, sigma: float) -> tuple[int, float]:
        """(k, w): in-range `sigma` [Pa] lies between levels k and k+1 with weight w on level
        k+1."""
        levels = self._levels
        if len(levels) == 1:
            return 0, 0.0
        k = min(max(bisect.bisect_right(levels, sigma) - 1, 0), len(levels) - 2)
        return k, (sigma - levels[k]) / (levels[k + 1] - levels[k])

    def clamp_temperature(self, T: float, t: float | None = None) -> float:
        """`T` [C] clamped to the grid, with the one-time warning of the out-of-range policy
        (dated `t` [s])."""
        return self._clamp("temperature", T, self.t_lo, self.t_hi, "C", t)

    def clamp_stress(self, sigma: float, t: float | None = None) -> float:
        """`sigma` [Pa] clamped to the stress levels (any value when there is one level), its
        warning dated `t` [s]."""
        if len(self._levels) == 1:
            return self._clamp("stress", sigma, -math.inf, math.inf, "Pa", t)
        return self._clamp("stress", sigma, self.s_lo, self.s_hi, "Pa", t)

    def _clamp(self, name, value, lo, hi, unit, t):
        return clamp(self._warned, name, value, lo, hi, unit, t)

    def __deepcopy__(self, memo):
        return self

    def __copy__(self):
        return self


def clamp(warned: set[str], name: str, value: float, lo: float, hi: float, unit: str,
          t: float | None = None) -> float:
    """Clamp `value` to [`lo`, `hi`] (in `unit`), warning once per `name` (recorded in the set
    `warned`).

    Raises ValueError for NaN. `t` [s], if given, dates the warning.

    Examples
    --------
    >>> clamp(set(), "temperature", 120.0, 30.0, 130.0, "C")
    120.0
    """
    value = float(value)
    if lo <= value <= hi:
        return value
    when = "" if t is None else f" at t = {t:g} s"
    if math.isnan(value):
        raise ValueError(f"{name} is NaN{when}")
    clamped = min(max(value, lo), hi)
    if name not in warned:
        warned.add(name)
        unit = f" {unit}" if unit else ""
        warnings.warn(f"{name} {value:g}{unit}{when} is outside the identified range "
                      f"[{lo:g}, {hi:g}]{unit}; clamped to {clamped:g}{unit} "
                      "(warned once)", RangeWarning, stacklevel=4)
    return clamped


def _check_grid(temps, stresses, shape):
    """Raise ValueError for a bad temperature grid, stress list or table shape."""
    if temps.ndim != 1 or len(temps) < 2 or not np.all(np.isfinite(temps)):
        raise ValueError("temps must be at least two finite temperatures [C]")
    steps = np.diff(temps)
    if not np.all(steps > 0) or np.ptp(steps) > 1e-9 * steps[0] * len(temps):
        raise ValueError(f"temps must be uniform and increasing (got {temps.tolist()})")
    if stresses.ndim != 1 or len(stresses) < 1 or not np.all(np.isfinite(stresses)):
        raise ValueError("stresses must be at least one finite stress [Pa]")
    if not np.all(np.diff(stresses) > 0):
        raise ValueError(f"stresses must be increasing (got {stresses.tolist()})")
    expected = (len(stresses), len(temps), len(temps))
    if shape != expected:
        raise ValueError(f"F must have shape {expected} (stresses, a, b), got {shape}")


def _table_is_valid(F):
    """True when no lower-triangle entry breaks a rule of `_check_table` (vectorised: a dense
    1 C table has ~10^5 entries per stress; `_check_table` then finds and names the first)."""
    n = F.shape[1]
    lower = np.tril(np.ones((n, n), dtype=bool))
    values = F[:, lower]
    if not (np.all(np.isfinite(values)) and np.all(values >= -_ATOL)
            and np.all(np.abs(F[:, np.arange(n), np.arange(n)]) <= _ATOL)):
        return False
    # the neighbour rules of _check_table, each where both entries lie in the lower triangle
    falls_in_a = (F[:, 1:, :] < F[:, :-1, :] - _ATOL)[:, np.tril(np.ones((n - 1, n), dtype=bool))]
    rises_in_b = (F[:, :, :-1] < F[:, :, 1:] - _ATOL)[:, np.tril(np.ones((n, n - 1), dtype=bool), -1)]
    return not (np.any(falls_in_a) or np.any(rises_in_b))


def _check_table(temps, stresses, F):
    """Raise TableError at the first entry (lower triangle) a FORC surface cannot have: first
    values (finite, zero diagonal, non-negative), then monotonicity between neighbours."""
    if _table_is_valid(F):
        return
    n = len(temps)
    lower = [(s, i, j) for s in range(len(stresses)) for i in range(n) for j in range(i + 1)]

    def name(s, i, j):
        return (f"F(a = {temps[i]:g} C, b = {temps[j]:g} C; stress {stresses[s]:g} Pa) "
                f"= {float(F[s, i, j])!r}")
    for s, i, j in lower:
        v = F[s, i, j]
        problem = ("is not finite" if not math.isfinite(v) else
                   "is not 0 (F vanishes on the diagonal a = b)" if i == j and abs(v) > _ATOL else
                   "is negative" if v < -_ATOL else "")
        if problem:
            raise forcfile.TableError(f"{name(s, i, j)} {problem}", [(s, i, j)])
    for s, i, j in lower:
        for other, rule in (((s, i - 1, j), "must not decrease in a"),
                            ((s, i, j + 1), "must not increase in b")):
            if other[1] >= other[2] and F[s, i, j] < F[other] - _ATOL:
                raise forcfile.TableError(f"F {rule}: {name(s, i, j)} is below "
                                          f"{name(*other)}", [other, (s, i, j)])


def _cell_coefficients(table):
    """Per stress interval and cell (i, j): F = c0 + c1 u + c2 v + c3 u v + w (d0 + ... + d3 u v).

    u, v are the cell's fractional a and b, w the weight of the upper stress level. Cells above
    the diagonal are zero; diagonal cells use the ghost corner -F(t_i+1, t_i).
    """
    S, n, _ = table.shape
    G = np.tril(table, -1)
    diag = np.arange(n - 1)
    G[:, diag, diag + 1] = -table[:, diag + 1, diag]
    f00, f10, f01, f11 = G[:, :-1, :-1], G[:, 1:, :-1], G[:, :-1, 1:], G[:, 1:, 1:]
    c = np.stack([f00, f10 - f00, f01 - f00, f11 - f10 - f01 + f00], axis=-1)
    c[:, np.triu_indices(n - 1, 1)[0], np.triu_indices(n - 1, 1)[1]] = 0.0
    levels = [c[0], c[0]] if S == 1 else list(c)
    cells: list[tuple[float, ...]] = []
    for k in range(len(levels) - 1):
        coeff = np.concatenate([levels[k], levels[k + 1] - levels[k]], axis=-1)
        cells.extend(map(tuple, coeff.reshape(-1, 8).tolist()))
    return cells


# --- the surface as one float64 array, for the compiled cores (`musclesim.fmu.compiled`) -------
# header slots of `pack`'s array; the stress levels, their inverse spacings and the cells follow
S_TLO, S_THI, S_INVH, S_NC, S_NS, S_SLO, S_SHI, S_MSLO, S_MSHI, S_NLEV = range(10)
S_HEAD = 10  # the levels start here


def stress_grid(surface: Hypersurface) -> tuple[float, float, list[float], list[float], int]:
    """(lo, hi, levels, 1 / level spacings, last interval) of `surface` for inline stress
    interpolation.

    A single level ignores stress: its range is every finite value and its weight is 0.
    """
    levels = [float(s) for s in surface.stresses]
    if len(levels) == 1:
        return -sys.float_info.max, sys.float_info.max, levels * 2, [0.0], 0
    inv = [1.0 / (hi - lo) for lo, hi in zip(levels, levels[1:])]
    return levels[0], levels[-1], levels, inv, len(levels) - 2


def pack(surface: Hypersurface) -> np.ndarray:
    """`surface` as one float64 array for the compiled cores: the header [t_lo, t_hi, inv_h,
    n_cells, number of stresses, s_lo, s_hi, the memory's stress range lo and hi (every finite
    value for a single level: `stress_grid`), nlev], then the nlev stress levels of
    the memory's interpolation (a single level twice), their nlev - 1 inverse spacings, then the
    cells' 8 coefficients each (`_cell_coefficients`, in `Hypersurface.cells`' order)."""
    m_lo, m_hi, levels, inv, _ = stress_grid(surface)
    head = [surface.t_lo, surface.t_hi, surface.inv_h, float(surface.n_cells),
            float(len(surface.stresses)), surface.s_lo, surface.s_hi, m_lo, m_hi,
            float(len(levels))]
    cells = np.array(surface.cells, dtype=float).ravel()
    return np.concatenate([np.array(head + levels + inv, dtype=float), cells])


def packed(surface: Hypersurface) -> np.ndarray:
    """`pack` (`surface`), kept on the (immutable) surface: packed once per process, read-only."""
    arr: np.ndarray | None = surface.__dict__.get("_packed")
    if arr is None:
        arr = pack(surface)
        arr.flags.writeable = False
        surface._packed = arr  # type: ignore[attr-defined]
    return arr


@jit
def fmin(a: float, b: float) -> float:
    """Python's ``min(a, b)``: `a` unless `b` is smaller."""
    return b if b < a else a


@jit
def fmax(a: float, b: float) -> float:
    """Python's ``max(a, b)``: `a` unless `b` is larger."""
    return b if b > a else a


@jit
def clip(value: float, lo: float, hi: float) -> float:
    """`clamp`'s arithmetic without its warning: `value` in [`lo`, `hi`] as is, else
    ``min(max(value, lo), hi)``."""
    if lo <= value <= hi:
        return value
    return fmin(fmax(value, lo), hi)


@jit
def stress_in_range(s: np.ndarray, sigma: float, log: np.ndarray, at: int, t: float) -> float:
    """The stress `sigma` [Pa] clamped to the stresses of the packed surface `s` (where it has
    more than one level); the first clamp is kept in `log` at `at`, `at` + 1, `at` + 2 (1, the
    stress, the time `t` [s]) for the slave to warn of."""
    if s[S_NS] > 1 and not s[S_SLO] <= sigma <= s[S_SHI]:
        if log[at] == 0.0:
            log[at], log[at + 1], log[at + 2] = 1.0, sigma, t
        sigma = fmin(fmax(sigma, s[S_SLO]), s[S_SHI])
    return sigma


@jit
def cell_eval(s: np.ndarray, kbase: int, a: float, b: float, w: float) -> float:
    """F at in-range `a`, `b` [C] of the packed surface `s` (`pack`): bilinear in the cell, cells
    from `kbase` (stress interval k times n_cells^2), weight `w` on the upper level; no checks
    (`Hypersurface.eval`)."""
    nc = int(s[S_NC])
    t_lo = s[S_TLO]
    inv_h = s[S_INVH]
    x = (a - t_lo) * inv_h
    i = int(x)
    if i >= nc:
        i = nc - 1
    y = (b - t_lo) * inv_h
    j = int(y)
    if j >= nc:
        j = nc - 1
    u = x - i
    v = y - j
    nlev = int(s[S_NLEV])
    o = S_HEAD + 2 * nlev - 1 + 8 * (kbase + i * nc + j)
    c0, c1, c2, c3 = s[o], s[o + 1], s[o + 2], s[o + 3]
    d0, d1, d2, d3 = s[o + 4], s[o + 5], s[o + 6], s[o + 7]
    return c0 + c1 * u + (c2 + c3 * u) * v + w * (d0 + d1 * u + (d2 + d3 * u) * v)


@jit
def surface_F(s: np.ndarray, a: float, b: float, sigma: float) -> float:
    """`Hypersurface.F` (`a`, `b`; `sigma`) of the packed surface `s` without its warnings:
    inputs clamped to the grid, 0 for a <= b, stress weights by division as `stress_weights`."""
    a = clip(a, s[S_TLO], s[S_THI])
    b = clip(b, s[S_TLO], s[S_THI])
    if a <= b:
        return 0.0
    if s[S_NS] > 1:
        sigma = clip(sigma, s[S_SLO], s[S_SHI])
    k, w = stress_weights_k(s, sigma)
    nc = int(s[S_NC])
    return cell_eval(s, k * nc * nc, a, b, w)


@jit
def stress_weights_k(s: np.ndarray, sigma: float) -> tuple[int, float]:
    """`Hypersurface.stress_weights` of the packed surface `s`: (k, w) of in-range `sigma`."""
    ns = int(s[S_NS])
    if ns == 1:
        return 0, 0.0
    k = -1
    while k + 1 < ns and s[S_HEAD + k + 1] <= sigma:  # bisect_right - 1
        k += 1
    k = min(max(k, 0), ns - 2)
    return k, (sigma - s[S_HEAD + k]) / (s[S_HEAD + k + 1] - s[S_HEAD + k])
