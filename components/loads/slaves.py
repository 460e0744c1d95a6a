"""FMU slaves of the loads: kernels (`musclesim.fmu.kernel`) over the jit cores of
musclesim.components.loads.loads.

Every load reads the wire's contraction `flange.s` [m] and gives the tension `flange.f` [N] it
puts on the wire (the SmaWire FMU's convention); equations in §loads.

Packed layouts (index constants below): BiasSpring kp = [k, preload], no state. DeadWeight kp =
[mass, g, inertia, k_link, zeta, omega (the link's angular frequency)], kx = [x, v (the moving
share's position and velocity), t, s (time and contraction at the last step), the step the link's
transition was computed for (NaN: none; the kernel computes it anew when the step changes), its
elements phi00, phi01, phi10, phi11]. Electromagnet
kp = [m_cal, g, V_supply, R, L, k_f, nonlinearity], kx = [coil current].
"""
from __future__ import annotations

import math

import numpy as np

from musclesim.components.loads import loads
from musclesim.fmu import Kernel, KernelSlave, experiment, jit, no_state

S_DESCRIPTION = "Contraction of the wire (SmaWire flange.s); positive = the wire shortens"

K, PRELOAD = range(2)  # BiasSpring's kp
MASS, G, INERTIA, K_LINK, ZETA, OMEGA = range(6)  # DeadWeight's kp
X, V, T_LAST, S_LAST, PHI_DT, PHI00, PHI01, PHI10, PHI11 = range(9)  # DeadWeight's kx
M_CAL, G_MAG, V_SUPPLY, R, L, K_F, NONLINEARITY = range(7)  # Electromagnet's kp; kx = [i]



@jit
def spring_evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """BiasSpring's kernel: writes the output `y` = (flange.f) from the input `u` = (flange.s) of
    the parameters `p`; no state `x`, the time `t` unused."""
    y[0] = loads.spring_core(u[0], p[K], p[PRELOAD])


@jit
def weight_evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """DeadWeight's kernel: writes the outputs `y` = (flange.f, lift) from the state `x` and the
    input `u` = (flange.s) of the parameters `p`; the time `t` unused."""
    y[0] = loads.weight_tension_core(x[X], u[0], p[MASS], p[G], p[INERTIA], p[K_LINK])
    y[1] = loads.weight_lift_core(x[X], u[0], p[INERTIA])


@jit
def weight_advance(p: np.ndarray, x: np.ndarray, u: np.ndarray, y: np.ndarray, t: float,
                   dt: float) -> None:
    """DeadWeight's kernel: the moving share's step of the state `x` (in place) from `t` over
    `dt`, the wire's end `u` = (flange.s), of the parameters `p`; the link's transition over `dt`
    kept in `x` (computed when the step changes); the outputs `y` unused."""
    if p[INERTIA] == 0.0:
        return
    if x[PHI_DT] != dt:
        phi = np.empty((2, 2))
        loads.link_transition_into(p[OMEGA], p[ZETA], dt, phi)
        x[PHI_DT], x[PHI00], x[PHI01], x[PHI10], x[PHI11] = (dt, phi[0, 0], phi[0, 1], phi[1, 0],
                                                              phi[1, 1])
    s = u[0]
    slope = (s - x[S_LAST]) / (t - x[T_LAST]) if t > x[T_LAST] else 0.0
    x[X], x[V] = loads.weight_step_core(x[X], x[V], s, slope, x[PHI00], x[PHI01], x[PHI10],
                                        x[PHI11], dt, p[ZETA], p[OMEGA])
    x[T_LAST] = t
    x[S_LAST] = s


@jit
def magnet_evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """Electromagnet's kernel: writes the outputs `y` = (flange.f, i) from the state `x` = (i) of
    the parameters `p`; the inputs `u` and time `t` unused."""
    y[0] = loads.magnet_tension_core(x[0], p[M_CAL], p[G_MAG], p[K_F], p[NONLINEARITY])
    y[1] = x[0]


@jit
def magnet_advance(p: np.ndarray, x: np.ndarray, u: np.ndarray, y: np.ndarray, t: float,
                   dt: float) -> None:
    """Electromagnet's kernel: the coil current's exact step of the state `x` = (i) in place over
    `dt`, the inputs `u` = (duty, flange.s) held, of the parameters `p`; the outputs `y` and time
    `t` unused."""
    x[0] = loads.coil_step_core(x[0], u[0], dt, p[V_SUPPLY], p[R], p[L])


class BiasSpring(KernelSlave):
    """Preloaded bias spring stretched by the wire's contraction (§loads)."""

    default_experiment = experiment(10.0, 0.00025)  # §multiplier-experiments (pulses)
    description = "Bias spring: tension preload + k s on the wire (§loads: 490 N/m, ~125 MPa)"
    kernel = Kernel(spring_evaluate, no_state, ("flange.s",), ("flange.f",))

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(loads.SpringParams)
        self.input("flange.s", 0.0, "m", S_DESCRIPTION, plausible="difference")
        self.output("flange.f", "N", "Tension of the spring on the wire", depends=["flange.s"])

    def setup(self) -> None:
        self.p = self.core_params(loads.SpringParams)
        self.kp = np.array([self.p.k, self.p.preload], dtype=float)


class DeadWeight(KernelSlave):
    """Weight hanging from the wire, quasi-static by default; inertia is an effect (§loads,
    §named-effects)."""

    default_experiment = experiment(20.0, 0.0004)  # §multiplier-experiments (bang-bang)
    description = ("Dead weight on the wire: tension m g, or (inertia effect) a mass on a "
                   "spring link pulled by the wire, its motion damped: m g + k_link (s - lift)")
    kernel = Kernel(weight_evaluate, weight_advance, ("flange.s",), ("flange.f", "lift"))

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(loads.WeightParams)
        self.input("flange.s", 0.0, "m", S_DESCRIPTION + ", lifting the weight",
                   plausible="difference")
        self.output("flange.f", "N", "Tension of the weight on the wire", depends=["flange.s"])
        self.output("lift", "m", "Lift of the weight (= flange.s unless its inertia is on)",
                    depends=["flange.s"])

    def setup(self) -> None:
        p = self.p = self.core_params(loads.WeightParams)
        self.kp = np.array([p.mass, p.g, p.inertia, p.k_link, p.zeta, loads.link_omega(p)])
        self.initialize()

    def initialize(self) -> None:
        # at rest at the wire's end; no transition computed yet
        self.kx = np.array([self.flange_s, 0.0, self.time, self.flange_s, math.nan, 0.0, 0.0, 0.0,
                            0.0])


class Electromagnet(KernelSlave):
    """Calibration weight plus a PWM-driven coil pulling a rare-earth magnet (§sma-bench,
    §loads)."""

    default_experiment = experiment(550.0, 0.0004)  # sma-position-control, §position-control
    description = ("Electromagnet load: 100 g calibration weight plus a coil (L di/dt = V duty - "
                   "R i) pulling a magnet with k_f i (1 + nonlinearity i) (§sma-bench)")
    kernel = Kernel(magnet_evaluate, magnet_advance, ("duty", "flange.s"), ("flange.f", "i"),
                    clamps=(("duty", 0.0, 1.0),))

    def __init__(self, **kwargs: object) -> None:
        super().__init__(**kwargs)
        self.parameters_of(loads.MagnetParams)
        self.input("duty", 0.0, "1", "PWM duty of the coil voltage, 0..1 (clamped, with one "
                   "warning)")
        self.input("flange.s", 0.0, "m", S_DESCRIPTION + " (the force does not depend on it)",
                   plausible="difference")
        self.output("flange.f", "N", "Tension on the wire: calibration weight plus the coil's pull")
        self.output("i", "A", "Coil current")

    def setup(self) -> None:
        p = self.p = self.core_params(loads.MagnetParams)
        self.kp = np.array([p.m_cal, p.g, p.V_supply, p.R, p.L, p.k_f, p.nonlinearity])
        self.kx = np.zeros(1)

    def initialize(self) -> None:
        duty = self.clamped_input("duty", 0.0, 1.0, self.time)
        self.kx = np.array([loads.coil_steady(duty, self.p)])  # settled at the start
