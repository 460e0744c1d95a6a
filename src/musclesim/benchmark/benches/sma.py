"""An SMA bench written apart from the library: a wire of non-uniform temperature, sensors, a PI.

The independent virtual hardware of the blind benchmark (`musclesim.benchmark.plan`
draws its cases). Nothing here comes from `musclesim.components`; the physics is another
representation than the library's, so that model and bench never differ by one effect alone:

- Heat (§thermal-model, §sma-material): the 1-D heat equation along the wire on `CELLS` finite
  volumes, graded toward the clamps (Chebyshev edges), per volume
  ``rho c A dx dT/dt = I^2 R_i - h pi d dx (T - T_amb) - eps sigma pi d dx (T^4 - T_amb^4)
  + conduction + rho A dx L dxi/dt``, with R_i = rho_e(xi_i) dx / A in series (one current),
  the clamps at T_clamp through a contact conductance. The linear part advances exactly
  (``expm``); Joule heat, radiation and any change of h are held over a sub-step; the latent
  heat is implicit (Newton per volume: an explicit one oscillates where L |dxi/dT| > c).
- Hysteresis (`musclesim.benchmark.benches.sma_kinetics`): no Preisach surface. The martensite
  fraction of each volume follows the cosine
  kinetics of Liang & Rogers (J. Intell. Mater. Syst. Struct. 1, 1990) in two populations of
  grains with their own bands (`POPULATIONS`), transformation temperatures shifted by the
  stress at `CC_SLOPE` (Clausius-Clapeyron); a branch starting inside a band (a reversal) is
  the major branch scaled to pass through the reversal point. The contraction is
  ``eps_L (1 - xi) + sigma / E_M - sigma / E(xi) - alpha (T - T_ref)`` averaged over the length,
  E(xi) = E_A + xi (E_M - E_A) (Liang & Rogers' mixture rule).
  Or (``hysteresis``) Tanaka's exponential kinetics, or a grid of relays (a discrete Preisach
  model); ``band_shift``/``band_scale`` give a case its own material; a training drift moves
  every band by ``drift_shift`` and scales the transformation strain by ``1 - drift_amplitude``,
  both settling as ``1 - exp(-t / drift_time)``. ``thermal="lumped"`` makes the wire one volume.
- Resistivity (``resistivity_law``): linear in the fractions (the model's), with a temperature
  coefficient, or the phases in parallel (1/rho = xi/rho_M + (1 - xi)/rho_A).
- Convection: h constant as the model's, or natural convection by the Churchill-Chu
  correlation (`air_convection`), or gusts (h times 1 + ``gust_level`` times a unit
  Ornstein-Uhlenbeck process of time constant ``gust_time``), or h growing as
  (excess / 50 K)^``h_exponent``, or a draught that steps h up part-way through; radiation at
  an emissivity the case draws (the study gives none).
- Thermocouple: junction behind a coat, two first-order stages (tau_sheath, tau_junction) on
  one volume near the middle, or (``tc_form``) one stage, or a three-stage RC ladder whose
  stages load each other (each of time constant (tau_sheath + tau_junction) / 6, the same
  total delay); gain, offset, bias, noise, quantisation. Strain sensor: a
  first-order stage, gain, offset (drifting, an outside case), noise, quantisation, an
  acquisition latency in samples.
- Controller: a PI on the thermocouple reading at the data rate (the voltage held over each
  frame, exactly what the diagnosis replays), 0-2.5 V, conditional-integration anti-windup.

>>> out = run(Bench(), 2.0)
>>> sorted(out), len(out["time"])
(['T_mean', 'T_meas', 'T_tc_volume', 'strain', 'strain_true', 'time', 'u'], 101)
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy import linalg

from musclesim.benchmark.benches.sma_kinetics import (EPS_L, STRESS, Kinetics, Relays, bands,
                                                      contraction)

ZERO_C = 273.15  # K
# the wire (§sma-wire, §sma-material)
DIAMETER = 127e-6  # m, §sma-wire
LENGTH = 58.42e-3  # m, §thermal-model
DENSITY = 6450.0  # kg/m^3, §sma-material
SPECIFIC_HEAT = 837.0  # J/(kg K), §sma-material
CONDUCTIVITY = 18.0  # W/(m K), §sma-material
RHO_MARTENSITE, RHO_AUSTENITE = 80e-8, 100e-8  # Ohm m, §sma-material
H_NOMINAL = 100.0  # W/(m^2 K) at 50 K excess, §convection
AREA = math.pi * DIAMETER ** 2 / 4  # m^2; 1.26677e-8 as the scenarios' load (§forc-identification)
SIGMA_SB = 5.670374419e-8  # W/(m^2 K^4): Stefan-Boltzmann (radiation; the study gives none)
U_MAX = 2.5  # V: the heating voltage's range (scenarios/params/sma-thermal-gains.toml)
CELLS = 18
FRAME = 0.02  # s: the data's and the controller's period (the scenario's 50 Hz)
SUBSTEPS = 2  # internal steps per frame (10 ms)
# the bench's reference: the tracking scenario's 75 C +- 30 K at 0.1 Hz from 45 C
# (§temperature-control)
REF_MEAN, REF_AMPLITUDE, REF_FREQUENCY = 348.15, 30.0, 0.1
PREROLL = 10.0  # s held at the reference's start before recording, from ambient


@dataclass(frozen=True)
class Bench:
    """Every condition of one bench run; the defaults are the model's values, ideal sensors.

    Temperatures in K, lengths in m; ``slips`` is ((time [s], strain lost), ...); a
    ``draught_time`` of None means no draught; ``convection`` is "constant" or "natural".
    """

    ambient: float = 293.15
    clamp_offset: float = 0.0  # K: clamps this much warmer than the ambient air
    length: float = LENGTH
    h: float = H_NOMINAL
    resistivity_factor: float = 1.0
    lead_resistance: float = 0.0  # Ohm in series, not measured by the voltage log
    contact: float = 1e-5  # W/K per clamp: wire to clamp; insulating terminals (metal: 1e-3+)
    emissivity: float = 0.0  # of the wire's surface, for radiation
    stress: float = STRESS
    convection: str = "constant"
    coat_diameter: float = DIAMETER  # m: the diameter the air sees (natural convection)
    draught_time: float | None = None
    draught_factor: float = 1.0
    latent_heating: float = 0.0  # J/kg absorbed as austenite forms
    latent_cooling: float = 0.0  # J/kg released as martensite forms
    # the bench's own PI, stable with a 0.5 s thermocouple lag inside its loop
    # (§temperature-control's scheduled gains, 0.12-0.35 V/K, are the model's design)
    kp: float = 0.07  # V/K
    ki: float = 0.1  # V/(K s)
    tc_position: float = 0.5  # of the length
    tc_tau_sheath: float = 0.0  # s
    tc_tau_junction: float = 0.0  # s
    tc_gain: float = 1.0  # on the Celsius reading
    tc_offset: float = 0.0  # K: the sensor's calibration
    tc_bias: float = 0.0  # K: a hidden bias (cold-junction compensation off)
    tc_noise: float = 0.0  # K
    tc_quantum: float = 0.0  # K
    gauge_tau: float = 0.0  # s
    gauge_gain: float = 1.0
    gauge_offset: float = 0.0
    gauge_drift: float = 0.0  # the offset's change over the run (the bridge warming), linear
    gauge_noise: float = 0.0
    gauge_quantum: float = 0.0
    latency: int = 0  # samples the strain log trails the controller's
    slips: tuple = ()
    seed: int = 0  # of the sensors' noise
    # forms (`musclesim.benchmark.family`): the defaults are the bench above
    hysteresis: str = "cosine"  # "cosine", "exponential" (kinetics) or "relay"
    band_shift: float = 0.0  # K: every band of this wire's material moved
    band_scale: float = 1.0  # every band's width scaled about its middle
    thermal: str = "conduction"  # or "lumped": one volume
    resistivity_law: str = "linear"  # or "tempco", "parallel"
    tempco: float = 0.0  # 1/K: the resistivity's temperature coefficient ("tempco")
    gust_level: float = 0.0  # relative spread of h in gusts (convection "gusts")
    gust_time: float = 5.0  # s
    h_exponent: float = 0.0  # h grows as (excess / 50 K)^h_exponent
    tc_form: str = "two-pole"  # or "first-order", "ladder"
    drift_shift: float = 0.0  # K: training drift's settled band shift
    drift_amplitude: float = 0.0  # training drift's settled relative loss of strain
    drift_time: float = 30.0  # s


def reference(t: Any) -> Any:
    """The bench's temperature reference [K] at times `t` [s] (the tracking scenario's sine)."""
    return REF_MEAN + REF_AMPLITUDE * np.sin(2 * np.pi * REF_FREQUENCY * np.asarray(t) - np.pi / 2)


# -- heat: finite volumes along the wire ---------------------------------------------------------

def widths(length: float, cells: int = CELLS) -> np.ndarray:
    """Widths [m] of the `cells` volumes of a wire of `length` [m], graded toward both clamps
    (Chebyshev edges: 0.4 mm there, 5 mm in the middle at the nominal length), where the
    temperature bends over a few mm."""
    edges = length * (1 - np.cos(np.pi * np.arange(cells + 1) / cells)) / 2
    return np.diff(edges)


def centres(length: float, cells: int = CELLS) -> np.ndarray:
    """Centres [m] from one clamp of the `cells` volumes of a wire of `length` [m]."""
    w = widths(length, cells)
    return np.cumsum(w) - w / 2


def thermal_system(bench: Bench, cells: int = CELLS) -> Any:
    """(A, capacity, loss_to_ambient, clamp_conductance) of the linear part dT/dt = A T + ... of
    `bench`'s wire in `cells` volumes: conduction between volumes and into the clamps, convection
    at the bench's h (§sma-bench, §convection)."""
    w = widths(bench.length, cells)
    cap = DENSITY * SPECIFIC_HEAT * AREA * w  # J/K per volume
    g = CONDUCTIVITY * AREA / ((w[:-1] + w[1:]) / 2)  # W/K between neighbours
    # a clamp: contact in series with the half volume next to it
    g_end = 1.0 / (1.0 / bench.contact + (w[0] / 2) / (CONDUCTIVITY * AREA))
    conv = bench.h * math.pi * DIAMETER * w  # W/K
    clamp = np.zeros(cells)
    clamp[[0, -1]] = g_end
    K = np.diag(-(conv + clamp)) + np.diag(g, 1) + np.diag(g, -1)
    K -= np.diag(np.r_[g, 0.0] + np.r_[0.0, g])
    return K / cap[:, None], cap, conv, clamp


def propagator(A: np.ndarray, dt: float) -> Any:
    """(Phi, Gamma): T(t + `dt`) = Phi T + Gamma b exactly for dT/dt = `A` T + b, b held."""
    phi = linalg.expm(A * dt)
    return phi, np.linalg.solve(A, phi - np.eye(len(A)))


def air_convection(dT: Any, T_amb: float, diameter: float) -> Any:
    """Natural convection h [W/(m^2 K)] of a horizontal cylinder of `diameter` [m], `dT` [K]
    warmer than the air at `T_amb` [K], by the Churchill-Chu correlation (Int. J. Heat Mass
    Transfer 18, 1975), air properties at the film temperature (power laws around 300 K). Not in
    the study; §convection's 100 W/(m^2 K) at 50 K is this law's size."""
    dT = np.maximum(np.abs(dT), 1e-3)
    Tf = T_amb + dT / 2
    k = 0.0263 * (Tf / 300) ** 0.8
    nu, alpha = 1.57e-5 * (Tf / 300) ** 1.75, 2.22e-5 * (Tf / 300) ** 1.8
    ra = 9.81 / Tf * dT * diameter ** 3 / (nu * alpha)
    prandtl = nu / alpha
    nusselt = (0.6 + 0.387 * ra ** (1 / 6) / (1 + (0.559 / prandtl) ** (9 / 16)) ** (8 / 27)) ** 2
    return nusselt * k / diameter


def _extra_loss(bench: Bench, T: np.ndarray, t: float, conv_area: Any,
                h_ratio: Any = None, gust: float = 0.0) -> Any:
    """Heat loss [W] per volume beyond the linear part: radiation, the convection law's change
    of h with the excess temperature (`h_ratio`: (excess temperatures, h / h at 50 K), a table of
    `air_convection`; ``h_exponent``), gusts (`gust`: the unit process's value now), a draught;
    `conv_area` the volumes' lateral areas."""
    dT = T - bench.ambient
    loss = bench.emissivity * SIGMA_SB * conv_area * (T ** 4 - bench.ambient ** 4)
    h: Any = bench.h * (1 + bench.gust_level * gust)
    if h_ratio is not None:
        h = h * np.interp(np.abs(dT), *h_ratio)
    if bench.h_exponent:
        h = h * (np.maximum(np.abs(dT), 1.0) / 50.0) ** bench.h_exponent
    if bench.draught_time is not None and t >= bench.draught_time:
        h = h * bench.draught_factor
    return loss + (h - bench.h) * conv_area * dT


def _stage(y: Any, u0: Any, u1: Any, tau: float, dt: float) -> Any:
    """A first-order stage y' = (u - y) / tau over `dt`, its input linear from u0 to u1 (exact)."""
    if tau <= 0:
        return u1
    a = math.exp(-dt / tau)
    s = (u1 - u0) / dt
    return u1 - s * tau + (y - u0 + s * tau) * a


def _quantise(x: Any, quantum: float) -> Any:
    return quantum * np.round(np.asarray(x) / quantum) if quantum > 0 else np.asarray(x)


def _slipped(bench: Bench, t: float) -> float:
    """Strain lost to the clamp's slips by time `t` (each a 0.2 s ramp)."""
    return sum(size * min(max((t - t0) / 0.2, 0.0), 1.0) for t0, size in bench.slips)


class _Plant:
    """The wire's state and one internal step of it (heat, kinetics, latent heat)."""

    def __init__(self, bench: Bench, dt: float, steps: int = 0) -> None:
        self.b, self.dt = bench, dt
        self.cells = 1 if bench.thermal == "lumped" else CELLS
        A, self.cap, self.conv, clamp = thermal_system(bench, self.cells)
        self.phi, self.gam = propagator(A, dt)
        self.w = widths(bench.length, self.cells)
        self.area = math.pi * DIAMETER * self.w
        t_clamp = bench.ambient + bench.clamp_offset
        self.b_const = (self.conv * bench.ambient + clamp * t_clamp) / self.cap
        self.ohm = bench.resistivity_factor * self.w / AREA  # Ohm per (Ohm m)
        self.nonlinear = (bench.emissivity > 0 or bench.convection != "constant"
                          or bench.draught_time is not None or bench.h_exponent != 0)
        self.gusts = np.zeros(steps + 1)
        if bench.convection == "gusts":  # a unit Ornstein-Uhlenbeck process, exact steps
            a = math.exp(-dt / bench.gust_time)
            e = np.random.default_rng([bench.seed, 5]).standard_normal(steps + 1)
            for i in range(1, steps + 1):
                self.gusts[i] = a * self.gusts[i - 1] + math.sqrt(1 - a * a) * e[i]
            self.nonlinear = True
        self.k = 0  # internal steps taken
        self.h_ratio = None
        if bench.convection == "natural":  # scaled to the bench's h at 50 K excess
            excess = np.linspace(0.0, 250.0, 501)
            law = air_convection(excess, bench.ambient, bench.coat_diameter)
            self.h_ratio = (excess, law / air_convection(50.0, bench.ambient, bench.coat_diameter))
        self.latent = bench.latent_heating > 0 or bench.latent_cooling > 0
        self.T = np.full(self.cells, bench.ambient)
        As, Af, Ms, Mf = bands(bench.stress)  # the case's material: bands moved and scaled
        heat, cool = (As + Af) / 2, (Ms + Mf) / 2  # about their middles
        material = tuple(m + bench.band_shift + (b - m) * bench.band_scale
                         for b, m in ((As, heat), (Af, heat), (Ms, cool), (Mf, cool)))
        if bench.hysteresis == "relay":
            self.kin: Any = Relays(self.T - ZERO_C, bench.stress,
                                   np.random.default_rng([bench.seed, 3]), bands_at=material)
        else:
            self.kin = Kinetics(self.T - ZERO_C, bench.stress, shape=bench.hysteresis,
                                bands_at=material)
        self.weights = self.w / self.w.sum()
        self.ramp = 0.0  # the training drift's share settled

    def resistivity(self) -> np.ndarray:
        """The volumes' resistivity [Ohm m] by the bench's law."""
        xi, b = self.kin.xi, self.b
        if b.resistivity_law == "parallel":
            return 1.0 / (xi / RHO_MARTENSITE + (1 - xi) / RHO_AUSTENITE)
        rho = RHO_AUSTENITE + (RHO_MARTENSITE - RHO_AUSTENITE) * xi
        if b.resistivity_law == "tempco":
            rho = rho * (1 + b.tempco * (self.T - 293.15))
        return rho

    def step(self, u: float, t: float) -> None:
        """Advance one internal step at voltage `u` [V] from time `t` [s]."""
        b = self.b
        R = self.resistivity() * self.ohm
        current = u / (R.sum() + b.lead_resistance)
        source = current * current * R
        if self.nonlinear:
            source = source - _extra_loss(b, self.T, t, self.area, self.h_ratio,
                                          self.gusts[min(self.k, len(self.gusts) - 1)])
        self.k += 1
        if b.drift_shift or b.drift_amplitude:
            self.ramp = 1 - math.exp(-max(t + self.dt, 0.0) / b.drift_time)
            self.kin.shift = b.drift_shift * self.ramp
        T = self.phi @ self.T + self.gam @ (source / self.cap + self.b_const)
        if self.latent:
            T = self._latent(T)
        else:
            self.kin.step(T - ZERO_C)
        self.T = T

    def _latent(self, T_trial: np.ndarray) -> np.ndarray:
        """End temperatures with the latent heat of the fractions' change, implicit (Newton)."""
        kin = self.kin
        kin.direction_for(T_trial - ZERO_C)
        heat = np.where(kin.heating[:, 0], self.b.latent_heating, self.b.latent_cooling)
        T, xi0 = T_trial, kin.xi
        if isinstance(kin, Relays):  # relays switch: explicit, their hysteresis keeps it stable
            x, xi, _ = kin.peek(T - ZERO_C)
            T = T + heat * (xi - xi0) / SPECIFIC_HEAT
            kin.commit(T - ZERO_C, x)
            return T
        for _ in range(6):  # F' = c - L dxi/dT >= c: monotone, two Newton steps converge
            x, xi, slope = kin.peek(T - ZERO_C)
            F = SPECIFIC_HEAT * (T - T_trial) - heat * (xi - xi0)
            if np.max(np.abs(F)) < 1e-6 * SPECIFIC_HEAT:  # within a micro-kelvin
                break
            T = T - F / (SPECIFIC_HEAT - heat * slope)
        kin.commit(T - ZERO_C, x)  # the branches were set by direction_for
        return T

    def strain(self) -> float:
        """Mean contraction of the wire (length-weighted over the volumes)."""
        eps_l = EPS_L * (1 - self.b.drift_amplitude * self.ramp)
        return float(self.weights @ contraction(self.kin.xi, self.T - ZERO_C, self.b.stress,
                                                eps_l))


def run(bench: Bench, duration: float, substeps: int = SUBSTEPS) -> dict[str, np.ndarray]:
    """Run `bench` for `duration` [s] after its pre-roll, `substeps` internal steps per frame;
    return the log at the data rate.

    Returns
    -------
    dict
        ``time``, ``u`` [V] (the voltage held over each frame), ``T_meas`` [K] (the
        thermocouple's reading the controller used), ``strain`` (the strain sensor's log, behind
        by ``bench.latency`` samples), and the truth: ``T_mean``, ``T_tc_volume`` [K],
        ``strain_true``.
    """
    rng = np.random.default_rng(bench.seed)
    dt = FRAME / substeps
    n_pre, n = int(round(PREROLL / FRAME)), int(round(duration / FRAME)) + 1
    plant = _Plant(bench, dt, (n_pre + n) * substeps)
    j = int(np.argmin(np.abs(centres(bench.length, plant.cells) / bench.length
                             - bench.tc_position)))
    tc = _Thermocouple(bench, dt)
    gauge = strain_in = plant.strain()
    integral = 0.0
    log = {k: np.empty(n) for k in ("u", "T_meas", "gauge", "T_mean", "T_tc_volume",
                                    "strain_true")}
    for k in range(-n_pre, n):
        t = k * FRAME
        celsius = tc.junction - ZERO_C
        reading = ZERO_C + bench.tc_gain * celsius + bench.tc_offset + bench.tc_bias
        reading = float(_quantise(reading + bench.tc_noise * rng.standard_normal(),
                                  bench.tc_quantum))
        e = float(reference(max(t, 0.0))) - reading
        trial = bench.kp * e + integral
        u = min(max(trial, 0.0), U_MAX)
        if trial == u or (trial > U_MAX) == (e < 0):  # anti-windup: integrate unless pushing out
            integral += bench.ki * e * FRAME
        if k >= 0:
            log["u"][k], log["T_meas"][k], log["gauge"][k] = u, reading, gauge
            log["T_mean"][k], log["T_tc_volume"][k] = plant.weights @ plant.T, plant.T[j]
            log["strain_true"][k] = strain_in
        for i in range(substeps):
            T0 = plant.T[j]
            plant.step(u, t + i * dt)
            tc.step(T0, plant.T[j])
            s_new = plant.strain() - _slipped(bench, t + (i + 1) * dt)
            gauge = _stage(gauge, strain_in, s_new, bench.gauge_tau, dt)
            strain_in = s_new
    return _finish(bench, log, n, rng)


class _Thermocouple:
    """The junction's temperature behind its coat, by the bench's ``tc_form``: two first-order
    stages, one (of both time constants' sum), or a three-stage RC ladder of the same total
    delay (x' = A x + b T, the stages loading each other; exact steps with the wire's
    temperature held)."""

    def __init__(self, bench: Bench, dt: float) -> None:
        self.b, self.dt = bench, dt
        self.sheath = self.junction = bench.ambient
        self.ladder = None
        total = bench.tc_tau_sheath + bench.tc_tau_junction
        if bench.tc_form == "ladder" and total > 0:
            tau = total / 6  # the ladder's first moment: (1 + 2 + 3) tau
            A = np.array([[-2.0, 1.0, 0.0], [1.0, -2.0, 1.0], [0.0, 1.0, -1.0]]) / tau
            self.ladder = propagator(A, dt)
            self.b_in = np.array([1.0 / tau, 0.0, 0.0])
            self.x = np.full(3, bench.ambient)

    def step(self, T0: float, T1: float) -> None:
        """One internal step, the wire's volume going from `T0` to `T1` [K]."""
        b = self.b
        if self.ladder is not None:
            phi, gam = self.ladder
            self.x = phi @ self.x + gam @ (self.b_in * T1)
            self.junction = float(self.x[-1])
        elif b.tc_form == "first-order":
            self.junction = _stage(self.junction, T0, T1, b.tc_tau_sheath + b.tc_tau_junction,
                                   self.dt)
        else:
            mid = self.sheath
            self.sheath = _stage(self.sheath, T0, T1, b.tc_tau_sheath, self.dt)
            self.junction = _stage(self.junction, mid, self.sheath, b.tc_tau_junction, self.dt)


def _finish(bench: Bench, log: Any, n: int, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """The strain sensor's gain, offset (drifting), noise, quantisation and latency applied to
    its log."""
    s = bench.gauge_gain * log.pop("gauge") + bench.gauge_offset
    s = s + bench.gauge_drift * np.arange(n) / max(n - 1, 1)
    s = _quantise(s + bench.gauge_noise * rng.standard_normal(n), bench.gauge_quantum)
    if bench.latency:
        s = np.concatenate([np.full(bench.latency, s[0]), s[:-bench.latency]])
    return {"time": np.round(np.arange(n) * FRAME, 9), "strain": s, **log}
