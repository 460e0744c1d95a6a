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

import numpy as np

from musclesim.components.checks import require
from musclesim.components.sma import preisach, surface as hypersurface, thermal
from musclesim.components.sma.preisach import mem_reset, mem_step
from musclesim.components.sma.reference_wire import ReferenceWire, WireParams, wire_table
from musclesim.components.sma.surface import S_THI, S_TLO, Hypersurface, fmax, fmin
from musclesim.components.sma.thermal import TP_SIZE, martensite_fraction_k, resistance_k, step_k
from musclesim.fmu import Kernel, declare, jit

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


# the wires' layout as a float64 array for the compiled functions below (`layout_array`): the
# moduli, the pretension, the offset, the wires' length and cross-section
L_EM, L_EA, L_PRETENSION, L_OFFSET, L_LENGTH, L_AREA = range(6)


def layout_array(layout: WireLayout, area: float) -> np.ndarray:
    """The `layout` of wires of cross-section `area` [m^2] as the compiled functions take it
    (slots ``L_*``)."""
    return np.array([layout.modulus_martensite, layout.modulus_austenite, layout.pretension,
                     layout.offset, layout.length, area], dtype=float)


def modulus(xi: float, layout: WireLayout) -> float:
    """Young's modulus of a wire of `layout` at martensite fraction `xi` (Reuss mix) [Pa]."""
    return float(modulus_k(layout_array(layout, 1.0), xi))


@jit
def modulus_k(lp: np.ndarray, xi: float) -> float:
    """`modulus` at martensite fraction `xi` of the layout array `lp`."""
    return 1.0 / (xi / lp[L_EM] + (1.0 - xi) / lp[L_EA])


def wire_terms(eps: float, xi: float, area: float, layout: WireLayout) -> tuple[float, float]:
    """(a, b) of a taut wire's tension a - s b theta [N, N/rad] (module equation), the wire of
    `layout` and cross-section `area` at strain `eps` and martensite fraction `xi`."""
    a, b = wire_terms_k(layout_array(layout, area), eps, xi)
    return float(a), float(b)


@jit
def wire_terms_k(lp: np.ndarray, eps: float, xi: float) -> tuple[float, float]:
    """`wire_terms` at strain `eps` and martensite fraction `xi` of the layout array `lp`."""
    E = modulus_k(lp, xi)
    area = lp[L_AREA]
    eps0 = lp[L_PRETENSION] / (lp[L_EM] * area)
    return E * area * (eps + eps0), E * area * lp[L_OFFSET] / lp[L_LENGTH]


def tensions(theta: float, eps: Sequence[float], xi: Sequence[float], area: float,
             layout: WireLayout) -> tuple[float, ...]:
    """Tensions (T_A, T_B) [N] of the wires at cap rotation `theta` (0 when slack), at strains
    `eps` and martensite fractions `xi`, of cross-section `area` and `layout`."""
    lp = layout_array(layout, area)
    return tuple(float(tension_k(lp, s, theta, e_i, x_i))
                 for s, e_i, x_i in zip((1.0, -1.0), eps, xi))


@jit
def tension_k(lp: np.ndarray, s: float, theta: float, eps: float, xi: float) -> float:
    """Tension [N] of the wire on side `s` (A +1, B -1) of the layout array `lp` at cap rotation
    `theta`, strain `eps` and martensite fraction `xi` (0 when slack)."""
    a, b = wire_terms_k(lp, eps, xi)
    return fmax(0.0, a - s * b * theta)


def moment_terms(theta: float, eps: Sequence[float], xi: Sequence[float], area: float,
                 layout: WireLayout) -> tuple[float, ...]:
    """(M0, K_w): the wires' moment on the cap is M0 - K_w theta near `theta` [N m, N m/rad];
    a wire slack at theta contributes nothing (`eps`, `xi`, `area`, `layout` as in `tensions`)."""
    M0, K = moment_terms_k(layout_array(layout, area), theta, eps[0], eps[1], xi[0], xi[1])
    return float(M0), float(K)


@jit
def moment_terms_k(lp: np.ndarray, theta: float, eps_a: float, eps_b: float, xi_a: float,
                   xi_b: float) -> tuple[float, float]:
    """`moment_terms` of the layout array `lp` at `theta`, wire A at (`eps_a`, `xi_a`), wire B
    at (`eps_b`, `xi_b`)."""
    M0 = K = 0.0
    e = lp[L_OFFSET]
    for s in (1.0, -1.0):
        a, b = wire_terms_k(lp, eps_a, xi_a) if s > 0 else wire_terms_k(lp, eps_b, xi_b)
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
    return float(static_rotation_k(layout_array(layout, area), beam.rotational_stiffness(beam_p),
                                   eps[0], eps[1], xi[0], xi[1]))


@jit
def static_rotation_k(lp: np.ndarray, K_beam: float, eps_a: float, eps_b: float, xi_a: float,
                      xi_b: float) -> float:
    """`static_rotation` of the layout array `lp` against the beams' stiffness `K_beam` [N
    m/rad], wire A at (`eps_a`, `xi_a`), wire B at (`eps_b`, `xi_b`)."""
    theta = 0.0
    for _ in range(4):  # at most one wire goes slack: two passes settle it
        M0, K_w = moment_terms_k(lp, theta, eps_a, eps_b, xi_a, xi_b)
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
    the sub-step's start). The physics is the compiled kernel below (`reset_k`, `step_bending`):
    the state lives in its arrays ``kp`` (`pack`) and ``kx`` (`state`), which the FMU steps;
    the attributes read them.

    Parameters
    ----------
    beam_p : beam.BeamParams
    layout : WireLayout
    wire : thermal.ThermalParams
        One wire's thermal data (both wires alike), under current drive (`wire_thermal`).
    surface : sma.surface.Hypersurface
        The wires' hysteresis at their pretension's stress (`hysteresis_surface`).
    z_tip : float
        Height [m] of the FMU's output tip.s (the study's laser, 17 mm).
    """

    def __init__(self, beam_p: beam.BeamParams, layout: WireLayout, wire: thermal.ThermalParams,
                 surface: Hypersurface, z_tip: float = 17e-3) -> None:
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
        memory = preisach.memory()
        self.kp = pack(self, z_tip, len(memory))
        self.kx = state(self.kp, memory)
        self.reset(20.0)

    def cold_stiffness(self) -> float:
        """Rotational stiffness [N m/rad] of beams and both taut, martensitic wires."""
        return self.K_beam + moment_terms(0.0, (0.0, 0.0), (1.0, 1.0), self.area, self.layout)[1]

    def reset(self, T_init: float) -> None:
        """Both wires at `T_init` [C] (heated there from martensite), the cap at rest in balance."""
        reset_k(self.kp, self.kx, T_init)

    def step(self, dt: float, u: Sequence[float], T_amb: float, t: float | None = None) -> None:
        """Advance by `dt` [s] from `t` [s] with the voltages `u` = (u_A, u_B) [V] and ambient
        `T_amb` [C] held."""
        step_bending(self.kp, self.kx, dt, u[0], u[1], T_amb)

    def _wires(self, slot: int) -> list[float]:
        return [float(self.kx[X_WIRES + i * self._stride() + slot]) for i in range(2)]

    def _stride(self) -> int:
        return W_MEMORY + int(self.kp[P_MEMORY])

    @property
    def T(self) -> list[float]:
        """The wires' temperatures [C], A then B."""
        return self._wires(W_T)

    @property
    def eps(self) -> list[float]:
        """The wires' strains (contraction, positive = shorter)."""
        return self._wires(W_EPS)

    @property
    def xi(self) -> list[float]:
        """The wires' martensite fractions."""
        return self._wires(W_XI)

    @property
    def power(self) -> list[float]:
        """The wires' Joule powers [W] over the last step."""
        return self._wires(W_P)

    @property
    def tension(self) -> list[float]:
        """The wires' tensions [N] (0 when slack)."""
        return self._wires(W_TENSION)

    @property
    def theta(self) -> float:
        """Rotation of the top cap [rad]."""
        return float(self.kx[X_THETA])

    @theta.setter
    def theta(self, value: float) -> None:
        self.kx[X_THETA] = value

    @property
    def omega(self) -> float:
        """Its rate [rad/s]."""
        return float(self.kx[X_OMEGA])

    @omega.setter
    def omega(self, value: float) -> None:
        self.kx[X_OMEGA] = value

    def deflection(self, z: float) -> float:
        """Lateral deflection [m] at height `z` [m] (toward wire A positive)."""
        return beam.deflection(self.theta, z, self.beam)

    def velocity(self, z: float) -> float:
        """Lateral velocity [m/s] at height `z` [m]."""
        return beam.deflection(self.omega, z, self.beam)


# --- the compiled kernel (`musclesim.fmu.kernel`): `BendingActuator`'s reset and step on float64
# arrays, operation for operation, so that it gives the same bits compiled or as Python ----------
ZERO_C = 273.15  # K; the FMU speaks K, the cores C
INPUTS = ("wireA.u", "wireB.u", "T_amb")
OUTPUTS = ("tip.s", "tip.v", "theta") + tuple(
    f"wire{side}.{v}" for side in SIDES for v in ("T", "strain", "f", "stress", "P"))

# parameter slots (`pack`): the layout array (``L_*``), then the series resistance, the longest
# sub-step, the beams' stiffness, the damping, the modal inertia, the hysteresis' stress and its
# maximum strain, the beams' length, the height of tip.s, the size of one Preisach memory; the
# wires' thermal parameters (`thermal.pack`) from P_THERMAL; the surface (`surface.pack`) from
# P_HEAD
(P_RS, P_MAX_SUBSTEP, P_K_BEAM, P_C, P_J, P_SIGMA, P_EPS_MAX, P_BEAM_LENGTH, P_Z_TIP,
 P_MEMORY) = range(6, 16)
P_THERMAL = 16
P_HEAD = P_THERMAL + TP_SIZE

# state slots (`state`): the cap's rotation and rate, then one block per wire (A, B): its
# temperature [C], strain, martensite fraction, power, tension, then its Preisach memory
X_THETA, X_OMEGA = range(2)
X_WIRES = 2
W_T, W_EPS, W_XI, W_P, W_TENSION = range(5)
W_MEMORY = 5


def pack(core: BendingActuator, z_tip: float, memory_size: int) -> np.ndarray:
    """The kernel's parameters of the actuator `core` (its beams, layout, wire and surface, and
    the constants it derives from them), tip.s read at `z_tip` [m], Preisach memories of
    `memory_size` floats (layout: the ``P_*`` slots)."""
    head = np.zeros(P_HEAD)
    head[:P_RS] = layout_array(core.layout, core.area)
    head[P_RS:P_THERMAL] = [core.layout.series_resistance, core.layout.max_substep, core.K_beam,
                            core.c, core.J, core.sigma, core.eps_max, core.beam.length, z_tip,
                            memory_size]
    head[P_THERMAL:P_HEAD] = thermal.pack(core.wire)
    return np.concatenate([head, hypersurface.packed(core.surface)])


def state(p: np.ndarray, memory: np.ndarray) -> np.ndarray:
    """A state array for the parameters `p` (`pack`), each wire's Preisach memory a copy of the
    new `memory` (`preisach.memory`); `reset_k` sets it."""
    stride = W_MEMORY + len(memory)
    x = np.zeros(X_WIRES + 2 * stride)
    for i in range(2):
        x[X_WIRES + i * stride + W_MEMORY:X_WIRES + (i + 1) * stride] = memory
    return x


@jit
def _wire(p: np.ndarray, x: np.ndarray, i: int) -> np.ndarray:
    """Wire `i`'s block (0 A, 1 B) of the state `x`, parameters `p`."""
    stride = W_MEMORY + int(p[P_MEMORY])
    return x[X_WIRES + i * stride:X_WIRES + (i + 1) * stride]


@jit
def _seen(s: np.ndarray, T: float) -> float:
    """`BendingActuator._seen`: temperature [C] the hysteresis (packed surface `s`) sees,
    saturated at its grid's ends."""
    return fmin(fmax(T, s[S_TLO]), s[S_THI])


@jit
def _tensions(p: np.ndarray, x: np.ndarray) -> None:
    """The wires' tensions at the state `x`'s rotation."""
    a, b = _wire(p, x, 0), _wire(p, x, 1)
    a[W_TENSION] = tension_k(p, 1.0, x[X_THETA], a[W_EPS], a[W_XI])
    b[W_TENSION] = tension_k(p, -1.0, x[X_THETA], b[W_EPS], b[W_XI])


@jit
def reset_k(p: np.ndarray, x: np.ndarray, T_init: float) -> None:
    """`BendingActuator.reset` of the parameters `p` into the state `x`: both wires at `T_init`
    [C] (heated there from martensite), the cap at rest in balance."""
    s = p[P_HEAD:]
    for i in range(2):
        g = _wire(p, x, i)
        g[W_T] = T_init
        eps = mem_reset(s, g[W_MEMORY:], _seen(s, T_init), p[P_SIGMA])
        g[W_EPS] = eps
        g[W_XI] = martensite_fraction_k(eps, p[P_EPS_MAX])
        g[W_P] = 0.0
    a, b = _wire(p, x, 0), _wire(p, x, 1)
    x[X_THETA] = static_rotation_k(p, p[P_K_BEAM], a[W_EPS], b[W_EPS], a[W_XI], b[W_XI])
    x[X_OMEGA] = 0.0
    _tensions(p, x)


@jit
def step_bending(p: np.ndarray, x: np.ndarray, dt: float, u_a: float, u_b: float,
                 T_amb: float) -> None:
    """`BendingActuator.step` of the parameters `p`: advance the state `x` by `dt` [s] with the
    voltages `u_a`, `u_b` [V] and ambient `T_amb` [C] held."""
    s = p[P_HEAD:]
    tp = p[P_THERMAL:P_HEAD]
    R_s = p[P_RS]
    for i in range(2):
        g = _wire(p, x, i)
        R = resistance_k(tp, g[W_XI])
        current = (u_a if i == 0 else u_b) / (R + R_s)
        g[W_P] = R * current * current
        g[W_T] = step_k(tp, g[W_T], current, T_amb, g[W_XI], 0.0, dt)
        g[W_EPS] = mem_step(s, g[W_MEMORY:], _seen(s, g[W_T]), p[P_SIGMA])
        g[W_XI] = martensite_fraction_k(g[W_EPS], p[P_EPS_MAX])
    n = max(1, int(math.ceil(dt / p[P_MAX_SUBSTEP] - 1e-9)))
    h = dt / n
    a, b = _wire(p, x, 0), _wire(p, x, 1)
    for _ in range(n):
        M0, K_w = moment_terms_k(p, x[X_THETA], a[W_EPS], b[W_EPS], a[W_XI], b[W_XI])
        K = p[P_K_BEAM] + K_w
        x[X_THETA], x[X_OMEGA] = beam.oscillator_step_k(x[X_THETA], x[X_OMEGA], M0 / K, K,
                                                        p[P_C], p[P_J], h)
    _tensions(p, x)


@jit
def evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """The outputs `y` (`OUTPUTS`) of the state `x` after the last step, parameters `p` (the
    inputs `u` and the time `t` play no part: no direct feedthrough)."""
    y[0] = beam.deflection_k(x[X_THETA], p[P_Z_TIP], p[P_BEAM_LENGTH])
    y[1] = beam.deflection_k(x[X_OMEGA], p[P_Z_TIP], p[P_BEAM_LENGTH])
    y[2] = x[X_THETA]
    for i in range(2):
        g = _wire(p, x, i)
        y[3 + 5 * i] = g[W_T] + ZERO_C
        y[4 + 5 * i] = g[W_EPS]
        y[5 + 5 * i] = g[W_TENSION]
        y[6 + 5 * i] = g[W_TENSION] / p[L_AREA]
        y[7 + 5 * i] = g[W_P]


@jit
def advance(p: np.ndarray, x: np.ndarray, u: np.ndarray, y: np.ndarray, t: float,
            dt: float) -> None:
    """Step the actuator of parameters `p`, state `x`, over [`t`, `t` + `dt`] [s] with the
    inputs `u` (`INPUTS`) held (the outputs `y` play no part)."""
    step_bending(p, x, dt, u[0], u[1], u[2] - ZERO_C)


KERNEL = Kernel(evaluate, advance, INPUTS, OUTPUTS)
