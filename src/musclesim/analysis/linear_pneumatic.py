"""Linear analysis with python-control: crawler controllability (SPEC 1.2), the SMA wire's
thermal models with the gain-scheduled temperature controller designed on them (SPEC 2.5), the
SMA bench's load path (SPEC 2.4) and the crawler's pressure loops (SPEC 1.1), the last two
identified on their FMUs."""
import math

import control as ct
import numpy as np

from musclesim.components.control.slaves import SCHEDULE_K
from musclesim.components.crawler.body import BodyParams, state_space
from musclesim.components.sma import thermal
from musclesim.components.sma.wire import ReferenceWire
from musclesim.errors import UserError

STATES = ["x1", "v1", "x2", "v2"]
INPUTS = ["f_a", "f1", "f2"]


def crawler_system(p=BodyParams()):
    """The crawler body as a python-control state-space system with full state output."""
    A, B = state_space(p)
    return ct.ss(A, B, np.eye(4), np.zeros((4, 3)), states=STATES, inputs=INPUTS,
                 outputs=STATES, name="crawler")


def _row_echelon_basis(Q, tol=1e-9):
    """Basis of the column space of Q in reduced row-echelon form (leading ones, like SPEC 1.2)."""
    M = Q.T
    pivots = []
    for j in range(M.shape[1]):
        if np.linalg.matrix_rank(M[:, pivots + [j]], tol) > len(pivots):
            pivots.append(j)
        if len(pivots) == M.shape[0]:
            break
    R = np.linalg.solve(M[:, pivots], M)
    R[np.abs(R) < tol] = 0.0
    return R


def crawler(p=BodyParams()):
    """Controllability of the crawler with the actuator force only and with all three inputs.

    Returns
    -------
    dict
        ``rank_fa_only`` and ``rank_all_inputs`` (ranks of the controllability matrices),
        ``controllable_subspace_fa_only`` (basis vectors over ``states``, reduced row-echelon
        form), ``centre_of_mass_reachable_fa_only`` (False when f_a alone cannot move the centre
        of mass), plus the states, inputs and parameters used.

    Examples
    --------
    >>> r = crawler()
    >>> r["rank_fa_only"], r["rank_all_inputs"]
    (2, 4)
    """
    sys = crawler_system(p)
    ctrb_fa = ct.ctrb(sys.A, sys.B[:, :1])
    ctrb_all = ct.ctrb(sys.A, sys.B)
    tol = 1e-9 * np.linalg.norm(ctrb_all)
    rank_fa = int(np.linalg.matrix_rank(ctrb_fa, tol))
    U, _, _ = np.linalg.svd(ctrb_fa)
    basis = _row_echelon_basis(U[:, :rank_fa])
    # centre-of-mass position and velocity as linear functionals of the state
    cm = np.array([[p.m1, 0, p.m2, 0], [0, p.m1, 0, p.m2]]) / (p.m1 + p.m2)
    cm_gain = float(np.abs(cm @ ctrb_fa).max())
    return {
        "system": "crawler",
        "spec": "SPEC.md 1.2",
        "parameters": {"m1": p.m1, "m2": p.m2, "k": p.k, "c": p.c},
        "states": STATES,
        "inputs": INPUTS,
        "rank_fa_only": rank_fa,
        "rank_all_inputs": int(np.linalg.matrix_rank(ctrb_all, tol)),
        "controllable_subspace_fa_only": basis.tolist(),
        "centre_of_mass_reachable_fa_only": bool(cm_gain > tol),
    }


def format_crawler(report):
    """Human-readable text of a `crawler` report."""
    vec = lambda v: "[" + ", ".join(f"{x:g}" for x in v) + "]"
    lines = [
        f"Crawler body (SPEC 1.2), states [{', '.join(report['states'])}], "
        f"m1 = {report['parameters']['m1']:g} kg, m2 = {report['parameters']['m2']:g} kg",
        f"controllability rank, f_a only:        {report['rank_fa_only']} of {len(report['states'])}",
        f"controllability rank, f_a, f1 and f2:  {report['rank_all_inputs']} of {len(report['states'])}",
        "controllable subspace with f_a only:  span of "
        + ", ".join(vec(v) for v in report["controllable_subspace_fa_only"]),
        "centre of mass movable with f_a only: "
        + ("yes" if report["centre_of_mass_reachable_fa_only"] else
           "no (no locomotion without friction)"),
    ]
    return "\n".join(lines)



# ---- SMA wire temperature control (SPEC 2.5) -------------------------------------------------
SMA_DESIGN = {
    "T_amb": 20.0,  # C, room temperature of the bench
    "sigma": 125e6,  # Pa, middle of the identified stresses 105..145 MPa (SPEC 2.3)
    "omega_n": 8.0,  # rad/s, closed-loop natural frequency, ~14x the free-cooling pole
    "zeta": 0.9,  # closed-loop damping
    "u_max": 2.5,  # V, Joule heating range of the bench (SPEC 2.1)
    "step": 4e-4,  # s, the position loop's 2.5 kHz (SPEC 2.1)
}


def sma_thermal_plant(T_op, p=thermal.ThermalParams(), wire=None, T_amb=20.0, sigma=125e6):
    """Linear thermal model of the wire around temperature T_op [C] under voltage drive.

    The lumped balance C dT/dt = u^2 / R(xi(T)) - h A_s (T - T_amb) (SPEC 2.1) is linearised at the
    equilibrium voltage u_op; xi(T) follows the heating branch of the reference wire at `sigma`
    (the resistance falls as austenite forms). Returns (python-control system from du [V] to dT
    [K], u_op [V]).
    """
    wire = wire or ReferenceWire()
    eps_max = float(wire.eps_max(sigma))

    def R(T):
        return thermal.resistance(thermal.martensite_fraction(float(wire.F(T, 30.0, sigma)),
                                                              eps_max), p)

    hA, C = p.h * thermal.lateral_surface(p), thermal.heat_capacity(p)
    u_op = math.sqrt(R(T_op) * hA * max(T_op - T_amb, 0.0))
    dR_dT = (R(min(T_op + 0.5, 130.0)) - R(max(T_op - 0.5, 30.0))) / (min(T_op + 0.5, 130.0)
                                                                      - max(T_op - 0.5, 30.0))
    a = (-hA - u_op ** 2 / R(T_op) ** 2 * dR_dT) / C
    b = 2 * u_op / R(T_op) / C
    return ct.ss([[a]], [[b]], [[1.0]], [[0.0]], inputs=["u"], outputs=["T"]), u_op


def design_pi(plant, omega_n, zeta):
    """PI gains placing the closed-loop poles of a first-order plant at omega_n, zeta.

    The plant is augmented with the integral of the error and the state feedback comes from
    python-control's `place`; u = Kp e + Ki integral(e) gives the same closed-loop poles.
    """
    a, b = plant.A[0, 0], plant.B[0, 0]
    A = np.array([[a, 0.0], [-1.0, 0.0]])
    B = np.array([[b], [0.0]])
    wd = omega_n * math.sqrt(1 - zeta ** 2)
    K = ct.place(A, B, [complex(-zeta * omega_n, wd), complex(-zeta * omega_n, -wd)])
    return float(K[0, 0]), float(-K[0, 1])


def pi_margins(plant, Kp, Ki, step):
    """Gain margin (None: infinite), phase margin [deg] and gain crossover [rad/s] of the loop
    PI x plant, and the largest pole radius of its closed loop sampled at `step` (below 1: the
    controller running sampled keeps it stable)."""
    loop = ct.tf([Kp, Ki], [1, 0]) * ct.tf(plant)
    gm, pm, _, _, wc, _ = ct.stability_margins(loop)
    sampled = ct.feedback(ct.sample_system(loop, step, method="zoh"))
    return {"gain_margin": None if math.isinf(gm) else float(gm), "phase_margin_deg": float(pm),
            "crossover": float(wc), "sampled_pole_radius": float(np.abs(ct.poles(sampled)).max())}


def sma_thermal(design=None):
    """Linear thermal models at the 21 scheduling points (30..130 C) and a PI per point.

    Returns
    -------
    dict
        ``points``: per operating point the temperature [C], equilibrium voltage [V], plant gain
        [K/V] and time constant [s], the gains Kp [V/K], Ki [V/(K s)], Kd, the loop's gain
        margin (None: infinite), phase margin [deg] and gain crossover [rad/s], and the largest
        closed-loop pole radius with controller and plant sampled at `step` (below 1: stable);
        ``design``: the settings used.
    """
    d = {**SMA_DESIGN, **(design or {})}
    wire, points = ReferenceWire(), []
    for x_K in SCHEDULE_K:
        T_op = x_K - 273.15
        plant, u_op = sma_thermal_plant(T_op, wire=wire, T_amb=d["T_amb"], sigma=d["sigma"])
        Kp, Ki = design_pi(plant, d["omega_n"], d["zeta"])
        points.append({"T_op": T_op, "u_op": u_op, "plant_gain": float(ct.dcgain(plant)),
                       "time_constant": -1.0 / plant.A[0, 0], "Kp": Kp, "Ki": Ki, "Kd": 0.0,
                       **pi_margins(plant, Kp, Ki, d["step"])})
    return {"system": "sma-thermal", "spec": "SPEC.md 2.5", "design": d, "points": points}


def format_sma_thermal(report):
    """Human-readable table of an `sma_thermal` report."""
    d = report["design"]
    lines = [f"SMA wire temperature loop (SPEC 2.5): PI per operating point, poles at "
             f"omega_n = {d['omega_n']:g} rad/s, zeta = {d['zeta']:g}; T_amb = {d['T_amb']:g} C, "
             f"{d['sigma'] / 1e6:g} MPa, sampled at {d['step'] * 1e3:g} ms",
             "  T_op C   u_op V   K K/V   tau s    Kp V/K   Ki V/Ks   PM deg   wc rad/s"]
    for q in report["points"]:
        lines.append(f"  {q['T_op']:6.1f} {q['u_op']:8.3f} {q['plant_gain']:7.1f} "
                     f"{q['time_constant']:6.2f} {q['Kp']:9.4f} {q['Ki']:9.4f} "
                     f"{q['phase_margin_deg']:8.1f} {q['crossover']:10.2f}")
    return "\n".join(lines)


def gain_table_toml(report):
    """The GainScheduledPID parameters of a report, as the TOML a scenario's instance reads."""
    lines = ["# GainScheduledPID gains for the SMA wire's temperature (SPEC 2.5), written by",
             "# `musclesim linear sma-thermal --write FILE`: do not edit, rerun the design.",
             "u_min = 0.0  # V: the wire is only heated", f"u_max = {report['design']['u_max']!r}  # V"]
    for i, (x, q) in enumerate(zip(SCHEDULE_K, report["points"]), start=1):
        lines.append(f'"x[{i}]" = {x!r}  # K, {q["T_op"]:g} C')
        lines += [f'"{k}[{i}]" = {q[k]!r}' for k in ("Kp", "Ki", "Kd")]
    return "\n".join(lines) + "\n"


# ---- the load path of the position-control bench (SPEC 2.1, 2.4) ------------------------------

LOAD_DESIGN = {
    "omega_n": 300.0,  # rad/s (48 Hz): far above the loading profiles (<= 1/17 Hz), far below
                       # the 2.5 kHz sampling, and above 1 / (2 zeta tau) (~270 rad/s for the
                       # coil's ~2 ms), below which the placed Kp turns negative
    "zeta": 0.9,
    "duty": (0.2, 0.7),  # the identification step of the PWM duty
    "step": 4e-4,  # s, the stress loop's 2.5 kHz (SPEC 2.1)
    "duration": 0.05,  # s, recorded after the step
}


def identify_load_path(fmu_dir="fmus", d=None):
    """First-order model duty -> load-cell force, identified from a duty step of the FMUs.

    The Electromagnet and LoadCell FMUs (as a scenario uses them, wire held still) are run with
    the duty replayed as a step; K [N per unit duty] and tau [s] are fitted by least squares to
    the recorded force. Returns (python-control system, K, tau, RMS fit residual [N]).
    """
    from scipy import optimize

    from musclesim.cosim.master import Master
    from musclesim.cosim.scenario import Instance, Scenario

    d = {**LOAD_DESIGN, **(d or {})}
    s = Scenario("load-path identification", None,
                 {"magnet": Instance("magnet", "Electromagnet"),
                  "loadcell": Instance("loadcell", "LoadCell")},
                 (("magnet.flange.f", "loadcell.f"),), d["step"], d["duration"],
                 algorithm="jacobi", record=("loadcell.f_meas",))
    n = s.n_steps + 1
    lo, hi = d["duty"]
    # settle at the low duty, then step: the first 5 % of the record before the step
    k0 = n // 20
    duty = np.where(np.arange(n) < k0, lo, hi)
    res = Master(s, fmu_dir, {"magnet.duty": duty}).run()
    t, f = res.time[k0:] - res.time[k0], res["loadcell.f_meas"][k0:]

    def model(p):
        K, tau, f0 = p
        return f0 + K * (hi - lo) * (1 - np.exp(-t / tau))

    fit = optimize.least_squares(lambda p: model(p) - f, [1.0, 0.01, f[0]],
                                 bounds=([0, 1e-6, -np.inf], [np.inf, 10.0, np.inf]))
    K, tau, _ = fit.x
    plant = ct.ss([[-1 / tau]], [[K / tau]], [[1.0]], [[0.0]], inputs=["duty"], outputs=["f"])
    return plant, float(K), float(tau), float(np.sqrt(np.mean(fit.fun ** 2)))


def sma_load(fmu_dir="fmus", design=None):
    """The stress loop: identified load path and the PI placed on it (python-control).

    Returns a dict with the identified K [N], tau [s] and fit residual, the gains Kp [1/N],
    Ki [1/(N s)], the loop's margins and the sampled closed loop's largest pole radius.
    """
    d = {**LOAD_DESIGN, **(design or {})}
    plant, K, tau, rms = identify_load_path(fmu_dir, d)
    Kp, Ki = design_pi(plant, d["omega_n"], d["zeta"])
    return {"system": "sma-load", "spec": "SPEC.md 2.1, 2.4", "design": d,
            "identified": {"K": K, "tau": tau, "fit_rms": rms},
            "Kp": Kp, "Ki": Ki, **pi_margins(plant, Kp, Ki, d["step"])}


def format_sma_load(report):
    """Human-readable summary of an `sma_load` report."""
    i, d = report["identified"], report["design"]
    return (f"SMA load path (SPEC 2.1, 2.4): duty -> load-cell force identified from a duty step "
            f"{d['duty'][0]:g} -> {d['duty'][1]:g}: K = {i['K']:.4g} N, tau = {i['tau'] * 1e3:.3g} "
            f"ms (fit RMS {i['fit_rms']:.2g} N)\n"
            f"PI with closed-loop poles at omega_n = {d['omega_n']:g} rad/s, zeta = {d['zeta']:g}: "
            f"Kp = {report['Kp']:.4g} 1/N, Ki = {report['Ki']:.4g} 1/(N s); phase margin "
            f"{report['phase_margin_deg']:.1f} deg at {report['crossover']:.1f} rad/s; sampled at "
            f"{d['step'] * 1e3:g} ms the closed loop's largest pole radius is "
            f"{report['sampled_pole_radius']:.4f}")


def load_gains_toml(report):
    """The PID parameters of an `sma_load` report, as the TOML a scenario's instance reads."""
    return "\n".join([
        "# PID gains of the SMA bench's stress loop (SPEC 2.4), written by",
        "# `musclesim linear sma-load --write FILE`: do not edit, rerun the design.",
        f"Kp = {report['Kp']!r}  # duty per N", f"Ki = {report['Ki']!r}  # duty per N s",
        "Kd = 0.0", "u_min = 0.0  # PWM duty", "u_max = 1.0", ""])


# ---- the pressure loops of the pneumatic crawler (SPEC 1.1, 1.5) ------------------------------

PNEUMATIC_DESIGN = {
    "scenario": "scenarios/pneumatic-identification.toml",
    "p_op": 12e3,  # Pa, operating point: the gait's working range, above the contact threshold
    # per actuator kind: the duty that inflates the chamber to p_op (and full contact) before the
    # PRBS, and the PRBS duty amplitude around 0 (valves closed: the chamber holds); the central
    # chamber, whose elongation adds volume, fills ~10x slower than an extremal one
    "fill_duty": {"central": 0.5, "extremal": 0.2},
    "amplitude": {"central": 0.5, "extremal": 0.1},
    "fill_time": 5.0,  # s, at most
    "bit": 0.1,  # s, PRBS bit length: five PWM carrier periods at 50 Hz
    "bits": 20,
    "seed": 0,
    "max_delay": 20,  # samples of input delay tried in the fit
    "crossover": 20.0,  # rad/s: pressures settle within ~0.2 s, well inside the 0.6 s phases
    "zero_ratio": 4.0,  # the PI zero sits this factor below the crossover
    "step": 1e-3,  # s, the DAQ's 1 kHz (SPEC 1.1)
}
ACTUATORS = ("central", "extremal")  # instance names in the identification scenario


def _fit_arx(p, u, max_delay):
    """Least-squares p[k+1] = a p[k] + b u[k-d] + c for d = 0..max_delay; the best (a, b, c, d,
    RMS residual)."""
    best = None
    for d in range(max_delay + 1):
        X = np.column_stack([p[d:-1], u[:len(u) - 1 - d] if d else u[:-1], np.ones(len(p) - 1 - d)])
        y = p[d + 1:]
        coef, *_ = np.linalg.lstsq(X, y, rcond=None)
        rms = float(np.sqrt(np.mean((X @ coef - y) ** 2)))
        if best is None or rms < best[4]:
            best = (*map(float, coef), d, rms)
    return best


def identify_pneumatic(fmu_dir="fmus", design=None):
    """Discrete models duty -> measured pressure of the central and the extremal actuator.

    Runs scenarios/pneumatic-identification.toml twice with the duties replayed: once inflating
    at ``fill_duty`` to find when each chamber reaches ``p_op`` with its contact full, then inflating until then and
    applying a seeded PRBS of +-``amplitude`` (each bit followed by its opposite). A first-order ARX model with input delay is fitted
    to the PRBS part. Returns ``{actuator: (python-control discrete system, fit dict)}``.
    """
    from musclesim.cosim import scenario as scenario_mod
    from musclesim.cosim.master import Master

    d = {**PNEUMATIC_DESIGN, **(design or {})}
    n_bit = round(d["bit"] / d["step"])
    # each random bit is followed by its opposite, so that the integrating chamber stays near p_op
    signs = np.where(np.random.default_rng(d["seed"]).integers(0, 2, d["bits"] // 2) > 0, 1.0, -1.0)
    prbs = np.column_stack([signs, -signs]).ravel().repeat(n_bit)
    s = scenario_mod.load(d["scenario"], stop_time=d["fill_time"])
    res = Master(s, fmu_dir, {f"{a}.duty": np.full(s.n_steps + 1, d["fill_duty"][a])
                              for a in ACTUATORS}).run()
    fill = {}
    for a in ACTUATORS:
        # an extremal chamber bulges while its contact builds: identify it once contact is full
        reached = np.flatnonzero((res[f"{a}_sensor.p_meas"] >= d["p_op"]) & (res[f"{a}.u"] >= 0.999))
        if not len(reached):
            raise UserError(f"{d['scenario']}: {a} does not reach p_op = {d['p_op']:g} Pa with full "
                            f"contact within {d['fill_time']:g} s at duty {d['fill_duty'][a]:g}")
        fill[a] = int(reached[0])
    n = max(fill.values()) + len(prbs)
    s = scenario_mod.load(d["scenario"], stop_time=n * d["step"])
    duties = {a: np.concatenate([np.full(fill[a], d["fill_duty"][a]), d["amplitude"][a] * prbs,
                                 np.zeros(n + 1 - fill[a] - len(prbs))]) for a in ACTUATORS}
    res = Master(s, fmu_dir, {f"{a}.duty": u for a, u in duties.items()}).run()
    out = {}
    for a in ACTUATORS:
        window = slice(fill[a], fill[a] + len(prbs))
        p, u = res[f"{a}_sensor.p_meas"][window], duties[a][window]
        A, B, c, delay, rms = _fit_arx(p, u, d["max_delay"])
        plant = ct.tf([B], np.r_[1.0, -A, np.zeros(delay)], d["step"], inputs="duty", outputs="p")
        out[a] = (plant, {"a": A, "b": B, "c": c, "delay_samples": delay, "fit_rms": rms,
                          "p_range": [float(p.min()), float(p.max())]})
    return out


def discrete_pi(plant, crossover, zero_ratio, step):
    """PI u = Kp e + Ki sum(e) step (the PID FMU's form) for a discrete plant: the zero at
    crossover / zero_ratio, Kp so that the loop gain is 1 at `crossover` [rad/s]."""
    z = np.exp(1j * crossover * step)
    shape = (1.0 + step / zero_ratio * crossover / (z - 1.0)) * complex(plant(z))
    Kp = 1.0 / float(abs(shape))
    return Kp, Kp * crossover / zero_ratio


def pneumatic(fmu_dir="fmus", design=None):
    """The pressure loops: identified discrete plants and a PI per actuator kind with margins.

    Returns a dict with, per actuator kind, the ARX fit (a, b, c, delay, RMS residual [Pa]),
    the integrator gain [Pa/s per unit duty], the gains Kp [1/Pa], Ki [1/(Pa s)], the discrete
    loop's gain margin (None: infinite), phase margin [deg], crossover [rad/s] and the largest
    closed-loop pole radius (below 1: stable).
    """
    d = {**PNEUMATIC_DESIGN, **(design or {})}
    loops = {}
    for a, (plant, fit) in identify_pneumatic(fmu_dir, d).items():
        Kp, Ki = discrete_pi(plant, d["crossover"], d["zero_ratio"], d["step"])
        pi = ct.tf([Kp, Ki * d["step"] - Kp], [1.0, -1.0], d["step"])  # Kp + Ki T / (z - 1)
        loop = pi * plant
        gms, pms, _, _, wcs, _ = ct.stability_margins(loop, returnall=True)
        # a gain margin below 1 is how much *lower* gain would destabilise (phase near -180 deg
        # at low frequency, plant and PI both integrating): report the upper one
        gm = min((float(g) for g in gms if g > 1), default=math.inf)
        pm, wc = min(zip(pms, wcs), default=(math.inf, math.nan))
        loops[a] = {"identified": {**fit, "rate_per_duty": fit["b"] / d["step"]},
                    "Kp": Kp, "Ki": Ki, "gain_margin": None if math.isinf(gm) else float(gm),
                    "phase_margin_deg": float(pm), "crossover": float(wc),
                    "closed_loop_pole_radius": float(np.abs(ct.poles(ct.feedback(loop))).max())}
    return {"system": "pneumatic", "spec": "SPEC.md 1.1, 1.5", "design": d, "loops": loops}


def format_pneumatic(report):
    """Human-readable summary of a `pneumatic` report."""
    d = report["design"]
    lines = [f"Pressure loops (SPEC 1.1, 1.5): duty -> measured pressure identified at "
             f"{d['p_op'] / 1e3:g} kPa from a PRBS of +-{d['amplitude']['central']:g} (central), "
             f"+-{d['amplitude']['extremal']:g} (extremal) duty "
             f"({d['bits']} bits of {d['bit'] * 1e3:g} ms); PI with loop crossover "
             f"{d['crossover']:g} rad/s, zero {d['zero_ratio']:g}x below, sampled at "
             f"{d['step'] * 1e3:g} ms"]
    for a, q in report["loops"].items():
        i, gm = q["identified"], q["gain_margin"]
        lines.append(
            f"  {a:9s} p[k+1] = {i['a']:.5f} p[k] + {i['b']:.4g} u[k-{i['delay_samples']}] "
            f"(fit RMS {i['fit_rms']:.3g} Pa; {i['rate_per_duty'] / 1e3:.4g} kPa/s per unit duty): "
            f"Kp = {q['Kp']:.4g} 1/Pa, Ki = {q['Ki']:.4g} 1/(Pa s); gain margin "
            + ("infinite" if gm is None else f"{20 * math.log10(gm):.1f} dB")
            + f", phase margin {q['phase_margin_deg']:.1f} deg at {q['crossover']:.1f} rad/s, "
              f"closed-loop pole radius {q['closed_loop_pole_radius']:.4f}")
    return "\n".join(lines)


def pneumatic_gains_toml(report, actuator):
    """The PID parameters of one actuator kind's loop, as the TOML a scenario's instance reads."""
    q = report["loops"][actuator]
    return "\n".join([
        f"# PID gains of the {actuator} soft actuator's pressure loop (SPEC 1.1), written by",
        "# `musclesim linear pneumatic --write DIR`: do not edit, rerun the design.",
        f"Kp = {float(q['Kp'])!r}  # duty per Pa", f"Ki = {float(q['Ki'])!r}  # duty per Pa s",
        "Kd = 0.0",
        "u_min = -1.0  # full exhaust", "u_max = 1.0  # full inflation", ""])
