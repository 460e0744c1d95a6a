"""A pneumatic crawler bench written apart from the library: chambers with heat exchange, LuGre
friction, a nonlinear actuator, slow video.

The independent virtual hardware of the crawler cases of the blind benchmark
(`musclesim.benchmark.plan` draws them). Nothing here comes from
`musclesim.components`; each part is another representation than the library's:

- Valves (§crawler-hardware, §valves): PWM on a carrier of its own phase; the spool's opening
  follows the command with a first-order lag; flow by the isentropic nozzle law
  (Saint-Venant-Wantzel, critical ratio ``(2 / (kappa + 1)) ** (kappa / (kappa - 1))``, laminar
  within 0.1 % of equal pressures), not the ISO 6358 conductance.
- Chambers: mass and energy balances of the air (kappa 1.4) with heat exchange to the silicone
  wall over ``tau_wall``, not a polytropic law; the central chamber grows with the elongation and
  bulges with its pressure; an extremal chamber grows as its silicone spreads on the ground.
- Contact: an extremal actuator's share of silicone on the ground is a logistic function of its
  pressure about its own threshold (the front one's higher, §gait), reached over a spreading
  time, not a ramp at a threshold.
- Friction (§friction): the LuGre model (Canudas de Wit et al., IEEE TAC 40, 1995) per block, its
  coefficients blended by the contact share, the bristles' stiffness proportional to the normal
  force; not Karnopp.
- Body (§two-mass): two masses, the central actuator a hardening spring ``k d (1 + k3 d^2)`` and a
  damper, its force on an effective area of its own; the board's incline as drawn.
- Controller: a PI per actuator on its sensor at 1 kHz (the duties logged, as the diagnosis
  replays them) following §gait's four-phase gait.
- Sensors: pressure sensors behind a short tube (a first-order lag), gain, noise,
  quantisation; the blocks' positions from video at `VIDEO_FPS`, scaled by the camera, tracked to
  a pixel with noise, delayed, and interpolated onto the DAQ's clock.

Hidden effects, each written here without the library's version: valve delay (the PWM windows
shifted), supply-pressure drop (a reservoir the pump refills through its curve), chamber leakage
(laminar, in p^2), pressure-dependent stiffness, actuator bending on an incline (the bent actuator
keeps part of its casing on the ground), friction decay (contamination that saturates); outside
the library: a long sensor tube, a change of surface part-way, a camera scale error.

>>> out = run(Crawler(), 0.2)
>>> sorted(out), len(out["time"])
(['duty', 'p_meas', 'p_true', 'time', 'x', 'x_true'], 201)
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

G = 9.81  # m/s^2
P_ATM = 101325.0  # Pa
R_AIR = 287.05  # J/(kg K)
KAPPA = 1.4  # air, adiabatic
CV = R_AIR / (KAPPA - 1)  # J/(kg K)
CP = KAPPA * CV
T_ROOM = 293.15  # K
R_CRIT = (2 / (KAPPA + 1)) ** (KAPPA / (KAPPA - 1))  # 0.528
S_A = 9.62e-4  # m^2: the central actuator's 35 mm section (§two-mass)
V_CENTRAL = 5.87e-5  # m^3: 30 mm bore x 83 mm (§crawler-hardware)
V_EXTREMAL = 1.41e-5  # m^3: 30 mm bore x 20 mm (§crawler-hardware: 26 mm with the connector)
# a miniature solenoid valve: Cd A of a 0.55 mm orifice (§crawler-hardware names none)
VALVE_AREA = 2.5e-7  # m^2
THETA = math.radians(7.5)  # §gait's board
# gait (§gait): 1.2 s protrusion, 1.8 s stance split over phases 1, 3, 4; references as
# the scenarios' characterisation gave them (scenarios/params/crawler-gait-references.toml)
T_PROTRUSION, T_STANCE = 1.2, 1.8
P_CENTRAL, P_ANCHOR = 8.59e3, 10.3e3  # Pa
DAQ = 1e-3  # s: the controllers' and the log's period (§crawler-hardware)
SUBSTEPS = 5  # internal steps per DAQ period
VIDEO_FPS = 30.0
V_STRIBECK = 2e-3  # m/s: the static coefficient fades above it (LuGre's Stribeck velocity)
ACTUATORS = ("back", "central", "front")


@dataclass(frozen=True)
class Crawler:
    """Every condition of one crawler bench run; the defaults are the model's values, ideal
    sensors. Pressures gauge [Pa]; ``surface_change`` is (time [s], factor on every friction
    coefficient) or None."""

    theta: float = THETA
    m1: float = 0.2  # kg, back block (§ideal-actuation)
    m2: float = 0.2  # kg, front block
    k: float = 200.0  # N/m (§ideal-actuation)
    k3: float = 0.0  # 1/m^2: hardening of the central actuator
    c: float = 1.3  # N s/m (§ideal-actuation)
    area: float = S_A  # m^2: the effective area the central pressure pushes on
    bulge: float = 0.0  # 1/Pa: the central chamber's volume grows by this share per Pa
    mu_s_high: float = 1.0  # §friction
    mu_s_low: float = 0.13
    mu_ratio: float = 0.75  # kinetic / static (§friction)
    bristle: float = 2e4  # 1/m: LuGre stiffness per newton of normal force
    p_contact_back: float = 8e3  # Pa: half the silicone on the ground
    p_contact_front: float = 8e3
    contact_width: float = 1e3  # Pa: of the logistic
    tau_contact: float = 0.05  # s: the silicone spreading
    dv_contact: float = 3e-6  # m^3: an extremal chamber's growth at full contact
    p_supply: float = 40e3
    p_exhaust: float = -20e3
    valve_area: float = VALVE_AREA
    tau_valve: float = 0.002  # s: the spool
    f_pwm: float = 50.0  # Hz
    pwm_phase: float = 0.0  # of a period
    tau_wall: float = 1.0  # s: the air's heat exchange with the silicone
    kp_central: float = 1.386e-3  # duty/Pa: the bench's PIs (about the scenarios' design)
    ki_central: float = 6.93e-3
    kp_extremal: float = 5.9e-5
    ki_extremal: float = 2.95e-4
    ref_factor: float = 1.0  # on the gait's pressure references
    sensor_tau: float = 0.0  # s: the pressure sensors' tubes
    sensor_gain: float = 1.0
    sensor_noise: float = 0.0  # Pa
    sensor_quantum: float = 0.0  # Pa
    video_scale: float = 1.0
    video_noise: float = 0.0  # m
    video_quantum: float = 0.0  # m: a pixel
    video_delay: float = 0.0  # s
    # hidden effects, off by default
    open_delay: float = 0.0  # s
    close_delay: float = 0.0  # s
    pump_reserve: float = 0.0  # pump's free flow / one open valve's choked flow; 0 = ideal source
    leak: float = 0.0  # kg/(s Pa): laminar leak of each chamber, in (p^2 - p_atm^2) / p_atm
    stiffening: float = 0.0  # k grows by this share per 10 kPa of central pressure
    bending: float = 0.0  # share of the silicone the bent actuator lifts off on this incline
    decay: float = 0.0  # share of the silicone's friction lost once contaminated
    decay_time: float = 5.0  # s
    surface_change: tuple | None = None
    seed: int = 0


def gait(t: float) -> Any:
    """Pressure references (back, central, front) [Pa] of the forward gait at time `t` (§gait).

    >>> gait(0.0), gait(2.0)[1], gait(2.9)
    ((10300.0, 0.0, 0.0), 8590.0, (0.0, 0.0, 10300.0))
    """
    d = T_STANCE / 3
    s = t % (T_PROTRUSION + T_STANCE)
    if s < d:
        return P_ANCHOR, 0.0, 0.0
    if s < d + T_PROTRUSION:
        return P_ANCHOR, P_CENTRAL, 0.0
    if s < 2 * d + T_PROTRUSION:
        return P_ANCHOR, P_CENTRAL, P_ANCHOR
    return 0.0, 0.0, P_ANCHOR


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


def open_share(a: float, b: float, duty: float, period: float, phase: float, delay_on: float,
               delay_off: float) -> float:
    """Share of [`a`, `b`] during which a PWM valve of `duty` is open: windows
    [k `period` + `phase` + `delay_on`, k `period` + `phase` + `duty` `period` + `delay_off`).

    >>> open_share(0.0, 0.02, 0.25, 0.02, 0.0, 0.0, 0.0)
    0.25
    >>> open_share(0.0, 0.001, 0.25, 0.02, 0.0, 0.002, 0.0)
    0.0
    """
    if duty <= 0.0:
        return 0.0
    if duty >= 1.0:
        return 1.0
    start, end = phase * period + delay_on, phase * period + duty * period + delay_off
    if end <= start:
        return 0.0
    k0, k1 = math.floor((a - end) / period), math.floor((b - start) / period) + 1
    return sum(max(0.0, min(b, k * period + end) - max(a, k * period + start))
               for k in range(k0, k1 + 1)) / (b - a)


class _Chamber:
    """One actuator's air (absolute pressure, temperature), valves and contact."""

    def __init__(self, volume: float) -> None:
        self.p, self.T, self.V = P_ATM, T_ROOM, volume
        self.spool_in = self.spool_out = 0.0
        self.contact = 0.0

    def step(self, bench: Crawler, dt: float, share_in: float, share_out: float, supply: float,
             V_new: float) -> Any:
        a = math.exp(-dt / bench.tau_valve)
        self.spool_in = share_in + (self.spool_in - share_in) * a
        self.spool_out = share_out + (self.spool_out - share_out) * a
        exhaust = P_ATM + bench.p_exhaust
        m_in = nozzle_flow(supply, self.p, bench.valve_area * self.spool_in, T_ROOM)
        back = nozzle_flow(self.p, supply, bench.valve_area * self.spool_in, self.T)
        m_out = nozzle_flow(self.p, exhaust, bench.valve_area * self.spool_out, self.T)
        leak = bench.leak * (self.p ** 2 - P_ATM ** 2) / P_ATM
        mass = self.p * self.V / (R_AIR * self.T)
        heat = mass * CV * (T_ROOM - self.T) / bench.tau_wall
        power = CP * T_ROOM * m_in - CP * self.T * (back + m_out + leak) + heat
        # the volume's change adiabatic (exact over the step), then the flows' and wall's energy
        p = self.p * (self.V / V_new) ** KAPPA + dt * (KAPPA - 1) / V_new * power
        mass += dt * (m_in - back - m_out - leak)
        self.p, self.V = max(p, 0.1 * P_ATM), V_new
        self.T = self.p * self.V / (R_AIR * max(mass, 1e-12))
        return m_in - back


class _Block:
    """One block's LuGre bristles."""

    def __init__(self) -> None:
        self.z = 0.0

    def force(self, v: float, normal: float, mu_s: float, mu_k: float, bench: Crawler,
              dt: float) -> float:
        """Friction force on the block over a step of dt at velocity v; advances the bristles."""
        sigma0 = bench.bristle * normal
        stribeck = math.exp(-(v / V_STRIBECK) ** 2)
        sigma1 = 2 * 0.7 * math.sqrt(sigma0 * 0.2) * stribeck  # damped presliding
        g = (mu_k + (mu_s - mu_k) * stribeck) * normal / sigma0
        z0 = self.z
        if abs(v) > 1e-12:  # the bristle ODE advanced exactly at constant v
            target = math.copysign(g, v)
            self.z = target + (z0 - target) * math.exp(-abs(v) * dt / g)
        dz = (self.z - z0) / dt
        return -(sigma0 * self.z + sigma1 * dz)


def _grip(bench: Crawler, t: float) -> Any:
    """Factor on the silicone's coefficients (decay) and on all (surface change) at time t."""
    silicone = 1.0 - bench.decay * (1.0 - math.exp(-t / bench.decay_time))
    everything = 1.0
    if bench.surface_change is not None and t >= bench.surface_change[0]:
        everything = bench.surface_change[1]
    return silicone, everything


def _control(bench: Crawler, t: float, reading: list[float], kp: tuple[float, ...],
             ki: tuple[float, ...], integral: list[float]) -> list[float]:
    """The PIs' duties (back, central, front) at DAQ time `t` from the sensors' `reading`, gains
    `kp`, `ki` of `bench`; their `integral` terms advanced in place (conditional integration)."""
    duty = []
    for i, ref in enumerate(gait(t)):
        e = bench.ref_factor * ref - reading[i]
        trial = kp[i] * e + integral[i]
        u = min(max(trial, -1.0), 1.0)
        if trial == u or (trial > 1.0) == (e < 0):  # anti-windup
            integral[i] += ki[i] * e * DAQ
        duty.append(u)
    return duty


def _blow(bench: Crawler, chambers: list[_Chamber], duty: list[float], x: list[float],
          thresholds: tuple[Any, ...], period: float, ts: float, dt: float,
          source: float) -> float:
    """One internal step `dt` at time `ts` of `bench`'s `chambers` through their PWM valves
    (`duty`, `period`) from `source` [Pa]: volumes from the body's positions `x` and the
    extremal chambers' contact (past their `thresholds`); return what they draw from the source
    (the reservoir's balance takes it)."""
    draw = 0.0
    for i, ch in enumerate(chambers):
        d = duty[i]
        share_in = open_share(ts, ts + dt, d, period, bench.pwm_phase, bench.open_delay,
                              bench.close_delay)
        share_out = open_share(ts, ts + dt, -d, period, bench.pwm_phase,
                               bench.open_delay, bench.close_delay)
        p_gauge = ch.p - P_ATM
        if i == 1:
            V_new = V_CENTRAL * (1 + bench.bulge * p_gauge) + S_A * (x[1] - x[0])
        else:
            w = 1.0 / (1.0 + math.exp(-(p_gauge - thresholds[i]) / bench.contact_width))
            ch.contact = w + (ch.contact - w) * math.exp(-dt / bench.tau_contact)
            V_new = V_EXTREMAL + bench.dv_contact * ch.contact
        draw += ch.step(bench, dt, share_in, share_out, source, max(V_new, 0.1 * V_EXTREMAL))
    return draw


def _move(bench: Crawler, chambers: list[_Chamber], blocks: list[_Block], x: list[float],
          v: list[float], masses: tuple[float, float], normals: list[float], ts: float,
          dt: float) -> None:
    """One internal step `dt` at time `ts` of `bench`'s body and friction: the blocks' positions
    `x` and velocities `v` advanced in place under the central `chambers`' pressure, the spring,
    the damper and each block's grip (`blocks`, of `masses` on `normals`)."""
    p_c = chambers[1].p - P_ATM
    k = bench.k * (1 + bench.stiffening * p_c / 1e4)
    d = x[1] - x[0]
    inner = k * d * (1 + bench.k3 * d * d) + bench.c * (v[1] - v[0]) - bench.area * p_c
    silicone, everything = _grip(bench, ts)
    forces = []
    for b, ch in enumerate((chambers[0], chambers[2])):
        share = ch.contact * (1.0 - bench.bending)
        mu_s = everything * (bench.mu_s_low + share * (silicone * bench.mu_s_high
                                                       - bench.mu_s_low))
        f = blocks[b].force(v[b], normals[b], mu_s, bench.mu_ratio * mu_s, bench, dt)
        forces.append(f)
    for b, sign in ((0, 1.0), (1, -1.0)):
        a = (sign * inner + forces[b]) / masses[b] - G * math.sin(bench.theta)
        v[b] += a * dt
        x[b] += v[b] * dt


def run(bench: Crawler, duration: float, substeps: int = SUBSTEPS) -> dict[str, np.ndarray]:
    """Run the crawler `bench` for `duration` [s] from rest, deflated, `substeps` internal steps
    per DAQ sample; return the log at the DAQ's rate.

    Returns
    -------
    dict
        ``time``; ``duty`` (n, 3): the PIs' duties (back, central, front), held over each DAQ
        period; ``p_meas`` (n, 3) [Pa gauge]: the sensors' readings the PIs used; ``x`` (n, 2) [m]:
        the blocks' positions from video; the truth ``p_true`` (n, 3) and ``x_true`` (n, 2).
    """
    rng = np.random.default_rng(bench.seed)
    dt = DAQ / substeps
    n = int(round(duration / DAQ)) + 1
    chambers = [_Chamber(V_EXTREMAL), _Chamber(V_CENTRAL), _Chamber(V_EXTREMAL)]
    blocks = [_Block(), _Block()]
    x = [0.0, 0.0]  # m, positions from rest
    v = [0.0, 0.0]
    masses = (bench.m1, bench.m2)
    normals = [m * G * math.cos(bench.theta) for m in masses]
    supply = P_ATM + bench.p_supply
    thresholds: tuple[Any, ...] = (bench.p_contact_back, None, bench.p_contact_front)
    kp = (bench.kp_extremal, bench.kp_central, bench.kp_extremal)
    ki = (bench.ki_extremal, bench.ki_central, bench.ki_extremal)
    integral = [0.0] * 3
    sensed = [0.0] * 3
    log = {k: np.empty((n, w)) for k, w in (("duty", 3), ("p_meas", 3), ("p_true", 3),
                                            ("x_true", 2))}
    # the pump's free flow: a reserve over one open valve's choked flow at the supply
    pump = bench.pump_reserve * nozzle_flow(supply, P_ATM, bench.valve_area, T_ROOM)
    reservoir = supply
    period = 1.0 / bench.f_pwm
    for j in range(n):
        t = j * DAQ
        reading = [bench.sensor_gain * s + bench.sensor_noise * rng.standard_normal()
                   for s in sensed]
        if bench.sensor_quantum:
            reading = [bench.sensor_quantum * round(r / bench.sensor_quantum) for r in reading]
        duty = _control(bench, t, reading, kp, ki, integral)
        log["duty"][j], log["p_meas"][j] = duty, reading
        log["p_true"][j] = [c.p - P_ATM for c in chambers]
        log["x_true"][j] = x
        for s in range(substeps):
            ts = t + s * dt
            draw = _blow(bench, chambers, duty, x, thresholds, period, ts, dt,
                         reservoir if pump else supply)  # pneumatics
            if pump:  # the reservoir (a 50 ml line) refilled along the pump's linear curve
                refill = pump * (1.0 - (reservoir - P_ATM) / bench.p_supply)
                reservoir += dt * R_AIR * T_ROOM / 5e-5 * (refill - draw)
                reservoir = min(max(reservoir, P_ATM), supply)
            _move(bench, chambers, blocks, x, v, masses, normals, ts, dt)  # body and friction
        # the sensors behind their tubes, sampled for the next period
        for i, ch in enumerate(chambers):
            p_gauge = ch.p - P_ATM
            sensed[i] = (p_gauge if bench.sensor_tau <= 0 else
                         p_gauge + (sensed[i] - p_gauge) * math.exp(-DAQ / bench.sensor_tau))
    time = np.round(np.arange(n) * DAQ, 9)
    log["x"] = _video(bench, time, log["x_true"], rng)
    return {"time": time, **log}


def _video(bench: Crawler, time: np.ndarray, x_true: np.ndarray,
           rng: np.random.Generator) -> np.ndarray:
    """The blocks' positions as the camera gives them on the DAQ's clock: frames at
    `VIDEO_FPS` (each `video_delay` late), scaled, noisy, to a pixel, linearly interpolated."""
    frames = np.arange(0.0, time[-1] + 1e-9, 1.0 / VIDEO_FPS)
    out = np.empty_like(x_true)
    for b in range(x_true.shape[1]):
        seen = bench.video_scale * np.interp(frames, time, x_true[:, b])
        seen = seen + bench.video_noise * rng.standard_normal(len(frames))
        if bench.video_quantum:
            seen = bench.video_quantum * np.round(seen / bench.video_quantum)
        out[:, b] = np.interp(time, frames + bench.video_delay, seen, left=seen[0])
    return out
