"""A pneumatic crawler bench written apart from the library, each subsystem in several forms:
valves, spools and chambers (`musclesim.benchmark.benches.crawler_air`), contact, friction, the
body's spring, the camera.

The independent virtual hardware of the crawler cases of the blind benchmark
(`musclesim.benchmark.plan` draws them). Nothing here comes from `musclesim.components`; the
defaults (the first form named in each field of `FORMS`) are other representations than the
library's:

- Valves (§crawler-hardware, §valves): PWM on a carrier of its own phase; the spool's opening
  follows the command (``spool``: a first-order lag; a damped second-order armature; a coil's dead
  time then a lag); flow by a ``valve_law``: the isentropic nozzle (Saint-Venant-Wantzel), the
  incompressible orifice, or ISO 6358's conductance and critical ratio ``valve_b`` (sources in
  `crawler_air`).
- Chambers (``chamber``): mass and energy balances of the air with heat exchange to the silicone
  wall over ``tau_wall``; isothermal; polytropic with ``polytropic_n``. The central chamber grows
  with the elongation and bulges with its pressure; an extremal chamber grows as its silicone
  spreads on the ground.
- Contact (``contact``; §contact: firm contact past a least pressure, the front one's higher,
  §gait): an extremal actuator's share of silicone on the ground about its own threshold, reached
  over a spreading time ``tau_contact`` (a lag, not §contact's ramp): ``"logistic"`` in the
  pressure (width ``contact_width``); ``"threshold"``, all or nothing; ``"bulging"``, linear from
  3 ``contact_width`` below the threshold to 3 above (the silicone bulging onto the ground).
- Friction (§friction; ``friction``): per block, its coefficients blended by the contact share:
  ``"lugre"``, the LuGre model (Canudas de Wit et al., IEEE TAC 40, 1995), the bristles' stiffness
  proportional to the normal force; ``"dahl"``, Dahl's model (Dahl, "A solid friction model",
  Aerospace Corp. TOR-158, 1968; AIAA J. 14, 1976; as in Canudas de Wit et al. 1995 without
  Stribeck: kinetic friction, static grip only by the presliding stiffness); ``"coulomb"``,
  switching Coulomb friction with stiction (Karnopp, ASME J. Dyn. Syst. Meas. Control 107, 1985),
  a block inside `V_STICK` held while the other forces stay below ``mu_s N``.
- Body (§two-mass): two masses, the central actuator a spring ``k d (1 + k3 d^2)`` (linear at
  ``k3 = 0``, stiffening above) and a damper, its force on an effective area of its own; the
  board's incline as drawn.
- Controller: a PI per actuator on its sensor at 1 kHz (the duties logged, as the diagnosis
  replays them) following §gait's four-phase gait.
- Sensors: pressure sensors behind a short tube (a first-order lag), gain, noise,
  quantisation; the blocks' positions from video at ``video_fps`` frames/s, scaled by the camera,
  tracked to a pixel with noise, delayed, and interpolated onto the DAQ's clock, or
  (``video_hold``) the last frame held, as a frame grabber gives it.

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

from musclesim.benchmark.benches.crawler_air import (CHAMBERS, P_ATM, R_AIR, SPOOLS, T_ROOM,
                                                     VALVE_LAWS, Air, Chamber, valve_flow)

G = 9.81  # m/s^2
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
V_STICK = 1e-4  # m/s: Karnopp's band, a block slower than this may stick
ACTUATORS = ("back", "central", "front")
# each form field's allowed values, its default first
FORMS = {"friction": ("lugre", "coulomb", "dahl"), "valve_law": tuple(VALVE_LAWS),
         "spool": SPOOLS, "chamber": CHAMBERS, "contact": ("logistic", "threshold", "bulging")}


@dataclass(frozen=True)
class Crawler:
    """Every condition of one crawler bench run; the defaults are the model's values, ideal
    sensors, each subsystem's first form (`FORMS`). Pressures gauge [Pa]; ``surface_change`` is
    (time [s], factor on every friction coefficient) or None.

    Raises
    ------
    ValueError
        A form field not one of its `FORMS`, or ``valve_b`` outside [0, 1).
    """

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
    contact_width: float = 1e3  # Pa: of the logistic; the bulging ramp spans six
    tau_contact: float = 0.05  # s: the silicone spreading
    dv_contact: float = 3e-6  # m^3: an extremal chamber's growth at full contact
    p_supply: float = 40e3
    p_exhaust: float = -20e3
    valve_area: float = VALVE_AREA
    tau_valve: float = 0.002  # s: the spool
    spool_zeta: float = 0.7  # the second-order spool's damping: well damped (an assumption)
    f_pwm: float = 50.0  # Hz
    pwm_phase: float = 0.0  # of a period
    tau_wall: float = 1.0  # s: the air's heat exchange with the silicone
    polytropic_n: float = 1.2  # the polytropic chamber's exponent (§chamber: 1 to 1.4)
    valve_b: float = 0.3  # ISO 6358's critical ratio (§valves)
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
    video_fps: float = VIDEO_FPS
    video_hold: bool = False  # the last frame held, not frames interpolated
    # the subsystems' forms (FORMS)
    friction: str = "lugre"
    valve_law: str = "nozzle"
    spool: str = "first-order"
    chamber: str = "energy"
    contact: str = "logistic"
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

    def __post_init__(self) -> None:
        for name, allowed in FORMS.items():
            if getattr(self, name) not in allowed:
                raise ValueError(f"Crawler.{name} = {getattr(self, name)!r}: not a form of the "
                                 f"bench; allowed: {', '.join(allowed)}")
        if not 0.0 <= self.valve_b < 1.0:
            raise ValueError(f"Crawler.valve_b = {self.valve_b}: ISO 6358's critical ratio is "
                             "in [0, 1)")


def air_settings(bench: Crawler) -> Air:
    """The settings of `bench`'s air (`musclesim.benchmark.benches.crawler_air.Air`)."""
    return Air(valve_law=bench.valve_law, valve_b=bench.valve_b, valve_area=bench.valve_area,
               spool=bench.spool, tau_valve=bench.tau_valve, spool_zeta=bench.spool_zeta,
               chamber=bench.chamber, polytropic_n=bench.polytropic_n, tau_wall=bench.tau_wall,
               leak=bench.leak, p_exhaust=bench.p_exhaust)


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


class _LuGre:
    """One block's LuGre bristles."""

    holds = False  # never stops the block itself

    def __init__(self) -> None:
        self.z = 0.0

    def force(self, v: float, normal: float, mu_s: float, mu_k: float, push: float,
              bench: Crawler, dt: float) -> float:
        """Friction force on the block over a step of `dt` at velocity `v` on `normal` with
        coefficients `mu_s`, `mu_k` (`push`: the other forces, unused; `bench`: the bristles);
        advances the bristles."""
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


class _Dahl(_LuGre):
    """One block's Dahl bristles: LuGre's without Stribeck nor damping, toward ``mu_k N``."""

    def force(self, v: float, normal: float, mu_s: float, mu_k: float, push: float,
              bench: Crawler, dt: float) -> float:
        """Friction force ``-sigma0 z`` on the block over a step of `dt` at velocity `v` on
        `normal` (`mu_k` the kinetic coefficient; `mu_s`, `push` unused; `bench`: the
        stiffness); the bristles ``dz/dx = 1 - z / g sgn v`` advanced exactly at constant v."""
        sigma0 = bench.bristle * normal
        g = mu_k * normal / sigma0  # the bristles' deflection at full slide
        if g <= 0.0:
            self.z = 0.0
        elif abs(v) > 1e-12:
            target = math.copysign(g, v)
            self.z = target + (self.z - target) * math.exp(-abs(v) * dt / g)
        return -sigma0 * self.z


class _Coulomb:
    """One block's switching Coulomb friction with stiction (Karnopp): held inside `V_STICK`
    while the other forces stay within ``mu_s N``."""

    holds = True  # stops the block: a stuck one, or one friction would turn round

    def __init__(self) -> None:
        self.stuck = False

    def force(self, v: float, normal: float, mu_s: float, mu_k: float, push: float,
              bench: Crawler, dt: float) -> float:
        """Friction force on the block at velocity `v` on `normal` under the other forces `push`
        with coefficients `mu_s`, `mu_k` (`bench`, `dt` unused); sets `stuck`."""
        self.stuck = abs(v) < V_STICK and abs(push) <= mu_s * normal
        if self.stuck:
            return -push
        return -math.copysign(mu_k * normal, v if abs(v) >= V_STICK else push)


FRICTIONS = {"lugre": _LuGre, "dahl": _Dahl, "coulomb": _Coulomb}


def _grip(bench: Crawler, t: float) -> Any:
    """Factor on the silicone's coefficients (decay) and on all (surface change) at time t."""
    silicone = 1.0 - bench.decay * (1.0 - math.exp(-t / bench.decay_time))
    everything = 1.0
    if bench.surface_change is not None and t >= bench.surface_change[0]:
        everything = bench.surface_change[1]
    return silicone, everything


def _contact(bench: Crawler, p_gauge: float, threshold: float) -> float:
    """The share of an extremal actuator's silicone on the ground that `bench`'s contact form
    gives at `p_gauge` [Pa] about its `threshold` [Pa], once spread."""
    if bench.contact == "threshold":
        return 1.0 if p_gauge > threshold else 0.0
    if bench.contact == "bulging":
        ramp = 6 * bench.contact_width
        return min(max((p_gauge - threshold) / ramp + 0.5, 0.0), 1.0)
    return 1.0 / (1.0 + math.exp(-(p_gauge - threshold) / bench.contact_width))


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


def _blow(bench: Crawler, chambers: list[Chamber], duty: list[float], x: list[float],
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
            w = _contact(bench, p_gauge, thresholds[i])
            ch.contact = w + (ch.contact - w) * math.exp(-dt / bench.tau_contact)
            V_new = V_EXTREMAL + bench.dv_contact * ch.contact
        draw += ch.step(dt, share_in, share_out, source, max(V_new, 0.1 * V_EXTREMAL))
    return draw


def _move(bench: Crawler, chambers: list[Chamber], blocks: list[Any], x: list[float],
          v: list[float], masses: tuple[float, float], normals: list[float], ts: float,
          dt: float) -> None:
    """One internal step `dt` at time `ts` of `bench`'s body and friction: the blocks' positions
    `x` and velocities `v` advanced in place under the central `chambers`' pressure, the spring,
    the damper and each block's grip (`blocks`, of `masses` on `normals`). A block whose friction
    `holds` it stops when stuck or where its velocity would change sign within the step (Karnopp's
    band is narrower than a step's change of velocity)."""
    p_c = chambers[1].p - P_ATM
    k = bench.k * (1 + bench.stiffening * p_c / 1e4)
    d = x[1] - x[0]
    inner = k * d * (1 + bench.k3 * d * d) + bench.c * (v[1] - v[0]) - bench.area * p_c
    silicone, everything = _grip(bench, ts)
    for b, (ch, sign) in enumerate(((chambers[0], 1.0), (chambers[2], -1.0))):
        share = ch.contact * (1.0 - bench.bending)
        mu_s = everything * (bench.mu_s_low + share * (silicone * bench.mu_s_high
                                                       - bench.mu_s_low))
        push = sign * inner - masses[b] * G * math.sin(bench.theta)  # all but friction
        f = blocks[b].force(v[b], normals[b], mu_s, bench.mu_ratio * mu_s, push, bench, dt)
        a = (sign * inner + f) / masses[b] - G * math.sin(bench.theta)
        v_new = v[b] + a * dt
        if blocks[b].holds and (blocks[b].stuck or v_new * v[b] < 0.0):
            v_new = 0.0
        v[b] = v_new
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
    air = air_settings(bench)
    chambers = [Chamber(V_EXTREMAL, air), Chamber(V_CENTRAL, air), Chamber(V_EXTREMAL, air)]
    blocks = [FRICTIONS[bench.friction]() for _ in range(2)]
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
    # the pump's free flow: a reserve over one open valve's flow from the supply to the room
    pump = bench.pump_reserve * valve_flow(air)(supply, P_ATM, bench.valve_area, T_ROOM)
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
    """The blocks' positions `x_true` as `bench`'s camera gives them on the DAQ's clock `time`:
    frames at ``video_fps`` (each ``video_delay`` late), scaled, noisy (from `rng`), to a pixel,
    linearly interpolated or, ``video_hold``, the last frame held."""
    frames = np.arange(0.0, time[-1] + 1e-9, 1.0 / bench.video_fps)
    out = np.empty_like(x_true)
    for b in range(x_true.shape[1]):
        seen = bench.video_scale * np.interp(frames, time, x_true[:, b])
        seen = seen + bench.video_noise * rng.standard_normal(len(frames))
        if bench.video_quantum:
            seen = bench.video_quantum * np.round(seen / bench.video_quantum)
        if bench.video_hold:  # the newest frame arrived by each sample (1 ns spares rounding)
            arrived = np.searchsorted(frames + bench.video_delay, time + 1e-9, side="right")
            out[:, b] = seen[np.maximum(arrived - 1, 0)]
        else:
            out[:, b] = np.interp(time, frames + bench.video_delay, seen, left=seen[0])
    return out
