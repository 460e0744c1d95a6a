"""The quadruped's body and feet (§quadruped): a body of mass M moving along x on four legs, each
foot a point of the leg's modal mass m_f held by the leg's lateral stiffness k and damping c:

    F_i   = k (x_b + s_i(t) - x_i) + c (v_b + s_i'(t) - v_i)     (leg force on foot i)
    m_f x_i'' = F_i + f_i,       M x_b'' = -sum_i F_i

s_i(t) is leg i's unloaded deflection at its foot (the BendingActuator FMU's tip.s, toward +x; held
as s_i + s_i' tau over a communication step): the loaded leg deflects by superposition, its own
dynamics (first mode, in the leg's FMU) give s_i, the foot's load adds F / k with the foot's own
small mass m_f. The coupling is one way: the foot's load does not reach the leg's mode or its wires'
stress (ground contact does not damp the leg's ringing; §quadruped). f_i is the crawler's stick-slip
friction (`crawler.friction.friction_force`, §friction) with coefficients chosen by direction: a
foot sliding, or pushed, toward +x slides easily (hook trailing), toward -x it grips. Each foot
carries a quarter of the weight. The body does not touch the ground.

Numerics: semi-implicit Euler in sub-steps of at most ``max_substep``. A foot inside the stick band
whose force stays below static friction stops (velocity 0), and a kinetic step that would reverse a
foot's velocity stops it there: without these remedies (§stick-slip-numerics) a foot chatters at the
per-step change of velocity, larger than any band narrow enough for feet moving at mm/s.

The FMU's kernel (`KERNEL`, compiled where numba is installed: `musclesim.fmu.compiled`) and
`Quadruped` run the same `step_core` on arrays: parameters `pack`; state `STATE` = [x, v, the
feet's positions (4), their velocities (4), their frictions (4), the legs' held deflections (4)];
inputs u = [s_1, s_1', s_2, s_2', ...] (`INPUTS`); outputs y = [x, v, then per foot its position,
friction and stuck flag] (`OUTPUTS`).
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import astuple, dataclass

import numpy as np

from musclesim.components.bending import actuator, beam
from musclesim.components.checks import require
from musclesim.components.crawler import friction
from musclesim.fmu import Kernel, declare, jit

G = 9.81  # m/s^2
LEGS = 4
FOOT_HEIGHT = 17e-3  # m, the foot point the body sees: where the study's laser reads (§quadruped)


def leg_stiffness() -> float:
    """Lateral stiffness [N/m] of a default bending-actuator leg at FOOT_HEIGHT: its first mode's
    stiffness with both wires cold, seen at the foot (K / lever^2)."""
    b, layout = beam.BeamParams(), actuator.WireLayout()
    area = math.pi * actuator.WIRE_50UM["diameter"] ** 2 / 4
    K = beam.rotational_stiffness(b) + actuator.moment_terms(0.0, (0.0, 0.0), (1.0, 1.0), area,
                                                             layout)[1]
    arm = beam.lever(FOOT_HEIGHT, b)
    return K / arm ** 2


LEG_STIFFNESS = leg_stiffness()


@dataclass(frozen=True)
class QuadrupedParams:
    """Body, legs and feet (§quadruped leaves them open: defaults and reasons in §quadruped).
    Each parameter is declared once here (`declare`): the FMU and the docs' tables read it."""

    body_mass: float = declare(5e-3, "kg", "Mass of the frame and the four actuators (open; "
                               "assumption: an FR4 frame with eight wires, caps and feet)",
                               source="§quadruped")
    foot_mass: float = declare(1e-5, "kg", "Mass of each foot's tip and hook (open; its mode on "
                               "the leg's stiffness, about 900 Hz, stays well above the leg's "
                               "own, about 300 Hz, so the two do not ring together)",
                               source="§quadruped")
    leg_stiffness: float = declare(LEG_STIFFNESS, "N/m", "Lateral stiffness of a leg at its "
                                   "foot (default: a default BendingActuator's cold stiffness "
                                   "there, K_cold / (z - L/2)^2 at z = 17 mm)",
                                   source="§quadruped")
    leg_damping_ratio: float = declare(0.03, "1", "Damping ratio of a foot on its leg's "
                                       "stiffness (open: as the bending actuator's first mode)",
                                       source="§quadruped")
    mu_s_forward: float = declare(0.2, "1", "Static friction of a foot toward +x, hook trailing "
                                  "(open; assumption: carbon fibre on a board)",
                                  source="§quadruped")
    mu_k_forward: float = declare(0.15, "1", "Kinetic friction of a foot toward +x: 0.75 "
                                  "static, as the crawler's", source="§quadruped, §friction")
    mu_s_backward: float = declare(0.8, "1", "Static friction of a foot toward -x, hook gripping "
                                   "(open)", source="§quadruped")
    mu_k_backward: float = declare(0.6, "1", "Kinetic friction of a foot toward -x: 0.75 "
                                   "static, as the crawler's", source="§quadruped, §friction")
    v_s: float = declare(1e-5, "m/s", "Stick velocity band of the feet in the crawler's "
                         "friction law (open: far below the feet's mm/s; the crawler's 1 mm/s "
                         "band is faster than this robot)", source="§quadruped, §friction")
    max_substep: float = declare(2e-5, "s", "Longest internal sub-step (numerics: about 1/8 of a "
                                 "radian of the foot's mode)", source="§quadruped")

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        require(self, positive=("body_mass", "foot_mass", "leg_stiffness", "v_s", "max_substep"),
                non_negative=("leg_damping_ratio", "mu_s_forward", "mu_k_forward",
                              "mu_s_backward", "mu_k_backward"))


def normal_force(p: QuadrupedParams) -> float:
    """Normal force on each foot of `p` [N]: a quarter of the weight of body and feet."""
    return (p.body_mass + LEGS * p.foot_mass) * G / LEGS


def leg_damping(p: QuadrupedParams) -> float:
    """Damping c [N s/m] of a leg of `p` at its foot from its damping ratio."""
    return 2 * p.leg_damping_ratio * math.sqrt(p.leg_stiffness * p.foot_mass)


# the kernel's parameters (`pack`): the fields in their declared order, then N and c
(BODY_MASS, FOOT_MASS, STIFFNESS, DAMPING_RATIO, MU_S_FORWARD, MU_K_FORWARD, MU_S_BACKWARD,
 MU_K_BACKWARD, V_S, MAX_SUBSTEP, NORMAL, DAMPING) = range(12)
# the kernel's state (`STATE` values): body position and velocity, then four values per foot each
X, V, FEET_X, FEET_V, FORCES, S_HELD = 0, 1, 2, 2 + LEGS, 2 + 2 * LEGS, 2 + 3 * LEGS
STATE = 2 + 4 * LEGS
INPUTS = tuple(f"leg{i}.{q}" for i in range(1, LEGS + 1) for q in ("s", "v"))
OUTPUTS = ("x", "v") + tuple(f"foot{i}.{q}" for i in range(1, LEGS + 1)
                             for q in ("s", "f", "stuck"))


def pack(p: QuadrupedParams) -> np.ndarray:
    """The kernel's parameters: `p`'s fields in their declared order (body_mass, foot_mass,
    leg_stiffness, leg_damping_ratio, mu_s_forward, mu_k_forward, mu_s_backward, mu_k_backward,
    v_s, max_substep), then each foot's normal force N (`normal_force`) and the legs' damping c
    (`leg_damping`)."""
    return np.array([*astuple(p), normal_force(p), leg_damping(p)], dtype=float)


def coefficients(v: float, f_n: float, p: QuadrupedParams) -> tuple[float, float]:
    """(mu_s, mu_k) of a foot of `p` moving at `v` [m/s] under the net force `f_n` [N]: by the
    direction of sliding, or of the force that would start it (+x: forward, easy; -x: backward,
    grip).

    Examples
    --------
    >>> p = QuadrupedParams()
    >>> coefficients(0.01, -1.0, p), coefficients(0.0, -1.0, p)
    ((0.2, 0.15), (0.8, 0.6))
    """
    mu_s, mu_k = coefficients_core(float(v), float(f_n), pack(p))
    return float(mu_s), float(mu_k)


@jit
def coefficients_core(v: float, f_n: float, p: np.ndarray) -> tuple[float, float]:
    """`coefficients` of a foot moving at `v` [m/s] under the net force `f_n` [N], the packed
    parameters `p` (`pack`)."""
    direction = v if abs(v) > p[V_S] else f_n
    if direction > 0:
        return p[MU_S_FORWARD], p[MU_K_FORWARD]
    return p[MU_S_BACKWARD], p[MU_K_BACKWARD]


@jit
def step_core(p: np.ndarray, x: np.ndarray, u: np.ndarray, dt: float) -> None:
    """Advance the state `x` (`STATE` values) by `dt` [s] in place with the legs' deflections and
    their rates `u` = [s_1, s_1', s_2, s_2', ...] [m, m/s] at the start of the step, each leg
    held as s + s' tau over it (parameters `p` from `pack`): `Quadruped.step`."""
    N, k, c, v_s, m_f = p[NORMAL], p[STIFFNESS], p[DAMPING], p[V_S], p[FOOT_MASS]
    n = max(1, math.ceil(dt / p[MAX_SUBSTEP] - 1e-9))
    h = dt / n
    for j in range(n):
        tau = j * h
        push = 0.0
        for i in range(LEGS):
            s, s_dot = u[2 * i], u[2 * i + 1]
            F = k * (x[X] + s + s_dot * tau - x[FEET_X + i]) + c * (x[V] + s_dot - x[FEET_V + i])
            v = x[FEET_V + i]
            mu_s, mu_k = coefficients_core(v, F, p)
            f = friction.friction_force(v, F, N, mu_s, mu_k, v_s)
            x[FORCES + i] = f
            if abs(v) <= v_s and abs(F) <= mu_s * N:
                x[FEET_V + i] = 0.0  # stuck: holds still
            else:
                v_new = v + h * (F + f) / m_f
                x[FEET_V + i] = 0.0 if (abs(v) > v_s and v_new * v < 0) else v_new
            x[FEET_X + i] += h * x[FEET_V + i]
            push += F
        x[V] -= h * push / p[BODY_MASS]
        x[X] += h * x[V]
    for i in range(LEGS):
        x[S_HELD + i] = u[2 * i] + u[2 * i + 1] * dt


@jit
def evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """Kernel outputs `y` (`OUTPUTS`: x, v, then per foot its position, its friction over the
    last sub-step and 1.0 while it holds still, else 0.0) of the state `x` (parameters `p`,
    inputs `u` and time `t` do not matter)."""
    y[0], y[1] = x[X], x[V]
    for i in range(LEGS):
        y[2 + 3 * i] = x[FEET_X + i]
        y[3 + 3 * i] = x[FORCES + i]
        y[4 + 3 * i] = 1.0 if x[FEET_V + i] == 0.0 else 0.0


@jit
def advance(p: np.ndarray, x: np.ndarray, u: np.ndarray, y: np.ndarray, t: float,
            dt: float) -> None:
    """Kernel step of the state `x` over [`t`, `t` + `dt`] [s] with the inputs `u` (`INPUTS`)
    held (parameters `p`; the outputs `y` are not needed): `step_core`."""
    step_core(p, x, u, dt)


# a NaN deflection or rate is refused ("input leg1.s is NaN at t = ..."): a range without bounds
KERNEL = Kernel(evaluate, advance, INPUTS, OUTPUTS,
                clamps=tuple((name, -math.inf, math.inf) for name in INPUTS))


class Quadruped:
    """Body and feet stepped together (module equation); state in one array (`STATE`), read
    through the attributes below as plain floats and lists.

    Examples
    --------
    Legs bent 0.1 mm forward at once: the feet break loose and slide forward, easily.

    >>> p = QuadrupedParams()
    >>> q = Quadruped(p)
    >>> q.step(p.max_substep, [1e-4] * 4, [0.0] * 4)
    >>> [round(f / normal_force(p), 3) for f in q.forces], q.feet_x[0] > 0
    ([-0.15, -0.15, -0.15, -0.15], True)
    """

    def __init__(self, p: QuadrupedParams) -> None:
        """The quadruped of parameters `p` (checked here), at rest."""
        p.check()
        self.p = p
        self.N = normal_force(p)
        self.c = leg_damping(p)
        self.packed = pack(p)
        self.reset()

    def reset(self) -> None:
        """Body and feet at rest at x = 0, legs straight."""
        self.state = np.zeros(STATE)

    @property
    def x(self) -> float:
        """Position of the body [m]."""
        return float(self.state[X])

    @property
    def v(self) -> float:
        """Velocity of the body [m/s]."""
        return float(self.state[V])

    @property
    def feet_x(self) -> list[float]:
        """Position of each foot [m]."""
        return self.state[FEET_X:FEET_X + LEGS].tolist()

    @property
    def feet_v(self) -> list[float]:
        """Velocity of each foot [m/s]."""
        return self.state[FEET_V:FEET_V + LEGS].tolist()

    @property
    def forces(self) -> list[float]:
        """Friction on each foot over the last sub-step [N]."""
        return self.state[FORCES:FORCES + LEGS].tolist()

    @property
    def s_held(self) -> list[float]:
        """Each leg's deflection held to the end of the last step, s + s' dt [m]."""
        return self.state[S_HELD:S_HELD + LEGS].tolist()

    def step(self, dt: float, s: Sequence[float], s_dot: Sequence[float]) -> None:
        """Advance by `dt` [s] with the legs' deflections `s` [m] and their rates `s_dot` [m/s] at
        the start of the step, each leg held as s + s_dot tau over it (`step_core`)."""
        u = np.array([q for i in range(LEGS) for q in (s[i], s_dot[i])], dtype=float)
        step_core(self.packed, self.state, u, float(dt))

    def stuck(self, i: int) -> bool:
        """Whether foot `i` holds still (its velocity is 0)."""
        return bool(self.state[FEET_V + i] == 0.0)
