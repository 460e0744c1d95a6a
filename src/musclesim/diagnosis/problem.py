"""The diagnosis problem: the data set's runs of the scenario, the units simulated, their replays.

A `Problem` holds a measured data set with its scenarios and FMU variables. Its `Unit` objects are
sets of instances simulated together against the data: the whole model with the data set's inputs
replayed, one *isolation unit* per component (the component plus the upstream instances whose
outputs were not measured, every measured signal feeding it replayed), and the model with every
measured signal replayed (`Problem.replayed`). Which measured ports stay coupled instead of being
replayed is declared in `musclesim.diagnosis.effects` (`COUPLED_PORTS`). Instances of a unit that
nothing fitted can change (a constant load, a reference) are simulated once and replayed in every
run of a fit (`Run.stepped`): the SMA tracking bench's runs take about a quarter less time.
"""
from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from musclesim.cosim import Master, Scenario, Signal, read_fmu
from musclesim.diagnosis.effects import COUPLED_PORTS, by_component, calibration_of
from musclesim.diagnosis.stats import HELD_OUT, TRAIN, noise_estimate
from musclesim.diagnosis.thresholds import METRIC_FLOOR, NOISE_FLOOR
from musclesim.errors import UserError

if TYPE_CHECKING:
    from musclesim.diagnosis.dataset import DataSet


@dataclass
class Run:
    """One experiment of the data set: a scenario to run and the data to compare it with."""

    experiment: str
    scenario: Scenario  # reduced to the unit and the span
    inputs: dict[Signal, np.ndarray]  # replayed input -> values per communication point
    time: np.ndarray | None = None  # data times relative to t0, the span's start (time series)
    # observed column (or metric) -> values
    measured: dict[Signal | str, np.ndarray] = field(default_factory=dict)
    # per data row (per run if scalar-only): its `stats.Part`
    part: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int8))
    t0: float = 0.0
    # instances of `scenario` simulated once, not in every run (`_sources`)
    sources: tuple[str, ...] = ()
    fed: dict[Signal, np.ndarray] = field(default_factory=dict)  # input they feed -> values

    def stepped(self, s: Scenario) -> tuple[Scenario, dict[Signal, np.ndarray]]:
        """(scenario, replayed inputs) the master runs for `s` (`scenario`, values applied):
        without the `sources`, their outputs replayed as recorded (`fed`)."""
        if not self.sources:
            return s, self.inputs
        keep = set(s.instances) - set(self.sources)
        return s.graph.restrict(keep, self.fed, s.record), {**self.inputs, **self.fed}


@dataclass
class Unit:
    """Instances simulated together (each run's `sources` once), the observed columns they
    produce, how they are run."""

    name: str
    instances: tuple[str, ...]
    observed: tuple[Signal | str, ...]  # signals, or a scalar-only data set's metrics
    runs: list[Run]
    scale: dict[Signal | str, float]  # observed column -> normalising range
    noise: dict[Signal | str, float]  # observed column -> noise std, normalised
    components: dict[str, str]  # instance -> component
    # columns compared allowing up to MAX_ALIGN samples of latency
    alignable: tuple[Signal | str, ...] = ()
    subjects: tuple[str, ...] = ()  # isolation units: the instances whose own closure it is
    # upstream outputs of recent runs, for restarting downstream (`simulate.simulate`); a copy
    # (dataclasses.replace) and one sent to a worker (pickled) start empty
    restarts: dict[Any, Any] = field(default_factory=dict, init=False, repr=False,
                                     compare=False)

    def __getstate__(self) -> dict[str, Any]:
        return {**self.__dict__, "restarts": {}}


def _span_scenario(s, duration):
    n = max(1, int(round(duration / s.step)))
    return replace(s, start_time=0.0, stop_time=n * s.step)


def _variables(s, fmu_dir):
    out = {}
    for name, inst in s.instances.items():
        md = read_fmu(Path(fmu_dir) / f"{inst.component}.fmu")
        out[name] = {v.name: v for v in md.modelVariables}
    return out


def _sources(s, observed):
    """The instances of scenario `s` that nothing a diagnosis fits can change: their component
    declares no effect and no calibration parameter, they read only replayed inputs or other
    such instances' outputs, and no `observed` column is theirs (the tracking bench's constant
    load, its reference). Their outputs are the same in every run of a fit: `Problem.unit`
    records them once and replays them (`Run.stepped`), bit for bit the values a reader takes
    under the Jacobi algorithm, where every instance reads the others' outputs of the same
    communication point (none under Gauss-Seidel, where a reader stepped after a source takes
    its output after its step)."""
    if s.algorithm != "jacobi":
        return set()
    return s.graph.fed_within(
        n for n, i in s.instances.items() if not by_component(i.component)
        and not calibration_of(i.component) and not any(c.instance == n for c in observed))


def _replays(s, keep, columns, input_columns, cut_all=False):
    """{input of a kept instance: the measured column replayed into it}.

    Measured inputs are replayed as such; a connection carrying a measured output is cut and
    replayed when its source is not kept, or with `cut_all` when it is a signal: a measured
    physical port (a variable starting with one of `effects.COUPLED_PORTS`, half of a two-way
    mechanical coupling such as the crawler body's flange position into its central actuator)
    stays coupled, since the coupled element would differentiate the measurement's noise and
    quantisation.
    """
    out = {}
    for k in s.graph.links:
        if k.target not in keep:
            continue
        if k.dst in columns:
            out[k.dst] = k.dst
        elif k.src in columns and (k.source not in keep or (
                cut_all and not k.output.startswith(COUPLED_PORTS))):
            out[k.dst] = k.src
    out.update({c: c for c in input_columns if c.instance in keep})
    return out


class Problem:
    """Data set `ds` prepared for diagnosis with the FMUs in `fmu_dir`: the full model, the
    isolation units, the regimes."""

    def __init__(self, ds: DataSet, fmu_dir: Any = "fmus") -> None:
        self.ds, self.fmu_dir = ds, fmu_dir
        missing = {e.scenario for e in ds.experiments.values()
                   if e.scenario_path is None and ds.scenarios is None}
        if missing:
            raise UserError(f"data set {ds.path}: scenario {sorted(missing)[0]!r} not found (a "
                            ".toml path relative to the manifest, or a name in the scenarios "
                            "folder)")
        self.scenarios = {name: ds.scenario_of(name) for name in ds.experiments}
        first = next(iter(self.scenarios.values()))
        self.vars = _variables(first, fmu_dir)
        self.components = {n: i.component for n, i in first.instances.items()}
        self.units_of: dict[Signal | str, str] = {}  # a column's or a metric's unit
        for col in ds.columns:
            v = self.vars.get(col.instance, {}).get(col.variable)
            if v is None:
                raise UserError(f"data set {ds.path}: column {str(col)!r} is not a variable of "
                                f"scenario "
                                f"{first.name!r} (instances: {', '.join(self.vars)})")
            self.units_of[col] = v.unit or "1"
        self.input_columns = {c for c in ds.columns
                              if self.vars[c.instance][c.variable].causality == "input"}
        for e in ds.experiments.values():
            self.units_of.update({m: mm.unit for m, mm in e.metrics.items()})
        self.scalar_only = ds.scalar_only
        self.part_names = ds.parts()
        # the runs of `_source_outputs`, one per experiment and sources
        self._recorded: dict[Any, Any] = {}

    # -- units --------------------------------------------------------------------------------
    def unit(self, name: str, instances: Iterable[str] | None = None,
             cut_all: bool = False) -> Unit:
        """The `Unit` named `name` of `instances` (None: the whole model with the data set's
        inputs replayed);
        `cut_all` replays every measured signal, even between two of `instances`."""
        ds = self.ds
        if self.scalar_only:
            return self._metric_unit()
        replayed_cols = set(ds.inputs) if instances is None else set(ds.columns)
        runs: list[Run] = []
        observed: tuple[Signal | str, ...] | None = None
        for ename, e in ds.experiments.items():
            s = self.scenarios[ename]
            if instances is None:
                # everything the observed columns depend on, minus what is replayed
                keep = s.graph.upstream({c.instance for c in ds.outputs}, replayed_cols)
            else:
                keep = set(instances)
            replay = _replays(s, keep, replayed_cols, self.input_columns & replayed_cols,
                              cut_all=cut_all)
            obs = tuple(c for c in ds.outputs if c.instance in keep and c not in replay)
            observed = obs if observed is None else observed
            t, cols = ds.experiment(ename)
            t0 = t[0]
            red = _span_scenario(s.graph.restrict(keep, replay, obs), t[-1] - t0)
            grid = t0 + np.arange(red.n_steps + 1) * red.step
            inputs = {dst: np.interp(grid, t, cols[col]) for dst, col in replay.items()}
            part = self._parts(ename, t)
            sources = _sources(red, obs)
            runs.append(Run(ename, red, inputs, t - t0, {c: cols[c] for c in obs}, part, t0,
                            tuple(sorted(sources)), self._source_outputs(red, sources, inputs)))
        assert observed is not None  # a data set has an experiment
        scale, noise = {}, {}
        for c in observed:
            y = np.concatenate([r.measured[c] for r in runs])
            scale[c] = float(np.ptp(y)) or 1.0
            noise[c] = max(np.median([noise_estimate(r.measured[c]) for r in runs]) / scale[c],
                           NOISE_FLOOR)
        keep_all = tuple(sorted(set().union(*(r.scenario.instances for r in runs))))
        # sensor channels nothing simulated in the unit reads (a reader's input is replayed, or
        # the reader is not in the unit): compared allowing an acquisition latency
        read = {src for r in runs for src, _ in r.scenario.connections}
        return Unit(name, keep_all, observed, runs, scale, noise,
                    {n: self.components[n] for n in keep_all},
                    tuple(c for c in observed if c not in read))

    def _source_outputs(self, s, sources, inputs):
        """{input of another instance: its values per communication point} fed by `sources`
        (`_sources`) in scenario `s` with replayed `inputs`, from one run of those that feed
        another instance and the sources upstream of them, alone (once for every unit that has
        the same)."""
        graph = s.graph
        feeds = [k for k in graph.links if k.source in sources and k.target not in sources]
        if not feeds:
            return {}
        # and the sources upstream of them (not one that feeds nothing)
        needed = graph.upstream({k.source for k in feeds})
        alone = graph.restrict(needed, record=dict.fromkeys(k.src for k in feeds))
        replayed = {k: v for k, v in inputs.items() if k.instance in needed}
        key = (repr(alone), tuple((k, v.tobytes()) for k, v in sorted(replayed.items())))
        if key not in self._recorded:  # every unit of the experiment has the same sources
            res = Master(alone, self.fmu_dir, replayed).run()
            if res.error:
                raise UserError(f"data set {self.ds.path}: {res.error}")
            self._recorded[key] = res
        res = self._recorded[key]
        return {k.dst: res[k.src] for k in feeds}

    def _parts(self, ename, t):
        train, held = self.part_names
        part = np.full(len(t), TRAIN, dtype=np.int8)
        if self.ds.split.fraction is not None:
            part[np.isin(t, self.ds.experiment(f"{ename}/held_out")[0])] = HELD_OUT
        elif ename in held:
            part[:] = HELD_OUT
        return part

    def _metric_unit(self):
        ds, runs = self.ds, []
        held = set(self.part_names[1])
        names = tuple(dict.fromkeys(m for e in ds.experiments.values() for m in e.metrics))
        for ename, e in ds.experiments.items():
            # a metric an experiment lacks is an empty comparison
            measured: dict[Signal | str, np.ndarray] = {
                m: np.array([e.metrics[m].value if m in e.metrics else math.nan]) for m in names}
            runs.append(Run(ename, self.scenarios[ename], {}, measured=measured,
                            part=np.array([HELD_OUT if ename in held else TRAIN],
                                          dtype=np.int8)))
        scale: dict[Signal | str, float] = {
            m: float(np.nanmax([abs(r.measured[m][0]) for r in runs])) or 1.0 for m in names}
        unc = {m: max((mm.uncertainty or 0.0) for e in ds.experiments.values()
                      for k, mm in e.metrics.items() if k == m) for m in names}
        noise: dict[Signal | str, float] = {
            m: unc[m] / scale[m] if unc[m] > 0 else METRIC_FLOOR for m in names}
        first = next(iter(self.scenarios.values()))
        return Unit("model", tuple(first.instances), names, runs, scale, noise,
                    dict(self.components))

    def replayed(self) -> Unit:
        """The model with every measured signal replayed where it feeds one (loops cut open at
        the measurements; measured physical ports stay coupled, `_replays`): the model in which
        section 4 compares before and after, so that a closed loop's oscillation phase does not
        hide what an effect explains. Its instances are those that still act on an observed
        signal (`affected`): a controller whose output is replayed from data is not simulated
        (the same values, in about 60 % of the time for the SMA tracking bench)."""
        if self.scalar_only:
            return self._metric_unit()
        name = "all measured signals replayed"
        unit = self.unit(name, sorted(self.components), cut_all=True)
        acting = [i for i in unit.instances if affected(unit, (i,))]
        return unit if len(acting) == len(unit.instances) else self.unit(name, acting,
                                                                          cut_all=True)

    def isolation_units(self) -> list[Unit]:
        """One unit per distinct isolation closure that observes something, smallest first."""
        if self.scalar_only:
            return []
        ds = self.ds
        graph = next(iter(self.scenarios.values())).graph
        measured = set(ds.columns)
        subjects: dict[frozenset[str], list[str]] = {}
        for inst in graph.instances:
            subjects.setdefault(frozenset(graph.upstream({inst}, measured)), []).append(inst)
        out = sorted((k for k in subjects if any(
            c.instance in k and c not in graph.inputs_of(k) for c in ds.outputs)),
            key=lambda k: (len(k), sorted(k)))
        return [replace(self.unit(" + ".join(sorted(k)), sorted(k)), subjects=tuple(subjects[k]))
                for k in out]


def downstream(unit: Unit, instances: Iterable[str]) -> set[str]:
    """`instances` and every instance they feed within `unit` (connections replayed from data
    cut)."""
    return unit.runs[0].scenario.graph.downstream(instances)


def affected(unit: Unit, instances: Iterable[str]) -> tuple[Signal | str, ...]:
    """The observed columns of `unit` that `instances` can change: their own outputs and those of
    every instance they feed (`downstream`). A sensor's effect changes its channel; the wire's,
    everything downstream of it. Every metric of a scalar-only unit."""
    if unit.runs[0].time is None:
        return tuple(unit.observed)
    reach = downstream(unit, instances)
    return tuple(c for c in unit.observed if isinstance(c, Signal) and c.instance in reach)
