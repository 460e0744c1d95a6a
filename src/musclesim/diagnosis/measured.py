"""A measured data set as values: `DataSet` and the manifest's tables (`Experiment`,
`MeasuredMetric`, `OpenValue`, `Split`), with the file names of the format.

What the files hold and how they are read and checked: `musclesim.diagnosis.dataset` (loading,
writing), `musclesim.diagnosis.manifest` (the format's checks) and
`musclesim.diagnosis.modelcheck` (the check against the model).
"""
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from musclesim.cosim import FORMAT, load_scenario
from musclesim.errors import UserError

MANIFEST = "manifest.toml"
DATA = "data.csv"
PARTS = ("train", "held_out")


@dataclass(frozen=True)
class MeasuredMetric:
    """One measured scalar: its value, unit and (optional) standard uncertainty, same unit."""

    value: float
    unit: str = "1"
    uncertainty: float = None
    description: str = ""


@dataclass(frozen=True)
class Experiment:
    """A named experiment: its time span in data.csv (None if scalar-only), scenario, metrics."""

    name: str
    span: tuple = None  # (t0, t1) [s], closed
    scenario: str = ""  # reference as written in the manifest
    scenario_path: Path = None  # the resolved scenario file, None if not found
    metrics: dict = field(default_factory=dict)  # name -> MeasuredMetric
    description: str = ""
    stop_time: float = None  # scalar-only: how long the model runs (None: the scenario's)
    conditions: dict = field(default_factory=dict)  # this experiment's own bench conditions


@dataclass(frozen=True)
class OpenValue:
    """A value the data set asks `musclesim calibrate` to fit: one value for every parameter
    in `targets` ("instance.parameter"), within (`lower`, `upper`), and why it is open."""

    targets: tuple
    lower: float
    upper: float
    why: str = ""


@dataclass(frozen=True)
class Split:
    """Training and held-out parts: by experiment names, or the last `fraction` of each in time."""

    train: tuple = ()
    held_out: tuple = ()
    fraction: float = None  # set for a split blocked in time


@dataclass
class DataSet:
    """A checked measured data set (see the module docstring for the format).

    ``time`` and ``data[i, j]`` (column ``columns[j]``) are None for a scalar-only set. ``units``
    maps every column to its unit: the manifest's, else the model's (read from the scenario's FMUs
    whenever they can be read, and required by the model check), else None (SI assumed);
    ``condition_units`` the model's unit of each condition, where known.
    """

    path: Path
    scenario: str
    scenario_path: Path
    inputs: tuple
    outputs: tuple
    units: dict
    experiments: dict  # name -> Experiment
    split: Split
    time: np.ndarray = None
    columns: tuple = ()
    data: np.ndarray = None
    description: str = ""
    reference: str = ""
    conditions: dict = field(default_factory=dict)  # "instance.variable" -> known constant value
    condition_units: dict = field(default_factory=dict)  # the model's unit of each condition
    calibrate: tuple = ()  # the open values `musclesim calibrate` fits (`OpenValue` each)
    # experiment -> its Scenario, loaded with the conditions (`loaded`): a data set that carries
    # them is diagnosed where the scenario files are not (a Dask worker of another machine)
    scenarios: dict = None
    format: int = FORMAT  # the manifest's format (1: the port names before format 2)

    @property
    def scalar_only(self):
        """True when the set holds metrics but no time series."""
        return self.time is None

    def __getitem__(self, column):
        return self.data[:, self.columns.index(column)]

    def scenario_of(self, experiment):
        """The Scenario experiment `experiment` runs: the one the set carries, else its file
        loaded with the bench conditions and the experiment's stop time."""
        if self.scenarios is not None:
            return self.scenarios[experiment]
        e = self.experiments[experiment]
        return load_scenario(e.scenario_path, self.overrides(experiment), e.stop_time)

    def loaded(self):
        """This data set carrying its experiments' scenarios (`scenario_of`), to be diagnosed
        without their files."""
        return replace(self, scenarios={name: self.scenario_of(name) for name in self.experiments})

    def overrides(self, experiment=None):
        """The bench conditions as scenario overrides (``"instance.variable=value"``), with
        those of the experiment named `experiment` after the set's."""
        own = self.experiments[experiment].conditions if experiment else {}
        return [f"{name}={value!r}" for name, value in {**self.conditions, **own}.items()]

    def parts(self):
        """Names of the training and the held-out parts: two tuples of names for `experiment`."""
        if self.split.fraction is None:
            return self.split.train, self.split.held_out
        return tuple(tuple(f"{e}/{part}" for e in self.experiments) for part in PARTS)

    def experiment(self, name):
        """Time and ``{column: values}`` of an experiment or a part named by `parts`.

        Raises
        ------
        UserError
            If the name is unknown or the set has no time series.
        """
        if self.scalar_only:
            raise UserError(f"data set {self.path} is scalar-only (no {DATA}); experiment "
                            f"{name!r} has metrics only: {sorted(self.experiments)}")
        base, _, part = name.partition("/")
        known = list(self.experiments)
        if self.split.fraction is not None:
            known += [n for pair in self.parts() for n in pair]
        if base not in self.experiments or (part and (part not in PARTS
                                                      or self.split.fraction is None)):
            raise UserError(f"data set {self.path} has no experiment {name!r} "
                            f"(known: {', '.join(known)})")
        rows = part_mask(self.time, self.experiments[base].span, part, self.split.fraction)
        return self.time[rows], {c: self.data[rows, j] for j, c in enumerate(self.columns)}


def part_mask(time, span, part="", fraction=None):
    """Rows of `time` in `span` (closed), or in its training / held-out part."""
    t0, t1 = span
    rows = (time >= t0) & (time <= t1)
    if part:
        cut = t1 - fraction * (t1 - t0)
        rows &= (time < cut) if part == "train" else (time >= cut)
    return rows

