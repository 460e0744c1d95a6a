"""`musclesim identify`: FORC surfaces from the recorded identification experiments
(§forc-identification).

Input: the records of ``scenarios/sma-forc-identification.toml`` at several constant stresses (the
case folders of a sweep, each with results.csv and summary.json). Per stress level the
`ForcReference` markers cut the record into the runs j = 0..n-1; run j heats from b0 to its peak
a_j and cools back. Its descending branch holds every reversal curve with peak a_j, so for every
grid b <= a_j (§forc-identification, no differentiation of data):

    F(a_j, b) = strain at the peak  -  strain on the descending branch where the measured
                temperature first reaches b (linear interpolation between samples)

The peak is the sample of the highest measured temperature of the run; the branch is the run
after it, reduced to the samples where the measured temperature reaches a new minimum (the
Preisach memory ignores a rise back below the running minimum). The stress of a level is the mean
of the recorded stress, which must be constant, rounded to `STRESS_ROUND`. The surfaces are written
as a FORC data file (`musclesim.components.sma.forcfile`): grid, stresses in Pa, temperatures in C,
strain dimensionless.

Records that cannot give a surface are refused with a `UserError` naming the file, column or run:
a missing column, a run without samples, a run whose measured maximum stays more than `PEAK_TOL`
below its peak, a descending branch that rises more than `RISE_TOL` above its running minimum or
stops more than `END_TOL` above a grid temperature, a stress that is not constant, two records at
one stress, and identified values that break the monotonicity of a FORC surface.

Validation on the virtual bench (§forc-identification) lives in `musclesim.hysteresis.validation`.
"""
from __future__ import annotations

import json
import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterable, Sequence

import numpy as np

from musclesim.cosim import Signal, read_time_series
from musclesim.errors import UserError
from musclesim.hysteresis import validation

if TYPE_CHECKING:
    from musclesim.components.sma.surface import Hypersurface

ZERO_C = 273.15  # K
# recorded signals the identification reads (scenario sma-forc-identification)
# (the phase flag reference.phase is recorded for plots; the peak is the measured maximum)
COLUMNS = {"temperature": Signal("thermocouple", "T_meas"), "strain": Signal("wire", "strain"),
           "stress": Signal("wire", "stress"), "run": Signal("reference", "run")}
PEAK_TOL = 0.5  # K, a run whose measured maximum stays further below a_j never reached its peak
RISE_TOL = 0.5  # K, allowed rise of the descending branch above its running minimum (ripple)
END_TOL = 0.5  # K, the branch may stop this far above a grid b (b0: nothing transforms there)
STRESS_ROUND = 1e3  # Pa, identified stresses are rounded to this
STRESS_REL_TOL = 1e-6  # the recorded stress may vary by this fraction of its mean (constant load)


@dataclass
class Record:
    """One constant-stress identification record.

    Attributes: ``path`` (results.csv), ``time`` [s], ``T`` measured temperature [C], ``strain``,
    ``stress`` [Pa] and ``run`` (index, -1 outside the runs) arrays, ``temps`` [C], the grid of
    the runs' peaks (a_j = temps[j]), and ``columns``, the recorded signal names read.
    """

    path: Path
    time: np.ndarray
    T: np.ndarray
    strain: np.ndarray
    stress: np.ndarray
    run: np.ndarray
    temps: np.ndarray
    columns: dict[str, Signal]


def grid_from_parameters(params: dict[str, float]) -> np.ndarray:
    """Peak grid [C] of a ForcReference with the (partial) parameters `params` (defaults:
    §forc-identification).

    Examples
    --------
    >>> g = grid_from_parameters({"T_step": 25.0})
    >>> g.tolist()
    [30.0, 55.0, 80.0, 105.0, 130.0]
    """
    from musclesim.components.sources.forc import ForcParams

    known = ForcParams.__dataclass_fields__
    p = ForcParams(**{k: float(v) for k, v in params.items() if k in known})
    p.check()
    return np.round(np.array([p.T_low + j * p.T_step for j in range(p.n_runs)]) - ZERO_C, 9)


def find_records(paths: str | Path | Iterable[str | Path]) -> list[Path]:
    """The results.csv files behind `paths`: run folders, results.csv files, or a sweep's output
    folder (every ``cases/*/``, in name order).

    Raises
    ------
    UserError
        For a path with no record, or a sweep case that did not complete.
    """
    if isinstance(paths, (str, Path)):
        paths = [paths]
    found: list[Path] = []
    for path in map(Path, paths):
        if path.is_file():
            found.append(path)
        elif (path / "results.csv").is_file():
            found.append(path / "results.csv")
        elif (path / "cases").is_dir():
            cases = sorted(p for p in (path / "cases").iterdir() if p.is_dir())
            if not cases:
                raise UserError(f"sweep folder {path} has no cases")
            for case in cases:
                summary = _summary(case / "results.csv")
                if summary is not None and summary.get("completed") is False:
                    raise UserError(f"sweep case {case} did not complete "
                                    f"({summary.get('error')}); rerun the sweep")
                if not (case / "results.csv").is_file():
                    raise UserError(f"sweep case {case} has no results.csv; rerun the sweep")
                found.append(case / "results.csv")
        else:
            raise UserError(f"{path} is neither a results.csv, a run folder holding one, nor a "
                            "sweep output folder (with cases/)")
    if not found:
        raise UserError("no identification records given")
    return found


def _summary(csv_path: str | Path) -> dict[str, Any] | None:
    path = Path(csv_path).parent / "summary.json"
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return None


def read_record(csv_path: str | Path, columns: dict[str, Signal] = COLUMNS) -> Record:
    """Read one identification record `csv_path` (results.csv, summary.json beside it for the
    grid), the signals `columns` names (default `COLUMNS`).

    The grid of the runs' peaks comes from the parameters of the instance that records the run
    markers (``reference`` of ``reference.run``) in summary.json; without summary.json the
    ForcReference defaults (30..130 C every 5 C) are used.

    Raises
    ------
    UserError
        For an unreadable or malformed file (every problem located) or a missing column.
    """
    csv_path = Path(csv_path)
    problems: list[str] = []
    table = read_time_series(csv_path, problems, str(csv_path))
    if problems or table is None:
        raise UserError("; ".join(problems))
    header, time, data = table
    assert time is not None and data is not None  # read_time_series said a problem otherwise
    cols = {"time": time}
    for key in COLUMNS:
        name = str(columns[key])  # the results.csv header
        if name not in header[1:]:
            raise UserError(f"{csv_path} has no column {name!r} (the {key} the "
                            "identification reads; record it in the scenario)")
        cols[key] = data[:, header.index(name) - 1]
    summary = _summary(csv_path) or {}
    instance = columns["run"].instance
    params = summary.get("parameters", {}).get(instance, {})
    try:
        temps = grid_from_parameters(params)
    except ValueError as exc:
        raise UserError(f"{csv_path.parent / 'summary.json'}: bad {instance} parameters "
                        f"({exc})") from None
    return Record(csv_path, cols["time"], cols["temperature"] - ZERO_C, cols["strain"],
                  cols["stress"], np.rint(cols["run"]).astype(int), temps, dict(columns))


def record_stress(rec: Record) -> float:
    """The constant stress [Pa] of record `rec`, rounded to STRESS_ROUND.

    Raises
    ------
    UserError
        If the recorded stress is not constant.
    """
    mean = float(np.mean(rec.stress))
    if not np.isfinite(mean) or np.ptp(rec.stress) > STRESS_REL_TOL * abs(mean):
        raise UserError(f"{rec.path}: the stress ({rec.columns['stress']}) varies from "
                        f"{np.min(rec.stress):g} to {np.max(rec.stress):g} Pa; the FORC "
                        "experiments need a constant stress")
    return round(mean / STRESS_ROUND) * STRESS_ROUND


def branch_increments(T: Sequence[float] | np.ndarray, strain: Sequence[float] | np.ndarray,
                      a: float, temps: Sequence[float] | np.ndarray,
                      where: str = "record") -> np.ndarray:
    """F(a, b) for every b in `temps` (<= a; 0 above) from one run's samples (§forc-identification).

    Parameters
    ----------
    T, strain : array_like
        The run's measured temperature [C] and strain, in time order (heating, then cooling).
    a : float
        The run's nominal peak a_j [C].
    temps : array_like
        Grid temperatures [C], increasing.
    where : str
        Names the run in error messages.

    Returns
    -------
    numpy.ndarray
        F(a, temps[k]); 0 where temps[k] >= a.

    Raises
    ------
    UserError
        If the run misses its peak, its descending branch rises, or it stops above a grid b.

    Examples
    --------
    >>> T = [30.0, 50.0, 70.0, 60.0, 40.0, 30.0]
    >>> eps = [0.0, 0.1, 0.4, 0.35, 0.2, 0.15]
    >>> branch_increments(T, eps, 70.0, [30.0, 50.0, 70.0, 90.0]).tolist()
    [0.25, 0.125, 0.0, 0.0]
    """
    T, strain, temps = (np.asarray(x, dtype=float) for x in (T, strain, temps))
    assert isinstance(T, np.ndarray) and isinstance(temps, np.ndarray)
    out = np.zeros(len(temps))
    if len(T) == 0:
        raise UserError(f"{where} has no samples")
    k = int(np.argmax(T))
    if T[k] < a - PEAK_TOL:
        raise UserError(f"{where} never reaches its peak {a:g} C (the measured maximum is "
                        f"{T[k]:.3f} C): the temperature loop does not follow the reference")
    Td, ed = T[k:], strain[k:]
    running = np.minimum.accumulate(Td)
    rise = Td - running
    if rise.max() > RISE_TOL:
        i = int(np.argmax(rise))
        raise UserError(f"{where}: the measured temperature rises again by {rise[i]:.3f} K to "
                        f"{Td[i]:.3f} C on the descending branch from {a:g} C (more than "
                        f"{RISE_TOL:g} K; the branch is not monotonic)")
    new_min = np.concatenate([[True], Td[1:] < running[:-1]])
    Tb, eb = Td[new_min][::-1], ed[new_min][::-1]  # increasing temperature
    below = temps < a
    b = temps[below]
    if b.size and b.min() < Tb[0] - END_TOL:
        raise UserError(f"{where} stops cooling at {Tb[0]:.3f} C, above the grid temperature "
                        f"{b.min():g} C (more than {END_TOL:g} K)")
    out[below] = ed[0] - np.interp(b, Tb, eb)
    return out


def identify_record(rec: Record) -> tuple[float, np.ndarray]:
    """(stress [Pa], table[i, k] = F(temps[i], temps[k])) of one constant-stress record `rec`."""
    sigma = record_stress(rec)
    n = len(rec.temps)
    table = np.zeros((n, n))
    runs = set(np.unique(rec.run).tolist()) - {-1}
    extra = sorted(r for r in runs if not 0 <= r < n)
    if extra:
        raise UserError(f"{rec.path}: run index {extra[0]} ({rec.columns['run']}) is off the "
                        f"grid of {n} runs ({rec.temps[0]:g}..{rec.temps[-1]:g} C)")
    for j in range(1, n):
        mask = rec.run == j
        where = f"{rec.path}: run {j} (peak {rec.temps[j]:g} C)"
        if not mask.any():
            raise UserError(f"{where} has no samples ({rec.columns['run']} never equals {j}); the "
                            "record is cut short or the grid differs")
        table[j] = branch_increments(rec.T[mask], rec.strain[mask], rec.temps[j], rec.temps, where)
    return sigma, table


def identify(paths: str | Path | Iterable[str | Path], out_path: str | Path | None = None,
             columns: dict[str, Signal] = COLUMNS) -> Hypersurface:
    """Identify the FORC hypersurface from constant-stress records and write it to `out_path`.

    Parameters
    ----------
    paths : path or sequence of paths
        A sweep output folder (cases/*/results.csv), run folders or results.csv files; one per
        stress level.
    out_path : path, optional
        The FORC data file to write (format: `musclesim.components.sma.forcfile`).
    columns : dict of str to Signal
        The recorded signals read (default `COLUMNS`).

    Returns
    -------
    Hypersurface
        The identified surfaces on the records' grid at their stresses.

    Raises
    ------
    UserError
        As listed in the module docstring.
    """
    from musclesim.components.sma import forcfile
    from musclesim.components.sma.surface import Hypersurface

    levels: dict[float, tuple[Path, np.ndarray]] = {}
    temps: np.ndarray | None = None
    for path in find_records(paths):
        rec = read_record(path, columns)
        if temps is not None and (len(rec.temps) != len(temps) or np.any(rec.temps != temps)):
            raise UserError(f"{path}: its grid {rec.temps[0]:g}..{rec.temps[-1]:g} C "
                            f"({len(rec.temps)} runs) differs from the other records'")
        temps = rec.temps
        sigma, table = identify_record(rec)
        if sigma in levels:
            raise UserError(f"{path} and {levels[sigma][0]} are both at {sigma:g} Pa; give one "
                            "record per stress")
        levels[sigma] = (path, table)
    stresses = sorted(levels)
    if temps is None:  # find_records found none: it raises
        raise UserError("no identification records given")
    table = np.stack([levels[s][1] for s in stresses])
    try:
        surface = Hypersurface(temps, stresses, table)
    except forcfile.TableError as exc:
        s, i, _ = exc.entries[-1]
        raise UserError(f"{levels[stresses[s]][0]}: the identified values are not a FORC "
                        f"surface (run {i}, peak {temps[i]:g} C): {exc}") from None
    if out_path is not None:
        out_path = Path(out_path)
        out_path.parent.mkdir(parents=True, exist_ok=True)
        tmp = out_path.with_name(f".{out_path.name}.tmp")  # renamed in place: never half-written
        forcfile.write(tmp, temps, stresses, table, comments=[
            "identified by `musclesim identify` from the FORC experiments "
            "(§forc-identification) in",
            *(f"  {levels[s][0]} ({s:g} Pa)" for s in stresses)])
        os.replace(tmp, out_path)
    return surface


def identify_main(paths: str | Path | Iterable[str | Path], out: str | Path,
                  validate: bool = False, as_json: bool = False) -> str | dict[str, Any]:
    """What `musclesim identify PATHS --out FILE [--validate] [--json]` prints.

    Identifies the surfaces from `paths` (a sweep output folder, run folders or results.csv
    files), writes them to `out` and returns a text summary (or a JSON-able dict when
    `as_json`); with `validate` the summary adds the validation numbers of `report`.
    """
    surface = identify(paths, out)
    info: dict[str, Any] = {"out": str(out), "stresses": [float(s) for s in surface.stresses],
            "grid": [float(surface.temps[0]), float(surface.temps[-1]),
                     float(surface.temps[1] - surface.temps[0])],
            "max_strain": {float(s): float(surface.table[k, -1, 0])
                           for k, s in enumerate(surface.stresses)}}
    if validate:
        info["validation"] = validation.report(surface)
    if as_json:
        return info
    text = [f"wrote {out}: FORC surfaces at "
            f"{', '.join(f'{s / 1e6:g}' for s in info['stresses'])} MPa on "
            f"{info['grid'][0]:g}..{info['grid'][1]:g} C every {info['grid'][2]:g} C",
            "maximum strain F(a0, b0): "
            + ", ".join(f"{v:.5f}" for v in info["max_strain"].values())]
    if validate:
        text.append(validation.format_report(info["validation"]))
    return "\n".join(text)
