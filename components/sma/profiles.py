"""Reference strain profiles SP I-IV and loading profiles LP I-VI of §reference-profiles: signal
generators.

A profile is packed once into a float64 array (`pack`: its shape, range and constants, the random
peaks' knots drawn in Python) and evaluated by the `jit` function `value_core`, written once: a
`Profile` called on times and the StrainProfile and LoadingProfile FMUs' kernels both call it.
"""
from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from musclesim.fmu.compiled import jit

EPS_MAX = 0.0376  # strain, top of the reference strain profiles (§reference-profiles)
SIGMA_LO, SIGMA_HI = 105e6, 145e6  # Pa, range of the loading profiles (§reference-profiles)
DURATION = 550.0  # s, length of a run (§position-control)
F_FAST, F_SLOW = 1 / 17, 1 / 47  # Hz, the sinusoids of SP I, LP I and LP II (§reference-profiles)
STRAIN_PROFILES = ("SP I", "SP II", "SP III", "SP IV")
LOADING_PROFILES = ("LP I", "LP II", "LP III", "LP IV", "LP V", "LP VI")
# the shapes `value_core` knows (the random profiles are PEAKS)
SHAPES = {"SP I": 0.0, "SP II": 1.0, "SP III": 2.0, "LP I": 3.0, "LP II": 4.0, "LP III": 5.0,
          "LP IV": 6.0}
PEAKS = 7.0
# layout of a packed profile (`pack`): these, then the n knots' times, then their levels
SHAPE, LO, HI, DURATION_, MID, HALF, W, N = range(8)


@jit
def peaks_core(p: np.ndarray, o: int, n: int, t: float) -> float:
    """The random peaks' signal at `t` [s]: half cosines between the `n` knots whose times are
    ``p[o:o + n]`` (increasing) and levels ``p[o + n:o + 2 n]`` (`random_peaks`)."""
    lo, hi = 0, n  # the knots at or before t (numpy's searchsorted, side "right")
    while lo < hi:
        mid = (lo + hi) // 2
        if p[o + mid] <= t:
            lo = mid + 1
        else:
            hi = mid
    i = lo - 1
    if i < 0:
        i = 0
    if i > n - 2:
        i = n - 2
    s = clip_core((t - p[o + i]) / (p[o + i + 1] - p[o + i]), 0.0, 1.0)
    a, b = p[o + n + i], p[o + n + i + 1]
    return a + (b - a) * (1 - math.cos(math.pi * s)) / 2


@jit
def clip_core(v: float, lo: float, hi: float) -> float:
    """numpy's clip of `v` to [`lo`, `hi`] (NaN kept; at a bound, the bound)."""
    if math.isnan(v):
        return v
    v = v if v > lo else lo
    return v if v < hi else hi


@jit
def value_core(p: np.ndarray, o: int, t: float) -> float:
    """The value at `t` [s] of the profile packed in `p` from `o` (`pack`), within its range."""
    shape, lo, hi, duration = p[o + SHAPE], p[o + LO], p[o + HI], p[o + DURATION_]
    mid, half, w = p[o + MID], p[o + HALF], p[o + W]
    if shape == 0.0:  # SP I
        v = mid - half * math.cos(w * t)
    elif shape == 1.0:  # SP II
        v = mid - half * math.exp(-4 * t / duration) * math.cos(w * t)
    elif shape == 2.0:  # SP III
        r = t / duration
        v = mid - half * (r if r <= 1.0 or math.isnan(r) else 1.0) * math.cos(w * t)
    elif shape == 3.0 or shape == 4.0:  # LP I, LP II
        v = mid + half * math.sin(w * t)
    elif shape == 5.0:  # LP III
        v = lo + (hi - lo) * clip_core(t / duration, 0.0, 1.0)
    elif shape == 6.0:  # LP IV
        v = hi - (hi - lo) * clip_core(t / duration, 0.0, 1.0)
    else:
        v = peaks_core(p, o + N + 1, int(p[o + N]), t)
    return clip_core(v, lo, hi)


@jit
def values_core(p: np.ndarray, ts: np.ndarray, out: np.ndarray) -> None:
    """`out` = the profile packed in `p` at each time of `ts` (1-d)."""
    for k in range(ts.shape[0]):
        out[k] = value_core(p, 0, ts[k])


@jit
def peaks_values_core(p: np.ndarray, ts: np.ndarray, out: np.ndarray) -> None:
    """`out` = the random peaks packed in `p` (n, the times, the levels) at each time of `ts`."""
    n = int(p[0])
    for k in range(ts.shape[0]):
        out[k] = peaks_core(p, 1, n, ts[k])


def _on_times(core: Callable[..., None], p: np.ndarray, t: np.ndarray) -> np.ndarray:
    """`core` (`values_core` or `peaks_values_core`) of `p` on the times `t`, in their shape."""
    flat = np.ascontiguousarray(t, dtype=float).reshape(-1)
    out = np.empty_like(flat)
    core(p, flat, out)
    return out.reshape(np.shape(t))


def pack(name: str, lo: float, hi: float, duration: float, seed: int) -> np.ndarray:
    """Profile `name` (SP I-IV, LP I-VI) as `value_core` reads it: [shape (`SHAPES`, or `PEAKS`),
    lo, hi, duration, mid, half, angular frequency, n], then the n knots' times and levels of a
    random profile (n = 0 for the others)."""
    if name not in SHAPES and name not in ("SP IV", "LP V", "LP VI"):
        raise ValueError(f"unknown profile {name!r}")
    mid, half = (lo + hi) / 2, (hi - lo) / 2
    w = 2 * math.pi * (F_SLOW if name == "LP II" else F_FAST)
    head = [SHAPES.get(name, PEAKS), lo, hi, duration, mid, half, w]
    if name in SHAPES:
        return np.array([*head, 0.0])
    start = None if name == "SP IV" else mid
    times, levels = peak_knots(lo, hi, duration, seed + (name == "LP VI"), start)
    return np.concatenate((head, [len(times)], times, levels))


class Profile:
    """A signal of time: ``p(t)`` takes a float or an array of times [s], values in [lo, hi].

    Attributes: ``name``, ``lo``, ``hi``, ``duration`` [s]. ``made``: the call that made it,
    ``(function, arguments)``, which copying and pickling repeat (an FMU's saved state holds it).
    ``kp``: the profile packed for `value_core` (`pack`), or None.
    """

    def __init__(self, name: str, fn: Callable[[np.ndarray], np.ndarray], lo: float, hi: float,
                 duration: float, made: tuple[Callable[..., Profile], tuple] | None = None,
                 kp: np.ndarray | None = None) -> None:
        """Profile `name`: values `fn` of time in [`lo`, `hi`] over `duration` [s], `made` by that
        call; `kp`: the profile packed for `value_core` (None: not packed)."""
        self.name, self.lo, self.hi, self.duration = name, lo, hi, duration
        self._fn, self.made, self.kp = fn, made, kp

    def __reduce_ex__(self, protocol):
        return self.made if self.made is not None else super().__reduce_ex__(protocol)

    def __call__(self, t):
        value = np.clip(self._fn(np.asarray(t, dtype=float)), self.lo, self.hi)
        return float(value) if np.ndim(value) == 0 else value

    def __repr__(self):
        return f"Profile({self.name!r}, [{self.lo:g}, {self.hi:g}], {self.duration:g} s)"


def strain_profile(name: str, lo: float = 0.0, hi: float = EPS_MAX, duration: float = DURATION,
                   seed: int = 0) -> Profile:
    """Reference strain profile `name` (SP I-IV of §reference-profiles) within [`lo`, `hi`].

    SP I: sinusoid at 1/17 Hz over the whole range, starting at lo. SP II: sinusoid at 1/17 Hz
    about the middle, its amplitude decaying from the full range with time constant duration / 4
    (nested minor loops). SP III: sinusoid at 1/17 Hz about the middle, its amplitude growing
    linearly to the full range at `duration` (each peak wipes out the last). SP IV: random peaks
    and troughs (generator seeded with `seed`), see `random_peaks`.

    Examples
    --------
    >>> sp = strain_profile("SP I")
    >>> sp(0.0), round(sp(8.5), 4)
    (0.0, 0.0376)
    """
    return _made(name, STRAIN_PROFILES, lo, hi, duration, seed, strain_profile)


def loading_profile(name: str, lo: float = SIGMA_LO, hi: float = SIGMA_HI,
                    duration: float = DURATION, seed: int = 0) -> Profile:
    """Loading (stress) profile `name` (LP I-VI of §reference-profiles) within [`lo`, `hi`]
    [Pa].

    LP I and LP II: sinusoids at 1/17 Hz and 1/47 Hz over the range, starting at the middle.
    LP III: linear increase lo -> hi over `duration`; LP IV: linear decrease hi -> lo (held after).
    LP V and LP VI: random peaks and troughs, seeded with `seed` and `seed + 1`.

    Examples
    --------
    >>> lp = loading_profile("LP III")
    >>> lp(0.0), lp(275.0), lp(600.0)
    (105000000.0, 125000000.0, 145000000.0)
    """
    return _made(name, LOADING_PROFILES, lo, hi, duration, seed, loading_profile)


def _made(name: str, names: tuple[str, ...], lo: float, hi: float, duration: float, seed: int,
          maker: Callable[..., Profile]) -> Profile:
    """The Profile `name` of `names`, packed (`pack`), as `maker` makes it."""
    if name not in names:
        raise ValueError(f"unknown profile {name!r}; choose one of {', '.join(names)}")
    kp = pack(name, lo, hi, duration, seed)
    return Profile(name, lambda t: _on_times(values_core, kp, t), lo, hi, duration,
                   (maker, (name, lo, hi, duration, seed)), kp=kp)


def random_peaks(lo: float, hi: float, duration: float, seed: int, start: float | None = None,
                 segment: tuple[float, float] = (4.0, 12.0)) -> Callable[[np.ndarray], np.ndarray]:
    """A signal through alternating random peaks and troughs within [`lo`, `hi`], joined by half
    cosines, over `duration` [s], its generator seeded with `seed`.

    Peaks are drawn from the upper 60 % of [lo, hi], troughs from the lower 60 %, each at least
    10 % of the range from the previous extreme; each swing lasts a uniform random time in
    `segment` [s]. The signal starts at `start` (default lo) and is smooth (C1).
    """
    times, values = peak_knots(lo, hi, duration, seed, start, segment)
    p = np.concatenate(([len(times)], times, values))
    return lambda t: _on_times(peaks_values_core, p, t)


def peak_knots(lo: float, hi: float, duration: float, seed: int, start: float | None = None,
               segment: tuple[float, float] = (4.0, 12.0)) -> tuple[np.ndarray, np.ndarray]:
    """(times, levels) of the knots of `random_peaks` (its arguments)."""
    rng = np.random.default_rng(seed)
    span = hi - lo
    knots, levels = [0.0], [lo if start is None else start]
    up = True
    while knots[-1] <= duration:
        while True:
            frac = rng.uniform(0.4, 1.0) if up else rng.uniform(0.0, 0.6)
            if abs(lo + frac * span - levels[-1]) >= 0.1 * span:
                break
        knots.append(knots[-1] + rng.uniform(*segment))
        levels.append(lo + frac * span)
        up = not up
    return np.array(knots), np.array(levels)
