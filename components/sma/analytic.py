"""Closed-form FORC surfaces for tests, benchmarks and examples (not identified from any wire)."""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from .surface import GRID_TEMPS, STRESSES, Hypersurface


def uniform(c: float) -> Callable[[float, float, float], float]:
    """F(a, b) = c (a - b)^2 / 2: the FORC increment of a density `c` [1/C^2] uniform over the
    triangle."""
    return lambda a, b, sigma: 0.5 * c * (a - b) ** 2


@dataclass(frozen=True)
class SmaLikeParams:
    """An SMA-shaped surface: steep transitions inside 30..130 C, shifting and growing with stress.

    F(a, b; sigma) = A(sigma) [S_h(a) - S_h(b)] [S_c(a) - S_c(b)], S_h and S_c logistic steps
    rescaled to 0 at 30 C and 1 at 130 C. The density A (S_h'(a) S_c'(b) + S_h'(b) S_c'(a)) is
    non-negative, so F is a valid FORC surface; heating follows S_h, cooling S_c.
    """

    eps_max: float = 0.0376  # strain, F(130 C, 30 C) at sigma_ref (§forc-identification)
    sigma_ref: float = 105e6  # Pa, stress of eps_max (§forc-identification)
    growth: float = 1.5e-9  # 1/Pa, relative amplitude growth (~4 % at 155 MPa,
    #                         §forc-identification)
    T_heat: float = 93.0  # C, heating transition centre, (As + Af) / 2 of a 90 C wire
    #                       (§sma-material)
    T_cool: float = 67.0  # C, cooling transition centre, (Ms + Mf) / 2 (§sma-material)
    width: float = 4.0  # C, logistic scale of both transitions (~10 C from start to finish,
    #                     §sma-material)
    sigma_mid: float = 125e6  # Pa, stress of T_heat and T_cool (the middle of §preisach's levels)
    slope: float = 7e6  # Pa/C, Clausius-Clapeyron shift of both transitions (§sma-material)
    lo: float = 30.0  # C, lower saturation (§sma-wire)
    hi: float = 130.0  # C, upper saturation (§sma-wire)

    def F(self, a: float, b: float, sigma: float) -> float:
        """The FORC increment [strain] at `a` >= `b` [C] and stress `sigma` [Pa]."""
        amp = self.eps_max * (1.0 + self.growth * (sigma - self.sigma_ref))
        shift = (sigma - self.sigma_mid) / self.slope
        h, c = self.T_heat + shift, self.T_cool + shift
        return amp * (self._step(a, h) - self._step(b, h)) * (self._step(a, c) - self._step(b, c))

    def _step(self, T, centre):
        def s(x):
            return 1.0 / (1.0 + math.exp(-(x - centre) / self.width))
        return (s(T) - s(self.lo)) / (s(self.hi) - s(self.lo))


def sma_like_surface(params: SmaLikeParams | None = None, temps: Sequence[float] = GRID_TEMPS,
                     stresses: Sequence[float] = STRESSES) -> Hypersurface:
    """`SmaLikeParams` `params` (default: its defaults) tabulated on `temps` [C] x `stresses`
    [Pa] (default: the §preisach grid, 21 x 21, five stresses).

    Examples
    --------
    >>> round(sma_like_surface().F(130.0, 30.0, 105e6), 6)
    0.0376
    """
    p = params or SmaLikeParams()
    return Hypersurface.from_function(p.F, temps, stresses)
