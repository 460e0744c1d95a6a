"""The SMA wire's thermal models and the gain-scheduled temperature controller designed on them
(§temperature-control), with python-control: a PI per scheduling point of the GainScheduledPID."""
from __future__ import annotations

import math
from typing import Any

import control as ct

from musclesim.analysis.design import design_pi, pi_margins
from musclesim.components.control.pid import SCHEDULE_K
from musclesim.components.sma import thermal
from musclesim.components.sma.reference_wire import ReferenceWire

SMA_DESIGN = {
    "T_amb": 20.0,  # C, room temperature of the bench
    "sigma": 125e6,  # Pa, middle of the identified stresses 105..145 MPa (§forc-identification)
    "omega_n": 8.0,  # rad/s, closed-loop natural frequency, ~14x the free-cooling pole
    "zeta": 0.9,  # closed-loop damping
    "u_max": 2.5,  # V, Joule heating range of the bench (§sma-bench)
    "step": 4e-4,  # s, the position loop's 2.5 kHz (§sma-bench)
}


def sma_thermal_plant(T_op: float, p: thermal.ThermalParams = thermal.ThermalParams(),
                      wire: ReferenceWire | None = None, T_amb: float = 20.0,
                      sigma: float = 125e6) -> tuple[ct.StateSpace, float]:
    """Linear thermal model of the wire (thermal parameters `p`) around temperature `T_op` [C]
    under voltage drive.

    The lumped balance C dT/dt = u^2 / R(xi(T)) - h A_s (T - `T_amb`) (§thermal-model) is
    linearised at the equilibrium voltage u_op; xi(T) follows the heating branch of the reference
    wire `wire` (default: `ReferenceWire()`) at stress `sigma` [Pa] (the resistance rises as
    austenite forms, §sma-material). Returns (python-control system
    from du [V] to dT [K], u_op [V]). """
    wire = wire or ReferenceWire()
    eps_max = float(wire.eps_max(sigma))

    def R(T: float) -> float:
        return thermal.resistance(thermal.martensite_fraction(float(wire.F(T, 30.0, sigma)),
                                                              eps_max), p)

    hA, C = p.h * thermal.lateral_surface(p), thermal.heat_capacity(p)
    u_op = math.sqrt(R(T_op) * hA * max(T_op - T_amb, 0.0))
    dR_dT = (R(min(T_op + 0.5, 130.0)) - R(max(T_op - 0.5, 30.0))) / (min(T_op + 0.5, 130.0)
                                                                      - max(T_op - 0.5, 30.0))
    a = (-hA - u_op ** 2 / R(T_op) ** 2 * dR_dT) / C
    b = 2 * u_op / R(T_op) / C
    return ct.ss([[a]], [[b]], [[1.0]], [[0.0]], inputs=["u"], outputs=["T"]), u_op


def sma_thermal(design: dict[str, Any] | None = None) -> dict[str, Any]:
    """Linear thermal models at the 21 scheduling points (30..130 C) and a PI per point;
    `design` overrides settings of `SMA_DESIGN`.

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
    return {"system": "sma-thermal", "reference": "§temperature-control", "design": d,
            "points": points}


def format_sma_thermal(report: dict[str, Any]) -> str:
    """Human-readable table of an `sma_thermal` report `report`."""
    d = report["design"]
    lines = [f"SMA wire temperature loop (§temperature-control): PI per operating point, poles at "
             f"omega_n = {d['omega_n']:g} rad/s, zeta = {d['zeta']:g}; T_amb = {d['T_amb']:g} C, "
             f"{d['sigma'] / 1e6:g} MPa, sampled at {d['step'] * 1e3:g} ms",
             "  T_op C   u_op V   K K/V   tau s    Kp V/K   Ki V/Ks   PM deg   wc rad/s"]
    for q in report["points"]:
        lines.append(f"  {q['T_op']:6.1f} {q['u_op']:8.3f} {q['plant_gain']:7.1f} "
                     f"{q['time_constant']:6.2f} {q['Kp']:9.4f} {q['Ki']:9.4f} "
                     f"{q['phase_margin_deg']:8.1f} {q['crossover']:10.2f}")
    return "\n".join(lines)


def gain_table_toml(report: dict[str, Any]) -> str:
    """The GainScheduledPID parameters of an `sma_thermal` report `report`, as the TOML a
    scenario's instance reads."""
    lines = ["# GainScheduledPID gains for the SMA wire's temperature (§temperature-control),",
             "# written by `musclesim linear sma-thermal --write FILE`: do not edit, rerun the design.",
             "u_min = 0.0  # V: the wire is only heated", f"u_max = {report['design']['u_max']!r}  # V"]
    for i, (x, q) in enumerate(zip(SCHEDULE_K, report["points"]), start=1):
        lines.append(f'"x[{i}]" = {x!r}  # K, {q["T_op"]:g} C')
        lines += [f'"{k}[{i}]" = {q[k]!r}' for k in ("Kp", "Ki", "Kd")]
    return "\n".join(lines) + "\n"
