"""Fitting free parameters of a unit on the training part: `Free`, `fit` (a `FitJob` run by a
`Fit`, giving a `FitResult`) and its 95 % intervals.

A fit scans the parameters' box coarsely, then runs bounded trust-region least squares from the
best point; it is scored on the held-out part by the caller. `fit_all` runs several fits on a
``pmap``: each as one task (`fit_task`), or, on a map that runs its tasks elsewhere side by side
(Dask's), each steered from a thread here with every simulation a task.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from scipy import optimize

from musclesim.batch import serial_map
from musclesim.cosim import ParamRef, Signal, reuse_fmus

from musclesim.diagnosis.box import axis, period_axis, residual_intervals, scan, step
from musclesim.diagnosis.simulate import Failed, Simulated, residuals, simulate, simulate_many
from musclesim.diagnosis.stats import (HELD_OUT, TRAIN, Part, gap, part_rows, part_segments,
                                       part_vector)
from musclesim.diagnosis.thresholds import (MAX_ITERATIONS, PASSES, STEPS,
                                           TOLERANCE)

if TYPE_CHECKING:
    from musclesim.diagnosis.problem import Unit


@dataclass(frozen=True)
class Free:
    """A free parameter: on `instances`, `name` between `lower` and `upper` (absolute values),
    from its nominal value `start`; periodic with `period` > 0 (a phase, scanned over a whole
    period); the further parameters `also` take the same value.

    >>> f = Free(("w1", "w2"), "h", 50.0, 150.0, 100.0, also=(ParamRef("cap", "h_air"),))
    >>> f.key, [str(r) for r in f.refs]
    ('w1,w2.h', ['w1.h', 'w2.h', 'cap.h_air'])
    """

    instances: tuple[str, ...]
    name: str
    lower: float
    upper: float
    start: float  # its nominal value
    period: float = 0.0  # > 0: periodic (a phase), scanned over a whole period
    also: tuple[ParamRef, ...] = ()  # further parameters that take the same value

    @property
    def refs(self) -> tuple[ParamRef, ...]:
        """Every parameter that takes this value: `name` of each instance, then `also`."""
        return tuple(ParamRef(inst, self.name) for inst in self.instances) + tuple(self.also)

    @property
    def key(self) -> str:
        """Its key in report.json, ``"inst1,inst2.name"`` (printed here only)."""
        return f"{','.join(self.instances)}.{self.name}"


def values_of(free: Sequence[Free], x: Sequence[float]) -> dict[ParamRef, float]:
    """``{ParamRef: value}`` of the `Free` parameters `free` at values `x`."""
    out: dict[ParamRef, float] = {}
    for f, v in zip(free, x):
        out.update(dict.fromkeys(f.refs, v))
    return out


@dataclass(frozen=True)
class FitJob:
    """What `fit` fits: `free` on `unit`'s training part, the other values `fixed`; from `x0`
    (default the nominal values) after a scan of the first `scan` parameters (default all);
    `known` Jacobian columns reused, `latency` held (see `fit`); `train_only`: the result
    has the training residuals at the fitted values and nothing that needs more runs (no
    held-out residuals, no intervals): a profile, where only the cost there counts."""

    unit: Unit
    free: list[Free]
    fmu_dir: Any  # a path, or what the map's tasks carry in its place (`pmap.ship_fmus`)
    fixed: dict[ParamRef, float] | None = None
    x0: list[float] | None = None
    scan: int | None = None
    known: dict[int, np.ndarray] | None = None
    latency: dict[Signal, int] | None = None
    train_only: bool = False


@dataclass(frozen=True)
class FitResult:
    """A fit's outcome: the values `x` with their 95 % `interval`s, the residuals of the whole
    runs there (None when they fail), the gaps on the training and the held-out part, whether
    the parameters change the cost at all (`applicable`), the runs it took, the Jacobian at `x`
    (box coordinates) and the sensor latencies held; `z`, the values in box coordinates, and
    `train`, the training residuals there with those latencies held ({column: [array per
    run]}, `stats.part_segments`; the Jacobian's rows follow them), None when the run failed."""

    x: list[float]
    interval: list[tuple[float, float]]
    residuals: dict[Any, list[np.ndarray]] | None
    train_gap: float
    heldout_gap: float
    applicable: bool
    evaluations: int
    jac: np.ndarray | None
    latency: dict[Signal, int]
    z: np.ndarray | None = None
    train: dict[Any, list[np.ndarray]] | None = None


def fit(unit: Unit, free: list[Free], fmu_dir: Any, fixed: dict[ParamRef, float] | None = None,
        x0: list[float] | None = None, scan: int | None = None,
        known: dict[int, np.ndarray] | None = None, latency: dict[Signal, int] | None = None,
        pmap: Callable[..., list] | None = None) -> FitResult:
    """Fit the `Free` parameters `free` of `unit` (its FMUs in `fmu_dir`) on the training
    part, the other values `fixed`; return the `FitResult`: the values with their 95 %
    intervals, the residuals there, the gaps, the Jacobian and the latencies held.

    A coarse scan of the first `scan` parameters (default all; `box.axis` points each, or
    `PERIOD_POINTS` even ones over a periodic parameter's period; one parameter at a time, then
    the best of each together), the others held at `x0` (default their nominal values), picks
    the start of a bounded trust-region least-squares fit of all of them in box coordinates
    [0, 1]. With ``scan=0`` the fit starts at `x0` (a calibration, or a refinement from it);
    when no scanned point changes the cost at all, the start is the fit (an effect that does
    not apply here, such as stress dependence in a model that keeps it).

    The Jacobian is by forward differences at the start of each least-squares pass and by
    Broyden's rank-one update after every accepted step (one run a step, not one per
    parameter); `known` ({index of a parameter: its column}, box coordinates) reuses columns
    computed before (the calibration's, when an effect is fitted together with it: a
    quasi-Newton start, every step still checked on the true cost). A pass that stopped short
    while its cost was still falling is followed by one from fresh differences (without
    `known` columns, which no pass makes fresh), at most `PASSES` in all. The result's
    ``jac`` and intervals are from differences at the fitted values (`known` columns as
    given), taken again there when the last Jacobian was an update. The sensor channels'
    latencies (`residuals`) are held during each pass: the given `latency` ({column: samples}, a
    calibration's), else chosen again between passes; the result's ``latency`` is the one held
    last. A latency trades against a lag effect on its channel (up to MAX_ALIGN samples of it):
    holding the calibration's while an effect is fitted keeps that trade the same for every
    candidate. Every point of the scan and of least squares is simulated as far as the training
    part reaches (``simulate(..., part=TRAIN)``); only the fitted values are run to the end, for the
    held-out residuals of the result. The points a step needs together (a Jacobian's, a scan's)
    are simulated with `pmap` (default: here, one after the other; the unit sent once where
    ``pmap.share`` can); a pass's first point goes with its differences' runs when together
    they fit on the map's workers at once (``pmap.width()``). Every run is a pure function of
    its point, so the result does not depend on the map.
    """
    return Fit(FitJob(unit, free, fmu_dir, fixed, x0, scan, known, latency), pmap).result()


class Fit:
    """One fit in progress (see `fit`): its runs cached by point, the sensor latencies held, and
    the secant Jacobian of the current least-squares pass. Points are box coordinates [0, 1]."""

    def __init__(self, job, pmap=None):
        self.job, self.free = job, job.free
        self.fixed, self.known = dict(job.fixed or {}), job.known
        self.lo = np.array([f.lower for f in self.free])
        self.span = np.array([f.upper - f.lower for f in self.free])
        self.cache, self.align, self.secant = {}, {}, {}
        self.sent = pmap.share(job.unit) if hasattr(pmap, "share") else job.unit
        self.mapped = pmap or serial_map
        self.width = pmap.width() if hasattr(pmap, "width") else 1  # runs the map makes at once

    # -- runs ---------------------------------------------------------------------------------
    def task(self, x, part):
        """The run of values `x` as `simulation_task` takes it."""
        return self.sent, {**self.fixed, **values_of(self.free, x)}, self.job.fmu_dir, part

    @staticmethod
    def key(z):
        """A point as the cache knows it."""
        return tuple(np.round(z, 12))

    def simulated(self, points, whole=()):
        """Run, mapped together, the training part of each of `points` not run yet and the whole
        runs of the values `whole` (returned, a `Simulated` each)."""
        new: dict[tuple[float, ...], np.ndarray] = {}
        for k, z in ((self.key(z), z) for z in points):
            if k not in self.cache:
                new.setdefault(k, self.lo + self.span * np.clip(z, 0, 1))
        tasks = [self.task(x, None) for x in whole] + [self.task(x, TRAIN) for x in new.values()]
        runs = simulation_batch(tasks) if self.mapped is serial_map else \
            self.mapped(simulation_task, tasks)
        self.cache.update(zip(new, runs[len(whole):]))
        return runs[:len(whole)]

    def run(self, z, free_choice=False):
        """The residuals at `z` (None if its run failed), at the latencies held unless
        `free_choice`."""
        self.simulated([z])
        sims = self.cache[self.key(z)]
        return None if sims.failed else residuals(self.job.unit, sims.runs,
                                                  align=None if free_choice else self.align)

    def latencies(self, z):
        """The sensor latencies that fit best at `z`."""
        chosen: dict[Signal, int] = {}
        if self.run(z, True) is not None:
            residuals(self.job.unit, self.cache[self.key(z)].runs, chosen)
        return chosen

    def train_vector(self, z):
        """The training residual vector at `z` (large where the run failed)."""
        res = self.run(z)
        if res is None:
            return np.full(_train_size(self.job.unit), 1e3)
        return part_vector(self.job.unit, res, TRAIN)

    def cost(self, z):
        """The training cost at `z`, at its best latencies."""
        res = self.run(z, True)
        return 1e6 if res is None else float(np.sum(np.square(part_vector(self.job.unit, res,
                                                                          TRAIN))))

    # -- the Jacobian -------------------------------------------------------------------------
    def differences(self, z):
        """[(column, step, point)] of the Jacobian's unknown columns at `z`."""
        return [(i, step(z[i]), z + np.eye(len(z))[i] * step(z[i])) for i in range(len(z))
                if i not in (self.known or {})]

    def jac(self, z):
        """Finite differences at a pass's start, Broyden's update at each accepted step."""
        f, secant = self.train_vector(z), self.secant
        if secant:
            s, J, fresh = z - secant["z"], secant["J"], secant["fresh"]
            if s.any():
                J, fresh = J + np.outer(f - secant["f"] - J @ s, s) / (s @ s), False
        else:
            J, fresh = self.differenced(z), True
        # still falling: the step to here lowered the cost by more than the tolerance
        falling = "f" in secant and secant["f"] @ secant["f"] - f @ f > TOLERANCE * (
            secant["f"] @ secant["f"])
        secant.update(J=J, z=z.copy(), f=f, falling=falling, fresh=fresh)
        return J

    def differenced(self, z):
        """The Jacobian at `z`: the `known` columns, and differences."""
        steps = self.differences(z)
        self.simulated([p for _, _, p in steps])
        f = self.train_vector(z)
        J = np.empty((f.size, len(z)))
        for i, col in (self.known or {}).items():
            J[:, i] = col
        for i, h, p in steps:
            J[:, i] = (self.train_vector(p) - f) / h
        return J

    def trial(self, z):
        """Least squares' residual vector at `z`; at a pass's start the runs of the Jacobian's
        differences go beside it when together they take no more than the map runs at once
        (the Jacobian follows unless the start fails)."""
        steps = self.differences(z)
        if not self.secant and 1 + len(steps) <= self.width:
            self.simulated([z] + [p for _, _, p in steps])
        return self.train_vector(z)

    # -- the fit ------------------------------------------------------------------------------
    def start(self):
        """(the point least squares starts from, applicable) after the scan."""
        job, free = self.job, self.free
        count = len(free) if job.scan is None else job.scan
        base = np.clip((np.array(job.x0 if job.x0 is not None else [f.start for f in free])
                        - self.lo) / self.span, 0, 1)
        if not count:
            return base, True
        axes = [axis(base[i]) if not free[i].period else
                period_axis(base[i], free[i].period / self.span[i]) for i in range(count)]
        return scan(base, axes, self.cost, self.simulated)

    def least_squares(self, z):
        """(point, Jacobian) after the passes of least squares from `z` with the sensor
        latencies held (the residuals then move smoothly with the parameters): the given
        `latency`, else chosen again after each pass. A pass that stopped short, its cost
        still falling at its last accepted step (its steps shrank to nothing under an updated
        Jacobian, or its evaluations ran out), goes on from fresh differences; columns given as
        `known` are not fresh in any pass, so such a fit takes no second pass for that (its
        refinement, `candidates.refine`, has none)."""
        J, latency = None, self.job.latency
        for _ in range(PASSES):
            self.align.clear()
            self.align.update(self.latencies(z) if latency is None else latency)
            self.secant.clear()
            opt = optimize.least_squares(self.trial, z, jac=self.jac, bounds=(0, 1),
                                         x_scale=1.0, ftol=TOLERANCE, xtol=TOLERANCE,
                                         method="trf",
                                         max_nfev=max(MAX_ITERATIONS, STEPS * len(self.free)))
            z, J = opt.x, opt.jac  # never above the start
            short = not self.known and self.secant["falling"] and opt.status in (0, 3)
            if not short and (latency is not None or self.latencies(z) == self.align):
                break
        return z, J

    def result(self):
        """The `FitResult`: the fitted values run over the whole runs, held-out part included;
        beside them, when the Jacobian was last updated by Broyden's formula (exact only along
        the steps taken), the runs of fresh differences there: the intervals and what reads
        ``jac`` (the collinearity of an effect with the calibration) take the sensitivities at
        the fitted values."""
        z, applicable = self.start()
        J = None
        if applicable:
            z, J = self.least_squares(z)
        x = self.lo + self.span * z
        if self.job.train_only:
            res = self.run(z)
            return FitResult([float(v) for v in x], [], None,
                             math.inf if res is None else gap(self.job.unit, res, TRAIN),
                             math.inf, applicable,
                             len(self.cache), J, dict(self.align), z,
                             None if res is None else part_segments(self.job.unit, res, TRAIN))
        chosen = dict(self.align) if self.align else self.latencies(z)
        interval = [(float(a), float(a + w)) for a, w in zip(self.lo, self.span)]
        refresh = J is not None and not (self.secant["fresh"]
                                         and np.array_equal(self.secant["z"], z))
        sims = self.simulated([p for _, _, p in self.differences(z)] if refresh else [],
                              whole=[x])[0]
        if refresh:
            J = self.differenced(z)
        if J is not None:
            interval = residual_intervals(self.train_vector(z), J, z, self.lo, self.span)
        res = None if sims.failed else residuals(self.job.unit, sims.runs)
        held = self.run(z) if self.align else None  # the Jacobian's residuals
        train = part_segments(self.job.unit, held if held is not None else res, TRAIN) \
            if res is not None else None
        return FitResult([float(v) for v in x], interval, res,
                         gap(self.job.unit, res, TRAIN) if res else math.inf,
                         gap(self.job.unit, res, HELD_OUT) if res else math.inf,
                         applicable, len(self.cache) + 1, J, chosen, z, train)


def known_columns(jac: np.ndarray | None, k: int) -> dict[int, np.ndarray] | None:
    """A calibration's Jacobian `jac` as `fit`'s ``known`` for a fit whose first `k` parameters
    are effects' and the rest that calibration's (None: nothing known)."""
    return None if jac is None else {k + i: jac[:, i] for i in range(jac.shape[1])}


def fit_all(jobs: Iterable[FitJob], pmap: Callable[..., list]) -> list[FitResult]:
    """The `FitResult` of every `FitJob` of `jobs`, in order.

    A `pmap` that runs its tasks elsewhere and may be called from several threads at once
    (``pmap.concurrent``, as `musclesim.batch.dask_map`'s) gets every simulation of every fit as
    a task, the fits steered side by side from threads of this process (which run no
    simulation): the runs of a Jacobian spread over the workers, and a long fit no longer holds
    one worker while the others wait. Any other map runs each fit whole as one task
    (`fit_task`). The results are the same either way.
    """
    jobs = list(jobs)
    if not getattr(pmap, "concurrent", False) or not jobs:
        return pmap(fit_task, jobs)
    pool = ThreadPoolExecutor(len(jobs), thread_name_prefix="musclesim-fit")
    try:
        return list(pool.map(lambda job: Fit(job, pmap).result(), jobs))
    finally:  # interrupted: not waiting for the fits (their next task fails once the map's
        # client is closed)
        pool.shutdown(wait=False, cancel_futures=True)


def fit_task(job: FitJob) -> FitResult:
    """One fit, as a task: `FitJob` -> `FitResult`, its FMUs read and unpacked once for all its
    runs."""
    with reuse_fmus():
        return Fit(job).result()


def simulation_task(args: tuple[Unit, dict[ParamRef, float], Any, Part | None]) -> Simulated:
    """One run of a fit, as a task: `args` (unit, values, fmu_dir, part) -> a `Simulated`,
    `simulate`'s runs or the message of the failure that stopped them (FMUs reused as
    `reuse_fmus` allows: a worker of `musclesim.batch.dask_client` keeps them for its life)."""
    unit, values, fmu_dir, part = args
    with reuse_fmus():
        try:
            return Simulated(simulate(unit, values, fmu_dir, part=part))
        except Failed as exc:
            return Simulated(None, str(exc))


def simulation_batch(tasks: list[tuple[Unit, dict[ParamRef, float], Any, Part | None]]
                     ) -> list[Simulated]:
    """`simulation_task` of each of `tasks`, in this process: those of one unit, FMU folder and
    part simulated together (`simulate_many`: the cases of a run in one pass)."""
    groups: dict[tuple[int, str, Part | None], list[int]] = {}
    for i, (unit, _, fmu_dir, part) in enumerate(tasks):
        groups.setdefault((id(unit), str(fmu_dir), part), []).append(i)
    out: list[Simulated | None] = [None] * len(tasks)
    with reuse_fmus():
        for members in groups.values():
            unit, _, fmu_dir, part = tasks[members[0]]
            sims = simulate_many(unit, [tasks[i][1] for i in members], fmu_dir, part)
            for i, sim in zip(members, sims):
                out[i] = sim
    return [sim for sim in out if sim is not None]


def _train_size(unit):
    return sum(int(np.count_nonzero(m)) for m in part_rows(unit, TRAIN)) * len(unit.observed)


