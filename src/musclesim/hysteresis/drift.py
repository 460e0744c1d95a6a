"""The long-duration drift test of §drift / 3.3 on the wire's cores, with the temperature imposed.

A new wire is cycled sinusoidally 30-130 C at 0.05 Hz, 20 cycles per test; the five stresses in
the order 125, 135, 115, 145, 105 MPa make a round, repeated 25 times (50 000 s). Each test's 20
cycles are averaged into one loop (strain against the phase of the cycle); reported per stress
is the RMSE between the averaged loops of tests 1 and 13 and of tests 13 and 25 (§drift).

The wire is the SmaWire FMU's hysteresis and drift cores (`musclesim.components.sma.preisach`,
`.drift`), stepped exactly as the FMU steps them but with the temperature imposed (an ideal
temperature loop, as sma-drift.toml's PI nearly is: 0.1 K RMS): 50 000 s of co-simulation at the
loop's 200 Hz would be 10 million steps of several FMUs, this is one Preisach step per sample
(`samples_per_cycle` per 20 s cycle, 200 by default: 1.6 K at most between samples).
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from musclesim.components.sma import datasets, drift
from musclesim.components.sma.preisach import PreisachModel
from musclesim.components.sma.thermal import martensite_fraction
from musclesim.cosim import load_scenario
from musclesim.errors import UserError

STRESS_ORDER = (125e6, 135e6, 115e6, 145e6, 105e6)  # Pa, one round (§drift)
WIRE_INSTANCE = "wire"  # the instance of the scenario whose drift parameters the test uses
_DRIFT_PARAMETERS = {"drift_amplitude": "amplitude_change", "drift_shift": "shift",
                     "drift_settle_cycles": "cycles_to_settle"}


@dataclass(frozen=True)
class Protocol:
    """The test's schedule (defaults §drift)."""

    stresses: tuple[float, ...] = STRESS_ORDER  # Pa, in the order of one round
    rounds: int = 25
    cycles: int = 20  # per test
    frequency: float = 0.05  # Hz
    T_lo: float = 30.0  # C
    T_hi: float = 130.0  # C
    samples_per_cycle: int = 200
    # tests (per stress, from 1) whose averaged loops are compared
    compare: tuple[int, ...] = (1, 13, 25)

    def check(self) -> None:
        """Raise UserError naming the first value outside its valid range."""
        for name in ("rounds", "cycles", "samples_per_cycle"):
            value = getattr(self, name)
            if not (isinstance(value, int) and value >= 1):
                raise UserError(f"{name} must be a positive integer (got {value!r})")
        if self.samples_per_cycle < 8:
            raise UserError(f"samples_per_cycle must be at least 8 (got {self.samples_per_cycle})")
        if not (self.frequency > 0 and self.T_lo < self.T_hi and self.stresses):
            raise UserError("the drift test needs a positive frequency, T_lo < T_hi and stresses")
        bad = [k for k in self.compare if not (isinstance(k, int) and 1 <= k <= self.rounds)]
        if bad or len(self.compare) < 2:
            raise UserError(f"the compared tests {list(self.compare)} must be at least two test "
                            f"numbers within 1..{self.rounds} (the rounds run)")


def cycle_temperatures(p: Protocol) -> list[float]:
    """The temperatures [C] of one cycle's samples of protocol `p`: a cosine from T_lo up to T_hi
    and back,
    sampled at the end of each of the cycle's steps (the start, T_lo, is the previous end)."""
    phase = 2 * math.pi * np.arange(1, p.samples_per_cycle + 1) / p.samples_per_cycle
    mid, amp = (p.T_hi + p.T_lo) / 2, (p.T_hi - p.T_lo) / 2
    return [float(x) for x in mid - amp * np.cos(phase)]


def run(protocol: Protocol | None = None, drift_params: drift.DriftParams | None = None,
        hysteresis: int | float = 0, cycles_start: float = 0.0) -> dict[str, Any]:
    """Run the drift test of `protocol` (default: §drift's) on a wire of drift parameters
    `drift_params` (default: the core's), hysteresis surface `hysteresis` (an id of
    `musclesim.components.sma.datasets`) and `cycles_start` transformation cycles before; return
    {"loops": {stress: {test: averaged loop (array)}}, "rmse": {stress: {"a-b": RMSE}},
    "temperatures": one cycle's temperatures [C], "cycles": transformation cycles counted at the
    end}.

    Only the tests named in ``protocol.compare`` are kept. The model is stepped as the SmaWire FMU
    steps it: the hysteresis sees T - shift(N) clipped to its grid, the strain is scaled by
    strain_scale(N), both with the cycles N counted before the step; each test starts where the
    previous ended (at T_lo), under its own stress.

    Examples
    --------
    >>> out = run(Protocol(rounds=2, cycles=2, samples_per_cycle=20, compare=(1, 2)),
    ...           drift.DriftParams(amplitude_change=0.1, shift=5.0, cycles_to_settle=10.0))
    >>> sorted(out["rmse"]) == sorted(STRESS_ORDER), all(r["1-2"] > 0 for r in out["rmse"].values())
    (True, True)
    """
    p = protocol or Protocol()
    p.check()
    dp = drift_params or drift.DriftParams()
    dp.check()
    surface = datasets.surface(hysteresis)
    temps = cycle_temperatures(p)
    t_lo, t_hi = surface.t_lo, surface.t_hi
    model = PreisachModel(surface)
    n_cycles = float(cycles_start)
    sigma = p.stresses[0]
    model.reset(min(max(p.T_lo, t_lo), t_hi), sigma)  # a new wire at T_lo
    xi = 1.0
    keep = set(p.compare)
    loops: dict[float, dict[int, np.ndarray]] = {s: {} for s in p.stresses}
    for test in range(1, p.rounds + 1):
        for sigma in p.stresses:
            eps_max = surface.F(t_hi, t_lo, sigma)
            strain = np.empty((p.cycles, len(temps)))
            for c in range(p.cycles):
                row = strain[c]
                for j, T in enumerate(temps):
                    shift = drift.temperature_shift(n_cycles, dp)
                    eps = model.step(min(max(T - shift, t_lo), t_hi), sigma)
                    row[j] = drift.strain_scale(n_cycles, dp) * eps
                    xi_new = martensite_fraction(eps, eps_max)
                    n_cycles = drift.count_cycles(n_cycles, xi, xi_new)
                    xi = xi_new
            if test in keep:
                loops[sigma][test] = strain.mean(axis=0)
    pairs = list(zip(p.compare, p.compare[1:]))
    rmse = {s: {f"{a}-{b}": float(np.sqrt(np.mean((loops[s][a] - loops[s][b]) ** 2)))
                for a, b in pairs} for s in p.stresses}
    return {"loops": loops, "rmse": rmse, "temperatures": temps, "cycles": n_cycles}


def scenario_parameters(scenario: str | Path) -> tuple[drift.DriftParams, float, float]:
    """(DriftParams, hysteresis id, cycles before the test) from the wire instance of the scenario
    file `scenario`: the drift test uses the same wire as the co-simulated test of that file."""
    s = load_scenario(scenario)
    if WIRE_INSTANCE not in s.instances:
        raise UserError(f"{scenario}: the drift test needs an instance {WIRE_INSTANCE!r} "
                        f"(a SmaWire); the file has {', '.join(s.instances)}")
    values = s.instances[WIRE_INSTANCE].parameters
    kwargs = {field: float(values[name]) for name, field in _DRIFT_PARAMETERS.items()
              if name in values}
    params = drift.DriftParams(**kwargs)
    try:
        params.check()
    except ValueError as exc:
        raise UserError(f"{scenario}: instance {WIRE_INSTANCE}: {exc}") from None
    return params, float(values.get("hysteresis", 0.0)), float(values.get("drift_cycles_start",
                                                                            0.0))


def drift_main(scenario: str | Path, protocol: Protocol, as_json: bool = False) -> str:
    """`musclesim drift`: run the test of `protocol` with the wire of scenario file `scenario`;
    return the text (with `as_json`, the report as JSON)."""
    params, hysteresis, start = scenario_parameters(scenario)
    try:
        out = run(protocol, params, hysteresis, start)
    except ValueError as exc:
        raise UserError(f"{scenario}: {exc}") from None
    report = {
        "scenario": str(scenario),
        "drift": {"amplitude_change": params.amplitude_change, "shift_K": params.shift,
                  "cycles_to_settle": params.cycles_to_settle},
        "protocol": {"stresses_Pa": list(protocol.stresses), "rounds": protocol.rounds,
                     "cycles_per_test": protocol.cycles, "frequency_Hz": protocol.frequency,
                     "band_C": [protocol.T_lo, protocol.T_hi],
                     "samples_per_cycle": protocol.samples_per_cycle},
        "rmse": {f"{s / 1e6:g} MPa": r for s, r in out["rmse"].items()},
        "cycles_counted": out["cycles"],
    }
    if as_json:
        return json.dumps(report, indent=2)
    pairs = list(next(iter(out["rmse"].values())))
    lines = [f"drift test (§drift): {protocol.rounds} rounds of {len(protocol.stresses)} tests, "
             f"{protocol.cycles} cycles {protocol.T_lo:g}-{protocol.T_hi:g} C at "
             f"{protocol.frequency:g} Hz each; wire of {scenario} (drift amplitude "
             f"{params.amplitude_change:g}, shift {params.shift:g} K, e-folding "
             f"{params.cycles_to_settle:g} cycles)",
             "RMSE between averaged loops [strain]:",
             "stress    " + "".join(f"  tests {pair:>7}" for pair in pairs)]
    for s, r in out["rmse"].items():
        lines.append(f"{s / 1e6:5.0f} MPa" + "".join(f"  {r[pair]:13.3e}" for pair in pairs))
    lines.append(f"transformation cycles counted: {out['cycles']:.0f}")
    return "\n".join(lines)
