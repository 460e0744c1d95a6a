"""Linear analysis with python-control: crawler controllability (SPEC 1.2) and the SMA wire's
thermal models with the gain-scheduled temperature controller designed on them (SPEC 2.5)."""
import math

import control as ct
import numpy as np

from musclesim.components.control.slaves import SCHEDULE_K
from musclesim.components.crawler.body import BodyParams, state_space
from musclesim.components.sma import thermal
from musclesim.components.sma.wire import ReferenceWire

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
        loop = ct.tf([Kp, Ki], [1, 0]) * ct.tf(plant)
        gm, pm, _, _, wc, _ = ct.stability_margins(loop)
        # the controller runs sampled at `step`: the sampled closed loop must stay stable
        sampled = ct.feedback(ct.sample_system(loop, d["step"], method="zoh"))
        points.append({"T_op": T_op, "u_op": u_op, "plant_gain": float(ct.dcgain(plant)),
                       "time_constant": -1.0 / plant.A[0, 0], "Kp": Kp, "Ki": Ki, "Kd": 0.0,
                       "gain_margin": None if math.isinf(gm) else float(gm),
                       "phase_margin_deg": float(pm), "crossover": float(wc),
                       "sampled_pole_radius": float(np.abs(ct.poles(sampled)).max())})
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
