"""The bending actuator of §bending-actuator as one physics core: two 50 um SMA wires at +-e beside
the beam pair (`beam`), each with its own thermal state (`sma.thermal`) and Preisach memory
(`sma.preisach`), pulling on the top cap.

Wire A lies on the side theta > 0 bends toward. With the cap turned by theta, wire A's chord
shortens by e theta and wire B's lengthens by as much. Each wire is elastic about its transformed
length (contraction strain eps from its hysteresis, positive = shorter):

    T_i = max(0, E(xi_i) A (eps_i + eps_0 - s_i e theta / L_w)),   s_A = +1, s_B = -1
    eps_0 = T_0 / (E_M A)            (equal pretension T_0 of both cold wires at theta = 0)
    1 / E(xi) = xi / E_M + (1 - xi) / E_A
    J theta'' + c theta' + (EI / L) theta = e (T_A - T_B)

A slack wire (T_i would be negative) pulls nothing. Each wire is heated by the voltage u_i through a
series resistance R_s (driver, leads): I = u / (R(xi) + R_s), P = R(xi) I^2. Each wire's hysteresis
is taken at the stress of its pretension (assumption, §bending-actuator: coupling it to the changing
tension makes this stiff system oscillate numerically). Temperatures in C, SI otherwise.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from musclesim.components.checks import require
from musclesim.components.sma import thermal
from musclesim.components.sma.preisach import PreisachModel
from musclesim.components.sma.reference_wire import ReferenceWire, WireParams, wire_table
from musclesim.components.sma.surface import Hypersurface
from musclesim.fmu import declare

from . import beam

WIRE_FILE = Path(__file__).parent / "params" / "flexinol-50um-90C.toml"
GRID_STEP = 1.0  # C, temperature grid of the tabulated hysteresis (as the 127 um reference wire)
SIDES = ("A", "B")

# (WireParams, stress) -> Hypersurface (built once per process)
_SURFACES: dict[tuple[WireParams, float], Hypersurface] = {}


def read_wire_file(path: str | Path = WIRE_FILE) -> dict[str, float]:
    """The [thermal] table of the wire parameter file `path` as a dict of floats.

    Raises
    ------
    ValueError
        Naming the file and the missing or non-numeric entry.

    Examples
    --------
    >>> read_wire_file()["h"]
    230.0
    """
    path = Path(path)
    table = wire_table(path, "thermal")
    names = ("diameter", "density", "specific_heat", "resistance_martensite",
             "resistance_austenite", "h")
    for key in names:
        if isinstance(table.get(key), bool) or not isinstance(table.get(key), (int, float)):
            raise ValueError(f"{path}: entry {key!r} must be a number (got {table.get(key)!r})")
    return {key: float(table[key]) for key in names}


WIRE_50UM = read_wire_file()  # read once at import: an FMU's first folder may be gone later


def resistivities(diameter: float, resistance_martensite: float,
                  resistance_austenite: float) -> tuple[float, float]:
    """(rho_M, rho_A) [Ohm m] of a wire of `diameter` [m] from its resistances per metre
    `resistance_martensite`, `resistance_austenite` [Ohm/m] (§sma-material's form).

    Examples
    --------
    >>> [round(r * 1e8, 1) for r in resistivities(50e-6, 470.0, 490.0)]  # uOhm cm
    [92.3, 96.2]
    """
    area = math.pi * diameter ** 2 / 4
    return resistance_martensite * area, resistance_austenite * area


def wire_thermal(length: float,
                 file_values: dict[str, float] | None = None) -> thermal.ThermalParams:
    """ThermalParams [SI] of a wire of `length` with the values `file_values` of a wire file
    (default: the 50 um wire), under current drive (the core divides the voltage by the circuit's
    resistance)."""
    d = file_values or WIRE_50UM
    rho_m, rho_a = resistivities(d["diameter"], d["resistance_martensite"],
                                 d["resistance_austenite"])
    return thermal.ThermalParams(length=length, diameter=d["diameter"], density=d["density"],
                                 specific_heat=d["specific_heat"], rho_martensite=rho_m,
                                 rho_austenite=rho_a, h=d["h"], drive="current")


def hysteresis_surface(wire_params: WireParams, sigma: float) -> Hypersurface:
    """The wire's hysteresis at the constant stress `sigma` [Pa], tabulated on a 1 C grid (~25
    ms, once per process and stress).

    `wire_params` is the reference wire's `sma.reference_wire.WireParams` (the 127 um wire's:
    the 50 um wire's hysteresis is scaled from it, §bending-actuator).

    Examples
    --------
    >>> from musclesim.components.sma.reference_wire import load_params
    >>> s = hysteresis_surface(load_params(), 100e6)
    >>> round(s.F(130.0, 30.0, 100e6), 4)
    0.0372
    """
    key = (wire_params, float(sigma))
    if key not in _SURFACES:
        wire = ReferenceWire(wire_params)
        _SURFACES[key] = wire.hypersurface(wire.grid(GRID_STEP), [float(sigma)])
    return _SURFACES[key]


@dataclass(frozen=True)
class WireLayout:
    """The wires' placement, pretension, elasticity and drive (defaults: §bending-actuator,
    §sma-material; open values and their reasons in §bending-actuator). Each parameter but
    `length` is declared once here (`declare`): the FMU and the docs' tables read it. The FMU
    declares the wires' length itself, as wire_length: its length is the beams'."""

    offset: float = declare(1.7e-3, "m", "Distance of each wire from the beams (the study)",
                            source="§bending-actuator")
    length: float = 10e-3  # m, free length, about the cap spacing (the FMU's wire_length)
    pretension: float = declare(0.196, "N", "Tension of each cold wire at rest (open; "
                                "assumption: 100 MPa on 50 um, below the data sheet's "
                                "recommended 172 MPa, so that a pulsed wire's extra pull keeps "
                                "it near that stress)", source="§bending-actuator, §sma-material")
    modulus_martensite: float = declare(28e9, "Pa", "Young's modulus of the wires' martensite "
                                        "(open; the data sheet's, Flexinol)",
                                        source="§bending-actuator, §sma-material")
    modulus_austenite: float = declare(75e9, "Pa", "Young's modulus of the wires' austenite "
                                       "(open; the data sheet's, Flexinol)",
                                       source="§bending-actuator, §sma-material")
    # the study's circuit must limit the current: 5 V straight across a 4.7 Ohm, 10 mm wire
    # would heat it some 600 K per pulse
    series_resistance: float = declare(16.5, "Ohm", "Driver and lead resistance in series with "
                                       "each wire (open; fitted to the study's one-wire "
                                       "tip-to-tip: 16.47 Ohm, 95 % interval [16.34, 16.61] "
                                       "Ohm; a 15 to 18 Ohm resistor is a common current limit)",
                                       source="§study-outcomes")
    max_substep: float = declare(5e-5, "s", "Longest mechanical sub-step (slack switching, "
                                 "moduli; numerics: well below the first mode's period, about "
                                 "3 ms)")

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        # a pretension is needed: the hysteresis is taken at its stress, and a wire detwins
        # (elongates, §forc-identification) only under stress
        require(self, positive=("offset", "length", "pretension", "modulus_martensite",
                                "modulus_austenite", "max_substep"),
                non_negative=("series_resistance",))


def modulus(xi: float, layout: WireLayout) -> float:
    """Young's modulus of a wire of `layout` at martensite fraction `xi` (Reuss mix) [Pa]."""
    return 1.0 / (xi / layout.modulus_martensite + (1.0 - xi) / layout.modulus_austenite)


def wire_terms(eps: float, xi: float, area: float, layout: WireLayout) -> tuple[float, float]:
    """(a, b) of a taut wire's tension a - s b theta [N, N/rad] (module equation), the wire of
    `layout` and cross-section `area` at strain `eps` and martensite fraction `xi`."""
    E = modulus(xi, layout)
    eps0 = layout.pretension / (layout.modulus_martensite * area)
    return E * area * (eps + eps0), E * area * layout.offset / layout.length


def tensions(theta: float, eps: Sequence[float], xi: Sequence[float], area: float,
             layout: WireLayout) -> tuple[float, ...]:
    """Tensions (T_A, T_B) [N] of the wires at cap rotation `theta` (0 when slack), at strains
    `eps` and martensite fractions `xi`, of cross-section `area` and `layout`."""
    out = []
    for s, e_i, x_i in zip((1.0, -1.0), eps, xi):
        a, b = wire_terms(e_i, x_i, area, layout)
        out.append(max(0.0, a - s * b * theta))
    return tuple(out)


def moment_terms(theta: float, eps: Sequence[float], xi: Sequence[float], area: float,
                 layout: WireLayout) -> tuple[float, ...]:
    """(M0, K_w): the wires' moment on the cap is M0 - K_w theta near `theta` [N m, N m/rad];
    a wire slack at theta contributes nothing (`eps`, `xi`, `area`, `layout` as in `tensions`)."""
    M0 = K = 0.0
    e = layout.offset
    for s, e_i, x_i in zip((1.0, -1.0), eps, xi):
        a, b = wire_terms(e_i, x_i, area, layout)
        if a - s * b * theta > 0:
            M0 += s * e * a
            K += e * b
    return M0, K


def static_rotation(eps: Sequence[float], xi: Sequence[float], area: float, layout: WireLayout,
                    beam_p: beam.BeamParams) -> float:
    """Cap rotation [rad] where the beams `beam_p` balance the wires (`eps`, `xi`, `area`,
    `layout` as in `tensions`; slack found by iteration).

    Examples
    --------
    >>> p, w = beam.BeamParams(), WireLayout()
    >>> area = math.pi * 25e-6 ** 2
    >>> static_rotation((0.0, 0.0), (1.0, 1.0), area, w, p)
    0.0
    """
    K_beam = beam.rotational_stiffness(beam_p)
    theta = 0.0
    for _ in range(4):  # at most one wire goes slack: two passes settle it
        M0, K_w = moment_terms(theta, eps, xi, area, layout)
        new = M0 / (K_beam + K_w)
        if new == theta:
            break
        theta = new
    return theta


class BendingActuator:
    """Two SMA wires and the beam pair stepped together (module equation).

    Per step of dt with the inputs held: each wire's temperature advances by the lumped thermal
    model (resistance at its martensite fraction at the start of the step) and its hysteresis
    takes the new temperature; then the first mode advances in sub-steps of at most
    ``max_substep``, each exact for the wires' moment linearised there (slack and moduli as at
    the sub-step's start).

    Parameters
    ----------
    beam_p : beam.BeamParams
    layout : WireLayout
    wire : thermal.ThermalParams
        One wire's thermal data (both wires alike), under current drive (`wire_thermal`).
    surface : sma.surface.Hypersurface
        The wires' hysteresis at their pretension's stress (`hysteresis_surface`).
    """

    def __init__(self, beam_p: beam.BeamParams, layout: WireLayout, wire: thermal.ThermalParams,
                 surface: Hypersurface) -> None:
        beam_p.check()
        layout.check()
        wire.check()
        if wire.drive != "current":
            raise ValueError("the wires' thermal parameters must be for current drive "
                             "(the core divides the voltage by R(xi) + series_resistance)")
        self.beam, self.layout, self.wire, self.surface = beam_p, layout, wire, surface
        self.area = thermal.cross_section(wire)
        self.J = beam.modal_inertia(beam_p)
        self.K_beam = beam.rotational_stiffness(beam_p)
        self.c = beam.damping_coefficient(self.cold_stiffness(), beam_p)
        self.sigma = layout.pretension / self.area  # Pa, the stress the hysteresis is taken at
        self.eps_max = surface.F(surface.t_hi, surface.t_lo, self.sigma)
        self.reset(20.0)

    def cold_stiffness(self) -> float:
        """Rotational stiffness [N m/rad] of beams and both taut, martensitic wires."""
        return self.K_beam + moment_terms(0.0, (0.0, 0.0), (1.0, 1.0), self.area, self.layout)[1]

    def reset(self, T_init: float) -> None:
        """Both wires at `T_init` [C] (heated there from martensite), the cap at rest in balance."""
        s = self.surface
        self.T = [T_init, T_init]
        self.models = [PreisachModel(s), PreisachModel(s)]
        self.eps = [model.reset(self._seen(T_init), self.sigma) for model in self.models]
        self.xi = [thermal.martensite_fraction(e, self.eps_max) for e in self.eps]
        self.power = [0.0, 0.0]
        self.theta = static_rotation(self.eps, self.xi, self.area, self.layout, self.beam)
        self.omega = 0.0
        self.tension = list(tensions(self.theta, self.eps, self.xi, self.area, self.layout))

    def _seen(self, T):
        """Temperature [C] the hysteresis sees: saturated at its grid's ends (§sma-wire)."""
        return min(max(T, self.surface.t_lo), self.surface.t_hi)

    def step(self, dt: float, u: Sequence[float], T_amb: float, t: float | None = None) -> None:
        """Advance by `dt` [s] from `t` [s] with the voltages `u` = (u_A, u_B) [V] and ambient
        `T_amb` [C] held."""
        R_s = self.layout.series_resistance
        for i, model in enumerate(self.models):
            R = thermal.resistance(self.xi[i], self.wire)
            current = u[i] / (R + R_s)
            self.power[i] = R * current * current
            self.T[i] = thermal.step(self.T[i], thermal.ThermalInputs(current, T_amb, self.xi[i]),
                                     dt, self.wire)
            self.eps[i] = model.step(self._seen(self.T[i]), self.sigma, t)
            self.xi[i] = thermal.martensite_fraction(self.eps[i], self.eps_max)
        n = max(1, math.ceil(dt / self.layout.max_substep - 1e-9))
        h = dt / n
        for _ in range(n):
            M0, K_w = moment_terms(self.theta, self.eps, self.xi, self.area, self.layout)
            K = self.K_beam + K_w
            self.theta, self.omega = beam.oscillator_step(self.theta, self.omega, M0 / K, K,
                                                          self.c, self.J, h)
        self.tension = list(tensions(self.theta, self.eps, self.xi, self.area, self.layout))

    def deflection(self, z: float) -> float:
        """Lateral deflection [m] at height `z` [m] (toward wire A positive)."""
        return beam.deflection(self.theta, z, self.beam)

    def velocity(self, z: float) -> float:
        """Lateral velocity [m/s] at height `z` [m]."""
        return beam.deflection(self.omega, z, self.beam)
