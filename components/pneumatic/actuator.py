"""Pneumatic soft actuator (§crawler-hardware, §gait, §chamber): a silicone chamber filled from an
inflation pump and emptied into an exhaust pump, each line through a PWM-driven solenoid valve (ISO
6358 orifice).

Pressures are gauge [Pa] everywhere except in the ISO 6358 flow law, which takes absolute ones.
Equations and where every default comes from: §pneumatics (docs/model/pneumatics.md).

The physics is written once, in `jit` functions on numbers and float64 arrays: the parameters
packed by `pack` (kp), the state in one array (kx, `start_state`: pressure, contact, elongation,
the last step's mean mass flow and each valve's command, position and pending switchings). The
FMU's kernel (`KERNEL`: `evaluate`, `advance`; `musclesim.fmu.kernel`) and the Python API below
(`Actuator`, `Valve`, `pwm_edges`, ...) call the same functions.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

import numpy as np

from musclesim.components.checks import require
from musclesim.fmu import Calibration, Kernel, declare, jit

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
                              "above the 20.7 kPa the study reaches)", source="§ideal-actuation",
                              plausible="inflating pressure")
    p_exhaust: float = declare(-20e3, "Pa", "Gauge pressure of the exhaust pump, in "
                               "(-101.3 kPa, 0] (assumption: a small vacuum pump)",
                               source="§crawler-hardware", plausible="gauge pressure",
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
                               source="§crawler-hardware, §gait",
                               plausible="inflating pressure", calibrate=Calibration(
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
    # a nuisance of the flow law's form, calibrated (0.5 = the ISO 6358 elliptic law)
    m_sub: float = declare(0.5, "1", "Subsonic index of the valves' flow law, in (0, 1]: the "
                           "unchoked flow is the choked one times (1 - x^2)^m_sub, x = (r - b) / "
                           "(1 - b) (ISO 6358-1:2013; 0.5, the ellipse of ISO 6358:1989)",
                           source="§valves, bench form (an orifice's law: ISO 6358-1:2013's "
                           "subsonic index)",
                           calibrate=Calibration(0.5, 1.6, True, "the valves' flow law: a real "
                                                 "orifice's unchoked flow is not the ellipse "
                                                 "(an isentropic nozzle's is about m_sub 0.35 "
                                                 "at b 0.3)"))

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
        if not 0.0 < self.m_sub <= 1.0:
            raise ValueError(f"m_sub must be within (0, 1] (got {self.m_sub!r})")


# kernel parameters (kp, `pack`): ActuatorParams' fields in order, then the pending switchings
# a valve's state holds
(CENTRAL, S_A, V0_, DV_CONTACT, P_SUPPLY, P_EXHAUST, C_IN, C_OUT, B, T_AIR, KAPPA, F_PWM,
 PWM_PHASE, P_CONTACT, T_CONTACT, DT_SUB, T_OPEN_DELAY, T_CLOSE_DELAY, C_LEAK, SUPPLY_DROP,
 M_SUB, CAP) = range(22)
# kernel state (kx, `start_state`): gauge pressure [Pa], contact, elongation [m] the volume stands
# at, net mass flow [kg/s] of the last step; then the inflation valve's and the exhaust valve's
# blocks (`valve_intervals`: command, position, number of pending switchings, their times, their
# directions)
PRESSURE, CONTACT, ELONGATION, M_FLOW, VALVES = range(5)
CMD, OPEN, N_PENDING, PENDING = range(4)


def pack(p: ActuatorParams) -> np.ndarray:
    """The kernel's parameters kp of `p`: its fields in declaration order (indices CENTRAL ..
    M_SUB), then CAP, the pending switchings a valve's state holds (`pending_capacity`)."""
    return np.array([getattr(p, f.name) for f in fields(p)] + [pending_capacity(p)],
                    dtype=np.float64)


def pending_capacity(p: ActuatorParams) -> int:
    """Switchings a valve of `p` can have scheduled and still to come after a step: those of the
    command's edges within the longest delay, two per PWM period and one per step start where
    the duty changes (steps down to half the internal step), and a margin."""
    delay = max(p.t_open_delay, p.t_close_delay)
    return 2 * math.ceil(delay * p.f_pwm) + 2 * math.ceil(delay / p.dt_sub) + 8


def start_state(kp: np.ndarray, elongation: float = 0.0) -> np.ndarray:
    """The kernel's state kx of the actuator `kp` (`pack`) at rest (gauge 0, no contact, valves
    shut and commanded shut) at the `elongation` [m] (central actuator)."""
    x = np.zeros(VALVES + 2 * (PENDING + 2 * int(kp[CAP])))
    x[ELONGATION] = elongation
    return x


@jit
def _max(a: float, b: float) -> float:
    """Python's max(a, b), to the bit (the first of equal ones)."""
    return b if b > a else a


@jit
def _min(a: float, b: float) -> float:
    """Python's min(a, b), to the bit (the first of equal ones)."""
    return b if b < a else a


@jit
def mass_flow(p_up: float, p_down: float, C: float, b: float, T_up: float = T_0,
              m: float = 0.5) -> float:
    """Mass flow [kg/s] from `p_up` to `p_down` (absolute [Pa]) through an ISO 6358 orifice of
    sonic conductance `C` [m^3/(s Pa)], critical pressure ratio `b` and subsonic index `m`
    (ISO 6358-1:2013; 0.5, the default, is the ellipse), the upstream air at `T_up` [K]; 0 when
    p_down >= p_up.

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
    if m == 0.5:  # the ellipse, as ISO 6358:1989 writes it (to the bit)
        return q * math.sqrt(1.0 - x * x)
    return q * (1.0 - x * x) ** m


@jit
def signed_flow(p_a: float, p_b: float, C: float, b: float, T: float = T_0,
                m: float = 0.5) -> float:
    """Mass flow [kg/s] from side a at `p_a` to side b at `p_b` (absolute pressures [Pa]),
    negative when it runs from b to a, through the orifice `C`, `b` (`mass_flow`); the upstream
    side's temperature is `T`, the subsonic index `m`.

    Examples
    --------
    >>> signed_flow(100e3, 500e3, 5e-10, 0.3) == -mass_flow(500e3, 100e3, 5e-10, 0.3)
    True
    """
    return mass_flow(p_a, p_b, C, b, T, m) if p_a >= p_b else -mass_flow(p_b, p_a, C, b, T, m)


def pwm_edges(t0: float, t1: float, duty: float, period: float,
              phase: float = 0.0) -> list[tuple[float, bool]]:
    """The PWM command of `duty` over [`t0`, `t1`): [(t0, state at t0), (time, on) of each
    switching in (t0, t1)], the carrier of `period` [s] shifted by `phase` [periods]
    (`edges_into`).

    Examples
    --------
    >>> pwm_edges(0.0, 0.05, 0.25, 0.02)
    [(0.0, True), (0.005, False), (0.02, True), (0.025, False), (0.04, True), (0.045, False)]
    >>> pwm_edges(0.013, 0.014, 1.0, 0.02)
    [(0.013, True)]
    >>> [(round(t, 9), on) for t, on in pwm_edges(0.0, 0.03, 0.25, 0.02, phase=0.875)]
    [(0.0, True), (0.0025, False), (0.0175, True), (0.0225, False)]
    """
    et, eon = np.empty(edge_capacity(t0, t1, period)), np.empty(edge_capacity(t0, t1, period))
    n = edges_into(t0, t1, duty, period, phase, et, eon)
    return [(te, on != 0.0) for te, on in zip(et[:n].tolist(), eon[:n].tolist())]


@jit
def edge_capacity(t0: float, t1: float, period: float) -> int:
    """Room for the PWM edges over [`t0`, `t1`) of a carrier of `period`: 2 per period the span
    touches, and the state at t0."""
    return 2 * int((t1 - t0) / period) + 8


@jit
def edges_into(t0: float, t1: float, duty: float, period: float, phase: float, et: np.ndarray,
               eon: np.ndarray) -> int:
    """`pwm_edges` of `duty` over [`t0`, `t1`), the carrier of `period` [s] shifted by `phase`
    [periods], written into `et` (times) and `eon` (1 on, 0 off); returns their number.

    The carrier's period k starts at k period + phase period (any phase: 1.25 is 0.25); the
    command is on for the first duty of each. The state at t0 comes from the same edge times as
    the switchings, so consecutive steps agree to the last bit.
    """
    et[0] = t0
    if duty <= 0.0 or duty >= 1.0:
        eon[0] = 1.0 if duty >= 1.0 else 0.0
        return 1
    shift = phase * period  # period k starts at k period + shift
    k = math.floor((t0 - shift) / period)
    up = 1 if (k + 1) * period + shift <= t0 else 0  # rounded across an integer
    down = 1 if k * period + shift > t0 else 0
    k += up - down
    eon[0] = 1.0 if t0 < k * period + shift + duty * period else 0.0
    n = 1
    rise = k * period + shift
    while rise < t1:
        if t0 < rise < t1:
            et[n], eon[n] = rise, 1.0
            n += 1
        fall = rise + duty * period
        if t0 < fall < t1:
            et[n], eon[n] = fall, 0.0
            n += 1
        k += 1
        rise = k * period + shift
    return n


@jit
def valve_intervals(x: np.ndarray, v: int, cap: int, et: np.ndarray, eon: np.ndarray, ne: int,
                    t1: float, d_open: float,
                    d_close: float) -> tuple[np.ndarray, np.ndarray, int]:
    """A valve's step (`Valve.open_intervals`): its state the block of `x` from `v` (command,
    position, number of pending switchings, then `cap` times and `cap` directions of them), the
    command's `ne` edges `et`, `eon` over [t0, `t1`) (`edges_into`), the valve opening `d_open`
    [s] and closing `d_close` [s] after its command; returns the (starts, ends, number) of the
    intervals the valve is open, the block advanced."""
    n0 = int(x[v + N_PENDING])
    pt, pon = np.empty(n0 + ne), np.empty(n0 + ne)
    for j in range(n0):
        pt[j], pon[j] = x[v + PENDING + j], x[v + PENDING + cap + j]
    npend = n0
    cmd = x[v + CMD] != 0.0
    for k in range(ne):
        on = eon[k] != 0.0
        if on != cmd:
            cmd = on
            ts = et[k] + (d_open if on else d_close)
            keep = 0  # the switchings scheduled at or after ts are cancelled
            for j in range(npend):
                if pt[j] < ts:
                    pt[keep], pon[keep] = pt[j], pon[j]
                    keep += 1
            pt[keep], pon[keep] = ts, (1.0 if on else 0.0)
            npend = keep + 1
    starts, ends = np.empty(npend + 1), np.empty(npend + 1)
    count, start, is_open, first = 0, et[0], x[v + OPEN] != 0.0, 0
    while first < npend and pt[first] < t1:
        ts, on = pt[first], pon[first] != 0.0
        first += 1
        if on and not is_open:
            start = ts
        elif is_open and not on:
            starts[count], ends[count] = start, ts
            count += 1
        is_open = on
    if is_open:
        starts[count], ends[count] = start, t1
        count += 1
    rest = npend - first
    if rest > cap:
        raise ValueError("a valve has more switchings pending than its state holds: valve "
                         "delays far above the step with the duty changing at every step")
    x[v + CMD], x[v + OPEN] = (1.0 if cmd else 0.0), (1.0 if is_open else 0.0)
    x[v + N_PENDING] = rest
    for j in range(rest):
        x[v + PENDING + j], x[v + PENDING + cap + j] = pt[first + j], pon[first + j]
    return starts, ends, count


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
        valve is open, opening `d_open` [s] and closing `d_close` [s] after its command
        (`valve_intervals`).

        A command edge at t makes the valve follow at t + d_open (opening) or t + d_close
        (closing) and cancels the switchings scheduled at or after that time: a command pulse
        shorter than d_open - d_close never opens the valve, a gap shorter than
        d_close - d_open never closes it.

        Examples
        --------
        >>> Valve().open_intervals([(0.0, True), (0.005, False)], 0.02, 0.002, 0.001)
        [(0.002, 0.006)]
        """
        cap = len(self.pending) + len(edges)
        x = np.zeros(PENDING + 2 * cap)
        x[CMD], x[OPEN], x[N_PENDING] = self.cmd, self.is_open, len(self.pending)
        for j, (ts, on) in enumerate(self.pending):
            x[PENDING + j], x[PENDING + cap + j] = ts, on
        et = np.array([te for te, _ in edges], dtype=np.float64)
        eon = np.array([1.0 if on else 0.0 for _, on in edges])
        starts, ends, n = valve_intervals(x, 0, cap, et, eon, len(edges), t1, d_open, d_close)
        self.cmd, self.is_open = bool(x[CMD]), bool(x[OPEN])
        rest = int(x[N_PENDING])
        self.pending = [(float(x[PENDING + j]), bool(x[PENDING + cap + j])) for j in range(rest)]
        return list(zip(starts[:n].tolist(), ends[:n].tolist()))


def open_time(intervals: list[tuple[float, float]], a: float, b: float) -> float:
    """Time [s] the `intervals` [(start, end)] cover within [`a`, `b`) (`time_open`)."""
    starts = np.array([s for s, _ in intervals], dtype=np.float64)
    ends = np.array([e for _, e in intervals], dtype=np.float64)
    return float(time_open(starts, ends, len(intervals), a, b))


@jit
def time_open(starts: np.ndarray, ends: np.ndarray, n: int, a: float, b: float) -> float:
    """Time [s] the first `n` intervals [`starts`, `ends`) cover within [`a`, `b`)."""
    total = 0.0
    for j in range(n):
        total += _max(0.0, _min(ends[j], b) - _max(starts[j], a))
    return total


def source_pressures(p: ActuatorParams) -> tuple[float, float]:
    """Effective gauge pressures [Pa] of the inflation and the exhaust pump of `p`."""
    return p.p_supply * (1.0 - p.supply_drop), p.p_exhaust


def volume(elongation: float, contact: float, p: ActuatorParams) -> float:
    """Chamber volume [m^3] of `p`: V0 + s_a `elongation` (central) or V0 + dV_contact `contact`
    (extremal), at least V_MIN V0 (`chamber_volume`).

    Examples
    --------
    >>> round(volume(0.01, 0.0, ActuatorParams()), 12)
    6.832e-05
    """
    return float(chamber_volume(pack(p), elongation, contact))


@jit
def chamber_volume(kp: np.ndarray, elongation: float, contact: float) -> float:
    """`volume` at the `elongation` [m] and `contact` of the actuator `kp`."""
    v = kp[V0_] + (kp[S_A] * elongation if kp[CENTRAL] != 0.0 else kp[DV_CONTACT] * contact)
    return _max(v, V_MIN * kp[V0_])


def contact_step(c: float, pressure: float, dt: float, p: ActuatorParams) -> float:
    """Contact state `c` of `p` after `dt` [s] at gauge pressure `pressure`: towards 1 above
    p_contact, towards 0 at or below it, at the rate 1 / t_contact (a jump when t_contact <= 0;
    `contact_rate`).

    Examples
    --------
    >>> contact_step(0.5, 9e3, 0.05, ActuatorParams())
    0.75
    """
    return float(contact_rate(pack(p), c, pressure, dt))


@jit
def contact_rate(kp: np.ndarray, c: float, pressure: float, dt: float) -> float:
    """`contact_step` from the contact `c` at gauge `pressure` [Pa] over `dt` [s] of the
    actuator `kp`."""
    target = 1.0 if pressure > kp[P_CONTACT] else 0.0
    if kp[T_CONTACT] <= 0:
        return target
    rate = dt / kp[T_CONTACT]
    return _min(c + rate, 1.0) if target else _max(c - rate, 0.0)


def bulge_contact(c: float, pressure: float, p: ActuatorParams) -> float:
    """Contact (from `c`, at gauge `pressure` [Pa]) of an extremal chamber `p` whose bulge follows
    at once (t_contact <= 0, dV_contact > 0; `bulge`):
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
    return float(bulge(pack(p), c, pressure))


@jit
def bulge(kp: np.ndarray, c: float, pressure: float) -> float:
    """`bulge_contact` from the contact `c` at gauge `pressure` [Pa] of the actuator `kp`."""
    v = chamber_volume(kp, 0.0, c)
    v_eq = v * ((P_ATM + pressure) / (P_ATM + kp[P_CONTACT])) ** (1.0 / kp[KAPPA])
    return _min(_max((v_eq - kp[V0_]) / kp[DV_CONTACT], 0.0), 1.0)


@jit
def contact_after(kp: np.ndarray, x: np.ndarray, pressure: float, dt: float) -> float:
    """The contact after a sub-step of `dt` [s] at gauge pressure `pressure` of the actuator
    `kp` in the state `x`: an extremal chamber whose bulge follows at once (`bulge`), else at
    its finite rate (`contact_rate`)."""
    if kp[T_CONTACT] <= 0 and kp[CENTRAL] == 0.0 and kp[DV_CONTACT] > 0:
        return bulge(kp, x[CONTACT], pressure)
    return contact_rate(kp, x[CONTACT], pressure, dt)


@jit
def holds(kp: np.ndarray, x: np.ndarray, elongation: float, dt: float) -> bool:
    """With no air flowing over the next step (valves shut, no leak) of the actuator `kp` in
    the state `x` to the `elongation` [m], whether its sub-steps of `dt` would leave pressure,
    contact and volume as they are: the contact already where
    its sub-step takes it at this pressure, the volume not following an elongation (an
    extremal chamber's does not; a central one's must stand still). The extremal
    actuators hold so most of a gait, their valves shut between pulses."""
    if kp[CENTRAL] != 0.0 and elongation != x[ELONGATION]:
        return False
    return contact_after(kp, x, x[PRESSURE], dt) == x[CONTACT]


@jit
def valves(kp: np.ndarray, x: np.ndarray, t: float, h: float,
           duty: float) -> tuple[np.ndarray, np.ndarray, int, np.ndarray, np.ndarray, int, int]:
    """Both valves of the actuator `kp`, their blocks of the state `x` advanced, over [`t`,
    `t` + `h`) with the `duty` in [-1, 1] held (> 0 drives the inflation valve, < 0 the exhaust
    valve): (starts, ends, number) of the inflation valve's open intervals, the same of the
    exhaust valve's, and the number of sub-steps."""
    duty = _min(_max(duty, -1.0), 1.0)
    period, t1 = 1.0 / kp[F_PWM], t + h
    cap = int(kp[CAP])
    et, eon = np.empty(edge_capacity(t, t1, period)), np.empty(edge_capacity(t, t1, period))
    ne = edges_into(t, t1, _max(duty, 0.0), period, kp[PWM_PHASE], et, eon)
    in_s, in_e, n_in = valve_intervals(x, VALVES, cap, et, eon, ne, t1, kp[T_OPEN_DELAY],
                                       kp[T_CLOSE_DELAY])
    ne = edges_into(t, t1, _max(-duty, 0.0), period, kp[PWM_PHASE], et, eon)
    out_s, out_e, n_out = valve_intervals(x, VALVES + PENDING + 2 * cap, cap, et, eon, ne, t1,
                                          kp[T_OPEN_DELAY], kp[T_CLOSE_DELAY])
    n = max(1, math.ceil(h / kp[DT_SUB] - 1e-9))
    return in_s, in_e, n_in, out_s, out_e, n_out, n


@jit
def substeps(kp: np.ndarray, x: np.ndarray, t: float, h: float, n: int, elongation: float,
             in_s: np.ndarray, in_e: np.ndarray, n_in: int, out_s: np.ndarray,
             out_e: np.ndarray, n_out: int) -> float:
    """The chamber of the actuator `kp` in the state `x` (advanced in place) over [`t`, `t` +
    `h`] in `n` sub-steps, the inflation valve open over the `n_in` intervals [`in_s`, `in_e`)
    and the exhaust valve over the `n_out` intervals [`out_s`, `out_e`) (`valves`), the
    elongation [m] moving linearly to `elongation`; returns the mass [kg] that flowed in."""
    p_in, p_out = kp[P_SUPPLY] * (1.0 - kp[SUPPLY_DROP]), kp[P_EXHAUST]  # source_pressures
    gain = kp[KAPPA] * R_AIR * kp[T_AIR]
    t1 = t + h
    e0, mass = x[ELONGATION], 0.0
    v = chamber_volume(kp, e0, x[CONTACT])
    for i in range(n):
        a = t + h * i / n
        b = t1 if i + 1 == n else t + h * (i + 1) / n
        pressure = x[PRESSURE]
        p_abs = P_ATM + pressure
        dm = 0.0
        if n_in:
            t_open = time_open(in_s, in_e, n_in, a, b)
            if t_open:
                dm += signed_flow(P_ATM + p_in, p_abs, kp[C_IN], kp[B], kp[T_AIR],
                                  kp[M_SUB]) * t_open
        if n_out:
            t_open = time_open(out_s, out_e, n_out, a, b)
            if t_open:
                dm -= signed_flow(p_abs, P_ATM + p_out, kp[C_OUT], kp[B], kp[T_AIR],
                                  kp[M_SUB]) * t_open
        if kp[C_LEAK] != 0.0:
            dm -= signed_flow(p_abs, P_ATM, kp[C_LEAK], kp[B], kp[T_AIR]) * (b - a)
        # the flows cannot push the pressure past their sources (the unchoked law's slope is
        # infinite at r -> 1)
        p_flow = pressure + gain * dm / v
        clamped = _min(_max(p_flow, _min(pressure, p_out)), _max(pressure, p_in))
        if clamped != p_flow:  # the mass that fits
            p_flow, dm = clamped, (clamped - pressure) * v / gain
        x[CONTACT] = contact_after(kp, x, p_flow, b - a)
        v_next = chamber_volume(kp, e0 + (elongation - e0) * (i + 1) / n, x[CONTACT])
        if v_next != v:  # polytropic change at the mass just reached: p_abs V^kappa constant
            p_flow = (P_ATM + p_flow) * (v / v_next) ** kp[KAPPA] - P_ATM
        x[PRESSURE], v = p_flow, v_next
        mass += dm
    x[ELONGATION] = elongation
    return mass


@jit
def step(kp: np.ndarray, x: np.ndarray, t: float, h: float, duty: float,
         elongation: float) -> float:
    """`Actuator.step` of the actuator `kp` in state `x`: advance `x` from `t` to `t` + `h` with
    the `duty` held and the `elongation` [m] reached at the end; return the mass [kg] that
    flowed in. A step in which no air flows (valves shut throughout, no leak) and that `holds`
    skips its sub-steps: the same state to the bit."""
    in_s, in_e, n_in, out_s, out_e, n_out, n = valves(kp, x, t, h, duty)
    if not (n_in or n_out or kp[C_LEAK] != 0.0) and holds(kp, x, elongation, h / n):
        x[ELONGATION] = elongation
        return 0.0
    return substeps(kp, x, t, h, n, elongation, in_s, in_e, n_in, out_s, out_e, n_out)


# ---- the FMU's kernel: u = [duty, flange_a.s, flange_b.s], y = [p, f_a, u, m_flow] -----------
@jit
def evaluate(p: np.ndarray, x: np.ndarray, u: np.ndarray, t: float, y: np.ndarray) -> None:
    """The outputs `y`: gauge pressure, force s_a p, contact, the last step's mean mass flow,
    from the state `x` of the parameters `p`; the inputs `u` and time `t` unused."""
    y[0] = x[PRESSURE]
    y[1] = p[S_A] * x[PRESSURE]
    y[2] = x[CONTACT]
    y[3] = x[M_FLOW]


@jit
def advance(p: np.ndarray, x: np.ndarray, u: np.ndarray, y: np.ndarray, t: float,
            dt: float) -> None:
    """The step of the state `x` (in place) over [`t`, `t` + `dt`] of the parameters `p` with the
    inputs `u` = (duty, flange_a.s, flange_b.s) held, the elongation flange_b.s - flange_a.s
    reached at its end; the outputs `y` unused."""
    mass = step(p, x, t, dt, u[0], u[2] - u[1])
    x[M_FLOW] = mass / dt if dt > 0 else 0.0


KERNEL = Kernel(evaluate, advance, inputs=("duty", "flange_a.s", "flange_b.s"),
                outputs=("p", "f_a", "u", "m_flow"), clamps=(("duty", -1.0, 1.0),))


class Actuator:
    """One soft actuator's state (gauge pressure, contact, valves, volume: the kernel's state
    `x`) and its step.

    Parameters
    ----------
    params : ActuatorParams
    elongation : float
        Elongation [m] of the central actuator at the start (the volume follows it).
    """

    def __init__(self, params: ActuatorParams, elongation: float = 0.0) -> None:
        self.params = params
        self.kp = pack(params)
        self.x = start_state(self.kp, elongation)

    @property
    def pressure(self) -> float:
        """Gauge pressure [Pa] of the chamber."""
        return float(self.x[PRESSURE])

    @property
    def contact(self) -> float:
        """Contact 0..1 with the ground."""
        return float(self.x[CONTACT])

    @property
    def elongation(self) -> float:
        """Elongation [m] the volume stands at."""
        return float(self.x[ELONGATION])

    def step(self, t: float, h: float, duty: float, elongation: float) -> float:
        """Advance from `t` to `t` + `h` with the `duty` in [-1, 1] held (> 0 inflates, < 0
        exhausts) and the elongation [m] moving linearly to `elongation`; return the mass [kg] that
        flowed in (`step`, with the shortcut asked of `_holds`)."""
        kp, x = self.kp, self.x
        in_s, in_e, n_in, out_s, out_e, n_out, n = valves(kp, x, t, h, duty)
        if not (n_in or n_out or kp[C_LEAK] != 0.0) and self._holds(elongation, h / n):
            x[ELONGATION] = elongation
            return 0.0
        return float(substeps(kp, x, t, h, n, elongation, in_s, in_e, n_in, out_s, out_e, n_out))

    def _holds(self, elongation: float, dt: float) -> bool:
        """Whether a step without flow leaves the state as it is (`holds`)."""
        return bool(holds(self.kp, self.x, elongation, dt))
