"""`musclesim diagnose`: where a model misses its bench, which unmodelled effect causes it, and how
far the gap shrinks once that effect is added, judged on held-out data (DESIGN.md, "Sim-to-real
gap diagnosis").

The steps, on a measured data set (`musclesim.dataset`):

1. Gap. The scenario runs with the data set's inputs replayed (`Master` ``inputs``) and every
   observed signal is compared: NRMSE by the measured range, bias (measured - model), lag (the
   shift of the model that best matches the data); scalar metrics by relative error. A sensor
   channel nothing in the model reads is compared allowing an acquisition latency of up to
   `MAX_ALIGN` samples, chosen on the training part in every comparison (`residuals`).
2. Where. Each component is re-simulated in its *isolation unit*: the component plus the upstream
   instances whose outputs were not measured, with every measured signal feeding the unit
   replayed. A unit deviates when the held-out gap of one of its signals exceeds `DEVIATES` times
   that signal's noise (estimated from the data's second differences, at least `NOISE_FLOOR` of
   the range; for a metric its uncertainty, else `METRIC_FLOOR`). Components of deviating units are located unless a unit that did not deviate observed
   them (they are exonerated). The nominal residual is also split by regime and the worst windows
   are listed.
3. Which effect. Every effect of a located component (`musclesim.effects`) is fitted on the
   training part (bounded least squares after a coarse scan) and scored on the held-out part. It
   counts only if it shrinks the held-out gap by at least `MIN_SHRINKAGE`, leaves at most
   `BEAT_RECALIBRATED` of the gap of the nominal model with as many nominal parameters
   recalibrated (`effects.CALIBRATION`), and its gain per sample in the regime the effect
   predicts is at least `SIGNATURE_MIN` of its average (signature). Greedy forward selection
   adds a second effect when it shrinks the remaining gap by `MIN_SHRINKAGE` again.
4. How far it shrinks: held-out gap per signal before and after, with block-bootstrap intervals,
   in the model with every measured signal replayed (`Problem.replayed`).

Verdict: ``none`` when no signal deviates beyond the noise; the best effect's name when the gap
left after it is unstructured (within `STRUCTURED` noise floors or `RESIDUAL_SHARE` of the gap
before), and also when it explains at least `MOST` of the gap but leaves a structured rest
(``complete`` false: a further difference outside the library); ``recalibration`` when no effect
counts but a recalibrated nominal parameter leaves an unstructured gap (a parameter is off, no
effect is missing); ``unexplained`` otherwise.

The fits are independent tasks: `diagnose` maps them with the ``pmap`` it is given (the CLI passes
Dask's, the same local cluster or scheduler as sweeps).
"""
import itertools
import math
from dataclasses import dataclass, field, replace

import numpy as np
from scipy import optimize

from musclesim.diagnosis import effects
from musclesim.cosim import scenario as scenario_mod
from musclesim.errors import UserError
from musclesim.cosim.scenario import split_signal

DEVIATES = 3.0  # a unit deviates above this many noise floors of held-out gap
STRUCTURED = 3.0  # a residual above this many noise floors is structured: not explained ...
RESIDUAL_SHARE = 0.1  # ... unless it is at most this share of the gap before
MOST = 0.5  # an effect that leaves a structured gap is still named if it explains this share
MIN_SHRINKAGE = 0.3  # an effect must shrink the held-out gap by this fraction
BEAT_RECALIBRATED = 0.85  # ... and leave at most this fraction of the recalibrated model's gap
NOISE_FLOOR = 2e-3  # the smallest noise floor, as a fraction of a signal's range
BOOTSTRAP = 400  # block-bootstrap resamples
BLOCKS = 20  # blocks per held-out part for the bootstrap
WINDOWS = 3  # worst time windows listed
METRIC_FLOOR = 0.02  # relative noise floor of a scalar metric without uncertainty
# an effect's regime must hold at least this share of its fair (per-sample) part of the gain:
# effects through the hysteresis's memory spread their gain beyond the regime that triggers them
SIGNATURE_MIN = 0.75
MAX_ALIGN = 2  # samples of acquisition latency allowed for a sensor channel nothing reads


# ---- the problem: runs of the scenario against the measured data ------------------------------

@dataclass
class Run:
    """One experiment of the data set: a scenario to run and the data to compare it with."""

    experiment: str
    scenario: object  # musclesim.scenario.Scenario, reduced to the unit and the span
    inputs: dict  # replayed input -> values per communication point
    time: np.ndarray = None  # data times relative to t0, the span's start (time series)
    measured: dict = field(default_factory=dict)  # observed column (or metric) -> values
    part: np.ndarray = None  # per data row (per run if scalar-only): 0 train, 1 held-out
    t0: float = 0.0


@dataclass
class Unit:
    """Instances simulated together, the observed columns they produce, how they are run."""

    name: str
    instances: tuple
    observed: tuple
    runs: list
    scale: dict  # observed column -> normalising range
    noise: dict  # observed column -> noise std, normalised
    components: dict  # instance -> component
    alignable: tuple = ()  # columns compared allowing up to MAX_ALIGN samples of latency
    subjects: tuple = ()  # isolation units: the instances whose own closure this unit is


def _span_scenario(s, duration):
    n = max(1, int(round(duration / s.step)))
    return replace(s, start_time=0.0, stop_time=n * s.step)


def _variables(s, fmu_dir):
    from musclesim.cosim.host import read_fmu

    out = {}
    for name, inst in s.instances.items():
        md = read_fmu(f"{fmu_dir}/{inst.component}.fmu")
        out[name] = {v.name: v for v in md.modelVariables}
    return out


def _closure(s, start, measured):
    """`start` plus the instances upstream of it whose signals are not `measured`."""
    unit, changed = set(start), True
    while changed:
        changed = False
        for src, dst in s.connections:
            a, b = split_signal(src)[0], split_signal(dst)[0]
            if b in unit and a not in unit and src not in measured and dst not in measured:
                unit.add(a)
                changed = True
    return unit


def _reduce(s, keep, replay_from, record):
    """The scenario restricted to `keep`, inputs fed by `replay_from` ({dst: column}) dropped."""
    conns = tuple((a, b) for a, b in s.connections
                  if split_signal(a)[0] in keep and split_signal(b)[0] in keep and b not in replay_from)
    return replace(s, instances={n: i for n, i in s.instances.items() if n in keep},
                   connections=conns, record=tuple(record), metrics={}, plots=())


def _replays(s, keep, columns, input_columns, cut_all=False):
    """{input of a kept instance: the measured column replayed into it}.

    Measured inputs are replayed as such; a connection carrying a measured output is cut and
    replayed when its source is not kept, or with `cut_all` when it is a signal: a measured
    physical port (a ``flange*`` variable, half of a two-way mechanical coupling such as the
    crawler body's flange position into its central actuator) stays coupled, since the coupled
    element would differentiate the measurement's noise and quantisation.
    """
    out = {}
    for src, dst in s.connections:
        if split_signal(dst)[0] not in keep:
            continue
        source, variable = split_signal(src)
        if dst in columns:
            out[dst] = dst
        elif src in columns and (source not in keep or (
                cut_all and not variable.startswith("flange"))):
            out[dst] = src
    out.update({c: c for c in input_columns if split_signal(c)[0] in keep})
    return out


def _inputs_of(s, keep):
    return {dst for _, dst in s.connections if split_signal(dst)[0] in keep}


def _advance(y, samples):
    """`y` moved `samples` earlier (its last value held at the end)."""
    if not samples:
        return y
    return np.concatenate([y[samples:], np.full(samples, y[-1])])


def _noise(y):
    """Std of white measurement noise in `y` from its second differences (var = 6 sigma^2)."""
    if len(y) < 4:
        return 0.0
    d2 = np.diff(y, 2)
    # the median absolute deviation keeps the signal's own curvature at its corners out
    return float(1.4826 * np.median(np.abs(d2 - np.median(d2))) / math.sqrt(6))


class Problem:
    """A data set prepared for diagnosis: the full model, the isolation units, the regimes."""

    def __init__(self, ds, fmu_dir="fmus"):
        self.ds, self.fmu_dir = ds, str(fmu_dir)
        missing = {e.scenario for e in ds.experiments.values() if e.scenario_path is None}
        if missing:
            raise UserError(f"data set {ds.path}: scenario {sorted(missing)[0]!r} not found (a "
                            ".toml path relative to the manifest, or a name in the scenarios folder)")
        self.scenarios = {name: scenario_mod.load(e.scenario_path, (), e.stop_time)
                          for name, e in ds.experiments.items()}
        first = next(iter(self.scenarios.values()))
        self.vars = _variables(first, fmu_dir)
        self.components = {n: i.component for n, i in first.instances.items()}
        self.units_of = {}
        for col in ds.columns:
            inst, var = split_signal(col)
            v = self.vars.get(inst, {}).get(var)
            if v is None:
                raise UserError(f"data set {ds.path}: column {col!r} is not a variable of scenario "
                                f"{first.name!r} (instances: {', '.join(self.vars)})")
            self.units_of[col] = v.unit or "1"
        self.input_columns = {c for c in ds.columns
                              if self.vars[split_signal(c)[0]][split_signal(c)[1]].causality == "input"}
        for e in ds.experiments.values():
            self.units_of.update({m: mm.unit for m, mm in e.metrics.items()})
        self.scalar_only = ds.scalar_only
        self.part_names = ds.parts()
        fed = {src for src, _ in first.connections} | {dst for _, dst in first.connections}
        # sensor channels no instance reads: compared allowing an acquisition latency
        self.alignable = {c for c in ds.outputs if c not in fed}

    # -- units --------------------------------------------------------------------------------
    def unit(self, name, instances=None, cut_all=False):
        """The `Unit` of `instances` (None: the whole model with the data set's inputs replayed);
        `cut_all` replays every measured signal, even between two of `instances`."""
        ds = self.ds
        if self.scalar_only:
            return self._metric_unit()
        replayed_cols = set(ds.inputs) if instances is None else set(ds.columns)
        runs, observed = [], None
        for ename, e in ds.experiments.items():
            s = self.scenarios[ename]
            if instances is None:
                # everything the observed columns depend on, minus what is replayed
                keep = _closure(s, {split_signal(c)[0] for c in ds.outputs}, replayed_cols)
            else:
                keep = set(instances)
            replay = _replays(s, keep, replayed_cols, self.input_columns & replayed_cols,
                              cut_all=cut_all)
            obs = tuple(c for c in ds.outputs if split_signal(c)[0] in keep and c not in replay)
            observed = obs if observed is None else observed
            t, cols = ds.experiment(ename)
            t0 = t[0]
            red = _span_scenario(_reduce(s, keep, replay, obs), t[-1] - t0)
            grid = t0 + np.arange(red.n_steps + 1) * red.step
            inputs = {dst: np.interp(grid, t, cols[col]) for dst, col in replay.items()}
            part = self._parts(ename, t)
            runs.append(Run(ename, red, inputs, t - t0, {c: cols[c] for c in obs}, part, t0))
        scale, noise = {}, {}
        for c in observed:
            y = np.concatenate([r.measured[c] for r in runs])
            scale[c] = float(np.ptp(y)) or 1.0
            noise[c] = max(np.median([_noise(r.measured[c]) for r in runs]) / scale[c],
                           NOISE_FLOOR)
        keep_all = tuple(sorted(set().union(*(r.scenario.instances for r in runs))))
        return Unit(name, keep_all, observed, runs, scale, noise,
                    {n: self.components[n] for n in keep_all},
                    tuple(c for c in observed if c in self.alignable))

    def _parts(self, ename, t):
        train, held = self.part_names
        part = np.zeros(len(t), dtype=np.int8)
        if self.ds.split.fraction is not None:
            part[np.isin(t, self.ds.experiment(f"{ename}/held_out")[0])] = 1
        elif ename in held:
            part[:] = 1
        return part

    def _metric_unit(self):
        ds, runs = self.ds, []
        held = set(self.part_names[1])
        names = tuple(dict.fromkeys(m for e in ds.experiments.values() for m in e.metrics))
        for ename, e in ds.experiments.items():
            # a metric an experiment lacks is an empty comparison
            measured = {m: np.array([e.metrics[m].value if m in e.metrics else math.nan])
                        for m in names}
            runs.append(Run(ename, self.scenarios[ename], {}, measured=measured,
                            part=np.array([int(ename in held)], dtype=np.int8)))
        scale = {m: float(np.nanmax([abs(r.measured[m][0]) for r in runs])) or 1.0
                 for m in names}
        unc = {m: max((mm.uncertainty or 0.0) for e in ds.experiments.values()
                      for k, mm in e.metrics.items() if k == m) for m in names}
        noise = {m: unc[m] / scale[m] if unc[m] > 0 else METRIC_FLOOR for m in names}
        first = next(iter(self.scenarios.values()))
        return Unit("model", tuple(first.instances), names, runs, scale, noise,
                    dict(self.components))

    def replayed(self):
        """Every instance, every measured signal replayed where it feeds one (loops cut open at
        the measurements; measured physical ports stay coupled, `_replays`): the model in which
        section 4 compares before and after, so that a closed loop's oscillation phase does not
        hide what an effect explains."""
        if self.scalar_only:
            return self._metric_unit()
        return self.unit("all measured signals replayed", sorted(self.components), cut_all=True)

    def isolation_units(self):
        """One unit per distinct isolation closure that observes something, smallest first."""
        if self.scalar_only:
            return []
        ds = self.ds
        s = next(iter(self.scenarios.values()))
        measured = set(ds.columns)
        subjects = {}
        for inst in s.instances:
            subjects.setdefault(frozenset(_closure(s, {inst}, measured)), []).append(inst)
        out = sorted((k for k in subjects if any(
            split_signal(c)[0] in k and c not in _inputs_of(s, k) for c in ds.outputs)),
            key=lambda k: (len(k), sorted(k)))
        return [replace(self.unit(" + ".join(sorted(k)), sorted(k)), subjects=tuple(subjects[k]))
                for k in out]


# ---- simulation and residuals ------------------------------------------------------------------

def _with_values(s, values):
    """Scenario `s` with ``{(instance, parameter): value}`` applied (instances not in `s` skipped)."""
    instances = dict(s.instances)
    for (inst, par), v in values.items():
        if inst in instances:
            old = instances[inst]
            instances[inst] = replace(old, parameters={**old.parameters, par: float(v)})
    return replace(s, instances=instances)


def simulate(unit, values, fmu_dir):
    """Model values of every run of `unit` with parameter `values`: [{column: array}] per run.

    Raises `Failed` when a run fails (the effect's values are then not viable).
    """
    from musclesim.cosim import master, results

    out = []
    for run in unit.runs:
        s = _with_values(run.scenario, values)
        res = master.Master(s, fmu_dir, run.inputs).run()
        if res.error:
            raise Failed(res.error)
        if run.time is None:  # scalar-only: the scenario's metrics
            metrics = results.compute_metrics(res, s.metrics)
            out.append({m: np.array([metrics[m]]) for m in unit.observed})
        else:
            out.append({c: np.interp(run.time, res.time, res[c]) for c in unit.observed})
    return out


class Failed(Exception):
    """A simulation of candidate values failed (reported, not raised to the user)."""


def residuals(unit, sims, shifts=None):
    """Normalised residuals (model - measured) / range: ``{column: [array per run]}``.

    An alignable column (a sensor channel nothing in the model reads) is compared shifted back
    by the whole number of samples, 0..MAX_ALIGN, that fits the training part best: its
    acquisition latency, a nuisance. `shifts`, a dict, receives the samples chosen.
    """
    out = {}
    for c in unit.observed:
        best = None
        for d in range(MAX_ALIGN + 1 if c in unit.alignable else 1):
            res = [(sim[c] - _advance(run.measured[c], d)) / unit.scale[c]
                   for run, sim in zip(unit.runs, sims)]
            cost = sum(float(np.nansum(np.square(r[run.part == 0])))
                       for r, run in zip(res, unit.runs))
            if best is None or cost < best[0]:
                best = (cost, d, res)
        out[c] = best[2]
        if shifts is not None and c in unit.alignable:
            shifts[c] = best[1]
    return out


def _part_rows(unit, part):
    return [run.part == part for run in unit.runs]


def _vector(unit, res, part, columns=None):
    """The residuals of `part` (0 train, 1 held-out) in one vector (a metric a run lacks dropped)."""
    rows = _part_rows(unit, part)
    v = np.concatenate([r[m] for c in columns or unit.observed for r, m in zip(res[c], rows)])
    return v[np.isfinite(v)]


def gap(unit, res, part, columns=None):
    """Pooled gap of `part`: RMS of the normalised residuals (of `columns`, default all)."""
    v = _vector(unit, res, part, columns)
    return float(np.sqrt(np.mean(np.square(v)))) if v.size else math.nan


def deviates(unit, res):
    """Whether some observed signal's held-out gap exceeds DEVIATES times its own noise."""
    return any(gap(unit, res, 1, [c]) > DEVIATES * unit.noise[c] for c in unit.observed)


def noise_floor(unit):
    """Pooled noise floor of the unit's observed columns (normalised)."""
    return math.sqrt(np.mean([unit.noise[c] ** 2 for c in unit.observed]))


# ---- fitting ----------------------------------------------------------------------------------

@dataclass(frozen=True)
class Free:
    """A free parameter: on `instances`, `name` between `lower` and `upper` (absolute values)."""

    instances: tuple
    name: str
    lower: float
    upper: float
    start: float  # its nominal value


def _values(free, x):
    return {(inst, f.name): v for f, v in zip(free, x) for inst in f.instances}


def fit(unit, free, fmu_dir, fixed=None, x0=None):
    """Fit `free` on the training part; return a dict with values, intervals and residuals.

    A coarse scan of the box (5 points per parameter, or the start and the corners' midpoints)
    picks the start of a bounded trust-region least-squares fit in box coordinates [0, 1].
    """
    fixed = dict(fixed or {})
    lo = np.array([f.lower for f in free])
    span = np.array([f.upper - f.lower for f in free])
    cache = {}

    def run(z):
        key = tuple(np.round(z, 12))
        if key not in cache:
            x = lo + span * np.clip(z, 0, 1)
            try:
                sims = simulate(unit, {**fixed, **_values(free, x)}, fmu_dir)
                cache[key] = residuals(unit, sims)
            except Failed:
                cache[key] = None
        return cache[key]

    def train_vector(z):
        res = run(z)
        if res is None:
            return np.full(_train_size(unit), 1e3)
        return _vector(unit, res, 0)

    starts = [np.clip((np.array([f.start for f in free]) - lo) / span, 0, 1)]
    if x0 is not None:
        starts.append(np.clip((np.asarray(x0) - lo) / span, 0, 1))
    grid = np.linspace(0, 1, 5) if len(free) == 1 else np.array([0.1, 0.5, 0.9])
    starts += [np.array(p) for p in itertools.product(grid, repeat=len(free))]
    costs = [float(np.sum(np.square(train_vector(z)))) for z in starts]
    z0 = starts[int(np.argmin(costs))]
    opt = optimize.least_squares(train_vector, z0, bounds=(0, 1), x_scale=1.0,
                                 diff_step=1e-3, max_nfev=12 * len(free) + 8, method="trf")
    z = opt.x  # trust-region steps never end above their start's cost
    x = lo + span * z
    interval = _interval(opt, lo, span)
    res = run(z)
    applicable = len({round(c, 12) for c in costs}) > 1
    return {"x": [float(v) for v in x], "interval": interval, "residuals": res,
            "train_gap": gap(unit, res, 0) if res else math.inf,
            "heldout_gap": gap(unit, res, 1) if res else math.inf,
            "applicable": applicable, "evaluations": len(cache)}


def _train_size(unit):
    return sum(int(np.count_nonzero(m)) for m in _part_rows(unit, 0)) * len(unit.observed)


def _interval(opt, lo, span):
    """95 % intervals from the Jacobian, the residuals' autocorrelation widening them."""
    r, J = opt.fun, opt.jac
    m, n = J.shape
    rho = float(np.corrcoef(r[:-1], r[1:])[0, 1]) if m > 2 and np.std(r) > 0 else 0.0
    inflate = (1 + max(rho, 0)) / max(1 - max(rho, 0), 1e-3)
    s2 = 2 * opt.cost / max(m - n, 1) * inflate
    try:
        cov = s2 * np.linalg.inv(J.T @ J)
        half = 1.96 * np.sqrt(np.clip(np.diag(cov), 0, None))
    except np.linalg.LinAlgError:
        half = np.full(n, np.inf)
    out = []
    for z, h, l, w in zip(opt.x, half, lo, span):
        out.append((float(l + w * max(z - h, 0)), float(l + w * min(z + h, 1))))
    return out


# ---- regimes, gap statistics, bootstrap --------------------------------------------------------

def _smooth_rate(t, y, window=0.25):
    """dy/dt after a centred moving average over about `window` seconds."""
    if len(t) < 3:
        return np.zeros_like(y)
    n = max(1, int(round(window / np.median(np.diff(t)))))
    ys = np.convolve(y, np.ones(n) / n, mode="same") if n > 1 else y
    return np.gradient(ys, t)


def _first(columns, units, want):
    return next((c for c in columns if units.get(c) in want), None)


def regimes(problem, unit):
    """``{regime: [row mask per run]}`` of `effects.REGIMES` that the measured columns define."""
    ds = problem.ds
    if problem.scalar_only:
        return {"all": [np.ones(1, bool) for _ in unit.runs]}
    cols_all = [c for c in ds.outputs] + [c for c in ds.inputs]
    temp = _first(cols_all, problem.units_of, ("K",))
    force = _first(cols_all, problem.units_of, ("N", "Pa"))
    strain = next((c for c in cols_all if split_signal(c)[1] == "strain"), None)
    positions = [c for c in cols_all if problem.units_of[c] == "m"]
    indicators = [c for c in ds.inputs if problem.units_of[c] == "1"
                  and problem.components.get(split_signal(c)[0]) == "FrictionSwitchingInputs"
                  and split_signal(c)[1] != "f_a"]
    force = force or next((c for c in cols_all if split_signal(c)[1] == "f_a"), None)
    pressure = _first(cols_all, problem.units_of, ("Pa",))
    out = {k: [] for k in effects.REGIMES}
    for run in unit.runs:
        t = run.time
        _, cols = ds.experiment(run.experiment)
        n = len(t)
        out["all"].append(np.ones(n, bool))
        out["late"].append(t >= 0.5 * t[-1])
        if temp:
            rate = _smooth_rate(t, cols[temp])
            out["changing"].append(np.abs(rate) > np.median(np.abs(rate)))
            out["heating"].append(rate > 0)
            out["cooling"].append(rate < 0)
            out["hot"].append(cols[temp] >= np.percentile(cols[temp], 80))
        if strain:
            rate = np.abs(_smooth_rate(t, cols[strain]))
            out["transformation"].append(rate > 0.1 * np.percentile(rate, 95))
        if force:
            f = cols[force]
            out["stress_extremes"].append(np.abs(f - np.median(f)) > max(np.std(f), 1e-12))
            out["high_force"].append(f > np.median(f))
            rate = np.abs(_smooth_rate(t, f))
            out["load_changing"].append(rate > np.median(rate))
        if pressure:
            rate = np.abs(_smooth_rate(t, cols[pressure]))
            out["pressure_changing"].append(rate > np.median(rate))
            out["pressurised"].append(cols[pressure] > np.median(cols[pressure]))
        if positions:
            speed = np.max([np.abs(_smooth_rate(t, cols[c], 0.05)) for c in positions], axis=0)
            moving = speed > 0.1 * np.percentile(speed, 95)
            out["slip"].append(moving)
            out["stick"].append(~moving)
        if indicators:
            near = np.zeros(n, bool)
            for c in indicators:
                for ts in t[1:][np.diff(cols[c]) != 0]:
                    near |= (t >= ts) & (t < ts + 0.5)
            out["switching"].append(near)
    return {k: v for k, v in out.items() if len(v) == len(unit.runs)}


def _row_sq(unit, res, part):
    """Per held-out row: the sum over observed columns of the squared normalised residuals."""
    rows = _part_rows(unit, part)
    return [np.nansum([np.square(res[c][i][m]) for c in unit.observed], axis=0)
            for i, m in enumerate(rows)]


def signature(unit, res_nominal, res_effect, regime_masks):
    """Gain of an effect per held-out sample in its regime vs overall: (ratio, consistent)."""
    rows = _part_rows(unit, 1)
    gain = np.concatenate([a - b for a, b in zip(_row_sq(unit, res_nominal, 1),
                                                 _row_sq(unit, res_effect, 1))])
    if regime_masks is None:
        return None, gain.sum() > 0
    mask = np.concatenate([m[r] for m, r in zip(regime_masks, rows)])
    if not mask.any() or gain.sum() <= 0:
        return None, False
    ratio = float(gain[mask].mean() / gain.mean())
    return ratio, ratio >= SIGNATURE_MIN


def _blocks(unit, part=1):
    """Contiguous blocks of held-out rows for the block bootstrap: (run, start, stop) triples."""
    out = []
    for i, m in enumerate(_part_rows(unit, part)):
        idx = np.flatnonzero(m)
        if idx.size:
            for chunk in np.array_split(idx, max(1, min(BLOCKS, idx.size))):
                out.append((i, chunk))
    return out


def bootstrap(unit, residual_sets, columns=None, seed=0):
    """Block-bootstrap resamples of held-out gaps: array [resample, set] for each residual set."""
    blocks = _blocks(unit)
    cols = columns or unit.observed
    sums = np.array([[sum(float(np.nansum(np.square(res[c][i][chunk]))) for c in cols)
                      for res in residual_sets] for i, chunk in blocks])
    counts = np.array([chunk.size * len(cols) for _, chunk in blocks], float)
    rng = np.random.default_rng(seed)
    pick = rng.integers(0, len(blocks), size=(BOOTSTRAP, len(blocks)))
    return np.sqrt(sums[pick].sum(axis=1) / counts[pick].sum(axis=1)[:, None])


def _interval95(samples):
    return [float(np.percentile(samples, 2.5)), float(np.percentile(samples, 97.5))]


def signal_gap(problem, unit, sims):
    """Per observed signal: NRMSE (all, held-out), bias and lag of the model against the data."""
    out = {}
    res = residuals(unit, sims)
    for c in unit.observed:
        meas = np.concatenate([r.measured[c] for r in unit.runs])
        model = np.concatenate([s[c] for s in sims])
        entry = {"nrmse": float(np.sqrt(np.nanmean(np.square(np.concatenate(res[c]))))),
                 "nrmse_heldout": gap(unit, res, 1, [c]),
                 "bias": float(np.nanmean(meas - model)),
                 "unit": problem.units_of.get(c, "1"), "range": unit.scale[c],
                 "noise": unit.noise[c]}
        if not problem.scalar_only:
            entry["lag"] = _lag(unit.runs[0].time, unit.runs[0].measured[c], sims[0][c])
        else:
            entry["relative_error"] = [float((s[c][0] - r.measured[c][0]) / r.measured[c][0])
                                       if r.measured[c][0] else math.nan
                                       for r, s in zip(unit.runs, sims)]
        out[c] = entry
    return out


def _lag(t, meas, model):
    """Shift [s] of the model that best matches the data (positive: the data lags the model)."""
    from scipy import signal

    a, b = meas - np.mean(meas), model - np.mean(model)
    if len(t) < 3 or not np.any(a) or not np.any(b):
        return 0.0
    dt = float(np.median(np.diff(t)))
    corr = signal.correlate(a, b, mode="full", method="fft")
    lags = signal.correlation_lags(len(a), len(b), mode="full")
    window = np.abs(lags) * dt <= 0.1 * (t[-1] - t[0])
    return float(lags[window][np.argmax(corr[window])] * dt)


def worst_windows(unit, res, count=WINDOWS, fraction=0.05):
    """The `count` time windows (a `fraction` of each experiment) with the largest gap."""
    rows = []
    for i, run in enumerate(unit.runs):
        sq = np.nansum([np.square(res[c][i]) for c in unit.observed], axis=0)
        n = max(2, int(len(run.time) * fraction))
        for j in range(0, len(run.time) - n + 1, n):
            rows.append((math.sqrt(sq[j:j + n].mean() / len(unit.observed)), run.experiment,
                         run.t0 + float(run.time[j]), run.t0 + float(run.time[j + n - 1])))
    rows.sort(reverse=True)
    return [{"experiment": e, "t0": a, "t1": b, "gap": g} for g, e, a, b in rows[:count]]


# ---- the diagnosis ----------------------------------------------------------------------------

@dataclass
class Candidate:
    """An effect placed on instances of its component, with its free parameters."""

    effect: object  # effects.Effect
    instances: tuple
    free: list

    @property
    def label(self):
        return self.effect.name + (f" ({self.instances[0]})" if self.effect.per_instance else "")


def _serial(fn, items):
    return [fn(x) for x in items]


def _fit_task(args):
    """One fit, as a Dask task: (unit, free, fmu_dir, fixed, x0) -> fit()."""
    return fit(*args)


def _nominal(problem, unit, inst, name):
    s = unit.runs[0].scenario
    if name in s.instances[inst].parameters:
        return float(s.instances[inst].parameters[name])
    return float(problem.vars[inst][name].start)


def _candidates(problem, unit, suspects):
    out = []
    by_comp = {}
    for inst in suspects:
        if inst in unit.components:
            by_comp.setdefault(unit.components[inst], []).append(inst)
    for comp, insts in by_comp.items():
        for e in effects.by_component(comp):
            groups = [(i,) for i in insts] if e.per_instance else [tuple(insts)]
            for g in groups:
                free = [Free(g, p.name, p.lower, p.upper, _nominal(problem, unit, g[0], p.name))
                        for p in e.parameters]
                out.append(Candidate(e, g, free))
    calib = []
    for comp, insts in by_comp.items():
        for p in effects.CALIBRATION.get(comp, ()):
            nom = _nominal(problem, unit, insts[0], p.name)
            calib.append(Free(tuple(insts), p.name, p.lower * nom, p.upper * nom, nom))
    return out, calib


def _locate(problem, isolated):
    """Suspect instances and the ranked `located` table from the isolation results.

    A unit that matches clears only its subjects (the instances it isolates): its other members
    may act on what it observes too weakly to show (the magnet's force on the temperature).
    """
    deviating = [u for u in isolated if u["deviates"]]
    cleared = set().union(*[set(u["unit"].subjects) for u in isolated if not u["deviates"]])
    suspects = set().union(*[set(u["unit"].instances) for u in deviating]) - cleared
    if deviating and not suspects:  # every member cleared alone: blame the interaction
        suspects = set(deviating[0]["unit"].instances)
    table = []
    for inst in problem.components:
        own = [u for u in isolated if inst in u["unit"].subjects] or \
            [u for u in isolated if inst in u["unit"].instances]
        if not own:
            continue
        u = own[0]  # its own unit, else the smallest holding it
        table.append({"instance": inst, "component": problem.components[inst],
                      "isolated_gap": u["gap"], "noise_floor": u["floor"], "unit": u["unit"].name,
                      "deviates": u["deviates"], "exonerated": inst in cleared,
                      "located": inst in suspects})
    table.sort(key=lambda r: (not r["located"], -r["isolated_gap"]))
    return suspects, table


def diagnose(ds, fmu_dir="fmus", pmap=None, progress=None, traces=None):
    """Diagnose measured data set `ds` (a `musclesim.dataset.DataSet`); return the report dict.

    `pmap(fn, items)` maps the fits (default: one after the other); `progress(text)` is told
    what runs; a dict given as `traces` receives the runs of `Problem.replayed`, nominal and with
    the selected effects, for plots.
    """
    pmap = pmap or _serial
    say = progress or (lambda text: None)
    problem = Problem(ds, fmu_dir)
    whole = problem.unit("model")
    say("nominal model")
    try:
        sims = simulate(whole, {}, fmu_dir)
    except Failed as exc:
        raise UserError(f"data set {ds.path}: the nominal scenario fails: {exc}") from None
    res_whole = residuals(whole, sims)
    floor_whole = noise_floor(whole)
    gap_whole = gap(whole, res_whole, 1)
    whole_deviates = deviates(whole, res_whole)
    report = {
        "data_set": str(ds.path), "scenario": ds.scenario or sorted(
            {e.scenario for e in ds.experiments.values()}), "scalar_only": problem.scalar_only,
        "parts": {"train": list(problem.part_names[0]), "held_out": list(problem.part_names[1])},
        "gap": {"signals": signal_gap(problem, whole, sims), "heldout_gap": gap_whole,
                "noise_floor": floor_whole, "deviates": bool(whole_deviates)},
    }
    say("isolating components")
    isolated = []
    for u in problem.isolation_units():
        try:
            r = residuals(u, simulate(u, {}, fmu_dir))
        except Failed:
            continue
        isolated.append({"unit": u, "gap": gap(u, r, 1), "floor": noise_floor(u),
                         "deviates": deviates(u, r), "res": r})
    suspects, located = _locate(problem, isolated)
    report["located"] = located
    report["units"] = [{"instances": list(u["unit"].instances), "observed": list(u["unit"].observed),
                        "heldout_gap": u["gap"], "noise_floor": u["floor"],
                        "deviates": u["deviates"]} for u in isolated]
    masks = regimes(problem, whole)
    report["regimes"] = _regime_table(whole, res_whole, masks)
    if not whole_deviates and not any(u["deviates"] for u in isolated):
        report.update(effects=[], recalibrated=[], selected=[], verdict="none",
                      explanation="the model matches the data within the noise on the held-out "
                                  "part: there is no gap to explain", noise_floor=floor_whole,
                      complete=True)
        _shrinkage(problem, report, {}, traces)
        return report

    # the unit the candidates are fitted in: the smallest deviating one holding every suspect
    fit_unit, res_nom = whole, res_whole
    if suspects:
        holders = [u for u in isolated if u["deviates"] and suspects <= set(u["unit"].instances)]
        if holders:
            fit_unit, res_nom = holders[0]["unit"], holders[0]["res"]
    else:
        suspects = set(whole.instances)
    report["fit_unit"] = {"instances": list(fit_unit.instances),
                          "observed": list(fit_unit.observed)}
    candidates, calib = _candidates(problem, fit_unit, suspects)
    say(f"fitting {len(candidates)} candidate effect(s) and {len(calib)} recalibration(s)")
    fits = pmap(_fit_task, [(fit_unit, c.free, fmu_dir, None, None) for c in candidates]
                + [(fit_unit, [f], fmu_dir, None, None) for f in calib])
    cand_fits = fits[:len(candidates)]
    recal, recal_table = _recalibrated(fit_unit, res_nom, calib, fits[len(candidates):],
                                       max((len(c.free) for c in candidates), default=1), fmu_dir)
    report["recalibrated"] = recal_table
    floor = noise_floor(fit_unit)
    scored = sorted(((_score(fit_unit, res_nom, c, f, recal, masks), c, f)
                     for c, f in zip(candidates, cand_fits)),
                    key=lambda t: (not t[0]["counts"], t[0]["heldout_gap_after"]))
    entries = [e for e, _, _ in scored]
    for a, b in zip(entries, entries[1:] + [None]):
        a["margin"] = None if b is None else (b["heldout_gap_after"] - a["heldout_gap_after"]) \
            / a["heldout_gap_before"]
    counting = [t for t in scored if t[0]["counts"]]
    selected, final = [], None
    if counting:
        e1, c1, f1 = counting[0]
        selected, final = [e1], f1
        if not _explained(f1["heldout_gap"], e1["heldout_gap_before"], floor) \
                and len(counting) > 1:
            say("greedy: a second effect")
            pairs = counting[1:4]
            pair_fits = pmap(_fit_task, [(fit_unit, c1.free + c.free, fmu_dir, None,
                                          f1["x"] + [fr.start for fr in c.free])
                                         for _, c, _ in pairs])
            (e2, c2, _), f12 = min(zip(pairs, pair_fits), key=lambda t: t[1]["heldout_gap"])
            regime = c2.effect.regime
            _, ok = signature(fit_unit, f1["residuals"], f12["residuals"],
                              None if regime == "all" else masks.get(regime))
            if ok and f12["heldout_gap"] <= (1 - MIN_SHRINKAGE) * f1["heldout_gap"]:
                selected.append(e2)
                e2["joint_values"] = dict(zip([f"{fr.name}" for fr in c1.free + c2.free],
                                              f12["x"]))
                final = f12
    report["effects"] = entries
    report["selected"] = [e["name"] for e in selected]
    report["verdict"], report["explanation"] = _verdict(selected, final, recal, recal_table,
                                                        floor)
    report["complete"] = bool(selected) and _explained(
        final["heldout_gap"], selected[0]["heldout_gap_before"], floor)
    report["noise_floor"] = floor
    _shrinkage(problem, report, _selected_values(report["effects"], report["selected"]),
               traces)
    return report


def _recalibrated(unit, res_nom, calib, calib_fits, k_max, fmu_dir):
    """The nominal model's competitors: {k: held-out gap with k nominal parameters refitted} and
    their table. k = 1 is the best single parameter on held-out data (the strictest rival);
    k = 2 refits the two best on training data together."""
    recal, table = {0: gap(unit, res_nom, 1)}, []
    if not calib_fits:
        return recal, table
    recal[1] = min(f["heldout_gap"] for f in calib_fits)
    table = [{"parameters": {f"{','.join(c.instances)}.{c.name}": f["x"][0]},
              "heldout_gap": f["heldout_gap"]} for c, f in zip(calib, calib_fits)]
    if len(calib) > 1 and k_max > 1:
        pair = [calib[i] for i in np.argsort([f["train_gap"] for f in calib_fits])[:2]]
        f2 = fit(unit, pair, fmu_dir)
        recal[2] = f2["heldout_gap"]
        table.append({"parameters": {f"{','.join(c.instances)}.{c.name}": x
                                     for c, x in zip(pair, f2["x"])},
                      "heldout_gap": f2["heldout_gap"]})
    return recal, table


def _shrinkage(problem, report, values, traces):
    """report["shrinkage"]: the held-out gap per signal of the model with every measured signal
    replayed (`Problem.replayed`), nominal and with `values`; the traces for the plots."""
    unit = problem.replayed()
    nominal = simulate(unit, {}, problem.fmu_dir)
    after = nominal
    if values:
        try:
            after = simulate(unit, values, problem.fmu_dir)
        except Failed:
            pass
    shifts = {}
    report["shrinkage"] = _whole_shrinkage(unit, residuals(unit, nominal),
                                           residuals(unit, after, shifts))
    report["aligned_samples"] = shifts
    if traces is not None:
        traces.update(unit=unit, nominal=nominal, selected=after)


def _verdict(selected, final, recal, recal_table, floor):
    """(verdict, explanation) from the selected effects and the recalibrated rivals."""
    best_recal = min(recal_table, key=lambda r: r["heldout_gap"], default=None)
    if not selected and best_recal and _explained(best_recal["heldout_gap"], recal[0], floor):
        values = ", ".join(f"{k} = {v:.4g}" for k, v in best_recal["parameters"].items())
        return "recalibration", (f"no unmodelled effect is needed: the nominal model with {values} "
                                 f"recalibrated leaves a held-out gap of "
                                 f"{best_recal['heldout_gap']:.3g} (noise floor {floor:.3g})")
    if not selected:
        return "unexplained", ("no candidate effect of the located component(s) shrinks the "
                               "held-out gap enough, beats the recalibrated nominal model and "
                               "shows in its regime")
    first, labels = selected[0], " + ".join(e["label"] for e in selected)
    before, after = first["heldout_gap_before"], final["heldout_gap"]
    if _explained(after, before, floor):
        return first["name"], (f"{labels} shrinks the held-out gap from {before:.3g} to "
                               f"{after:.3g} (noise floor {floor:.3g})")
    if after <= (1 - MOST) * before:
        return first["name"], (f"{labels} explains {1 - after / before:.0%} of the held-out gap "
                               f"({before:.3g} -> {after:.3g}); the rest, {after / floor:.1f} "
                               "noise floors, stays structured: a further difference the "
                               "library does not hold")
    return "unexplained", (f"the best candidate ({labels}) leaves a structured held-out gap of "
                           f"{after:.3g}, {after / floor:.1f} noise floors, of {before:.3g}")


def _explained(after, before, floor):
    """Whether a held-out gap left `after` is unstructured: within STRUCTURED noise floors, or
    at most RESIDUAL_SHARE of the gap `before`."""
    return after <= STRUCTURED * floor or after <= RESIDUAL_SHARE * before


def _selected_values(entries, selected):
    """``{(instance, parameter): value}`` of the selected effects (joint values when refitted)."""
    out = {}
    for e in entries:
        if e["name"] in selected:
            for name, spec in e["parameters"].items():
                out.update({(inst, name): spec["value"] for inst in e["instances"]})
    joint = next((e.get("joint_values") for e in entries if e.get("joint_values")), None)
    if joint:
        for e in entries:
            if e["name"] in selected:
                out.update({(inst, name): joint[name] for name in e["parameters"] if name in joint
                            for inst in e["instances"]})
    return out


def _whole_shrinkage(unit, before, after):
    """Held-out gap per signal and pooled, before and after, with bootstrap intervals."""
    out = {}
    for c in unit.observed:
        b = bootstrap(unit, [before, after], [c])
        out[c] = {"before": gap(unit, before, 1, [c]), "after": gap(unit, after, 1, [c]),
                  "interval_before": _interval95(b[:, 0]), "interval_after": _interval95(b[:, 1])}
    b = bootstrap(unit, [before, after])
    out["all"] = {"before": gap(unit, before, 1), "after": gap(unit, after, 1),
                  "interval_before": _interval95(b[:, 0]), "interval_after": _interval95(b[:, 1])}
    return out


def _score(unit, res_nom, cand, f, recal, masks):
    before = gap(unit, res_nom, 1)
    after = f["heldout_gap"]
    res = f["residuals"]
    k = len(cand.free)
    recal_gap = recal.get(k, recal.get(max(recal)))
    regime = cand.effect.regime
    ratio, consistent = (None, False) if res is None else \
        signature(unit, res_nom, res, masks.get(regime) if regime != "all" else None)
    entry = {"name": cand.effect.name, "label": cand.label, "component": cand.effect.component,
             "instances": list(cand.instances), "spec": cand.effect.spec,
             "parameters": {fr.name: {"value": x, "interval": list(iv), "lower": fr.lower,
                                      "upper": fr.upper, "off": fr.start}
                            for fr, x, iv in zip(cand.free, f["x"], f["interval"])},
             "applicable": f["applicable"], "heldout_gap_before": before,
             "heldout_gap_after": after, "shrinkage": 1 - after / before if before else 0.0,
             "recalibrated_gap": recal_gap,
             "beats_recalibrated": bool(after <= BEAT_RECALIBRATED * recal_gap),
             "signature": {"regime": regime, "gain_ratio": ratio, "consistent": bool(consistent)}}
    if res is not None:
        boot = bootstrap(unit, [res_nom, res])
        entry["interval"] = _interval95(1 - boot[:, 1] / boot[:, 0])
        entry["per_signal"] = {}
        for c in unit.observed:
            b = bootstrap(unit, [res_nom, res], [c])
            entry["per_signal"][c] = {"before": gap(unit, res_nom, 1, [c]),
                                      "after": gap(unit, res, 1, [c]),
                                      "interval_before": _interval95(b[:, 0]),
                                      "interval_after": _interval95(b[:, 1])}
    else:
        entry["interval"] = [0.0, 0.0]
    entry["counts"] = bool(f["applicable"] and res is not None
                           and entry["shrinkage"] >= MIN_SHRINKAGE
                           and entry["beats_recalibrated"] and consistent)
    return entry


def _regime_table(unit, res, masks):
    out = {}
    for key, per_run in masks.items():
        sq = np.concatenate([np.nansum([np.square(res[c][i][m]) for c in unit.observed], axis=0)
                             for i, m in enumerate(per_run)])
        n = sum(int(m.sum()) for m in per_run)
        total = sum(m.size for m in per_run)
        out[key] = {"fraction": n / total if total else 0.0,
                    "gap": math.sqrt(sq.sum() / (n * len(unit.observed))) if n else None,
                    "description": effects.REGIMES[key]}
    return {"by_regime": out, "worst_windows": [] if unit.runs[0].time is None
            else worst_windows(unit, res)}
