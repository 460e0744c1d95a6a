"""The independent crawler bench's air (`musclesim.benchmark.benches.crawler`): valve laws,
spools and chambers, each in several forms the bench's fields choose. Written apart from the
library: numpy and scipy only.

- Valve laws (`VALVE_LAWS`), each linear within 0.1 % of equal pressures (a regularisation of
  the bench: the square-root laws' infinite slope there would ring the small chambers):

  - ``"nozzle"``: the isentropic nozzle, Saint-Venant-Wantzel (Beater, "Pneumatic drives",
    Springer 2007, ch. 3), choked below ``R_CRIT``;
  - ``"orifice"``: the incompressible orifice, ``A sqrt(2 rho_up dp)`` (Bernoulli; White, "Fluid
    mechanics", §6.12), never choked;
  - ``"iso6358"``: ISO 6358's sonic conductance and critical ratio ``b`` with its elliptic subsonic
    law (ISO 6358-1:2013), the conductance chosen so that the choked flow is the nozzle's at the
    same area (`iso6358_conductance`): the forms differ in shape, not in size.
- Spools (`SPOOLS`), the opening following the PWM valve's open share: ``"first-order"`` (a lag
  ``tau_valve``); ``"second-order"`` (a damped oscillator of natural frequency ``1 / tau_valve``
  and damping ``spool_zeta``, advanced exactly over a step, its opening clipped to [0, 1]: an
  armature on a spring, Beater ch. 4); ``"dead-time"`` (the coil's build-up as a pure delay of
  ``tau_valve / 2``, then a lag of ``tau_valve / 2``).
- Chambers (`CHAMBERS`): ``"energy"``: mass and energy balances of the air (kappa 1.4) with heat
  exchange to the silicone wall over ``tau_wall`` (Beater ch. 2); ``"isothermal"``: ``p V = m R
  T_room`` (the wall exchange irrelevant); ``"polytropic"``: ``p = p_atm (rho / rho_atm) ** n``,
  the polytropic law anchored at the ambient state, so that ``p V^n / m^n`` stays constant
  whatever the flows; the temperature only follows from the ideal gas, ``T = p V / (m R)``, for
  the air leaving the chamber (no state of its own).

>>> air = Air("nozzle", 0.3, 2.5e-7, "first-order", 0.002, 0.7, "energy", 1.2, 1.0, 0.0, -20e3)
>>> Chamber(1e-5, air).step(1e-4, 1.0, 0.0, 2 * P_ATM, 1e-5) > 0  # an open inlet fills it
True
"""
from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from functools import partial
from typing import Any, Callable

import numpy as np
from scipy import linalg

P_ATM = 101325.0  # Pa
R_AIR = 287.05  # J/(kg K)
KAPPA = 1.4  # air, adiabatic
CV = R_AIR / (KAPPA - 1)  # J/(kg K)
CP = KAPPA * CV
T_ROOM = 293.15  # K
R_CRIT = (2 / (KAPPA + 1)) ** (KAPPA / (KAPPA - 1))  # 0.528
LAMINAR = 0.999  # pressure ratio above which every valve law is linear in the pressure drop
RHO_0, T_0 = 1.185, 293.15  # kg/m^3, K: ISO 6358's reference state (§valves)
# the nozzle's choked flow per (area * p_up / sqrt(T_up)): sqrt(kappa / R) (2 / (kappa + 1)) ** ...
CHOKED = math.sqrt(KAPPA / R_AIR) * (2 / (KAPPA + 1)) ** ((KAPPA + 1) / (2 * (KAPPA - 1)))


@dataclass(frozen=True)
class Air:
    """The air's forms and settings of one bench, as its
    `musclesim.benchmark.benches.crawler.Crawler` names them (and declares their defaults):
    `valve_law`, `valve_b`, `valve_area` [m^2], `spool`, `tau_valve` [s], `spool_zeta`,
    `chamber`, `polytropic_n`, `tau_wall` [s], `leak` [kg/(s Pa)], `p_exhaust` [Pa gauge]."""

    valve_law: str
    valve_b: float
    valve_area: float
    spool: str
    tau_valve: float
    spool_zeta: float
    chamber: str
    polytropic_n: float
    tau_wall: float
    leak: float
    p_exhaust: float


def nozzle_flow(p_up: Any, p_down: Any, area: Any, T_up: Any) -> Any:
    """Mass flow [kg/s] from `p_up` to `p_down` (absolute [Pa]; the upstream air at `T_up` [K])
    through a nozzle of effective area `area`: isentropic, choked below `R_CRIT`, linear within
    0.1 % of equal pressures.

    >>> round(nozzle_flow(200e3, 100e3, 2.5e-7, 293.15) * 1e5, 4)  # choked
    11.8023
    >>> nozzle_flow(100e3, 100e3, 2.5e-7, 293.15)
    0.0
    """
    if p_down >= p_up or area <= 0:
        return 0.0
    scale = area * p_up * math.sqrt(2 * KAPPA / ((KAPPA - 1) * R_AIR * T_up))

    def psi(r: Any) -> Any:
        return math.sqrt(max(r ** (2 / KAPPA) - r ** ((KAPPA + 1) / KAPPA), 0.0))

    r = max(p_down / p_up, R_CRIT)
    if r > 0.999:
        return scale * psi(0.999) * (1 - r) / 0.001
    return scale * psi(r)


def orifice_flow(p_up: float, p_down: float, area: float, T_up: float) -> float:
    """Mass flow [kg/s] from `p_up` to `p_down` (absolute [Pa]) through an orifice of effective
    area `area` by the incompressible law ``area sqrt(2 rho dp)``, ``rho`` the upstream air's (at
    `T_up` [K]); never choked; linear within 0.1 % of equal pressures.

    >>> round(orifice_flow(102e3, 100e3, 2.5e-7, 293.15) * 1e5, 4)
    1.7408
    """
    if p_down >= p_up or area <= 0:
        return 0.0
    rho = p_up / (R_AIR * T_up)
    dp = p_up - p_down
    if dp < (1 - LAMINAR) * p_up:
        edge = (1 - LAMINAR) * p_up
        return area * math.sqrt(2 * rho * edge) * dp / edge
    return area * math.sqrt(2 * rho * dp)


def iso6358_conductance(area: float) -> float:
    """ISO 6358's sonic conductance C [m^3/(s Pa)] whose choked flow ``C p_up RHO_0 sqrt(T_0 /
    T_up)`` is the nozzle's, ``area p_up CHOKED / sqrt(T_up)``, of effective area `area` [m^2]:
    ``C = area CHOKED / (RHO_0 sqrt(T_0))``.

    >>> round(iso6358_conductance(2.5e-7) * 1e8, 4)  # in dm^3/(s bar)
    0.0498
    """
    return area * CHOKED / (RHO_0 * math.sqrt(T_0))


def iso6358_flow(p_up: float, p_down: float, area: float, T_up: float, b: float = 0.3) -> float:
    """Mass flow [kg/s] from `p_up` to `p_down` (absolute [Pa]; the upstream air at `T_up` [K])
    by ISO 6358 with critical ratio `b`, the conductance `iso6358_conductance` of `area`: choked at
    ``r = p_down / p_up <= b``, elliptic above, linear within 0.1 % of equal pressures.

    >>> round(iso6358_flow(400e3, 100e3, 2.5e-7, 293.15) / nozzle_flow(400e3, 100e3, 2.5e-7,
    ...       293.15), 12)  # both choked
    1.0
    """
    if p_down >= p_up or area <= 0:
        return 0.0
    choked = iso6358_conductance(area) * p_up * RHO_0 * math.sqrt(T_0 / T_up)
    r = p_down / p_up
    if r <= b:
        return choked
    if r > LAMINAR:
        edge = math.sqrt(1 - ((LAMINAR - b) / (1 - b)) ** 2)
        return choked * edge * (1 - r) / (1 - LAMINAR)
    return choked * math.sqrt(1 - ((r - b) / (1 - b)) ** 2)


VALVE_LAWS: dict[str, Callable[..., Any]] = {"nozzle": nozzle_flow, "orifice": orifice_flow,
                                             "iso6358": iso6358_flow}


def valve_flow(air: Air) -> Callable[[float, float, float, float], float]:
    """The valve law of `air` as a function of (p_up, p_down, area, T_up)."""
    if air.valve_law == "iso6358":
        return partial(iso6358_flow, b=air.valve_b)
    return VALVE_LAWS[air.valve_law]


class FirstOrder:
    """A spool whose opening lags its command by `tau` [s], advanced exactly over a step."""

    def __init__(self, tau: float) -> None:
        self.tau, self.x = tau, 0.0

    def advance(self, share: float, dt: float) -> float:
        """The opening after `dt` [s] of the open `share` held."""
        self.x = share + (self.x - share) * math.exp(-dt / self.tau)
        return self.x


class SecondOrder:
    """A spool as a damped oscillator, natural frequency ``1 / tau`` [1/s], damping `zeta`,
    advanced exactly over a step of a held command (zero-order hold); its opening clipped to
    [0, 1] (the state overshoots, the armature stops)."""

    def __init__(self, tau: float, zeta: float) -> None:
        self.tau, self.zeta = tau, zeta
        self.x = self.v = 0.0
        self._dt = -1.0
        self._step = np.zeros((2, 3))

    def advance(self, share: float, dt: float) -> float:
        """The opening after `dt` [s] of the open `share` held."""
        if dt != self._dt:  # the transition over dt: exp of the system augmented by its input
            w = 1.0 / self.tau
            a = np.array([[0.0, 1.0, 0.0], [-w * w, -2 * self.zeta * w, w * w], [0.0, 0.0, 0.0]])
            self._dt, self._step = dt, linalg.expm(a * dt)[:2]
        (a11, a12, b1), (a21, a22, b2) = self._step.tolist()
        self.x, self.v = (a11 * self.x + a12 * self.v + b1 * share,
                          a21 * self.x + a22 * self.v + b2 * share)
        return min(max(self.x, 0.0), 1.0)


class DeadTime:
    """A spool behind a coil: its command delayed by ``tau / 2`` [s] (interpolated between
    steps; a constant step assumed), then lagged by ``tau / 2``."""

    def __init__(self, tau: float) -> None:
        self.tau, self.x = tau, 0.0
        self._dt = -1.0
        self._past: deque[float] = deque()
        self._n, self._frac = 0, 0.0

    def advance(self, share: float, dt: float) -> float:
        """The opening after `dt` [s] of the open `share` held."""
        if dt != self._dt:
            steps = self.tau / 2 / dt
            self._dt, self._n = dt, int(steps)
            self._frac = steps - self._n
            self._past = deque([0.0] * (self._n + 2), maxlen=self._n + 2)  # closed before
        self._past.appendleft(share)  # _past[k]: the share k steps ago
        late = self._past[self._n] + self._frac * (self._past[self._n + 1] - self._past[self._n])
        self.x = late + (self.x - late) * math.exp(-dt / (self.tau / 2))
        return self.x


SPOOLS = ("first-order", "second-order", "dead-time")
CHAMBERS = ("energy", "isothermal", "polytropic")


def spool(air: Air) -> FirstOrder | SecondOrder | DeadTime:
    """A closed spool of `air`'s form."""
    if air.spool == "second-order":
        return SecondOrder(air.tau_valve, air.spool_zeta)
    if air.spool == "dead-time":
        return DeadTime(air.tau_valve)
    return FirstOrder(air.tau_valve)


class Chamber:
    """One actuator's air (absolute pressure, temperature, volume), its inlet and exhaust valves
    and its contact share, in the forms of `air`, at rest in the room in a `volume` [m^3]."""

    def __init__(self, volume: float, air: Air) -> None:
        self.p, self.T, self.V = P_ATM, T_ROOM, volume
        self.air = air
        self.spool_in, self.spool_out = spool(air), spool(air)
        self.contact = 0.0
        self._flow = valve_flow(air)

    def step(self, dt: float, share_in: float, share_out: float, supply: float,
             V_new: float) -> Any:
        """Advance `dt` [s] with the inlet open a `share_in` of it from `supply` [Pa] and the
        exhaust a `share_out`, to the volume `V_new` [m^3]; return the net flow drawn from the
        supply [kg/s]."""
        air, flow = self.air, self._flow
        opening_in = self.spool_in.advance(share_in, dt)
        opening_out = self.spool_out.advance(share_out, dt)
        exhaust = P_ATM + air.p_exhaust
        m_in = flow(supply, self.p, air.valve_area * opening_in, T_ROOM)
        back = flow(self.p, supply, air.valve_area * opening_in, self.T)
        m_out = flow(self.p, exhaust, air.valve_area * opening_out, self.T)
        leak = air.leak * (self.p ** 2 - P_ATM ** 2) / P_ATM
        mass = self.p * self.V / (R_AIR * self.T)
        if air.chamber == "energy":
            heat = mass * CV * (T_ROOM - self.T) / air.tau_wall
            power = CP * T_ROOM * m_in - CP * self.T * (back + m_out + leak) + heat
            # the volume's change adiabatic (exact over the step), then the flows' and wall's
            p = self.p * (self.V / V_new) ** KAPPA + dt * (KAPPA - 1) / V_new * power
            mass += dt * (m_in - back - m_out - leak)
            self.p, self.V = max(p, 0.1 * P_ATM), V_new
            self.T = self.p * self.V / (R_AIR * max(mass, 1e-12))
            return m_in - back
        mass = max(mass + dt * (m_in - back - m_out - leak), 1e-12)
        isothermal = mass * R_AIR * T_ROOM / V_new  # the pressure at room temperature
        if air.chamber == "isothermal":
            self.p, self.T = isothermal, T_ROOM
        else:
            self.p = P_ATM * (isothermal / P_ATM) ** air.polytropic_n
            self.T = self.p * V_new / (R_AIR * mass)
        self.V = V_new
        return m_in - back
