"""Inverse of the modified Preisach model (§preisach-inverse): strain and stress in, temperature
out."""
from __future__ import annotations

import copy
import math

import numpy as np

from .preisach import MemoryParams, StressInput, clamp, push_extremum
from .surface import Hypersurface

N_DENSE = 201  # points per axis of the densified surfaces and of the inverse bases
#                (§preisach-inverse)


class InverseBases:
    """The a- and b-inverse bases of §preisach-inverse, built once from a `Hypersurface`.

    Each constant-stress surface is densified to n x n temperatures (exactly: the dense points
    include the grid, and the surface is piecewise linear along each grid line) and inverted along
    F. The F axis is normalised per row, F = f_l * F_max with F_max = F(a0, b') for the a-inverse
    (b', F) -> a' and F_max = F(a', b0) for the b-inverse (a', F) -> b', and its n levels are spaced
    f_l = (1 - cos(pi l / (n - 1))) / 2: densest near 0 and F_max, where the branches flatten
    towards saturation and the inverse bends most (this cuts the worst constant-stress error about
    fivefold against uniform levels). Where F is flat the inverse takes the least heating (smallest
    a') or the least cooling (largest b'). Between stresses the inverse temperatures and F_max are
    interpolated linearly (§preisach-inverse), which differs from the forward model's linear
    interpolation of F by a fraction of a percent of the strain where a transition shifts with
    stress. A step costs one bilinear interpolation per stress level.

    Attributes (flat lists, level-major): ``a_table[(s * n + j) * n + l]`` = a' for
    b' = dense[j]; ``a_fmax[s * n + j]``; ``b_table[(s * n + i) * n + l]`` = b' for
    a' = dense[i]; ``b_fmax[s * n + i]``. Immutable: ``copy.deepcopy`` returns it unchanged.
    """

    def __init__(self, surface: Hypersurface, n: int = N_DENSE) -> None:
        """The inverse tables of `surface`, densified to `n` x `n` temperatures."""
        if not (isinstance(n, int) and n >= 2):
            raise ValueError(f"n must be an integer >= 2 (got {n!r})")
        self.n = n
        self.dense = np.linspace(surface.t_lo, surface.t_hi, n)
        self.t_lo, self.t_hi = surface.t_lo, surface.t_hi
        self.inv_h = (n - 1) / (surface.t_hi - surface.t_lo)
        a_tab, a_max, b_tab, b_max = [], [], [], []
        for D in _dense_levels(surface, self.dense):
            a_inv, fa, b_inv, fb = _invert(D, self.dense)
            a_tab.append(a_inv)
            a_max.append(fa)
            b_tab.append(b_inv)
            b_max.append(fb)
        self.a_table, self.a_fmax = np.ravel(a_tab).tolist(), np.ravel(a_max).tolist()
        self.b_table, self.b_fmax = np.ravel(b_tab).tolist(), np.ravel(b_max).tolist()

    def __deepcopy__(self, memo):
        return self

    def __copy__(self):
        return self


class PreisachInverse(StressInput):
    """Feed-forward inverse of `PreisachModel` (§preisach-inverse): step(eps_r, sigma_r) -> T_out.

    It keeps the forward model's memory (the same extrema stack, frozen terms and rules of
    `MemoryParams`) as if the forward model were driven by the temperatures it outputs, so that
    a `PreisachModel` with the same surface and parameters fed with T_out reproduces eps_r up
    to the interpolation error of the bases at constant stress (under time-varying stress, see
    the direction below):

    - rising strain: T_out = a-inverse(b' = last minimum, eps_r - S_heat), S_heat the prefix sum;
    - falling strain: T_out = b-inverse(a' = last maximum, S_cool - eps_r);
    - a T_out beyond an older extremum wipes it out (the pair is dropped, T_out recomputed, and
      kept at least at that extremum so that the forward model wipes it out too).

    The direction is that of the reference (§position-control: the sign of d eps_r / dt, stress
    changes ignored): the inverse turns only when eps_r moves back, and only if the branch at the
    turning point X lies across it. When the stress alone would move T_out back (eps_r still rising,
    but the ascending branch under the new stress lies above it), or forward while eps_r moves back,
    T_out holds at X and the strain follows the stress until the reference catches up. Turning there
    instead would put eps_r on the flat start of the other branch, a jump of several C within one
    sample and back at the next: an ideal plant follows it, a heated wire, whose temperature lags,
    does not, and its memory parts from the inverse's (a 0.02 s lag made SP III under LP II miss by
    5e-3 strain where holding misses by 1e-3). A reversal smaller than ``tol`` holds T_out at X too.
    T_out is thus monotone between turns of eps_r, and a forward model fed with it keeps the
    inverse's memory.

    Under time-varying stress the forward strain jumps where a wipe-out joins terms frozen at
    other stresses (§preisach's rule); a reference inside such a jump holds T_out until it is
    passed.

    Out-of-range policy: stress as `PreisachModel`; eps_r outside [0, max F(a0, b0)] is clamped
    with a one-time warning; a reference the current stress cannot reach saturates T_out at
    a0 (or b'), as the wire would. State: plain attributes (``copy.deepcopy`` saves it).

    Parameters
    ----------
    surface : Hypersurface
    params : MemoryParams, optional
        Must equal the forward model's for the memories to agree.
    bases : InverseBases, optional
        Built from `surface` when not given (share one between inverses of the same surface).
    """

    def __init__(self, surface: Hypersurface, params: MemoryParams | None = None,
                 bases: InverseBases | None = None) -> None:
        self.params = params or MemoryParams()
        self.params.check()
        self.surface = surface
        self.bases = bases or InverseBases(surface)
        self._tol = float(self.params.tol)
        self._n = self.bases.n
        self._x_scale = (self._n - 1) / math.pi
        self._t_lo, self._t_hi, self._inv_h = surface.t_lo, surface.t_hi, self.bases.inv_h
        self._eps_hi = float(surface.table[:, -1, 0].max())
        self._init_stress(surface, self._n * self._n)
        self.reset(0.0, surface.s_lo)

    def reset(self, eps_r: float, sigma: float, t: float | None = None) -> float:
        """Start from the all-off state at b0, then take `eps_r` [-], `sigma` [Pa] (at time `t`
        [s], used only in warnings); return T_out [C]."""
        self.clear(sigma, t)
        return self.step(eps_r, sigma, t)

    def clear(self, sigma: float, t: float | None = None) -> None:
        """The all-off memory at b0 under stress `sigma` [Pa] (at time `t` [s]), before any
        reference: `reset`
        without its first step (clear, then step the first sample, is reset bit for bit)."""
        self._set_stress(sigma, t)
        self._all_off()
        self._eps = 0.0  # the reference the all-off memory produces

    def peek(self, eps_r: float, sigma: float, t: float | None = None) -> float:
        """The T_out [C] `step` would return for `eps_r` [-], `sigma` [Pa] at `t` [s], leaving the
        memory unchanged: what an output at a communication point needs before the sample is
        committed (the FMU's direct feedthrough). Out-of-range warnings count as given.

        Examples
        --------
        >>> from musclesim.components.sma.analytic import sma_like_surface
        >>> inv = PreisachInverse(sma_like_surface())
        >>> T = inv.step(0.02, 125e6)
        >>> inv.peek(0.01, 125e6) < T, inv.extrema
        (True, [30.0])
        """
        trial = copy.copy(self)  # floats and flags are rebound by step, the lists change in place
        trial.extrema, trial.prefix, trial.stresses = self.extrema[:], self.prefix[:], self.stresses[:]
        return trial.step(eps_r, sigma, t)

    def step(self, eps_r: float, sigma: float, t: float | None = None) -> float:
        """Take the reference strain `eps_r` [-] and stress `sigma` [Pa] (at time `t` [s], used
        only in warnings); return the temperature T_out [C] that makes the forward model produce
        eps_r."""
        if not 0.0 <= eps_r <= self._eps_hi:
            eps_r = clamp(self._warned, "reference strain", eps_r, 0.0, self._eps_hi, "", t)
        if sigma != self._sigma:
            self._set_stress(sigma, t)
        X, last = self.X, self._eps
        self._eps = eps_r
        if self.rising:
            T = self._reverse(eps_r) if eps_r < last else max(self._rise(eps_r), X)
        else:
            T = self._reverse(eps_r) if eps_r > last else min(self._fall(eps_r), X)
        self.X, self.X_sigma = T, self._sig
        return T

    def _rise(self, eps_r):
        """T on the ascending branch from the last minimum, wiping out smaller maxima."""
        E, P = self.extrema, self.prefix
        T = self._heat(E[-1], eps_r - P[-1])
        while len(E) > 2 and T >= E[-2]:
            top = E[-2]
            self._wipe_pair()
            T = max(self._heat(E[-1], eps_r - P[-1]), top)
        return T

    def _fall(self, eps_r):
        """T on the descending branch from the last maximum, wiping out larger minima."""
        E, P = self.extrema, self.prefix
        T = self._cool(E[-1], P[-1] - eps_r)
        while T <= E[-2]:
            if len(E) == 2:
                return self._all_off()
            bottom = E[-2]
            self._wipe_pair()
            T = min(self._cool(E[-1], P[-1] - eps_r), bottom)
        return T

    def _reverse(self, eps_r):
        """eps_r moved back: turn at X, unless the branch at X does not lie across eps_r or the
        turn is within tol (then hold at X)."""
        X, last = self.X, self.extrema[-1]
        k, w = self.surface.stress_weights(self.X_sigma)
        if self.rising:
            term = self.surface.eval(X, last, k, w)
            if self._cool(X, self.prefix[-1] + term - eps_r) >= X - self._tol:
                return X
        else:
            term = -self.surface.eval(last, X, k, w)
            if self._heat(X, eps_r - self.prefix[-1] - term) <= X + self._tol:
                return X
        self._record(term)
        # a bounded stack may have shifted the prefix sum: still pass the band, or the forward
        # model would not record this reversal
        if self.rising:
            return max(self._rise(eps_r), math.nextafter(X + self._tol, math.inf))
        return min(self._fall(eps_r), math.nextafter(X - self._tol, -math.inf))

    def _heat(self, bp, target):
        """a-inverse basis: the peak a' >= bp whose FORC from bp has increment `target`."""
        return self._invert(self.bases.a_fmax, self.bases.a_table, bp, target, self._t_hi, True)

    def _cool(self, ap, target):
        """b-inverse basis: the end b' <= ap of the FORC from peak ap with increment `target`."""
        return self._invert(self.bases.b_fmax, self.bases.b_table, ap, target, self._t_lo, False)

    def _invert(self, fmax_table, table, x0, target, limit, above):
        """Look up a basis: the temperature on the FORC through x0 with increment `target`,
        above x0 (a-basis) or below it (b-basis); `limit` when the increment is out of reach."""
        n, w = self._n, self._w
        y = (x0 - self._t_lo) * self._inv_h
        j = int(y)
        if j >= n - 1:
            j = n - 2
        v = y - j
        q = self._k * n + j
        f0 = fmax_table[q] + v * (fmax_table[q + 1] - fmax_table[q])
        f1 = fmax_table[q + n] + v * (fmax_table[q + n + 1] - fmax_table[q + n])
        fmax = f0 + w * (f1 - f0)
        if target <= 0.0 or fmax <= 0.0:
            return x0
        if target >= fmax:
            return limit
        x = math.acos(1.0 - 2.0 * target / fmax) * self._x_scale
        T = _bilinear(table, self._k_base + j * n, n, x, v, w)
        return T if (T > x0) == above else x0

    def _record(self, term):
        """Push X with the term the forward model froze there, then turn round."""
        push_extremum(self, term)

    def _all_off(self):
        """Cooling reached b0: every hysteron is off, the memory is empty; T_out = b0."""
        self._clear_memory()
        return self._t_lo


def _bilinear(tab, row, n, x, v, w):
    """Interpolate table rows `row` and `row + n` at fractional column x, weight v between
    them, at this stress level and the next (n * n further on), weight w."""
    l = int(x)
    h = x - l
    q = row + l
    a = tab[q] + h * (tab[q + 1] - tab[q])
    b = tab[q + n] + h * (tab[q + n + 1] - tab[q + n])
    lower = a + v * (b - a)
    q += n * n
    a = tab[q] + h * (tab[q + 1] - tab[q])
    b = tab[q + n] + h * (tab[q + n + 1] - tab[q + n])
    return lower + w * (a + v * (b - a) - lower)


def _dense_levels(surface, dense):
    """D[i, j] = F(dense[i], dense[j]) at each stress level (twice for a single level); 0 for
    i < j."""
    nc = surface.n_cells
    cells = np.array(surface.cells).reshape(-1, nc, nc, 8)
    coeff = [c[..., :4] for c in cells] + [cells[-1][..., :4] + cells[-1][..., 4:]]
    x = (dense - surface.t_lo) * surface.inv_h
    idx = np.minimum(x.astype(int), nc - 1)
    frac = x - idx
    A, B = np.meshgrid(np.arange(len(dense)), np.arange(len(dense)), indexing="ij")
    u, v = frac[A], frac[B]
    levels = []
    for c in coeff:
        cc = c[idx[A], idx[B]]
        D = cc[..., 0] + cc[..., 1] * u + (cc[..., 2] + cc[..., 3] * u) * v
        levels.append(np.tril(D))
    return levels


def _invert(D, dense):
    """Invert one dense level along F: (a-table, a F_max, b-table, b F_max), tables [row, l]."""
    n = len(dense)
    levels = (1.0 - np.cos(np.linspace(0.0, math.pi, n))) / 2
    a_inv, b_inv = np.empty((n, n)), np.empty((n, n))
    fa, fb = D[-1, :].copy(), D[:, 0].copy()
    for j in range(n):
        a_inv[j] = np.maximum(_first_crossing(dense[j:], D[j:, j], levels * fa[j]), dense[j])
        b_inv[j] = np.minimum(_first_crossing(dense[j::-1], D[j, j::-1], levels * fb[j]),
                              dense[j])
    return a_inv, fa, b_inv, fb


def _first_crossing(x, y, targets):
    """For y non-decreasing along x: the first x where y reaches each target (linear between
    samples; the least movement where y is flat; the ends beyond its range)."""
    y = np.maximum.accumulate(y)
    if len(x) == 1:
        return np.full(len(targets), x[0])
    i = np.clip(np.searchsorted(y, targets, side="left"), 1, len(x) - 1)
    y0, y1 = y[i - 1], y[i]
    frac = np.where(y1 > y0, (targets - y0) / np.where(y1 > y0, y1 - y0, 1.0), 1.0)
    found = x[i - 1] + np.clip(frac, 0.0, 1.0) * (x[i] - x[i - 1])
    return np.where(targets <= y[0], x[0], found)
