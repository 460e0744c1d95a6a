"""The load path of the SMA position-control bench (§sma-bench, §position-control): the duty ->
load-cell force model identified on the Electromagnet and LoadCell FMUs, and the stress loop's PI
placed on it."""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Sequence

import control as ct
import numpy as np

from musclesim.analysis.design import design_pi, pi_margins
from musclesim.components import fixedorder

LOAD_DESIGN = {
    "omega_n": 300.0,  # rad/s (48 Hz): far above the loading profiles (<= 1/17 Hz), far below
                       # the 2.5 kHz sampling, and above 1 / (2 zeta tau) (~270 rad/s for the
                       # coil's ~2 ms), below which the placed Kp turns negative
    "zeta": 0.9,
    "duty": (0.2, 0.7),  # the identification step of the PWM duty
    "step": 4e-4,  # s, the stress loop's 2.5 kHz (§sma-bench)
    "duration": 0.05,  # s, recorded after the step
}


def _fit_step(t: Sequence[float] | np.ndarray, f: Sequence[float] | np.ndarray,
              step: float) -> tuple[float, float, float]:
    """K, tau and the RMS residual of f = f0 + K step (1 - exp(-t / tau)) fitted by least squares
    (§loads): Gauss-Newton from K = 1, tau = 10 ms, f0 = f[0], each step halved until it lowers
    the sum of squares and tau kept within [1e-6, 10] s, stopping when no step lowers it. In a
    fixed order of operations (`fixedorder.least_squares`, exactly rounded sums, the C library's
    exp): scipy's least_squares solves through LAPACK, whose last digits depend on the CPU."""
    t, f = [float(v) for v in t], [float(v) for v in f]

    def residual(K: float, tau: float, f0: float) -> list[float]:
        return [f0 + K * step * (1.0 - math.exp(-ti / tau)) - fi for ti, fi in zip(t, f)]

    def cost(r: list[float]) -> float:
        return math.fsum([v * v for v in r])

    x = (1.0, 0.01, f[0])
    r = residual(*x)
    for _ in range(200):
        K, tau, f0 = x
        e = [math.exp(-ti / tau) for ti in t]
        jacobian = [[step * (1.0 - ei) for ei in e],  # d/dK
                    [-K * step * ei * ti / (tau * tau) for ei, ti in zip(e, t)],  # d/dtau
                    [1.0] * len(t)]  # d/df0
        dx = fixedorder.least_squares(jacobian, [-v for v in r])
        lam = 1.0
        while lam > 1e-12:
            trial = (max(K + lam * dx[0], 0.0), min(max(tau + lam * dx[1], 1e-6), 10.0),
                     f0 + lam * dx[2])
            r_trial = residual(*trial)
            if cost(r_trial) < cost(r):
                break
            lam /= 2.0
        else:
            break  # no step lowers the sum of squares: the minimum, to rounding
        x, r = trial, r_trial
    return x[0], x[1], math.sqrt(cost(r) / len(r))


def identify_load_path(fmu_dir: str | Path = "fmus", d: dict[str, Any] | None = None
                       ) -> tuple[ct.StateSpace, float, float, float]:
    """First-order model duty -> load-cell force, identified from a duty step of the FMUs.

    The Electromagnet and LoadCell FMUs of `fmu_dir` (as a scenario uses them, wire held still)
    are run with the duty replayed as a step (`d` overrides settings of `LOAD_DESIGN`); K [N per
    unit duty] and tau [s] are fitted by least squares to the recorded force. Returns
    (python-control system, K, tau, RMS fit residual [N]).
    """
    from musclesim.cosim import Instance, Master, Scenario, Signal

    d = {**LOAD_DESIGN, **(d or {})}
    s = Scenario("load-path identification", None,
                 {"magnet": Instance("magnet", "Electromagnet"),
                  "loadcell": Instance("loadcell", "LoadCell")},
                 ((Signal("magnet", "flange.f"), Signal("loadcell", "f")),), d["step"],
                 d["duration"], algorithm="jacobi", record=(Signal("loadcell", "f_meas"),))
    n = s.n_steps + 1
    lo, hi = d["duty"]
    # settle at the low duty, then step: the first 5 % of the record before the step
    k0 = n // 20
    duty = np.where(np.arange(n) < k0, lo, hi)
    res = Master(s, fmu_dir, {Signal("magnet", "duty"): duty}).run()
    t, f = res.time[k0:] - res.time[k0], res[Signal("loadcell", "f_meas")][k0:]

    K, tau, fit_rms = _fit_step(t, f, hi - lo)
    plant = ct.ss([[-1 / tau]], [[K / tau]], [[1.0]], [[0.0]], inputs=["duty"], outputs=["f"])
    return plant, K, tau, fit_rms


def sma_load(fmu_dir: str | Path = "fmus",
             design: dict[str, Any] | None = None) -> dict[str, Any]:
    """The stress loop: the load path identified on the FMUs of `fmu_dir` and the PI placed on it
    (python-control); `design` overrides settings of `LOAD_DESIGN`.

    Returns a dict with the identified K [N], tau [s] and fit residual, the gains Kp [1/N],
    Ki [1/(N s)], the loop's margins and the sampled closed loop's largest pole radius.
    """
    d = {**LOAD_DESIGN, **(design or {})}
    plant, K, tau, rms = identify_load_path(fmu_dir, d)
    Kp, Ki = design_pi(plant, d["omega_n"], d["zeta"])
    return {"system": "sma-load", "reference": "§loads, §position-control", "design": d,
            "identified": {"K": K, "tau": tau, "fit_rms": rms},
            "Kp": Kp, "Ki": Ki, **pi_margins(plant, Kp, Ki, d["step"])}


def format_sma_load(report: dict[str, Any]) -> str:
    """Human-readable summary of an `sma_load` report `report`."""
    i, d = report["identified"], report["design"]
    return (f"SMA load path (§loads, §position-control): duty -> load-cell force identified "
            f"from a duty step {d['duty'][0]:g} -> {d['duty'][1]:g}: K = {i['K']:.4g} N, tau = "
            f"{i['tau'] * 1e3:.3g} ms (fit RMS {i['fit_rms']:.2g} N)\n"
            f"PI with closed-loop poles at omega_n = {d['omega_n']:g} rad/s, zeta = {d['zeta']:g}: "
            f"Kp = {report['Kp']:.4g} 1/N, Ki = {report['Ki']:.4g} 1/(N s); phase margin "
            f"{report['phase_margin_deg']:.1f} deg at {report['crossover']:.1f} rad/s; sampled at "
            f"{d['step'] * 1e3:g} ms the closed loop's largest pole radius is "
            f"{report['sampled_pole_radius']:.4f}")


def load_gains_toml(report: dict[str, Any]) -> str:
    """The PID parameters of an `sma_load` report `report`, as the TOML a scenario's instance
    reads."""
    return "\n".join([
        "# PID gains of the SMA bench's stress loop (§position-control), written by",
        "# `musclesim linear sma-load --write FILE`: do not edit, rerun the design.",
        f"Kp = {report['Kp']!r}  # duty per N", f"Ki = {report['Ki']!r}  # duty per N s",
        "Kd = 0.0", "u_min = 0.0  # PWM duty", "u_max = 1.0", ""])
