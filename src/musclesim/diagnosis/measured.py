"""A measured data set as values: `DataSet` and the manifest's tables (`Experiment`,
`MeasuredMetric`, `OpenValue`, `Split`), with the file names of the format.

The data set's addresses are typed: its columns are `Signal`s (data.csv's header parsed once, at
load), its bench conditions and open values name `ParamRef`s; `DataSet.values` gives the stated
values to apply with `musclesim.cosim.with_values`. What the files hold and how they are read and
checked: `musclesim.diagnosis.dataset` (loading, writing), `musclesim.diagnosis.manifest` (the
format's checks) and `musclesim.diagnosis.modelcheck` (the check against the model).
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from musclesim.cosim import FORMAT, ParamRef, Scenario, Signal, load_scenario, with_values
from musclesim.errors import UserError

MANIFEST = "manifest.toml"
DATA = "data.csv"
PARTS = ("train", "held_out")


@dataclass(frozen=True)
class MeasuredMetric:
    """One measured scalar: its value, unit and (optional) standard uncertainty, same unit."""

    value: float
    unit: str = "1"
    uncertainty: float | None = None
    description: str = ""


@dataclass(frozen=True)
class Experiment:
    """A named experiment: its time span in data.csv (None if scalar-only), scenario, metrics."""

    name: str
    span: tuple[float, float] | None = None  # (t0, t1) [s], closed
    scenario: str = ""  # reference as written in the manifest
    scenario_path: Path | None = None  # the resolved scenario file, None if not found
    metrics: dict[str, MeasuredMetric] = field(default_factory=dict)
    description: str = ""
    stop_time: float | None = None  # scalar-only: how long the model runs (None: the scenario's)
    conditions: dict[ParamRef, float] = field(default_factory=dict)  # its own bench conditions


@dataclass(frozen=True)
class OpenValue:
    """A value the data set asks `musclesim calibrate` to fit: one value for every parameter
    in `targets`, within (`lower`, `upper`), and why it is open."""

    targets: tuple[ParamRef, ...]
    lower: float
    upper: float
    why: str = ""


@dataclass(frozen=True)
class Split:
    """Training and held-out parts: by experiment names, or the last `fraction` of each in time."""

    train: tuple[str, ...] = ()
    held_out: tuple[str, ...] = ()
    fraction: float | None = None  # set for a split blocked in time


@dataclass
class DataSet:
    """A checked measured data set (see `musclesim.diagnosis.dataset` for the format).

    ``time`` and ``data[i, j]`` (column ``columns[j]``) are None for a scalar-only set. ``units``
    maps every column to its unit: the manifest's, else the model's (read from the scenario's FMUs
    whenever they can be read, and required by the model check), else None (SI assumed);
    ``condition_units`` the model's unit of each condition, where known.
    """

    path: Path
    scenario: str
    scenario_path: Path | None
    inputs: tuple[Signal, ...]
    outputs: tuple[Signal, ...]
    units: dict[Signal, str | None]
    experiments: dict[str, Experiment]
    split: Split
    time: np.ndarray | None = None
    columns: tuple[Signal, ...] = ()
    data: np.ndarray | None = None
    description: str = ""
    reference: str = ""
    conditions: dict[ParamRef, float] = field(default_factory=dict)  # known constant values
    condition_units: dict[ParamRef, str] = field(default_factory=dict)  # the model's, where known
    calibrate: tuple[OpenValue, ...] = ()  # the open values `musclesim calibrate` fits
    # experiment -> its Scenario, loaded with the conditions (`loaded`): a data set that carries
    # them is diagnosed where the scenario files are not (a Dask worker of another machine)
    scenarios: dict[str, Scenario] | None = None
    format: int = FORMAT  # the manifest's format (1: the port names before format 2)

    @property
    def scalar_only(self) -> bool:
        """True when the set holds metrics but no time series."""
        return self.time is None

    def __getitem__(self, column: Signal) -> np.ndarray:
        """The values of data.csv's column `column` (a time series set's)."""
        assert self.data is not None, "a scalar-only set has no columns"
        return self.data[:, self.columns.index(column)]

    def scenario_of(self, experiment: str) -> Scenario:
        """The Scenario experiment `experiment` runs: the one the set carries, else its file
        loaded with the experiment's stop time and the bench conditions (`values`) set."""
        if self.scenarios is not None:
            return self.scenarios[experiment]
        e = self.experiments[experiment]
        assert e.scenario_path is not None, f"experiment {experiment!r} has no scenario file"
        return with_values(load_scenario(e.scenario_path, (), e.stop_time),
                           self.values(experiment))

    def loaded(self) -> DataSet:
        """This data set carrying its experiments' scenarios (`scenario_of`), to be diagnosed
        without their files."""
        return replace(self, scenarios={name: self.scenario_of(name) for name in self.experiments})

    def values(self, experiment: str | None = None) -> dict[ParamRef, float]:
        """The bench conditions the set states, with those of the experiment named `experiment`
        after (over) the set's: the values to apply with `musclesim.cosim.with_values`."""
        own = self.experiments[experiment].conditions if experiment else {}
        return {**self.conditions, **own}

    def parts(self) -> tuple[tuple[str, ...], tuple[str, ...]]:
        """Names of the training and the held-out parts: two tuples of names for `experiment`."""
        if self.split.fraction is None:
            return self.split.train, self.split.held_out
        train, held_out = (tuple(f"{e}/{part}" for e in self.experiments) for part in PARTS)
        return train, held_out

    def experiment(self, name: str) -> tuple[np.ndarray, dict[Signal, np.ndarray]]:
        """Time and ``{column: values}`` of the experiment or the part named `name` (see
        `parts`).

        Raises
        ------
        UserError
            If the name is unknown or the set has no time series.
        """
        if self.time is None or self.data is None:
            raise UserError(f"data set {self.path} is scalar-only (no {DATA}); experiment "
                            f"{name!r} has metrics only: {sorted(self.experiments)}")
        base, _, part = name.partition("/")
        known = list(self.experiments)
        if self.split.fraction is not None:
            known += [n for pair in self.parts() for n in pair]
        span = self.experiments[base].span if base in self.experiments else None
        if span is None or (part and (part not in PARTS or self.split.fraction is None)):
            raise UserError(f"data set {self.path} has no experiment {name!r} "
                            f"(known: {', '.join(known)})")
        rows = part_mask(self.time, span, part, self.split.fraction)
        return self.time[rows], {c: self.data[rows, j] for j, c in enumerate(self.columns)}


def part_mask(time: np.ndarray, span: tuple[float, float], part: str = "",
              fraction: float | None = None) -> np.ndarray:
    """Rows of `time` in `span` (closed), or in its `part` ("train" or "held_out", the last
    `fraction` of the span held out; "" for the whole span)."""
    t0, t1 = span
    rows = (time >= t0) & (time <= t1)
    if part:
        assert fraction is not None, "a part needs the held-out fraction"
        cut = t1 - fraction * (t1 - t0)
        rows &= (time < cut) if part == "train" else (time >= cut)
    return rows
