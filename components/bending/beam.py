"""The bending actuator's carbon-fibre beam pair as a leaf spring with its first bending mode
(§bending-actuator): Euler-Bernoulli beams clamped in the base cap, loaded at the top cap by the
wires' eccentric tension, i.e. by an end moment M.

Under a pure end moment the beams bend with uniform curvature M / EI, so the top cap (rigid, at
height L) turns by theta = M L / EI and every point of the actuator deflects as

    w(z) = theta z^2 / (2 L)            for z <= L (the beams)
    w(z) = theta (z - L / 2)            for z >= L (the rigid cap and the foot above it)

The first bending mode is taken with this shape (Rayleigh): one coordinate theta with rotational
stiffness K = EI / L (plus what the wires add), modal inertia J = m_tip (z_tip - L / 2)^2 + m_beams
L^2 / 20 (the cap and foot as a point mass), viscous damping c = 2 zeta sqrt(K J). Lengths in m,
angles in rad.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from musclesim.components.checks import require
from musclesim.fmu import declare, jit


@dataclass(frozen=True)
class BeamParams:
    """Beam pair, caps and foot (§bending-actuator leaves all but the cap spacing open: defaults and
    their reasons in §bending-actuator). Each parameter is declared once here (`declare`): the FMU
    and the docs' tables read it."""

    length: float = declare(10e-3, "m", "Free beam length between the caps (the study: caps "
                            "10 mm apart)", source="§bending-actuator")
    n_beams: float = declare(2.0, "1", "Number of coplanar beams (the study: 2)",
                             source="§bending-actuator", type="Integer")
    width: float = declare(1.0e-3, "m", "Width of each beam (open; assumption: a common "
                           "pultruded carbon-fibre strip)", source="§bending-actuator")
    thickness: float = declare(0.2e-3, "m", "Thickness of each beam in the bending direction "
                               "(open; at 0.2 mm the beams' EI / L, 0.016 N m/rad, equals one "
                               "cold wire's e^2 E_M A_w / L_w: the beams are the return spring "
                               "without the wires pulling against a wall)",
                               source="§bending-actuator")
    modulus: float = declare(120e9, "Pa", "Young's modulus of the beams (open; assumption: "
                             "unidirectional carbon fibre along the fibres, 110 to 140 GPa)",
                             source="§bending-actuator")
    density: float = declare(1600.0, "kg/m3", "Density of the beams (open; assumption: "
                             "carbon-fibre composite; the beams hardly count in the modal "
                             "inertia)", source="§bending-actuator")
    tip_mass: float = declare(0.2e-3, "kg", "Mass of the top cap and foot (open; assumption: an "
                              "FR4 cap of about 10 x 4 x 1.6 mm, 0.12 g, and the foot above it up "
                              "to the laser's 17 mm)", source="§bending-actuator")
    tip_height: float = declare(13e-3, "m", "Height of their centre of mass above the base "
                                "(open)", source="§bending-actuator")
    damping_ratio: float = declare(0.03, "1", "Damping ratio of the first bending mode with both "
                                   "wires cold (open; assumption: a carbon-fibre beam in air with "
                                   "the wires' internal friction)", source="§bending-actuator")

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("length", "n_beams", "width", "thickness", "modulus",
                                "density", "tip_mass"),
                non_negative=("tip_height", "damping_ratio"))


def bending_stiffness(p: BeamParams) -> float:
    """EI of the beam pair `p` [N m^2]: n E b t^3 / 12.

    Examples
    --------
    >>> round(bending_stiffness(BeamParams(n_beams=1, width=1e-3, thickness=1e-3,
    ...                                    modulus=12e9)), 12)
    0.001
    """
    return p.n_beams * p.modulus * p.width * p.thickness ** 3 / 12


def rotational_stiffness(p: BeamParams) -> float:
    """End moment per rotation of the top cap of the beams `p`, EI / L [N m/rad]."""
    return bending_stiffness(p) / p.length


def deflection(theta: float, z: float, p: BeamParams) -> float:
    """Lateral deflection [m] of the beams `p` at height `z` [m] above the base for a cap rotation
    `theta` [rad].

    Examples
    --------
    >>> p = BeamParams(length=0.01)
    >>> round(deflection(0.01, 0.017, p), 9), round(deflection(0.01, 0.01, p), 9)
    (0.00012, 5e-05)
    """
    return float(deflection_k(theta, z, p.length))


@jit
def deflection_k(theta: float, z: float, L: float) -> float:
    """`deflection` at height `z` [m] for a cap rotation `theta` [rad] of beams of length `L`
    [m]."""
    if z >= L:
        return theta * (z - L / 2)
    return theta * z * z / (2 * L)


def lever(z: float, p: BeamParams) -> float:
    """d(deflection at `z`) / d theta [m/rad] of the beams `p`: how far a point at height z moves
    per radian."""
    return deflection(1.0, z, p)


def beam_mass(p: BeamParams) -> float:
    """Mass of the beam pair `p` [kg]."""
    return p.n_beams * p.width * p.thickness * p.length * p.density


def modal_inertia(p: BeamParams) -> float:
    """Inertia of the first mode of the beams `p` in the coordinate theta [kg m^2] (module
    equation)."""
    arm = lever(p.tip_height, p)
    return p.tip_mass * arm * arm + beam_mass(p) * p.length ** 2 / 20


def natural_frequency(K: float, p: BeamParams) -> float:
    """Undamped first resonance [Hz] of the beams `p` for a total rotational stiffness `K`
    [N m/rad]."""
    return math.sqrt(K / modal_inertia(p)) / (2 * math.pi)


def damping_coefficient(K_ref: float, p: BeamParams) -> float:
    """Viscous damping c [N m s/rad] giving the damping ratio of the beams `p` at stiffness
    `K_ref`."""
    return 2 * p.damping_ratio * math.sqrt(K_ref * modal_inertia(p))


def oscillator_step(x: float, v: float, x_eq: float, K: float, c: float, J: float,
                    dt: float) -> tuple[float, float]:
    """Exact solution of `J` x'' + `c` x' + `K` (x - `x_eq`) = 0 after `dt` from (`x`, `v`):
    return (x, v).

    Stable at any step; exact while K, c and x_eq are held.

    Examples
    --------
    >>> x, v = oscillator_step(1.0, 0.0, 0.0, 4.0, 0.0, 1.0, math.pi)  # one period of omega = 2
    >>> round(x, 12), round(v, 12)
    (1.0, 0.0)
    """
    x_new, v_new = oscillator_step_k(x, v, x_eq, K, c, J, dt)
    return float(x_new), float(v_new)


@jit
def oscillator_step_k(x: float, v: float, x_eq: float, K: float, c: float, J: float,
                      dt: float) -> tuple[float, float]:
    """`oscillator_step`: (x, v) of `J` x'' + `c` x' + `K` (x - `x_eq`) = 0 after `dt` from
    (`x`, `v`)."""
    y = x - x_eq
    w = math.sqrt(K / J)
    zeta = c / (2 * math.sqrt(K * J))
    if zeta < 1 - 1e-9:
        wd = w * math.sqrt(1 - zeta * zeta)
        e = math.exp(-zeta * w * dt)
        cs, sn = math.cos(wd * dt), math.sin(wd * dt)
        y_new = e * (y * cs + (v + zeta * w * y) / wd * sn)
        v_new = e * (v * cs - (w * w * y + zeta * w * v) / wd * sn)
        return x_eq + y_new, v_new
    if zeta <= 1 + 1e-9:  # critical damping
        e = math.exp(-w * dt)
        b = v + w * y
        return x_eq + e * (y + b * dt), e * (v - w * b * dt)
    root = w * math.sqrt(zeta * zeta - 1)
    r1, r2 = -zeta * w + root, -zeta * w - root
    a = (v - r2 * y) / (r1 - r2)
    b = y - a
    e1, e2 = math.exp(r1 * dt), math.exp(r2 * dt)
    return x_eq + a * e1 + b * e2, r1 * a * e1 + r2 * b * e2
