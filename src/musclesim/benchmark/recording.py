"""Recording the blind benchmark's cases: the own bench's virtual hardware run with a case's
hidden values and the sensors' nuisances (`record`; `record_many` runs a bench's cases in one
compiled pass), and a recording written as an unlabelled measured data set (`write_case`,
`make_case`).

A case is a dict as `musclesim.benchmark.cases.plan` (or `musclesim.benchmark.plan`) makes it,
written to key.json as it is: its hidden ``values`` keep their ``"instance.parameter"`` keys and
are parsed here, once, into `ParamRef`s.
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from musclesim.benchmark import plan as independent_plan
from musclesim.benchmark.cases import BENCHES, STOP_TIME
from musclesim.cosim import (Master, ParamRef, Results, Scenario, Signal, load_scenario, run_cases,
                             with_values)
from musclesim.diagnosis import write_data_set
from musclesim.errors import UserError

# nuisances (the same for every case; magnitudes of a bench like §sma-bench's)
TC_NOISE, TC_QUANTUM = 0.08, 0.05  # K
STRAIN_NOISE, STRAIN_QUANTUM = 2e-5, 1e-5
LASER_NOISE, LASER_QUANTUM = 2e-6, 1e-6  # m (the laser-noise effect of the library as nuisance)
LOADCELL_NOISE, LOADCELL_QUANTUM = 2e-3, 1e-3  # N
PRESSURE_NOISE, PRESSURE_QUANTUM = 30.0, 10.0  # Pa
VIDEO_NOISE, VIDEO_QUANTUM = 2e-4, 1e-4  # m: block edges tracked on video
VIDEO = (Signal("body", "flange_a.s"), Signal("body", "flange_b.s"))  # the video's columns
STRAIN = Signal("wire", "strain")  # a strain gauge's column
LASER = Signal("laser", "s_meas")
# (sensor instance, noise, quantum, modulus of the case's seed that seeds it)
NUISANCES = [("thermocouple", TC_NOISE, TC_QUANTUM, 100000),
             ("laser", LASER_NOISE, LASER_QUANTUM, 100001),
             ("loadcell", LOADCELL_NOISE, LOADCELL_QUANTUM, 100003),
             ("sensor1", PRESSURE_NOISE, PRESSURE_QUANTUM, 100019),
             ("sensorc", PRESSURE_NOISE, PRESSURE_QUANTUM, 100043),
             ("sensor2", PRESSURE_NOISE, PRESSURE_QUANTUM, 100049)]
HELD_OUT_FRACTION = 0.35


def _scenario_path(bench: str, scenarios_dir: str | Path) -> Path:
    return Path(scenarios_dir) / f"{BENCHES[bench][0]}.toml"


def bench_scenario(case: dict[str, Any], scenarios_dir: str | Path) -> Scenario:
    """The scenario of `case`'s bench (a file in `scenarios_dir`) with its hidden values set
    (what `record` runs)."""
    s = load_scenario(_scenario_path(case["bench"], scenarios_dir), (),
                      STOP_TIME.get(case["bench"]))
    return with_values(s, {ParamRef.parse(k): v for k, v in case["values"].items()})


def record(case: dict[str, Any], s: Scenario,
           fmu_dir: str | Path) -> tuple[np.ndarray, dict[Signal, np.ndarray]]:
    """Run the virtual hardware of `case` on its bench's scenario `s` (`bench_scenario`) with
    the FMUs in `fmu_dir`: (time, {column: values}) as the bench records them."""
    return record_many([(case, s)], fmu_dir)[0]


def record_many(items: Sequence[tuple[dict[str, Any], Scenario]], fmu_dir: str | Path
                ) -> list[tuple[np.ndarray, dict[Signal, np.ndarray]]]:
    """`record` of each (case, its bench's scenario) of `items`: the cases of one bench in one
    compiled pass where they fuse (`musclesim.cosim.run_cases`), each with its own run's bits."""
    masters = [Master(_with_nuisances(case, s), fmu_dir) for case, s in items]
    return [_as_recorded(case, res) for (case, _), res in zip(items, run_cases(masters))]


def _with_nuisances(case: dict[str, Any], s: Scenario) -> Scenario:
    """`s` with the nuisances on the sensors `case`'s bench has, recording what it records."""
    _, inputs, outputs, _ = BENCHES[case["bench"]]
    # the nuisances on the sensors this bench has (with_values skips the others)
    s = with_values(s, {ParamRef(inst, par): v for inst, noise, quantum, modulus in NUISANCES
                        for par, v in (("noise_std", noise), ("quantum", quantum),
                                       ("seed", case["seed"] % modulus))})
    return replace(s, record=tuple(inputs + outputs), metrics={}, plots=())


def _as_recorded(case: dict[str, Any], res: Results
                 ) -> tuple[np.ndarray, dict[Signal, np.ndarray]]:
    """(time, {column: values}) of `case`'s run `res` as its bench records them: the strain
    gauge's and the video's noise and quantisation, the acquisition's lag."""
    _, inputs, outputs, _ = BENCHES[case["bench"]]
    if res.error:
        raise UserError(f"{case['case']}: the virtual hardware failed: {res.error}")
    rng = np.random.default_rng(case["seed"])
    cols = {c: res[c].copy() for c in inputs + outputs}
    if STRAIN in cols:  # a strain gauge: its noise and quantisation (the laser's in-FMU)
        strain = cols[STRAIN] + STRAIN_NOISE * rng.standard_normal(
            len(res.time)) + _outside_strain(case, res.time)
        cols[STRAIN] = STRAIN_QUANTUM * np.round(strain / STRAIN_QUANTUM)
    for c in VIDEO:  # noise, pixel quantisation
        if c in cols:
            x = cols[c] + VIDEO_NOISE * rng.standard_normal(len(res.time))
            cols[c] = VIDEO_QUANTUM * np.round(x / VIDEO_QUANTUM)
    lag = case["latency_samples"]
    # the gauge's (or laser's, or the video's) own acquisition lags the controller's log
    for c in (STRAIN, LASER, *VIDEO) if lag else ():
        if c in cols:
            cols[c] = np.concatenate([np.full(lag, cols[c][0]), cols[c][:-lag]])
    return res.time, cols


def _outside_strain(case: dict[str, Any], t: np.ndarray) -> np.ndarray:
    """What an outside change adds to the strain reading at times `t` (zeros without one)."""
    span = t[-1] - t[0]
    add = case.get("strain_drift", 0.0) * (t - t[0]) / span
    for at, lost in case.get("slips", ()):
        add = add - lost * (t >= t[0] + at * span)
    return add


def make_case(case: dict[str, Any], out: str | Path, fmu_dir: str | Path = "fmus",
              scenarios_dir: str | Path = "scenarios") -> Path:
    """Record `case` on its bench (the own benches' scenarios in `scenarios_dir`, their FMUs in
    `fmu_dir`) and write its data set into ``out/cases/<case>`` (`out` the benchmark's folder),
    here (what `run` does on its map); return that folder."""
    stated: dict[ParamRef, float] | None
    if case["bench"] in ("independent-crawler", independent_plan.BENCH):
        time, cols, stated = independent_plan.record(case)
    else:
        (time, cols), stated = record(case, bench_scenario(case, scenarios_dir), fmu_dir), None
    folder = Path(out) / "cases" / case["case"]
    write_case(case, folder, time, cols, stated, scenarios_dir)
    return folder


def write_case(case: dict[str, Any], folder: Path, time: np.ndarray,
               cols: dict[Signal, np.ndarray], stated: dict[ParamRef, float] | None,
               scenarios_dir: str | Path) -> None:
    """Write `case`'s recording (`time`, `cols`) as a data set in `folder`, naming its model's
    scenario (in `scenarios_dir`) and the conditions the bench `stated`."""
    ip = independent_plan
    if case["bench"] in ("independent-crawler", "crawler-family"):
        scenario, inputs, outputs = ip.CRAWLER_SCENARIO, ip.CRAWLER_INPUTS, ip.CRAWLER_OUTPUTS
        what = "the independent crawler bench"
    elif case["bench"] in (ip.BENCH, "family"):
        scenario, inputs, outputs = ip.SCENARIO, ip.INPUTS, ip.OUTPUTS
        what = "the independent SMA bench"
    else:
        scenario, inputs, outputs, _ = BENCHES[case["bench"]]
        what = f"bench {scenario}"
    ref = str((Path(scenarios_dir) / f"{scenario}.toml").resolve())
    write_data_set(folder, time, cols, inputs, outputs, ref, f"blind case {case['case']} on {what}",
                   stated, held_out_fraction=HELD_OUT_FRACTION)
