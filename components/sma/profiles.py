"""Reference strain profiles SP I-IV and loading profiles LP I-VI of §reference-profiles: signal
generators."""
from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

EPS_MAX = 0.0376  # strain, top of the reference strain profiles (§reference-profiles)
SIGMA_LO, SIGMA_HI = 105e6, 145e6  # Pa, range of the loading profiles (§reference-profiles)
DURATION = 550.0  # s, length of a run (§position-control)
F_FAST, F_SLOW = 1 / 17, 1 / 47  # Hz, the sinusoids of SP I, LP I and LP II (§reference-profiles)
STRAIN_PROFILES = ("SP I", "SP II", "SP III", "SP IV")
LOADING_PROFILES = ("LP I", "LP II", "LP III", "LP IV", "LP V", "LP VI")


class Profile:
    """A signal of time: ``p(t)`` takes a float or an array of times [s], values in [lo, hi].

    Attributes: ``name``, ``lo``, ``hi``, ``duration`` [s]. ``made``: the call that made it,
    ``(function, arguments)``, which copying and pickling repeat (an FMU's saved state holds it).
    """

    def __init__(self, name: str, fn: Callable[[np.ndarray], np.ndarray], lo: float, hi: float,
                 duration: float, made: tuple[Callable[..., Profile], tuple] | None = None) -> None:
        """Profile `name`: values `fn` of time in [`lo`, `hi`] over `duration` [s], `made` by that
        call."""
        self.name, self.lo, self.hi, self.duration = name, lo, hi, duration
        self._fn, self.made = fn, made

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
    mid, half = (lo + hi) / 2, (hi - lo) / 2
    w = 2 * math.pi * F_FAST
    fns = {
        "SP I": lambda t: mid - half * np.cos(w * t),
        "SP II": lambda t: mid - half * np.exp(-4 * t / duration) * np.cos(w * t),
        "SP III": lambda t: mid - half * np.minimum(t / duration, 1.0) * np.cos(w * t),
        "SP IV": random_peaks(lo, hi, duration, seed),
    }
    return Profile(name, _pick(fns, name), lo, hi, duration,
                   (strain_profile, (name, lo, hi, duration, seed)))


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
    mid, half = (lo + hi) / 2, (hi - lo) / 2
    fns = {
        "LP I": lambda t: mid + half * np.sin(2 * math.pi * F_FAST * t),
        "LP II": lambda t: mid + half * np.sin(2 * math.pi * F_SLOW * t),
        "LP III": lambda t: lo + (hi - lo) * np.clip(t / duration, 0.0, 1.0),
        "LP IV": lambda t: hi - (hi - lo) * np.clip(t / duration, 0.0, 1.0),
        "LP V": random_peaks(lo, hi, duration, seed, start=mid),
        "LP VI": random_peaks(lo, hi, duration, seed + 1, start=mid),
    }
    return Profile(name, _pick(fns, name), lo, hi, duration,
                   (loading_profile, (name, lo, hi, duration, seed)))


def random_peaks(lo: float, hi: float, duration: float, seed: int, start: float | None = None,
                 segment: tuple[float, float] = (4.0, 12.0)) -> Callable[[np.ndarray], np.ndarray]:
    """A signal through alternating random peaks and troughs within [`lo`, `hi`], joined by half
    cosines, over `duration` [s], its generator seeded with `seed`.

    Peaks are drawn from the upper 60 % of [lo, hi], troughs from the lower 60 %, each at least
    10 % of the range from the previous extreme; each swing lasts a uniform random time in
    `segment` [s]. The signal starts at `start` (default lo) and is smooth (C1).
    """
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
    times, values = np.array(knots), np.array(levels)

    def fn(t):
        i = np.clip(np.searchsorted(times, t, side="right") - 1, 0, len(times) - 2)
        s = np.clip((t - times[i]) / (times[i + 1] - times[i]), 0.0, 1.0)
        return values[i] + (values[i + 1] - values[i]) * (1 - np.cos(math.pi * s)) / 2
    return fn


def _pick(fns, name):
    if name not in fns:
        raise ValueError(f"unknown profile {name!r}; choose one of {', '.join(fns)}")
    return fns[name]
