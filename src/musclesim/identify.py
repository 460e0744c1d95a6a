"""`musclesim identify`: FORC surfaces from the recorded identification experiments (SPEC 2.3).

Input: the records of ``scenarios/sma-forc-identification.toml`` at several constant stresses (the
case folders of a sweep, each with results.csv and summary.json). Per stress level the
`ForcReference` markers cut the record into the runs j = 0..n-1; run j heats from b0 to its peak
a_j and cools back. Its descending branch holds every reversal curve with peak a_j, so for every
grid b <= a_j (SPEC 2.3, no differentiation of data):

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

Validation on the virtual bench (SPEC 2.3): `surface_error` (identified against the reference
wire's exact F on the grid), `validation_runs` (the identified model's strain error against the
virtual wire on runs not used for identification, at constant and under time-varying stress) and
`memory_checks` (rate independence, wiping-out, congruency of the virtual wire).
"""
import json
import math
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from musclesim.errors import UserError

ZERO_C = 273.15  # K
# recorded signals the identification reads (scenario sma-forc-identification)
# (the phase flag reference.phase is recorded for plots; the peak is the measured maximum)
COLUMNS = {"temperature": "thermocouple.T_meas", "strain": "wire.strain", "stress": "wire.stress",
           "run": "reference.run"}
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
    columns: dict


def grid_from_parameters(params):
    """Peak grid [C] of a ForcReference with these (partial) parameters (defaults: SPEC 2.3).

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


def find_records(paths):
    """The results.csv files behind `paths`: run folders, results.csv files, or a sweep's output
    folder (every ``cases/*/``, in name order).

    Raises
    ------
    UserError
        For a path with no record, or a sweep case that did not complete.
    """
    if isinstance(paths, (str, Path)):
        paths = [paths]
    found = []
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


def _summary(csv_path):
    path = Path(csv_path).parent / "summary.json"
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return None


def read_record(csv_path, columns=COLUMNS):
    """Read one identification record (results.csv, summary.json beside it for the grid).

    The grid of the runs' peaks comes from the parameters of the instance that records the run
    markers (``reference`` in ``reference.run``) in summary.json; without summary.json the
    ForcReference defaults (30..130 C every 5 C) are used.

    Raises
    ------
    UserError
        For an unreadable file or a missing column, naming the file and the column.
    """
    csv_path = Path(csv_path)
    try:
        with csv_path.open() as fh:
            header = fh.readline().strip().split(",")
        data = np.loadtxt(csv_path, delimiter=",", skiprows=1, ndmin=2)
    except (OSError, ValueError) as exc:
        raise UserError(f"{csv_path}: cannot read the record ({exc})") from None
    cols = {}
    for key in ("time", *COLUMNS):
        name = "time" if key == "time" else columns[key]
        if name not in header:
            raise UserError(f"{csv_path} has no column {name!r} (the {key} the identification "
                            f"reads; record it in the scenario)")
        cols[key] = data[:, header.index(name)]
    summary = _summary(csv_path) or {}
    instance = columns["run"].partition(".")[0]
    params = summary.get("parameters", {}).get(instance, {})
    try:
        temps = grid_from_parameters(params)
    except ValueError as exc:
        raise UserError(f"{csv_path.parent / 'summary.json'}: bad {instance} parameters "
                        f"({exc})") from None
    return Record(csv_path, cols["time"], cols["temperature"] - ZERO_C, cols["strain"],
                  cols["stress"], np.rint(cols["run"]).astype(int), temps, dict(columns))


def record_stress(rec):
    """The constant stress [Pa] of a record, rounded to STRESS_ROUND.

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


def branch_increments(T, strain, a, temps, where="record"):
    """F(a, b) for every b in `temps` (<= a; 0 above) from one run's samples (SPEC 2.3).

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


def identify_record(rec):
    """(stress [Pa], table[i, k] = F(temps[i], temps[k])) of one constant-stress record."""
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


def identify(paths, out_path=None, columns=COLUMNS):
    """Identify the FORC hypersurface from constant-stress records and write it to `out_path`.

    Parameters
    ----------
    paths : path or sequence of paths
        A sweep output folder (cases/*/results.csv), run folders or results.csv files; one per
        stress level.
    out_path : path, optional
        The FORC data file to write (format: `musclesim.components.sma.forcfile`).
    columns : dict
        Recorded signal names (default `COLUMNS`).

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

    levels = {}
    temps = None
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
        forcfile.write(out_path, temps, stresses, table, comments=[
            "identified by `musclesim identify` from the FORC experiments (SPEC 2.3) in",
            *(f"  {levels[s][0]} ({s:g} Pa)" for s in stresses)])
    return surface


# ---- validation on the virtual bench (SPEC 2.3) ------------------------------------------------

def surface_error(surface, wire=None):
    """Largest |F_identified - F_wire| on the surface's grid and stresses, F_wire the reference
    wire's exact FORC increment; also per stress and where the largest error sits.

    Returns a dict: ``max_abs`` [strain], ``max_rel`` (of the wire's maximum strain at that
    stress), ``at`` (stress Pa, a C, b C), ``per_stress`` {stress: max_abs}.
    """
    from musclesim.components.sma.wire import ReferenceWire

    wire = wire or ReferenceWire()
    temps = surface.temps
    i, j = np.tril_indices(len(temps))
    best, per = (-1.0, None, 0.0), {}
    for s, sigma in enumerate(surface.stresses):
        exact = wire.F(temps[i], temps[j], float(sigma))
        err = np.abs(surface.table[s, i, j] - exact)
        k = int(np.argmax(err))
        per[float(sigma)] = float(err[k])
        if err[k] > best[0]:
            best = (float(err[k]), (float(sigma), float(temps[i[k]]), float(temps[j[k]])),
                    float(err[k] / wire.eps_max(sigma)))
    return {"max_abs": best[0], "max_rel": best[2], "at": best[1], "per_stress": per}


def strain_error(surface, T, sigma, eps_ref):
    """Drive a PreisachModel on `surface` with T [C], sigma [Pa] (arrays or a constant stress)
    and compare with eps_ref: dict of ``rmse``, ``max_abs`` and ``rmse_percent`` (of
    max |eps_ref|), plus the model's strain ``eps``."""
    from musclesim.components.sma.preisach import PreisachModel
    from musclesim.components.sma.surface import RangeWarning

    T = np.asarray(T, dtype=float)
    sigma = np.broadcast_to(np.asarray(sigma, dtype=float), T.shape)
    model = PreisachModel(surface)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)  # validation stresses may touch the ends
        model.reset(float(T[0]), float(sigma[0]))
        eps = np.array([model.step(float(t), float(s)) for t, s in zip(T, sigma)])
    err = eps - np.asarray(eps_ref, dtype=float)
    rmse = float(np.sqrt(np.mean(err ** 2)))
    return {"rmse": rmse, "max_abs": float(np.abs(err).max()),
            "rmse_percent": 100 * rmse / float(np.abs(eps_ref).max()), "eps": eps}


def validation_profiles(duration=550.0, dt=0.05):
    """Temperature [C] and stress [Pa] paths of the validation runs (none is a FORC run).

    - ``minor loops, 120 MPa``: a sine about 80 C whose amplitude decays from 50 K (nested minor
      loops, each a reversal inside the previous one) at constant 120 MPa (between two
      identified stresses);
    - ``random peaks, 130 MPa``: random temperature peaks and troughs over 30..130 C;
    - ``LP I``: a sine 35..125 C at 1/23 Hz under the loading profile LP I (105..145 MPa at
      1/17 Hz, SPEC 2.4);
    - ``LP V``: random temperature peaks and troughs under LP V (random stress).

    Returns {name: (t, T, sigma)}.
    """
    from musclesim.components.sma import profiles

    t = np.arange(0.0, duration + dt / 2, dt)
    decay = 80.0 - 50.0 * np.exp(-3 * t / duration) * np.cos(2 * math.pi * t / 17.0)
    rand_T = profiles.random_peaks(30.0, 130.0, duration, seed=11)(t)
    return {
        "minor loops, 120 MPa": (t, decay, np.full_like(t, 120e6)),
        "random peaks, 130 MPa": (t, rand_T, np.full_like(t, 130e6)),
        "LP I": (t, 80.0 - 45.0 * np.cos(2 * math.pi * t / 23.0),
                 profiles.loading_profile("LP I", duration=duration)(t)),
        "LP V": (t, profiles.random_peaks(30.0, 130.0, duration, seed=12)(t),
                 profiles.loading_profile("LP V", duration=duration)(t)),
    }


def validation_runs(surface, truth=None, duration=550.0, dt=0.05):
    """The identified model's strain error against the virtual wire on `validation_profiles`.

    The virtual wire is the SmaWire FMU's own hysteresis (data set 0: the reference wire on its
    1 C, 10 MPa table) driven by the same temperature and stress; the thermal part does not
    enter, as both see the wire's temperature. Returns {name: {rmse, max_abs, rmse_percent,
    eps_max}}, eps_max the wire's largest strain on the run.
    """
    from musclesim.components.sma import datasets
    from musclesim.components.sma.preisach import PreisachModel

    truth = truth or datasets.surface(0)
    report = {}
    for name, (t, T, sigma) in validation_profiles(duration, dt).items():
        wire = PreisachModel(truth)
        wire.reset(float(T[0]), float(sigma[0]))
        eps_wire = np.array([wire.step(float(x), float(s)) for x, s in zip(T, sigma)])
        res = strain_error(surface, T, sigma, eps_wire)
        report[name] = {"rmse": res["rmse"], "max_abs": res["max_abs"],
                        "rmse_percent": res["rmse_percent"],
                        "eps_max": float(np.abs(eps_wire).max())}
    return report


def memory_checks(surface=None, sigma=120e6):
    """Rate independence, wiping-out and congruency of the virtual wire's hysteresis (SPEC 2.3)
    at constant stress; each number is a largest strain difference that must vanish.

    - ``rate_independence``: a sine path 30 -> 120 -> 45 -> 100 -> 30 C sampled at 0.1 s for one
      run and at 1 s for one ten times as slow, compared as strain against temperature on the
      slow run's samples (the same path at two speeds gives the same strain);
    - ``wiping_out``: the strain while cooling 110 -> 40 C after the history
      30 -> 90 -> 50 -> 80 -> 55 -> 110 against that after 30 -> 55 -> 110: heating to 110 erases
      the smaller maxima 90 and 80 with their minima (``memory`` is how far apart the two
      histories keep the strain on the rise below 90 C, before the erasure);
    - ``congruency``: the minor loop 85 -> 70 -> 85 C after two different histories
      (30 -> 130 -> 40 -> 85 and 30 -> 130 -> 66 -> 85, which leave the loop's start at different
      strains), its strain relative to the loop's start compared along the loop: minor loops
      between the same bounds are congruent.

    Returns {name: largest |difference|}, ``memory`` (above), ``loop_span`` (the congruent loops' strain span) and
    ``offset`` (how far apart the two histories put the loops' starts).
    """
    from musclesim.components.sma import datasets
    from musclesim.components.sma.preisach import MemoryParams, PreisachModel

    surface = surface or datasets.surface(0)

    def drive(path):
        m = PreisachModel(surface, MemoryParams(tol=0.0))
        m.reset(float(path[0]), sigma)
        return np.array([m.step(float(T), sigma) for T in path])

    def legs(points, n=200):
        out = [np.array([points[0]])]
        for lo, hi in zip(points, points[1:]):
            x = np.linspace(0, 1, n + 1)[1:]
            out.append(lo + (hi - lo) * (1 - np.cos(math.pi * x)) / 2)
        return np.concatenate(out)

    corners = [30.0, 120.0, 45.0, 100.0, 30.0]
    fast, slow = legs(corners, 100), legs(corners, 1000)
    eps_fast, eps_slow = drive(fast), drive(slow)
    # compare at the fast run's samples: sample m of leg l is sample 10 m of the slow run's leg
    legs_n, m = len(corners) - 1, np.arange(1, 101)
    same = np.concatenate([[0], *(l * 1000 + 10 * m for l in range(legs_n))])
    rate = float(np.abs(eps_fast - eps_slow[same]).max())

    rise, fall = legs([55.0, 110.0])[1:], legs([110.0, 40.0])[1:]
    plain = drive(np.concatenate([legs([30.0, 55.0]), rise, fall]))
    inner = drive(np.concatenate([legs([30.0, 90.0, 50.0, 80.0, 55.0]), rise, fall]))
    n_fall = len(fall)
    wipe = float(np.abs(plain[-n_fall:] - inner[-n_fall:]).max())
    below = rise < 90.0  # before the rise passes the largest erased maximum
    memory = float(np.abs(plain[-n_fall - len(rise):-n_fall][below]
                          - inner[-n_fall - len(rise):-n_fall][below]).max())

    loop = legs([85.0, 70.0, 85.0])[1:]
    first = drive(np.concatenate([legs([30.0, 130.0, 40.0, 85.0]), loop]))[-len(loop) - 1:]
    second = drive(np.concatenate([legs([30.0, 130.0, 66.0, 85.0]), loop]))[-len(loop) - 1:]
    cong = float(np.abs((first - first[0]) - (second - second[0])).max())
    return {"rate_independence": rate, "wiping_out": wipe, "congruency": cong,
            "memory": memory, "loop_span": float(np.ptp(first)),
            "offset": float(abs(first[0] - second[0]))}


def report(surface):
    """All validation numbers of an identified surface (SPEC 2.3) as one dict.

    ``grid_floor`` repeats the validation runs with the reference wire tabulated exactly on the
    identified grid and stresses (a perfect identification): the part of the error that comes
    from the model's grid (bilinear in 5 C cells, linear in stress), not from the identification.
    """
    from musclesim.components.sma.wire import ReferenceWire

    exact = ReferenceWire().hypersurface(surface.temps, surface.stresses)
    return {"surface_error": surface_error(surface),
            "validation_runs": validation_runs(surface),
            "grid_floor": validation_runs(exact),
            "memory_checks": memory_checks()}


def format_report(rep):
    """Human-readable text of `report`."""
    se = rep["surface_error"]
    lines = [f"identified F against the reference wire on the grid: max |error| "
             f"{se['max_abs']:.3g} ({100 * se['max_rel']:.2f} % of the maximum strain) at "
             f"{se['at'][0] / 1e6:g} MPa, a = {se['at'][1]:g} C, b = {se['at'][2]:g} C"]
    lines += [f"  {s / 1e6:g} MPa: {e:.3g}" for s, e in se["per_stress"].items()]
    lines.append("strain error of the identified model against the virtual wire (validation runs):")
    lines += [f"  {n}: RMSE {v['rmse']:.3g} ({v['rmse_percent']:.2f} % of max strain "
              f"{v['eps_max']:.4f}), max {v['max_abs']:.3g}; exact F on the same grid: "
              f"{rep['grid_floor'][n]['rmse_percent']:.2f} %"
              for n, v in rep["validation_runs"].items()]
    mc = rep["memory_checks"]
    lines.append(f"virtual wire memory checks (largest strain difference): rate independence "
                 f"{mc['rate_independence']:.2g}, wiping-out {mc['wiping_out']:.2g}, "
                 f"congruency {mc['congruency']:.2g} (histories differ by {mc['memory']:.4f} "
                 f"before the erasure; loop span {mc['loop_span']:.4f})")
    return "\n".join(lines)


def identify_main(paths, out, validate=False, as_json=False):
    """What `musclesim identify PATHS --out FILE [--validate] [--json]` prints.

    Identifies the surfaces from `paths` (a sweep output folder, run folders or results.csv
    files), writes them to `out` and returns a text summary (or a JSON-able dict when
    `as_json`); with `validate` the summary adds the validation numbers of `report`.
    """
    surface = identify(paths, out)
    info = {"out": str(out), "stresses": [float(s) for s in surface.stresses],
            "grid": [float(surface.temps[0]), float(surface.temps[-1]),
                     float(surface.temps[1] - surface.temps[0])],
            "max_strain": {float(s): float(surface.table[k, -1, 0])
                           for k, s in enumerate(surface.stresses)}}
    if validate:
        info["validation"] = report(surface)
    if as_json:
        return info
    text = [f"wrote {out}: FORC surfaces at "
            f"{', '.join(f'{s / 1e6:g}' for s in info['stresses'])} MPa on "
            f"{info['grid'][0]:g}..{info['grid'][1]:g} C every {info['grid'][2]:g} C",
            "maximum strain F(a0, b0): "
            + ", ".join(f"{v:.5f}" for v in info["max_strain"].values())]
    if validate:
        text.append(format_report(info["validation"]))
    return "\n".join(text)
