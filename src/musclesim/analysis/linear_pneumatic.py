"""The pressure loops of the pneumatic crawler (§crawler-hardware, §gait): discrete models duty ->
measured pressure identified on the FMUs from a PRBS, and a PI per actuator kind with its
margins."""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable

import control as ct
import numpy as np

from musclesim.analysis.design import discrete_pi
from musclesim.components import fixedorder
from musclesim.errors import UserError

PNEUMATIC_DESIGN = {
    "scenario": "pneumatic-identification",  # a scenario file, or a shipped one's name
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
    "step": 1e-3,  # s, the DAQ's 1 kHz (§crawler-hardware)
}
ACTUATORS = ("central", "extremal")  # instance names in the identification scenario


def _fit_arx(p: np.ndarray, u: np.ndarray, max_delay: int) -> tuple[Any, ...]:
    """Least-squares p[k+1] = a p[k] + b u[k-d] + c for d = 0..max_delay; the best (a, b, c, d,
    RMS residual). In a fixed order of operations (`fixedorder.least_squares`, exactly rounded
    sums): numpy's lstsq rounds with the CPU's BLAS kernel, and the fit is ill-conditioned
    (p is nearly constant), so its digits from the eighth on would depend on the CPU."""
    best: tuple[Any, ...] | None = None
    for d in range(max_delay + 1):
        columns = [p[d:-1], u[:len(u) - 1 - d] if d else u[:-1], np.ones(len(p) - 1 - d)]
        y = p[d + 1:]
        coef = fixedorder.least_squares(columns, y)
        residual = coef[0] * columns[0] + coef[1] * columns[1] + coef[2] * columns[2] - y
        rms = math.sqrt(math.fsum((residual * residual).tolist()) / len(y))
        if best is None or rms < best[4]:
            best = (*coef, d, rms)
    assert best is not None  # max_delay >= 0: one fit at least
    return best


def _arx_response(fit: dict[str, Any]) -> Callable[[complex], complex]:
    """The identified plant b z^-d / (z - a) as a function of z (Python's complex arithmetic)."""
    a, b, d = fit["a"], fit["b"], fit["delay_samples"]
    return lambda z: b / (z ** (d + 1) - a * z ** d)


def identify_pneumatic(fmu_dir: str | Path = "fmus", design: dict[str, Any] | None = None
                       ) -> dict[str, tuple[Any, dict[str, Any]]]:
    """Discrete models duty -> measured pressure of the central and the extremal actuator.

    Runs the shipped scenario pneumatic-identification on the FMUs of `fmu_dir` twice
    (`design` overrides settings of `PNEUMATIC_DESIGN`) with the duties replayed: once inflating
    at ``fill_duty`` to find when each chamber reaches ``p_op`` with its contact full, then
    inflating until then and applying a seeded PRBS of +-``amplitude`` (each bit followed by its opposite). A
    first-order ARX model with input delay is fitted to the PRBS part. Returns ``{actuator:
    (python-control discrete system, fit dict)}``.
    """
    from musclesim.cosim import Master, Signal, load_scenario, locate_scenario

    d = {**PNEUMATIC_DESIGN, **(design or {})}
    n_bit = round(d["bit"] / d["step"])
    # each random bit is followed by its opposite, so that the integrating chamber stays near p_op
    signs = np.where(np.random.default_rng(d["seed"]).integers(0, 2, d["bits"] // 2) > 0, 1.0, -1.0)
    prbs = np.column_stack([signs, -signs]).ravel().repeat(n_bit)
    s = load_scenario(locate_scenario(d["scenario"]), stop_time=d["fill_time"])
    res = Master(s, fmu_dir, {Signal(a, "duty"): np.full(s.n_steps + 1, d["fill_duty"][a])
                              for a in ACTUATORS}).run()
    fill = {}
    for a in ACTUATORS:
        # an extremal chamber bulges while its contact builds: identify it once contact is full
        reached = np.flatnonzero((res[Signal(f"{a}_sensor", "p_meas")] >= d["p_op"])
                                 & (res[Signal(a, "u")] >= 0.999))
        if not len(reached):
            raise UserError(f"{d['scenario']}: {a} does not reach p_op = {d['p_op']:g} Pa with "
                            f"full contact within {d['fill_time']:g} s at duty {d['fill_duty'][a]:g}")
        fill[a] = int(reached[0])
    n = max(fill.values()) + len(prbs)
    s = load_scenario(locate_scenario(d["scenario"]), stop_time=n * d["step"])
    duties = {a: np.concatenate([np.full(fill[a], d["fill_duty"][a]), d["amplitude"][a] * prbs,
                                 np.zeros(n + 1 - fill[a] - len(prbs))]) for a in ACTUATORS}
    res = Master(s, fmu_dir, {Signal(a, "duty"): u for a, u in duties.items()}).run()
    out = {}
    for a in ACTUATORS:
        window = slice(fill[a], fill[a] + len(prbs))
        p, u = res[Signal(f"{a}_sensor", "p_meas")][window], duties[a][window]
        A, B, c, delay, rms = _fit_arx(p, u, d["max_delay"])
        plant = ct.tf([B], np.r_[1.0, -A, np.zeros(delay)], d["step"], inputs="duty", outputs="p")
        out[a] = (plant, {"a": A, "b": B, "c": c, "delay_samples": delay, "fit_rms": rms,
                          "p_range": [float(p.min()), float(p.max())]})
    return out


def pneumatic(fmu_dir: str | Path = "fmus", design: dict[str, Any] | None = None
              ) -> dict[str, Any]:
    """The pressure loops: discrete plants identified on the FMUs of `fmu_dir` and a PI per
    actuator kind with margins; `design` overrides settings of `PNEUMATIC_DESIGN`.

    Returns a dict with, per actuator kind, the ARX fit (a, b, c, delay, RMS residual [Pa]),
    the integrator gain [Pa/s per unit duty], the gains Kp [1/Pa], Ki [1/(Pa s)], the discrete
    loop's gain margin (None: infinite), phase margin [deg], crossover [rad/s] and the largest
    closed-loop pole radius (below 1: stable).
    """
    d = {**PNEUMATIC_DESIGN, **(design or {})}
    loops = {}
    for a, (plant, fit) in identify_pneumatic(fmu_dir, d).items():
        Kp, Ki = discrete_pi(_arx_response(fit), d["crossover"], d["zero_ratio"], d["step"])
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
    return {"system": "pneumatic", "reference": "§crawler-hardware, §gait", "design": d,
            "loops": loops}


def format_pneumatic(report: dict[str, Any]) -> str:
    """Human-readable summary of a `pneumatic` report `report`."""
    d = report["design"]
    lines = [f"Pressure loops (§crawler-hardware, §gait): duty -> measured pressure identified at "
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


def pneumatic_gains_toml(report: dict[str, Any], actuator: str) -> str:
    """The PID parameters of the loop of `actuator` ("central" or "extremal") in a `pneumatic`
    report `report`, as the TOML a scenario's instance reads."""
    q = report["loops"][actuator]
    return "\n".join([
        f"# PID gains of the {actuator} soft actuator's pressure loop (§crawler-hardware),",
        "# written by `musclesim linear pneumatic --write DIR`: do not edit, rerun the design.",
        f"Kp = {float(q['Kp'])!r}  # duty per Pa", f"Ki = {float(q['Ki'])!r}  # duty per Pa s",
        "Kd = 0.0",
        "u_min = -1.0  # full exhaust", "u_max = 1.0  # full inflation", ""])
