"""Reference SMA wire (virtual hardware): stress-dependent hysteron density and its FORC increment.

Each hysteron is a piece of wire that turns austenite (contracts) when heated to a and martensite
again when cooled to b. Its centre c = (a + b) / 2 is its local transformation temperature and its
width w = a - b its local hysteresis. Centres follow a sharp logistic population plus a diffuse
Gaussian one, both moved by stress along the Clausius-Clapeyron slope (§sma-material); widths are
Gaussian. The strain amplitude grows with stress as martensite detwins. The density is zero
outside the Preisach triangle T_low <= b <= a <= T_high (§preisach), so the wire saturates there.
Temperatures in degrees C, stresses in Pa, strains as contraction / length (§sma-wire).
"""
from __future__ import annotations

import math
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass, fields
from typing import Any
from pathlib import Path

import numpy as np
from scipy.special import expit, ndtr

from musclesim.components.checks import require
from .surface import Hypersurface

FloatArray = float | np.ndarray  # a value, or values that broadcast together
DEFAULT_PARAMS = Path(__file__).parent / "params" / "flexinol-127um-90C.toml"

# Gauss-Legendre on [-1, 1] with 48 nodes (the positive half; the rule is symmetric) for the width
# quadrature, error ~1e-16: numpy.polynomial.legendre.leggauss(48) written out, bit for bit as it
# gives them here. It computes them at run time through LAPACK (eigvalsh), whose kernel is chosen
# per CPU; a stored table is the same on every CPU (test: against leggauss).
_NODES_HALF = (
    0.03238017096286937, 0.0970046992094627, 0.1612223560688917, 0.22476379039468905,
    0.28736248735545555, 0.3487558862921607, 0.4086864819907167, 0.4669029047509584,
    0.523160974722233, 0.5772247260839727, 0.6288673967765136, 0.6778723796326639,
    0.7240341309238146, 0.7671590325157404, 0.8070662040294426, 0.8435882616243935,
    0.8765720202742479, 0.9058791367155696, 0.9313866907065543, 0.9529877031604308,
    0.9705915925462473, 0.9841245837228269, 0.9935301722663508, 0.9987710072524261,
)
_WEIGHTS_HALF = (
    0.06473769681268365, 0.06446616443594982, 0.06392423858464787, 0.06311419228625373,
    0.06203942315989242, 0.0607044391658936, 0.059114839698395344, 0.057277292100402916,
    0.05519950369998403, 0.05289018948519344, 0.0503590355538542, 0.04761665849249024,
    0.04467456085669423, 0.04154508294346455, 0.0382413510658305, 0.034777222564770394,
    0.031167227832798097, 0.027426509708357034, 0.023570760839324047, 0.019616160457356056,
    0.015579315722943226, 0.011477234579234614, 0.007327553901276135, 0.0031533460523098414,
)
_NODES = np.concatenate([-np.array(_NODES_HALF[::-1]), np.array(_NODES_HALF)])
_WEIGHTS = np.concatenate([np.array(_WEIGHTS_HALF[::-1]), np.array(_WEIGHTS_HALF)])
_WIDTH_SDS = 4.0  # the width density is a Gaussian truncated at this many standard deviations


@dataclass(frozen=True)
class WireParams:
    """Hysteron density parameters; values and their sources live in the parameter file."""

    T_low: float  # C, lower saturation temperature b0 (§sma-wire)
    T_high: float  # C, upper saturation temperature a0 (§sma-wire)
    eps_sat: float  # saturated transformation strain (§forc-identification)
    sigma_det: float  # Pa, detwinning stress scale of the strain amplitude (§forc-identification)
    sigma_ref: float  # Pa, stress at which centre_ref holds (§forc-identification)
    centre_ref: float  # C, median hysteron centre at sigma_ref (§forc-identification)
    cc_slope: float  # Pa/K, Clausius-Clapeyron slope (§sma-material)
    width_mean: float  # K, mean hysteron width a - b (§forc-identification)
    width_sd: float  # K, spread of the width
    sharp_scale: float  # K, logistic scale of the sharp population (§sma-material)
    diffuse_fraction: float  # share of the diffuse population (§forc-identification)
    diffuse_sd: float  # K, spread of the diffuse population (§forc-identification)

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("eps_sat", "sigma_det", "cc_slope", "width_mean", "width_sd",
                                "sharp_scale", "diffuse_sd"))
        if not 0 <= self.diffuse_fraction <= 1:
            raise ValueError(f"diffuse_fraction must lie in [0, 1] (got {self.diffuse_fraction!r})")
        if not self.T_low < self.T_high:
            raise ValueError(f"T_low must be below T_high (got {self.T_low!r}, {self.T_high!r})")


def wire_table(path: Path, name: str) -> dict[str, Any]:
    """The table [`name`] of the wire parameter file `path`; ValueError naming the file when it
    cannot be read or has no such table."""
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))[name]
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError, KeyError) as exc:
        raise ValueError(f"{path}: not a wire parameter file with a [{name}] table "
                         f"({exc})") from None


def load_params(path: str | Path = DEFAULT_PARAMS) -> WireParams:
    """Read the [hysteresis] table of the wire parameter file `path` into a checked WireParams.

    Raises
    ------
    ValueError
        Naming the file and the missing, unknown or non-numeric entry.

    Examples
    --------
    >>> load_params().sigma_ref
    155000000.0
    """
    path = Path(path)
    table = wire_table(path, "hysteresis")
    names = {f.name for f in fields(WireParams)}
    for key in sorted(set(table) ^ names):
        raise ValueError(f"{path}: {'unknown' if key in table else 'missing'} entry {key!r}")
    for key, value in table.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f"{path}: entry {key!r} must be a number (got {value!r})")
    p = WireParams(**{k: float(v) for k, v in table.items()})
    try:
        p.check()
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
    return p


def _libm(fn, x):
    """The C library's `fn` (math.exp, math.expm1) element by element, once per distinct value.

    numpy's own exp and expm1, which it takes on CPUs with AVX-512, round some values differently
    from the C library's: the wire's tables, the SMA runs on them and the designs made on the wire
    would change with the CPU."""
    x = np.asarray(x, dtype=float)
    if x.size <= 256:
        return np.array([fn(v) for v in x.ravel().tolist()], dtype=float).reshape(x.shape)
    values, index = np.unique(x.ravel(), return_inverse=True)
    return np.array([fn(v) for v in values.tolist()], dtype=float)[index].reshape(x.shape)


def max_strain(sigma: FloatArray, p: WireParams) -> np.ndarray:
    """Strain of the fully transformed wire `p` at stress `sigma` [Pa], eps_sat (1 - exp(-sigma /
    sigma_det))
    (§forc-identification)."""
    return p.eps_sat * -_libm(math.expm1, -np.asarray(sigma, dtype=float) / p.sigma_det)


def centre(sigma: FloatArray, p: WireParams) -> np.ndarray:
    """Median hysteron centre [C] of the wire `p` at stress `sigma` [Pa]: moves up 1 / cc_slope K
    per Pa
    (§sma-material)."""
    return p.centre_ref + (np.asarray(sigma, dtype=float) - p.sigma_ref) / p.cc_slope


def _centre_cdf(c, c0, p):
    x = c - c0
    f = p.diffuse_fraction
    return (1 - f) * expit(x / p.sharp_scale) + f * ndtr(x / p.diffuse_sd)


def _centre_pdf(c, c0, p):
    x = c - c0
    s = expit(x / p.sharp_scale)
    gauss = (_libm(math.exp, -0.5 * (x / p.diffuse_sd) ** 2)
             / (p.diffuse_sd * math.sqrt(2 * math.pi)))
    return (1 - p.diffuse_fraction) * s * (1 - s) / p.sharp_scale + p.diffuse_fraction * gauss


def _width_support(p):
    return max(0.0, p.width_mean - _WIDTH_SDS * p.width_sd), p.width_mean + _WIDTH_SDS * p.width_sd


def _width_pdf(w, p):
    lo, hi = _width_support(p)
    mass = ndtr((hi - p.width_mean) / p.width_sd) - ndtr((lo - p.width_mean) / p.width_sd)
    z = (w - p.width_mean) / p.width_sd
    inside = (w >= lo) & (w <= hi)
    norm = p.width_sd * math.sqrt(2 * math.pi) * mass
    return np.where(inside, _libm(math.exp, -0.5 * z * z) / norm, 0.0)


def _plane_mass(a, b, c0, p):
    """Mass of the unit, untruncated density on {b <= b_h <= a_h <= a}: integral over the width w
    of q(w) [P(a - w / 2) - P(b + w / 2)], P the centre CDF, by Gauss-Legendre on w's support."""
    lo, hi = _width_support(p)
    half = 0.5 * (np.clip(a - b, lo, hi) - lo)
    w = lo + half[..., None] * (_NODES + 1)
    c0 = c0[..., None]
    inner = _centre_cdf(a[..., None] - w / 2, c0, p) - _centre_cdf(b[..., None] + w / 2, c0, p)
    if half.size > 1:  # q(w) once per distinct width (a grid has few): the same numbers
        halves, index = np.unique(half.ravel(), return_inverse=True)
        q = _width_pdf(lo + halves[:, None] * (_NODES + 1), p)[index].reshape(w.shape)
    else:
        q = _width_pdf(w, p)
    return half * np.sum(_WEIGHTS * q * inner, axis=-1)


def _total_mass(sigma, p):
    """_plane_mass over the whole triangle, evaluated once per distinct stress."""
    levels, index = np.unique(sigma, return_inverse=True)
    c0 = centre(levels, p)
    total = _plane_mass(np.full_like(levels, p.T_high), np.full_like(levels, p.T_low), c0, p)
    return total[index].reshape(sigma.shape)


def _as_arrays(a, b, sigma):
    a, b, sigma = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (a, b, sigma)))
    if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b)) and np.all(np.isfinite(sigma))):
        raise ValueError("temperatures and stress must be finite numbers")
    if np.any(sigma < 0):
        raise ValueError(f"stress must be non-negative (got {sigma.min()!r} Pa)")
    return a, b, sigma


def forc_increment(a: FloatArray, b: FloatArray, sigma: FloatArray, p: WireParams) -> np.ndarray:
    """FORC increment F(a, b; sigma): strain of all hysterons in {b <= b_h <= a_h <= a} (§preisach).

    Parameters
    ----------
    a, b : float or array_like
        Peak and end temperature of the reversal curve [C]; outside [T_low, T_high] they count as
        the nearest saturation temperature (no hysterons live there).
    sigma : float or array_like
        Stress [Pa], non-negative. All three broadcast together.
    p : WireParams

    Returns
    -------
    numpy.ndarray or numpy.float64
        F >= 0; F(T_high, T_low; sigma) is the wire's maximum strain; 0 where a <= b.

    Examples
    --------
    >>> p = load_params()
    >>> round(float(forc_increment(130, 30, 105e6, p)), 4)
    0.0376
    """
    a, b, sigma = _as_arrays(a, b, sigma)
    c0 = centre(sigma, p)
    a = np.clip(a, p.T_low, p.T_high)
    b = np.clip(b, p.T_low, p.T_high)
    total = _total_mass(sigma, p)
    return (max_strain(sigma, p) * _plane_mass(a, b, c0, p) / total)[()]


def density(a: FloatArray, b: FloatArray, sigma: FloatArray, p: WireParams) -> np.ndarray:
    """Hysteron density mu(`a`, `b`; `sigma`) [1/K^2] of the wire `p`: zero outside the
    triangle, integrates to F.

    Examples
    --------
    >>> p = load_params()
    >>> float(density(100, 110, 155e6, p)), float(density(120, 20, 155e6, p))
    (0.0, 0.0)
    """
    a, b, sigma = _as_arrays(a, b, sigma)
    c0 = centre(sigma, p)
    total = _total_mass(sigma, p)
    inside = (b >= p.T_low) & (a <= p.T_high) & (a >= b)
    mu = _width_pdf(a - b, p) * _centre_pdf((a + b) / 2, c0, p) * max_strain(sigma, p) / total
    return np.where(inside, mu, 0.0)[()]


def outside_mass(sigma: FloatArray, p: WireParams) -> np.ndarray:
    """Share of the untruncated density of the wire `p` that falls outside the Preisach triangle
    at stress `sigma` [Pa]."""
    return (1.0 - _total_mass(np.asarray(sigma, dtype=float), p))[()]


class ReferenceWire:
    """The reference wire as a FORC-increment source: ``F(a, b, sigma)`` is what
    ``Hypersurface.from_function`` tabulates and what the loop explorer cycles.

    Parameters
    ----------
    params : WireParams or path-like, optional
        Parameters, or a parameter file to load (default: the 127 um, 90 C wire).

    Examples
    --------
    >>> wire = ReferenceWire()
    >>> round(float(wire.F(130, 30, 155e6)), 4), round(float(wire.F(85, 60, 155e6)), 4)
    (0.04, 0.0204)
    """

    def __init__(self, params: WireParams | str | Path | None = None) -> None:
        if not isinstance(params, WireParams):
            params = load_params(params or DEFAULT_PARAMS)
        self.params = params

    def F(self, a: FloatArray, b: FloatArray, sigma: FloatArray) -> np.ndarray:
        """FORC increment F(`a`, `b`; `sigma`) [-] (see `forc_increment`)."""
        return forc_increment(a, b, sigma, self.params)

    def grid(self, step: float) -> np.ndarray:
        """Temperatures [C] every `step` over the saturation range T_low..T_high."""
        p = self.params
        return np.linspace(p.T_low, p.T_high, int(round((p.T_high - p.T_low) / step)) + 1)

    def hypersurface(self, temps: Sequence[float] | np.ndarray,
                     stresses: Sequence[float] | np.ndarray) -> Hypersurface:
        """The wire tabulated as a `Hypersurface` on `temps` [C] x `stresses` [Pa]: what
        ``Hypersurface.from_function(self.F, temps, stresses)`` gives (up to round-off), vectorised
        over the Preisach triangle (a 1 C grid takes ~25 ms per stress instead of seconds).

        Examples
        --------
        >>> h = ReferenceWire().hypersurface(range(30, 131, 5), [105e6, 155e6])
        >>> round(h.F(130.0, 30.0, 105e6), 4), round(h.F(85.0, 60.0, 155e6), 4)
        (0.0376, 0.0204)
        """
        grid = np.asarray(temps, dtype=float)
        i, j = np.tril_indices(len(grid))
        table = np.zeros((len(stresses), len(grid), len(grid)))
        for s, sigma in enumerate(stresses):
            table[s, i, j] = self.F(grid[i], grid[j], float(sigma))
        return Hypersurface(grid, stresses, table)

    def mu(self, a: FloatArray, b: FloatArray, sigma: FloatArray) -> np.ndarray:
        """Hysteron density mu(`a`, `b`; `sigma`) [1/K^2] (see `density`)."""
        return density(a, b, sigma, self.params)

    def eps_max(self, sigma: FloatArray) -> np.ndarray:
        """Maximum strain F(T_high, T_low; `sigma`) [-]."""
        return max_strain(sigma, self.params)
