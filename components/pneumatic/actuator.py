"""Pneumatic soft actuator (§crawler-hardware, §gait, §chamber): a silicone chamber filled from an
inflation pump and emptied into an exhaust pump, each line through a PWM-driven solenoid valve (ISO
6358 orifice).

Pressures are gauge [Pa] everywhere except in the ISO 6358 flow law, which takes absolute ones.
Equations and where every default comes from: §pneumatics (docs/model/pneumatics.md).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

from musclesim.components.checks import require
from musclesim.fmu import Calibration, declare

P_ATM = 101325.0  # Pa, standard atmosphere (gauge 0)
RHO_0 = 1.185  # kg/m^3, ISO 6358 reference density
T_0 = 293.15  # K, ISO 6358 reference temperature
R_AIR = 287.05  # J/(kg K), specific gas constant of air
V_MIN = 0.1  # share of V0 a chamber squeezed flat keeps (assumption: walls, connector)


@dataclass(frozen=True)
class ActuatorParams:
    """One soft actuator with its valves and pumps; defaults: the central one (§crawler-hardware,
    §two-mass). Each parameter is declared once here (`declare`): the FMU, the docs' tables and
    the diagnosis's catalogues read it."""

    central: float = declare(1.0, "1", "1 = central longitudinal actuator (volume from the "
                             "elongation), 0 = extremal friction actuator (volume from the "
                             "contact)", source="§crawler-hardware", type="Boolean")
    s_a: float = declare(9.62e-4, "m2", "Cross-section: f_a = s_a p (a 35 mm tube)",
                         source="§two-mass", calibrate=Calibration(
                             0.8, 1.1, True, "the central actuator's effective area: its walls "
                             "take part of the force"))
    V0: float = declare(5.87e-5, "m3", "Chamber volume at rest (central: 30 mm inner diameter "
                        "(35 mm OD, 2.5 mm walls) x 83 mm; extremal: 1.41e-5 m3, 30 mm x 20 mm)",
                        source="§crawler-hardware")
    dV_contact: float = declare(3e-6, "m3", "Extremal chamber's growth from casing to silicone "
                                "contact (assumption: a few mm of bulge on a 30 mm chamber)")
    # not calibrated: the effect "supply-pressure drop" scales it by a constant, so calibrating it
    # would absorb the effect exactly
    p_supply: float = declare(40e3, "Pa", "Gauge pressure of the inflation pump (assumption: "
                              "above the 20.7 kPa the study reaches)", source="§ideal-actuation")
    p_exhaust: float = declare(-20e3, "Pa", "Gauge pressure of the exhaust pump, in "
                               "(-101.3 kPa, 0] (assumption: a small vacuum pump)",
                               source="§crawler-hardware",
                               calibrate=Calibration(0.7, 1.3, True, "the exhaust pump's vacuum"))
    C_in: float = declare(5e-10, "m3/(s.Pa)", "Sonic conductance of the inflation valve (ISO "
                          "6358; assumption: a miniature solenoid valve of 3 l/(min bar), about "
                          "6 Nl/min at 1 bar gauge)",
                          source="§crawler-hardware, §valves",
                          calibrate=Calibration(0.5, 2.0, True, "inflation valve"))
    C_out: float = declare(5e-10, "m3/(s.Pa)", "Sonic conductance of the exhaust valve (ISO "
                           "6358; assumption: the same valve)",
                           source="§crawler-hardware, §valves",
                           calibrate=Calibration(0.5, 2.0, True, "exhaust valve"))
    b: float = declare(0.3, "1", "Critical pressure ratio of the valves, in [0, 1) (ISO 6358; "
                       "assumption: a typical valve)", source="§valves")
    T: float = declare(T_0, "K", "Air temperature (room temperature, the ISO 6358 reference)")
    kappa: float = declare(1.2, "1", "Polytropic exponent, 1 (isothermal) .. 1.4 (adiabatic) "
                           "(assumption: between the two)", source="§chamber")
    f_pwm: float = declare(50.0, "Hz", "PWM carrier frequency (assumption: the study gives none)")
    # a bench's own PWM timer starts anywhere, which matters when its duties are replayed
    pwm_phase: float = declare(
        0.0, "1", "Phase of a period at which the carrier's periods start on the master's clock, "
        "periodic (1.25 is 0.25; assumption: 0)", source="§crawler-hardware, §valves",
        calibrate=Calibration(-0.5, 1.5, False, "where the valves' PWM carrier starts on the "
                              "data's clock", period=1.0))
    p_contact: float = declare(8e3, "Pa", "Gauge pressure above which the silicone makes firm "
                               "ground contact (assumption; the study found it by eye)",
                               source="§crawler-hardware, §gait", calibrate=Calibration(
                                   0.7, 1.25, True, "the pressure above which an extremal "
                                   "actuator's silicone grips the ground"))
    t_contact: float = declare(0.2, "s", "Time of the contact's 0 -> 1 change; <= 0: at once "
                               "(assumption: the study's up to 0.4 s switching includes the "
                               "pressure build-up)", source="§crawler-hardware")
    dt_sub: float = declare(1e-4, "s", "Internal step (assumption: 10 per 1 ms communication "
                            "step, the DAQ's 1 kHz)", source="§crawler-hardware")
    # effects, off by default
    t_open_delay: float = declare(0.0, "s", "Effect, 0 = off: the valve opens this long after "
                                  "its command rises (a few ms)", source="§valves",
                                  effect=(0.0, 0.02))
    t_close_delay: float = declare(0.0, "s", "Effect, 0 = off: the valve closes this long after "
                                   "its command falls (a few ms)", source="§valves",
                                   effect=(0.0, 0.02))
    C_leak: float = declare(0.0, "m3/(s.Pa)", "Effect, 0 = off: sonic conductance of a leak "
                            "from the chamber to the atmosphere (ISO 6358 orifice)",
                            source="§named-effects", effect=(0.0, 5e-11))
    supply_drop: float = declare(0.0, "1", "Effect, 0 = off: the supply pressure sags to "
                                 "p_supply (1 - supply_drop)", source="§named-effects",
                                 effect=(0.0, 0.5))

    def check(self) -> None:
        """Raise ValueError naming the first parameter outside its valid range."""
        for f in fields(self):
            if not math.isfinite(getattr(self, f.name)):
                raise ValueError(f"{f.name} must be a finite number "
                                 f"(got {getattr(self, f.name)!r})")
        require(self, positive=("s_a", "V0", "C_in", "C_out", "T", "f_pwm", "dt_sub"),
                non_negative=("dV_contact", "p_supply", "t_open_delay", "t_close_delay", "C_leak"))
        if self.central not in (0.0, 1.0):
            raise ValueError(f"central must be 1 (central actuator) or 0 (extremal actuator) "
                             f"(got {self.central!r})")
        if not 0.0 <= self.b < 1.0:
            raise ValueError(f"b must be within [0, 1) (got {self.b!r})")
        if not 1.0 <= self.kappa <= 1.4:
            raise ValueError(f"kappa must be within [1, 1.4] (isothermal to adiabatic; "
                             f"got {self.kappa!r})")
        if not -P_ATM < self.p_exhaust <= 0.0:
            raise ValueError(f"p_exhaust must be within (-{P_ATM:g}, 0] Pa gauge "
                             f"(got {self.p_exhaust!r})")
        if not 0.0 <= self.supply_drop < 1.0:
            raise ValueError(f"supply_drop must be within [0, 1) (got {self.supply_drop!r})")


def mass_flow(p_up: float, p_down: float, C: float, b: float, T_up: float = T_0) -> float:
    """Mass flow [kg/s] from `p_up` to `p_down` (absolute [Pa]) through an ISO 6358 orifice of
    sonic conductance `C` [m^3/(s Pa)] and critical pressure ratio `b`, the upstream air at
    `T_up` [K]; 0 when p_down >= p_up.

    Examples
    --------
    >>> mass_flow(500e3, 100e3, 5e-10, 0.3)  # choked (r = 0.2 <= b): C p_up rho_0
    0.00029625
    >>> mass_flow(100e3, 100e3, 5e-10, 0.3)
    0.0
    """
    if p_down >= p_up or C == 0:
        return 0.0
    q = C * p_up * RHO_0 * math.sqrt(T_0 / T_up)
    r = p_down / p_up
    if r <= b:
        return q
    x = (r - b) / (1.0 - b)
    return q * math.sqrt(1.0 - x * x)


def signed_flow(p_a: float, p_b: float, C: float, b: float, T: float = T_0) -> float:
    """Mass flow [kg/s] from side a at `p_a` to side b at `p_b` (absolute pressures [Pa]),
    negative when it runs from b to a, through the orifice `C`, `b` (`mass_flow`); the upstream
    side's temperature is `T`.

    Examples
    --------
    >>> signed_flow(100e3, 500e3, 5e-10, 0.3) == -mass_flow(500e3, 100e3, 5e-10, 0.3)
    True
    """
    return mass_flow(p_a, p_b, C, b, T) if p_a >= p_b else -mass_flow(p_b, p_a, C, b, T)


def pwm_edges(t0: float, t1: float, duty: float, period: float,
              phase: float = 0.0) -> list[tuple[float, bool]]:
    """The PWM command of `duty` over [`t0`, `t1`): [(t0, state at t0), (time, on) of each
    switching in (t0, t1)], the carrier of `period` [s] shifted by `phase` [periods].

    The carrier's period k starts at k period + phase period (any phase: 1.25 is 0.25); the
    command is on for the first duty of each. The state at t0 comes from the same edge times as
    the switchings, so consecutive steps agree to the last bit.

    Examples
    --------
    >>> pwm_edges(0.0, 0.05, 0.25, 0.02)
    [(0.0, True), (0.005, False), (0.02, True), (0.025, False), (0.04, True), (0.045, False)]
    >>> pwm_edges(0.013, 0.014, 1.0, 0.02)
    [(0.013, True)]
    >>> [(round(t, 9), on) for t, on in pwm_edges(0.0, 0.03, 0.25, 0.02, phase=0.875)]
    [(0.0, True), (0.0025, False), (0.0175, True), (0.0225, False)]
    """
    if duty <= 0.0 or duty >= 1.0:
        return [(t0, duty >= 1.0)]
    shift = phase * period  # period k starts at k period + shift
    k = math.floor((t0 - shift) / period)
    k += ((k + 1) * period + shift <= t0) - (k * period + shift > t0)  # rounded across an integer
    edges = [(t0, t0 < k * period + shift + duty * period)]
    while (rise := k * period + shift) < t1:
        for te, on in ((rise, True), (rise + duty * period, False)):
            if t0 < te < t1:
                edges.append((te, on))
        k += 1
    return edges


@dataclass
class Valve:
    """A solenoid valve following its command with opening and closing delays.

    `cmd` is the command (True = energised), `is_open` the valve, `pending` the switchings
    [(time, opens)] the command's edges scheduled and that are still to come, in time order.
    """

    cmd: bool = False
    is_open: bool = False
    pending: list[tuple[float, bool]] = field(default_factory=list)

    def open_intervals(self, edges: list[tuple[float, bool]], t1: float, d_open: float,
                       d_close: float) -> list[tuple[float, float]]:
        """Take the command `edges` over [t0, `t1`) (`pwm_edges`) and return the intervals the
        valve is open, opening `d_open` [s] and closing `d_close` [s] after its command.

        A command edge at t makes the valve follow at t + d_open (opening) or t + d_close
        (closing) and cancels the switchings scheduled at or after that time: a command pulse
        shorter than d_open - d_close never opens the valve, a gap shorter than
        d_close - d_open never closes it.

        Examples
        --------
        >>> Valve().open_intervals([(0.0, True), (0.005, False)], 0.02, 0.002, 0.001)
        [(0.002, 0.006)]
        """
        for te, on in edges:
            if on != self.cmd:
                self.cmd = on
                ts = te + (d_open if on else d_close)
                self.pending = [e for e in self.pending if e[0] < ts] + [(ts, on)]
        intervals, start = [], edges[0][0]
        while self.pending and self.pending[0][0] < t1:
            ts, on = self.pending.pop(0)
            if on and not self.is_open:
                start = ts
            elif self.is_open and not on:
                intervals.append((start, ts))
            self.is_open = on
        if self.is_open:
            intervals.append((start, t1))
        return intervals


def open_time(intervals: list[tuple[float, float]], a: float, b: float) -> float:
    """Time [s] the `intervals` [(start, end)] cover within [`a`, `b`)."""
    return sum(max(0.0, min(e, b) - max(s, a)) for s, e in intervals)


def source_pressures(p: ActuatorParams) -> tuple[float, float]:
    """Effective gauge pressures [Pa] of the inflation and the exhaust pump of `p`."""
    return p.p_supply * (1.0 - p.supply_drop), p.p_exhaust


def volume(elongation: float, contact: float, p: ActuatorParams) -> float:
    """Chamber volume [m^3] of `p`: V0 + s_a `elongation` (central) or V0 + dV_contact `contact`
    (extremal), at least V_MIN V0.

    Examples
    --------
    >>> round(volume(0.01, 0.0, ActuatorParams()), 12)
    6.832e-05
    """
    v = p.V0 + (p.s_a * elongation if p.central else p.dV_contact * contact)
    return max(v, V_MIN * p.V0)


def contact_step(c: float, pressure: float, dt: float, p: ActuatorParams) -> float:
    """Contact state `c` of `p` after `dt` [s] at gauge pressure `pressure`: towards 1 above
    p_contact, towards 0 at or below it, at the rate 1 / t_contact (a jump when t_contact <= 0).

    Examples
    --------
    >>> contact_step(0.5, 9e3, 0.05, ActuatorParams())
    0.75
    """
    target = 1.0 if pressure > p.p_contact else 0.0
    if p.t_contact <= 0:
        return target
    rate = dt / p.t_contact
    return min(c + rate, 1.0) if target else max(c - rate, 0.0)


def bulge_contact(c: float, pressure: float, p: ActuatorParams) -> tuple[float, float]:
    """Contact (from `c`, at gauge `pressure` [Pa]) of an extremal chamber `p` whose bulge follows
    at once (t_contact <= 0, dV_contact > 0):
    the chamber grows or shrinks at its mass (p_abs V^kappa constant) until its gauge pressure is
    p_contact, within contact 0..1. A jump of the volume instead would throw the pressure back
    across p_contact at every sub-step.

    Examples
    --------
    >>> p = ActuatorParams(central=0.0, t_contact=0.0)
    >>> bulge_contact(0.0, 5e3, p), bulge_contact(0.5, 50e3, p)
    (0.0, 1.0)
    >>> c = bulge_contact(0.0, 8.5e3, p)  # grows until the pressure is back at p_contact
    >>> round((P_ATM + 8.5e3) * (volume(0, 0, p) / volume(0, c, p)) ** p.kappa - P_ATM, 6)
    8000.0
    """
    v = volume(0.0, c, p)
    v_eq = v * ((P_ATM + pressure) / (P_ATM + p.p_contact)) ** (1.0 / p.kappa)
    return min(max((v_eq - p.V0) / p.dV_contact, 0.0), 1.0)


class Actuator:
    """One soft actuator's state (gauge pressure, contact, valves, volume) and its step.

    Parameters
    ----------
    params : ActuatorParams
    elongation : float
        Elongation [m] of the central actuator at the start (the volume follows it).
    """

    def __init__(self, params: ActuatorParams, elongation: float = 0.0) -> None:
        self.params = params
        self.pressure = 0.0  # Pa gauge
        self.contact = 0.0
        self.elongation = elongation  # m, the elongation the volume stands at
        self.inflate, self.exhaust = Valve(), Valve()

    def step(self, t: float, h: float, duty: float, elongation: float) -> float:
        """Advance from `t` to `t` + `h` with the `duty` in [-1, 1] held (> 0 inflates, < 0
        exhausts) and the elongation [m] moving linearly to `elongation`; return the mass [kg] that
        flowed in."""
        p = self.params
        duty = min(max(duty, -1.0), 1.0)
        period, t1 = 1.0 / p.f_pwm, t + h
        delays = p.t_open_delay, p.t_close_delay
        open_in = self.inflate.open_intervals(
            pwm_edges(t, t1, max(duty, 0.0), period, p.pwm_phase), t1, *delays)
        open_out = self.exhaust.open_intervals(
            pwm_edges(t, t1, max(-duty, 0.0), period, p.pwm_phase), t1, *delays)
        n = max(1, math.ceil(h / p.dt_sub - 1e-9))
        if not (open_in or open_out or p.C_leak) and self._holds(elongation, h / n):
            self.elongation = elongation
            return 0.0
        p_in, p_out = source_pressures(p)
        gain = p.kappa * R_AIR * p.T
        times = [t + h * i / n for i in range(n)] + [t1]
        e0, mass = self.elongation, 0.0
        v = volume(e0, self.contact, p)
        for i in range(n):
            a, b = times[i], times[i + 1]
            p_abs = P_ATM + self.pressure
            dm = 0.0
            if open_in and (t_open := open_time(open_in, a, b)):
                dm += signed_flow(P_ATM + p_in, p_abs, p.C_in, p.b, p.T) * t_open
            if open_out and (t_open := open_time(open_out, a, b)):
                dm -= signed_flow(p_abs, P_ATM + p_out, p.C_out, p.b, p.T) * t_open
            if p.C_leak:
                dm -= signed_flow(p_abs, P_ATM, p.C_leak, p.b, p.T) * (b - a)
            # the flows cannot push the pressure past their sources (the unchoked law's slope is
            # infinite at r -> 1)
            p_flow = self.pressure + gain * dm / v
            clamped = min(max(p_flow, min(self.pressure, p_out)), max(self.pressure, p_in))
            if clamped != p_flow:  # the mass that fits
                p_flow, dm = clamped, (clamped - self.pressure) * v / gain
            self.contact = self._contact_after(p_flow, b - a)
            v_next = volume(e0 + (elongation - e0) * (i + 1) / n, self.contact, p)
            if v_next != v:  # polytropic change at the mass just reached: p_abs V^kappa constant
                p_flow = (P_ATM + p_flow) * (v / v_next) ** p.kappa - P_ATM
            self.pressure, v = p_flow, v_next
            mass += dm
        self.elongation = elongation
        return mass

    def _holds(self, elongation, dt):
        """With no air flowing over the next step (valves shut, no leak), whether its sub-steps
        of `dt` would leave pressure, contact and volume as they are: the contact already where
        its sub-step takes it at this pressure, the volume not following an elongation (an
        extremal chamber's does not; a central one's must stand still). The extremal
        actuators hold so most of a gait, their valves shut between pulses."""
        if self.params.central and elongation != self.elongation:
            return False
        return self._contact_after(self.pressure, dt) == self.contact

    def _contact_after(self, pressure, dt):
        """The contact after a sub-step of dt at gauge pressure `pressure`: an extremal chamber
        whose bulge follows at once (`bulge_contact`), else at its finite rate (`contact_step`)."""
        p = self.params
        if p.t_contact <= 0 and not p.central and p.dV_contact > 0:
            return bulge_contact(self.contact, pressure, p)
        return contact_step(self.contact, pressure, dt, p)
