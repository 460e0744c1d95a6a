"""Cold ends: heat lost into the clamps makes the wire's temperature uneven (§named-effects,
§sma-material).

A wire held in clamps that conduct heat is a fin at each end: with the core (the middle, where a
thermocouple sits) at excess temperature theta over the ambient, the excess a distance x from a
clamp is, quasi-statically,

    theta(x) = theta (1 - beta exp(-x / L_f)),   L_f = sqrt(k d / (4 h)),
    beta = G_c / (G_c + G_f),                    G_f = sqrt(k A h pi d)

with G_c the contact conductance of a clamp and G_f the fin conductance of the wire (k its
thermal conductivity, A its cross-section). ``end_cooling`` is beta: 0 for insulating clamps (the
nominal, uniform wire), near 1 for metal clamps in good contact (G_c >> G_f, about 1e-4 W/K for
the 127 um wire). The core of a wire much longer than L_f (2.4 mm for 127 um in still air, the
wire 58 mm) keeps its lumped balance; the ends are colder, transform later on heating and sooner
on cooling, and carry less of the strain: what a larger h cannot mimic. The profile adapts on
L_f^2 / alpha = rho c d / (4 h), the wire's own thermal time constant, so taking it as following
the core at once is the first-order approximation.

Each end is cut into `EDGES` zones (in units of L_f); a zone has its mean excess factor
1 - beta mean(exp(-x / L_f)) and its share of the length, both ends together. Beyond the last
edge (exp(-4) = 1.8 %) the wire counts as core.

>>> zones(0.0, 58.42e-3, 127e-6, 18.0, 100.0)
[]
>>> [(round(w, 3), round(g, 3)) for w, g in zones(1.0, 58.42e-3, 127e-6, 18.0, 100.0)]
[(0.041, 0.213), (0.082, 0.617), (0.205, 0.918)]
"""
from __future__ import annotations

import math
from collections.abc import Sequence

EDGES = (0.0, 0.5, 1.5, 4.0)  # zone edges from a clamp, in fin lengths L_f


def fin_length(diameter: float, conductivity: float, h: float) -> float:
    """L_f = sqrt(k d / (4 h)) [m]: the e-folding length of the excess temperature from a clamp,
    for a wire of `diameter` [m] and thermal `conductivity` k [W/(m K)] in air of convection
    coefficient `h` [W/(m^2 K)]."""
    return math.sqrt(conductivity * diameter / (4 * h))


def fin_conductance(diameter: float, conductivity: float, h: float) -> float:
    """G_f = sqrt(k A h pi d) [W/K]: what one long wire end conducts per kelvin at its root
    (`diameter`, `conductivity`, `h` as in `fin_length`)."""
    area = math.pi * diameter ** 2 / 4
    return math.sqrt(conductivity * area * h * math.pi * diameter)


def end_cooling(contact: float, diameter: float, conductivity: float, h: float) -> float:
    """beta = G_c / (G_c + G_f) of a clamp of contact conductance `contact` [W/K] (`diameter`,
    `conductivity`, `h` as in `fin_length`)."""
    g_f = fin_conductance(diameter, conductivity, h)
    return contact / (contact + g_f)


def zones(beta: float, length: float, diameter: float, conductivity: float,
          h: float) -> list[tuple[float, float]]:
    """[(share of the length, excess factor)] of the cold end zones, both ends together, of a
    wire of `length` [m] (`diameter`, `conductivity`, `h` as in `fin_length`) with end cooling
    `beta`; the core (factor 1) has the rest of the length. Empty when `beta` is 0 (a uniform
    wire)."""
    if beta == 0:
        return []
    if not 0 <= beta <= 1:
        raise ValueError(f"end_cooling must lie in [0, 1] (got {beta!r})")
    fin = fin_length(diameter, conductivity, h)
    if 2 * EDGES[-1] * fin >= length:
        raise ValueError(f"the wire ({length:g} m) is too short for its cold ends ({EDGES[-1]:g} "
                         f"fin lengths of {fin:.3g} m each): the core would not be uniform")
    out = []
    for x0, x1 in zip(EDGES, EDGES[1:]):
        mean_exp = (math.exp(-x0) - math.exp(-x1)) / (x1 - x0)
        out.append((2 * (x1 - x0) * fin / length, 1 - beta * mean_exp))
    return out


def zone_temperatures(T_core: float, T_amb: float,
                      table: Sequence[tuple[float, float]]) -> list[float]:
    """Each zone's temperature [C] for the core at `T_core` and the ambient `T_amb`, the zones
    those of `table` (`zones`)."""
    return [T_amb + g * (T_core - T_amb) for _, g in table]
