"""The independent SMA bench's hysteresis (`musclesim.benchmark.benches.sma`), in three forms:
the martensite fraction of each volume by phase kinetics in two populations of grains with their
own bands, shifted by the stress (Clausius-Clapeyron), with reversal memory (`Kinetics`), of the
cosine shape of Liang & Rogers (J. Intell. Mater. Syst. Struct. 1, 1990) or the exponential shape
of Tanaka (Res Mechanica 18, 1986); or a grid of relays (`Relays`: a discrete Preisach model,
Mayergoyz, "Mathematical models of hysteresis", 1991), each switching at its own temperatures,
drawn from the same bands. And the contraction strain they make. Written apart from the library:
numpy only.
"""
from __future__ import annotations

from typing import Any

import numpy as np

STRESS = 125e6  # Pa: the tracking bench's constant load (§forc-identification's stresses)
CC_SLOPE = 7e6  # Pa/K: Clausius-Clapeyron, the low end of §sma-material's 7-14 MPa/K
# Two populations of grains with their own transformation bands [C] at STRESS (weight, As, Af, Ms,
# Mf) and the transformation strain: a least-squares match (rounded) of the strain-temperature loop
# of the tracking scenario's wire under 125 MPa (§forc-identification: ~3.8 % over 30-130 C;
# half-way at ~78 C heating, ~64 C cooling), 1.3e-4 RMS apart over its 45-105 C cycles (one
# population: 1.5e-3, without the loop's tails). §sma-material's data-sheet 88/98/72/62 C at low
# stress cannot meet §forc-identification's figures (the measured behaviour wins, §sma-material)
POPULATIONS = ((0.45, 70.0, 85.0, 70.0, 55.5),  # sharp: the steep middle of the loop
               (0.55, 53.0, 108.0, 95.0, 30.0))  # diffuse: the slow approach to saturation
EPS_L = 0.036
E_AUSTENITE, E_MARTENSITE = 75e9, 28e9  # Pa: Flexinol data sheet (§sma-material names data sheets)
ALPHA = 11e-6  # 1/K: thermal expansion, Flexinol data sheet (§thermal-model names the term)
T_REF = 20.0  # C: strain is contraction from the length at room temperature (§thermal-model)


# -- hysteresis: cosine kinetics per volume ------------------------------------------------------

SHAPES = ("cosine", "exponential")
STEEPNESS = 3.0  # Tanaka's exponential: the fraction left at the band's middle is ~ e^-1.5


def _shape(x: Any, heating: Any, shape: str) -> tuple[Any, Any]:
    """(g, dg/dx) of a branch at `x` in [0, 1] across its band: g = 1 (martensite) at x = 0, 0 at
    x = 1. Cosine: 0.5 + 0.5 cos(pi x) both ways. Exponential (Tanaka): heating, the martensite
    decays fastest as the band starts (exp(-k x)); cooling, it forms fastest as it starts at the
    top (1 - exp(-k (1 - x))), each normalised to reach 0 and 1 at the band's ends."""
    if shape == "cosine":
        return 0.5 + 0.5 * np.cos(np.pi * x), -0.5 * np.pi * np.sin(np.pi * x)
    k, end = STEEPNESS, np.exp(-STEEPNESS)
    up = (np.exp(-k * x) - end) / (1 - end)
    down = 1 - (np.exp(-k * (1 - x)) - end) / (1 - end)
    d_up = -k * np.exp(-k * x) / (1 - end)
    d_down = -k * np.exp(-k * (1 - x)) / (1 - end)
    return np.where(heating, up, down), np.where(heating, d_up, d_down)


def branch(T: np.ndarray, lo: Any, hi: Any) -> np.ndarray:
    """Martensite fraction at temperatures `T` on a major branch whose band is [`lo`, `hi`]: 1
    below, 0 above, a half cosine between (Liang & Rogers 1990).

    >>> branch(np.array([40.0, 60.0, 80.0]), 50.0, 70.0).round(3).tolist()
    [1.0, 0.5, 0.0]
    """
    x = np.minimum(np.maximum((T - lo) / (hi - lo), 0.0), 1.0)
    return 0.5 + 0.5 * np.cos(np.pi * x)


def bands(stress: float) -> tuple[np.ndarray, ...]:
    """Per population (As, Af, Ms, Mf) [C] at `stress` [Pa], arrays: shifted from `STRESS` by
    the Clausius-Clapeyron slope `CC_SLOPE` (§sma-material)."""
    shift = (stress - STRESS) / CC_SLOPE
    return tuple(np.array([p[i] for p in POPULATIONS]) + shift for i in range(1, 5))


class Kinetics:
    """Martensite fractions of the volumes (each a mix of `POPULATIONS`) with their reversal
    memory.

    Each population of each volume is on a branch ``xi = offset + scale * branch(T, lo, hi)``:
    heating, its austenite band [As, Af] scaled through the reversal point (offset 0); cooling,
    its martensite band [Mf, Ms] scaled so that xi reaches 1 at Mf. From full martensite (or
    full austenite) a population follows its major branch itself. ``xi`` is the volumes' mean
    fraction (weighted over the populations). The volumes start at temperatures `T` [C] under
    `stress` [Pa], every population at fraction `xi`. `shape` is one of `SHAPES`; `bands_at`
    (As, Af, Ms, Mf) [C] per population replaces `bands`' (a case's own material). ``shift`` [K]
    moves every band (a training drift): the branches are functions of T - shift.
    """

    def __init__(self, T: Any, stress: float, xi: float = 1.0, shape: str = "cosine",
                 bands_at: tuple[np.ndarray, ...] | None = None) -> None:
        self.As, self.Af, self.Ms, self.Mf = bands_at or bands(stress)
        self.shape, self.shift = shape, 0.0
        self.weights = np.array([p[0] for p in POPULATIONS])
        T = np.asarray(T, float)
        dims = T.shape + (len(POPULATIONS),)
        self.x = np.full(dims, float(xi))  # per volume and population
        self.xi = self.x @ self.weights
        self.T = T.copy()
        self.heating = np.ones(dims, bool)
        self.lo, self.hi = np.zeros(dims), np.ones(dims)
        self.offset, self.scale = np.zeros(dims), np.ones(dims)
        self._branches(np.ones(dims, bool))

    def _branches(self, new: np.ndarray) -> None:
        """Branches through the present (T, x) for the entries `new` (after a reversal)."""
        lo = np.where(self.heating, self.As, self.Mf)
        hi = np.where(self.heating, self.Af, self.Ms)
        x = np.clip((self.T[..., None] - self.shift - lo) / (hi - lo), 0.0, 1.0)
        g = _shape(x, self.heating, self.shape)[0]
        # heating: x = s g through (T, x); cooling: x = 1 - s (1 - g) through it
        s_h = np.where(g > 1e-12, self.x / np.maximum(g, 1e-12), 0.0)
        s_c = np.where(g < 1 - 1e-12, (1 - self.x) / np.maximum(1 - g, 1e-12), 0.0)
        self.lo, self.hi = np.where(new, lo, self.lo), np.where(new, hi, self.hi)
        self.scale = np.where(new, np.where(self.heating, s_h, s_c), self.scale)
        self.offset = np.where(new, np.where(self.heating, 0.0, 1 - s_c), self.offset)

    def direction_for(self, T: Any) -> None:
        """Start new branches where moving to `T` [C] reverses the temperature."""
        dT = (np.asarray(T, float) - self.T)[..., None]
        turn = np.where(self.heating, dT < -1e-12, dT > 1e-12)
        if turn.any():
            self.heating = self.heating ^ turn
            self._branches(turn)

    def peek(self, T: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(fractions per population, mean xi, dxi/dT) at temperatures `T` [C] on the present
        branches (nothing committed)."""
        width = self.hi - self.lo
        u = (T[..., None] - self.shift - self.lo) / width
        g, dg = _shape(np.clip(u, 0.0, 1.0), self.heating, self.shape)
        x = self.offset + self.scale * g
        slope = np.where((u > 0) & (u < 1), self.scale * dg / width, 0.0)
        return x, x @ self.weights, slope @ self.weights

    def commit(self, T: Any, x: np.ndarray) -> None:
        """Take temperatures `T` [C] and fractions `x` (from `peek` at `T`) as the state."""
        self.x, self.xi, self.T = x, x @ self.weights, np.asarray(T, float).copy()

    def step(self, T: Any) -> np.ndarray:
        """Move the volumes to temperatures `T` [C]; return their mean fractions."""
        T = np.asarray(T, float)
        self.direction_for(T)
        self.commit(T, self.peek(T)[0])
        return self.xi


class Relays:
    """A grid of hysteresis relays per volume (a discrete Preisach model): relay i turns
    austenite (0) above `alpha` [i], martensite (1) below `beta` [i] < `alpha` [i], and keeps its
    state between. The thresholds are drawn from `POPULATIONS`' bands (or `bands_at`) by the
    cosine branch's distribution, the heating and cooling draws correlated so that each relay's
    loop is open; ``xi`` the volumes' mean fraction. Same interface as `Kinetics` (its ``peek``
    slope is zero: a relay switches, it has no dxi/dT), ``shift`` likewise.
    """

    def __init__(self, T: Any, stress: float, rng: np.random.Generator, count: int = 2000,
                 bands_at: tuple[np.ndarray, ...] | None = None) -> None:
        As, Af, Ms, Mf = bands_at or bands(stress)
        weights = np.array([p[0] for p in POPULATIONS])
        pop = rng.choice(len(weights), size=count, p=weights / weights.sum())
        u = rng.uniform(size=count)
        v = np.clip(u + rng.uniform(-0.1, 0.1, size=count), 0.0, 1.0)
        depth = lambda q: np.arccos(1 - 2 * q) / np.pi  # noqa: E731: the cosine's quantile
        self.alpha = As[pop] + (Af - As)[pop] * depth(u)
        self.beta = np.minimum(Mf[pop] + (Ms - Mf)[pop] * depth(v), self.alpha - 1.0)
        self.T = np.asarray(T, float).copy()
        self.state = np.ones(self.T.shape + (count,), bool)
        self.xi = self.state.mean(axis=-1)
        self.heating = np.ones(self.T.shape + (1,), bool)
        self.shift = 0.0

    def direction_for(self, T: Any) -> None:
        """Record the direction of the move to `T` [C] (relays need no branch)."""
        self.heating = (np.asarray(T, float) >= self.T)[..., None]

    def peek(self, T: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(relay states, mean xi, 0) at temperatures `T` [C], nothing committed."""
        t = np.asarray(T, float)[..., None] - self.shift
        x = np.where(t > self.alpha, False, np.where(t < self.beta, True, self.state))
        xi = x.mean(axis=-1)
        return x, xi, np.zeros_like(xi)

    def commit(self, T: Any, x: np.ndarray) -> None:
        """Take temperatures `T` [C] and states `x` (from `peek`) as the state."""
        self.state, self.xi, self.T = x, x.mean(axis=-1), np.asarray(T, float).copy()

    def step(self, T: Any) -> np.ndarray:
        """Move the volumes to temperatures `T` [C]; return their mean fractions."""
        self.direction_for(T)
        self.commit(T, self.peek(np.asarray(T, float))[0])
        return self.xi


def contraction(xi: Any, T: Any, stress: float, eps_l: float = EPS_L) -> Any:
    """Contraction strain of volumes at fractions `xi`, temperatures `T` [C], `stress` [Pa]
    with transformation strain `eps_l` (positive = shorter than at room temperature under the
    load, §sma-wire)."""
    modulus = E_AUSTENITE + xi * (E_MARTENSITE - E_AUSTENITE)
    return eps_l * (1 - xi) + stress / E_MARTENSITE - stress / modulus - ALPHA * (T - T_REF)
