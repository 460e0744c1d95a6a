"""Lumped thermal model of an SMA wire (§thermal-model, data §sma-material), candidate effects off
by default.

    m c_p dT/dt = P(u, xi) + m L xi_rate - h(T) A_s (T - T_amb)

P = R(xi) I^2 under current drive or V^2 / R(xi) under voltage drive, R(xi) = L (xi rho_M +
(1 - xi) rho_A) / A with xi the martensite fraction. Effects (issue 3): latent heat L (heat
absorbed while austenite forms, xi falling) and convection h(T) = h (|T - T_amb| / dT_ref)^n
growing with the excess temperature; heat lost into the clamps leaves this balance of the wire's
core unchanged and cools its ends (`ends`). Temperatures in degrees C.
The update is exponential (Rosenbrock-Euler): exact in one step when h is constant and the inputs
are held, sub-stepped with h(T), stable at any step.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, fields
from typing import NamedTuple

import numpy as np
from scipy.optimize import brentq

from musclesim.components.checks import require
from musclesim.components.sma.surface import fmax, fmin
from musclesim.fmu import Calibration, declare, jit

DRIVES = ("voltage", "current")


@dataclass(frozen=True)
class ThermalParams:
    """Wire geometry, material data and effects (defaults: §sma-wire, §sma-material; effects
    off). Each FMU parameter is declared once here (`declare`): the SmaWire and CapstanMultiplier
    FMUs, the docs' tables and the diagnosis's catalogues read it."""

    length: float = declare(58.42e-3, "m", "Wire length (the study's main wire)",
                            source="§sma-wire")
    diameter: float = declare(127e-6, "m", "Wire diameter (the study's wires)", source="§sma-wire")
    density: float = declare(6450.0, "kg/m3", "Density of NiTi (data sheets, literature)",
                             source="§sma-material")
    specific_heat: float = declare(837.0, "J/(kg.K)", "Specific heat of NiTi (data sheets, "
                                   "literature)", source="§sma-material", calibrate=Calibration(
                                       0.8, 1.2, True, "data-sheet value of NiTi, alloy dependent"))
    rho_martensite: float = declare(80e-8, "Ohm.m", "Resistivity of martensite, 80 uOhm cm (data "
                                    "sheets: 63 Ohm/m for a 127 um wire)", source="§sma-material",
                                    calibrate=Calibration(0.85, 1.15, True, "resistivity varies "
                                                          "with the alloy and the contacts"))
    rho_austenite: float = declare(100e-8, "Ohm.m", "Resistivity of austenite, 100 uOhm cm (data "
                                   "sheets: 79 Ohm/m for a 127 um wire)", source="§sma-material",
                                   calibrate=Calibration(0.85, 1.15, True, "resistivity varies "
                                                         "with the alloy and the contacts"))
    h: float = declare(100.0, "W/(m2.K)", "Convection coefficient at 50 K excess (literature: "
                       "natural convection from a 127 um wire in still air)", source="§convection",
                       calibrate=Calibration(0.6, 1.6, True, "convection depends on the air "
                                             "around the wire (§convection: 50-150 W/(m^2 K))"))
    # electrical input: "voltage" [V] or "current" [A] (§thermal-model); the FMUs' drive_current
    drive: str = "voltage"
    max_substep: float = 1e-3  # s, sub-step of h(T) (second order: about 1e-6 K off at 50 Hz)
    latent_heat: float = declare(0.0, "J/kg", "Effect, 0 = off: latent heat of transformation "
                                 "(12e3-24e3 when on)", source="§thermal-model, §sma-material",
                                 effect=(0.0, 30e3))
    h_exponent: float = declare(0.0, "1", "Effect, 0 = off: exponent n of the convection h "
                                "(|T - T_amb| / 50 K)^n (thin-wire correlations give 0.06-0.15)",
                                source="§named-effects, §convection", effect=(0.0, 0.5))
    h_dT_ref: float = 50.0  # K, excess temperature at which h holds (§convection)

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("length", "diameter", "density", "specific_heat",
                                "rho_martensite", "rho_austenite", "max_substep", "h_dT_ref"),
                non_negative=("h", "latent_heat", "h_exponent"))
        if self.drive not in DRIVES:
            raise ValueError(f"drive must be one of {DRIVES} (got {self.drive!r})")


def params_of(values: object, drive: str, skip: tuple[str, ...] = ()) -> ThermalParams:
    """The `ThermalParams` of the declared parameters' values, read as attributes of `values` (an
    FMU slave that declared them with ``parameters_of(ThermalParams)``), but not those in `skip`
    (their defaults hold), with the electrical input `drive` ("voltage" or "current")."""
    return ThermalParams(drive=drive, **{f.name: getattr(values, f.name)
                                         for f in fields(ThermalParams)
                                         if "unit" in f.metadata and f.name not in skip})


class ThermalInputs(NamedTuple):
    """Inputs held over one step."""

    u: float  # V or A, per ThermalParams.drive
    T_amb: float  # C, ambient air
    xi: float = 1.0  # martensite fraction (1 = cold wire), sets the resistance
    xi_rate: float = 0.0  # 1/s, d xi / dt; matters only with latent heat


# the role of a wire FMU's input T_amb for the diagnosis (SmaWire, CapstanMultiplier): calibrated as
# a constant, unless the data set states the bench's ambient
AMBIENT = Calibration(-8.0, 8.0, False, "the bench's room air; stated in the data set's "
                      "[conditions] when measured")


def cross_section(p: ThermalParams) -> float:
    """Cross-section area pi d^2 / 4 [m^2] of the wire `p`."""
    return math.pi * p.diameter ** 2 / 4


def lateral_surface(p: ThermalParams) -> float:
    """Lateral surface A_s = pi d L [m^2] of the wire `p` (§sma-wire)."""
    return math.pi * p.diameter * p.length


def heat_capacity(p: ThermalParams) -> float:
    """Heat capacity m c_p [J/K] of the wire `p`."""
    return p.density * cross_section(p) * p.length * p.specific_heat


def time_constant(p: ThermalParams) -> float:
    """Free-cooling time constant m c_p / (h A_s) = rho c d / 4h [s] of the wire `p`
    (§convection)."""
    return heat_capacity(p) / (p.h * lateral_surface(p))


def resistance(xi: float, p: ThermalParams) -> float:
    """Electrical resistance R(xi) = L (xi rho_M + (1 - xi) rho_A) / A [Ohm] of the wire `p` at
    martensite fraction `xi` (§thermal-model).

    Examples
    --------
    >>> p = ThermalParams()
    >>> round(resistance(1.0, p) / p.length, 1), round(resistance(0.0, p) / p.length, 1)
    (63.2, 78.9)
    """
    return resistance_k(packed(p), xi)


def joule_power(u: float, xi: float, p: ThermalParams) -> float:
    """Joule heating [W] of the input `u` on the wire `p` at martensite fraction `xi`: V^2 / R
    under voltage drive, R I^2 under current drive."""
    return joule_power_k(packed(p), u, xi)


def convection_coefficient(T: float, T_amb: float, p: ThermalParams) -> float:
    """h(T) [W/(m^2 K)] of the wire `p` at `T` in air at `T_amb` [C]: h, or h (|T - T_amb| /
    dT_ref)^n with the effect on."""
    return convection_k(packed(p), T, T_amb)


def martensite_fraction(eps: float, eps_max: float) -> float:
    """xi = 1 - `eps` / `eps_max` clipped to [0, 1]: a hysteron switched on is austenite
    (§preisach)."""
    return martensite_fraction_k(eps, eps_max)


def derivative(T: float, inputs: ThermalInputs, p: ThermalParams) -> float:
    """dT/dt [K/s] of the lumped balance of the wire `p` at temperature `T` [C] with `inputs`
    (module equation)."""
    return derivative_k(packed(p), T, inputs.u, inputs.T_amb, inputs.xi, inputs.xi_rate)


def step(T: float, inputs: ThermalInputs, dt: float, p: ThermalParams) -> float:
    """Temperature [C] of the wire `p` after `dt` [s] from `T` [C] with `inputs` held.

    Update T += dt_s f(T) phi(dt_s k / (m c_p)), phi(x) = (1 - e^-x) / x, k = (1 + n) h(T) A_s
    the loss's derivative in T. With h constant (n = 0) one such update is the exact
    solution; with h(T) it runs in ceil(dt / max_substep) sub-steps and is second order. Either
    way it is stable at any step.

    Examples
    --------
    >>> p = ThermalParams(drive="current")
    >>> T = step(80.0, ThermalInputs(u=0.0, T_amb=20.0), time_constant(p), p)
    >>> abs((T - 20.0) / 60.0 - math.exp(-1)) < 1e-12
    True
    """
    return step_k(packed(p), T, inputs.u, inputs.T_amb, inputs.xi, inputs.xi_rate, dt)


def step_coupled(T: float, inputs: ThermalInputs, dt: float, p: ThermalParams,
                 xi_at: Callable[[float], float]) -> tuple[float, float]:
    """Step the wire `p` from `T` [C] over `dt` [s] with `inputs` held, the latent heat coupled
    implicitly to the hysteresis: return (T_new, xi_new).

    Solves T_new = step(T, inputs with xi_rate = (xi_new - xi) / dt, dt) with xi_new =
    xi_at(T_new) clipped to [0, 1]. `xi_at` (of T) is the martensite fraction the hysteresis
    model would reach at T from its present memory (without committing it). Along a branch xi falls as
    T rises, so the root is unique. An explicit xi_rate from the previous step would oscillate
    wherever L |dxi/dT| > c_p, i.e. on steep branches. Without latent heat this is `step`
    followed by one xi_at call.
    """
    seen = {}  # xi_at of each temperature tried: the search and the result ask twice

    def xi_end(T_end):
        if T_end not in seen:
            seen[T_end] = min(1.0, max(0.0, xi_at(T_end)))
        return seen[T_end]

    if p.latent_heat == 0:
        T_new = step(T, inputs._replace(xi_rate=0.0), dt, p)
        return T_new, xi_end(T_new)

    def advance(T_end):
        return step(T, inputs._replace(xi_rate=(xi_end(T_end) - inputs.xi) / dt), dt, p)

    # g(T) = T - advance(T) changes sign between the step without latent heat, T0 (g(T0) has
    # the sign of xi - xi_at(T0); T0 itself is the root when the wire does not transform there),
    # and the step of a whole transformation toward that side (xi stays in [0, 1]); no
    # monotonicity of xi_at in T is needed, which a change of stress under the memory breaks
    T0 = step(T, inputs._replace(xi_rate=0.0), dt, p)
    xi0 = xi_end(T0)
    if xi0 == inputs.xi:
        return T0, xi0
    end = 0.0 if xi0 < inputs.xi else 1.0
    other = step(T, inputs._replace(xi_rate=(end - inputs.xi) / dt), dt, p)
    lo, hi = sorted((T0, other))
    if hi - lo < 1e-12:
        return lo, xi_end(lo)
    if p.h_exponent:
        return _root(lambda x: x - advance(x), lo, hi, xi_end)
    # one exact update, affine in xi_rate (the latent term adds L / c_p xi_rate dt phi):
    # advance(x) is T0 moved toward `other` in proportion to the fraction's change, so the
    # search asks only the hysteresis, not the thermal step
    slope = (other - T0) / (end - inputs.xi)

    def g(x):
        return x - T0 - slope * (xi_end(x) - inputs.xi)

    # advance(T0) = T0 - g(T0) lies between T0 and the root wherever the fraction moves one way
    # between them (it transforms less short of T0): a bracket as wide as the latent heat's
    # effect in this step, not a whole transformation's, when g changes sign there
    x1 = T0 - g(T0)
    if g(x1) == 0 or (g(x1) < 0) != (g(T0) < 0):
        lo, hi = sorted((T0, x1))
    return _root(g, lo, hi, xi_end)


def _root(g, lo, hi, xi_end):
    """(T, xi_end(T)) at the root of `g` in [lo, hi] (its sign changes there, or it is zero at
    an end)."""
    T_new = brentq(g, lo, hi, xtol=1e-10)
    return T_new, xi_end(T_new)


# --- the lumped model on a float64 array, for the compiled cores (`musclesim.fmu.compiled`) ---
# slots of `pack`'s array: the parameters and the derived constants the functions above compute
# per call (same operations, same order, so the same bits)
(TP_LENGTH, TP_AREA, TP_RHO_M, TP_RHO_A, TP_CURRENT, TP_H, TP_H_EXPONENT, TP_DT_REF,
 TP_MAX_SUBSTEP, TP_SURFACE, TP_HEAT_CAPACITY, TP_LATENT) = range(12)
TP_SIZE = 12


def packed(p: ThermalParams) -> np.ndarray:
    """`pack` (`p`), kept on `p` (immutable) so that the functions above pack it once."""
    try:
        return p.__dict__["_packed"]
    except KeyError:
        object.__setattr__(p, "_packed", pack(p))
        return p.__dict__["_packed"]


def pack(p: ThermalParams) -> np.ndarray:
    """The thermal parameters `p` as a float64 array (slots ``TP_*``): length, cross-section,
    resistivities, drive (1 = current), h, its exponent and reference excess, the sub-step,
    the lateral surface, the heat capacity and the latent factor rho A L L_h (the mass times
    the latent heat)."""
    return np.array([p.length, cross_section(p), p.rho_martensite, p.rho_austenite,
                     0.0 if p.drive == "voltage" else 1.0, p.h, p.h_exponent, p.h_dT_ref,
                     p.max_substep, lateral_surface(p), heat_capacity(p),
                     p.density * cross_section(p) * p.length * p.latent_heat], dtype=float)


@jit
def resistance_k(tp: np.ndarray, xi: float) -> float:
    """`resistance` at martensite fraction `xi` of the packed parameters `tp` (`pack`)."""
    rho = xi * tp[TP_RHO_M] + (1 - xi) * tp[TP_RHO_A]
    return rho * tp[TP_LENGTH] / tp[TP_AREA]


@jit
def joule_power_k(tp: np.ndarray, u: float, xi: float) -> float:
    """`joule_power` of the input `u` at martensite fraction `xi`, packed parameters `tp`."""
    r = resistance_k(tp, xi)
    return u * u / r if tp[TP_CURRENT] == 0.0 else r * u * u


@jit
def convection_k(tp: np.ndarray, T: float, T_amb: float) -> float:
    """`convection_coefficient` at `T` in air at `T_amb` [C], packed parameters `tp`."""
    if tp[TP_H_EXPONENT] == 0:
        return tp[TP_H]
    return tp[TP_H] * (abs(T - T_amb) / tp[TP_DT_REF]) ** tp[TP_H_EXPONENT]


@jit
def martensite_fraction_k(eps: float, eps_max: float) -> float:
    """`martensite_fraction` of the strain `eps` and the maximum `eps_max`."""
    return fmin(1.0, fmax(0.0, 1.0 - eps / eps_max))


@jit
def derivative_k(tp: np.ndarray, T: float, u: float, T_amb: float, xi: float,
                 xi_rate: float) -> float:
    """`derivative` at `T` [C] of the packed parameters `tp`, the inputs spelled out (`u`,
    `T_amb`, `xi`, `xi_rate`: `ThermalInputs`)."""
    h = convection_k(tp, T, T_amb)
    heat = (joule_power_k(tp, u, xi) + tp[TP_LATENT] * xi_rate
            - h * tp[TP_SURFACE] * (T - T_amb))
    return heat / tp[TP_HEAT_CAPACITY]


@jit
def phi_k(x: float) -> float:
    """(1 - exp(-`x`)) / `x`, with its limit 1 at x = 0."""
    return -math.expm1(-x) / x if x > 1e-12 else 1.0


@jit
def step_k(tp: np.ndarray, T: float, u: float, T_amb: float, xi: float, xi_rate: float,
           dt: float) -> float:
    """`step` from `T` [C] over `dt` [s] of the packed parameters `tp`, the inputs spelled out
    (`u`, `T_amb`, `xi`, `xi_rate`: `ThermalInputs`)."""
    n = 1
    if tp[TP_H_EXPONENT] != 0:
        n = max(1, int(math.ceil(dt / tp[TP_MAX_SUBSTEP] - 1e-9)))
    dt_s = dt / n
    mc = tp[TP_HEAT_CAPACITY]
    for _ in range(n):
        h = convection_k(tp, T, T_amb)
        k = (1 + tp[TP_H_EXPONENT]) * h * tp[TP_SURFACE]
        T = T + dt_s * derivative_k(tp, T, u, T_amb, xi, xi_rate) * phi_k(dt_s * k / mc)
    return T

