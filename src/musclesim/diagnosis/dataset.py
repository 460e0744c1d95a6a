"""Measured data sets for the sim-to-real gap diagnosis: the format, loading, validation, writing.

A measured data set is a directory holding ``manifest.toml`` and, for time series, ``data.csv``
in the format of a run's ``results.csv``; the manifest names the scenario, the replayed input and
observed output columns, optional units, known bench conditions (``[conditions]``: constant
values of the model's parameters or of inputs nothing in the scenario feeds, such as the ambient
temperature ``"wire.T_amb" = 298.15``), the experiments (named time spans) and the split into
training and held-out parts; a scalar-only set has metrics per experiment instead of data.csv.
A condition that varies is replayed as an input column instead.
The format with examples: the user guide's data-set page (§data-sets).

Inside musclesim the addresses are typed: data.csv's header is parsed once, at load, into
`musclesim.cosim.Signal`s (the columns, inputs and outputs), the conditions and open values name
`musclesim.cosim.ParamRef`s, and `write` prints them back with ``str()``.

Validation reports every problem at once in one `musclesim.errors.UserError`, each naming its
file (and line, column or experiment): malformed TOML or CSV, missing or unknown columns,
duplicated or non-increasing time, NaN/inf, spans outside the data or overlapping, a split that
names unknown experiments or leaves a part empty. Wherever the scenario and its FMUs can be read,
every unit given must equal the model's, and a column or condition in kelvin whose values are
degrees Celsius is refused. A scenario reference that is not found is a problem only when
checking against the model (``check_model=True``: the scenarios may not exist yet when the data
are recorded); then every column must also be a variable of the scenario's instances and every
metric a metric of the scenario.

Examples
--------
>>> import tempfile, pathlib
>>> d = pathlib.Path(tempfile.mkdtemp())
>>> _ = (d / "data.csv").write_text("time,a.x\\n0,1\\n1,2\\n2,4\\n3,8\\n")
>>> _ = (d / "manifest.toml").write_text('scenario = "s"\\noutputs = ["a.x"]\\n'
...                                      '[split]\\nheld_out_fraction = 0.5\\n')
>>> ds = load(d)
>>> ds.parts()
(('all/train',), ('all/held_out',))
>>> ds.experiment("all/held_out")[0]
array([2., 3.])
"""
from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from musclesim.cosim import FORMAT, ParamRef, Signal, read_time_series
from musclesim.diagnosis import modelcheck
from musclesim.diagnosis.manifest import build, find_scenario, read_manifest
from musclesim.diagnosis.measured import (DATA, MANIFEST, DataSet, Experiment, MeasuredMetric,
                                          OpenValue, Split)
from musclesim.errors import UserError

# the format's names, kept where they were before the split (``dataset.MeasuredMetric``, ...)
__all__ = ["load", "write", "find_scenario", "DataSet", "Experiment", "MeasuredMetric",
           "OpenValue", "Split", "MANIFEST", "DATA", "COLDEST_KELVIN"]
COLDEST_KELVIN = modelcheck.COLDEST_KELVIN


def load(path: str | Path, check_model: bool = False, fmu_dir: str | Path = "fmus",
         scenarios_dir: str | Path | None = None,
         models: Mapping[str, str] | None = None) -> DataSet:
    """Read and check the measured data set in directory `path` (or its manifest.toml).

    Parameters
    ----------
    path : str or Path
        The data set's directory (holding manifest.toml and, for time series, data.csv).
    check_model : bool
        Also check against the scenario and its FMUs: the scenario must exist, columns must be
        variables of its instances, metrics must be its metrics, units must equal the model's.
    fmu_dir : str or Path
        Folder of built FMUs, used when `check_model`.
    scenarios_dir : str or Path, optional
        Where scenario names are looked up (see `find_scenario`).
    models : dict, optional
        ``{experiment: scenario}`` replacing the manifest's models, ``"*"`` for every experiment
        (the same data against another model, e.g. the ideal-actuation crawler). A reference
        ending in ``.toml`` is a path from the current folder, else a name in `scenarios_dir`.

    Returns
    -------
    DataSet

    Raises
    ------
    UserError
        Naming the data set and every problem found.
    """
    path = Path(path)
    if path.name == MANIFEST and path.is_file():
        path = path.parent
    manifest_path = path / MANIFEST
    if not path.is_dir():
        raise UserError(f"data set {path} is not a directory")
    problems: list[str] = []
    manifest = read_manifest(manifest_path, problems)
    data_path = path / DATA
    table = read_time_series(data_path, problems, DATA) if data_path.is_file() else None
    ds = None
    if manifest is not None:
        ds = build(path, manifest, table, data_path.is_file(), scenarios_dir, problems)
    if ds is not None and models:
        ds = _with_models(ds, models, scenarios_dir, problems)
    if ds is not None and check_model:
        modelcheck.check_model(ds, fmu_dir, problems)
    elif ds is not None:
        modelcheck.check_units(ds, fmu_dir, problems)
    if ds is not None:
        modelcheck.check_kelvin(ds, problems)
    if problems:
        raise UserError(f"data set {path} has {len(problems)} problem(s): " + "; ".join(problems))
    assert ds is not None, "a data set not built has its problems"
    return ds


def _with_models(ds: DataSet, models: Mapping[str, str], scenarios_dir: str | Path | None,
                 problems: list[str]) -> DataSet:
    """`ds` with the experiments' scenarios replaced by `models` (see `load`)."""
    for name in sorted(set(models) - set(ds.experiments) - {"*"}):
        problems.append(f"model for experiment {name!r}: the data set has no such experiment "
                        f"(experiments: {', '.join(ds.experiments)})")
    experiments = {}
    for name, e in ds.experiments.items():
        ref = models.get(name, models.get("*"))
        if ref is not None:
            path = Path(ref) if ref.endswith(".toml") else \
                find_scenario(ref, ds.path, scenarios_dir)
            e = replace(e, scenario=ref, scenario_path=path if path and path.is_file() else None)
        experiments[name] = e
    return replace(ds, experiments=experiments)


def write(path: str | Path, time: np.ndarray, cols: Mapping[Signal, np.ndarray],
          inputs: Sequence[Signal], outputs: Sequence[Signal], scenario_ref: str,
          description: str = "", conditions: Mapping[ParamRef, float] | None = None,
          held_out_fraction: float = 0.35) -> None:
    """Write a measured data set in folder `path`, the format `load` reads.

    Parameters
    ----------
    path : str or Path
        The data set's folder (made if missing).
    time : numpy.ndarray
        The samples' times [s].
    cols : mapping of Signal to numpy.ndarray
        The recorded columns, each as long as `time`; those in `inputs` and `outputs` are written.
    inputs, outputs : sequence of Signal
        The replayed and the observed columns, in data.csv's order (headers ``str(signal)``).
    scenario_ref : str
        The manifest's scenario: a name, or a path ending in ``.toml``.
    description : str
        The manifest's description.
    conditions : mapping of ParamRef to float, optional
        The bench conditions the set states (its ``[conditions]`` table).
    held_out_fraction : float
        The last this much of the data is held out.
    """
    path = Path(path)
    path.mkdir(parents=True, exist_ok=True)
    names = [*inputs, *outputs]
    np.savetxt(path / DATA, np.column_stack([time] + [cols[c] for c in names]),
               delimiter=",", header=",".join(["time", *map(str, names)]), comments="",
               fmt="%.9g")
    lines = [f"format = {FORMAT}", f"description = {json.dumps(description)}",
             f"scenario = {json.dumps(scenario_ref)}",
             f"inputs = {json.dumps([str(s) for s in inputs])}",
             f"outputs = {json.dumps([str(s) for s in outputs])}", "",
             "[split]", f"held_out_fraction = {held_out_fraction}", ""]
    if conditions:
        lines += ["[conditions]"] + [f"{json.dumps(str(k))} = {float(v)!r}"
                                     for k, v in conditions.items()] + [""]
    (path / MANIFEST).write_text("\n".join(lines))
