"""Validation of identified FORC surfaces on the virtual bench (§forc-identification).

`surface_error` compares the identified F with the reference wire's exact F on the grid,
`validation_runs` the identified model's strain with the virtual wire's on runs not used for
identification (constant and time-varying stress), and `memory_checks` verifies rate
independence, wiping-out and congruency of the virtual wire.
"""
from __future__ import annotations

import math
import warnings
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

if TYPE_CHECKING:
    from musclesim.components.sma.surface import Hypersurface
    from musclesim.components.sma.reference_wire import ReferenceWire

Profiles = dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]  # name: (t, T, sigma)

def surface_error(surface: Hypersurface, wire: ReferenceWire | None = None) -> dict[str, Any]:
    """Largest |F_identified - F_wire| on the grid and stresses of the identified `surface`,
    F_wire the exact FORC increment of `wire` (default: the reference wire); also per stress and
    where the largest error sits.

    Returns a dict: ``max_abs`` [strain], ``max_rel`` (of the wire's maximum strain at that
    stress), ``at`` (stress Pa, a C, b C), ``per_stress`` {stress: max_abs}.
    """
    from musclesim.components.sma.reference_wire import ReferenceWire

    wire = wire or ReferenceWire()
    temps = surface.temps
    i, j = np.tril_indices(len(temps))
    best: tuple[float, tuple[float, float, float] | None, float] = (-1.0, None, 0.0)
    per: dict[float, float] = {}
    for s, sigma in enumerate(surface.stresses):
        exact = wire.F(temps[i], temps[j], float(sigma))
        err = np.abs(surface.table[s, i, j] - exact)
        k = int(np.argmax(err))
        per[float(sigma)] = float(err[k])
        if err[k] > best[0]:
            best = (float(err[k]), (float(sigma), float(temps[i[k]]), float(temps[j[k]])),
                    float(err[k] / wire.eps_max(sigma)))
    return {"max_abs": best[0], "max_rel": best[2], "at": best[1], "per_stress": per}


def strain_error(surface: Hypersurface, T: Sequence[float] | np.ndarray,
                 sigma: float | Sequence[float] | np.ndarray,
                 eps_ref: Sequence[float] | np.ndarray) -> dict[str, Any]:
    """Drive a PreisachModel on `surface` with `T` [C], `sigma` [Pa] (arrays or a constant
    stress) and compare with `eps_ref`: dict of ``rmse``, ``max_abs`` and ``rmse_percent`` (of
    max |eps_ref|), plus the model's strain ``eps``."""
    from musclesim.components.sma.preisach import PreisachModel
    from musclesim.components.sma.surface import RangeWarning

    T = np.asarray(T, dtype=float)
    assert isinstance(T, np.ndarray)
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


def validation_profiles(duration: float = 550.0, dt: float = 0.05) -> Profiles:
    """Temperature [C] and stress [Pa] paths of the validation runs (none is a FORC run), of
    `duration` [s] sampled every `dt` [s].

    - ``minor loops, 120 MPa``: a sine about 80 C whose amplitude decays from 50 K (nested minor
      loops, each a reversal inside the previous one) at constant 120 MPa (between two
      identified stresses);
    - ``random peaks, 130 MPa``: random temperature peaks and troughs over 30..130 C;
    - ``LP I``: a sine 35..125 C at 1/23 Hz under the loading profile LP I (105..145 MPa at
      1/17 Hz, §position-control);
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


def validation_runs(surface: Hypersurface, truth: Hypersurface | None = None,
                    duration: float = 550.0, dt: float = 0.05) -> dict[str, dict[str, float]]:
    """The strain error of the model on the identified `surface` against the virtual wire on
    `validation_profiles` (of `duration` [s], every `dt` [s]).

    The virtual wire is `truth`, by default the SmaWire FMU's own hysteresis (data set 0: the
    reference wire on its 1 C, 10 MPa table), driven by the same temperature and stress; the thermal
    part does not enter, as both see the wire's temperature. Returns {name: {rmse, max_abs,
    rmse_percent, eps_max}}, eps_max the wire's largest strain on the run.
    """
    from musclesim.components.sma import datasets
    from musclesim.components.sma.preisach import PreisachModel

    truth = truth or datasets.surface(0)
    report: dict[str, dict[str, float]] = {}
    for name, (t, T, sigma) in validation_profiles(duration, dt).items():
        wire = PreisachModel(truth)
        wire.reset(float(T[0]), float(sigma[0]))
        eps_wire = np.array([wire.step(float(x), float(s)) for x, s in zip(T, sigma)])
        res = strain_error(surface, T, sigma, eps_wire)
        report[name] = {"rmse": res["rmse"], "max_abs": res["max_abs"],
                        "rmse_percent": res["rmse_percent"],
                        "eps_max": float(np.abs(eps_wire).max())}
    return report


def memory_checks(surface: Hypersurface | None = None, sigma: float = 120e6) -> dict[str, float]:
    """Rate independence, wiping-out and congruency of the virtual wire's hysteresis `surface`
    (default: the SmaWire FMU's, §forc-identification) at constant stress `sigma` [Pa]; each
    number is a largest strain difference that must vanish.

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

    Returns {name: largest |difference|}, ``memory`` (above), ``loop_span`` (the congruent loops'
    strain span) and ``offset`` (how far apart the two histories put the loops' starts).
    """
    from musclesim.components.sma import datasets
    from musclesim.components.sma.preisach import MemoryParams, PreisachModel

    hysteresis = surface or datasets.surface(0)

    def drive(path: np.ndarray) -> np.ndarray:
        m = PreisachModel(hysteresis, MemoryParams(tol=0.0))
        m.reset(float(path[0]), sigma)
        return np.array([m.step(float(T), sigma) for T in path])

    def legs(points: list[float], n: int = 200) -> np.ndarray:
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


def report(surface: Hypersurface) -> dict[str, Any]:
    """All validation numbers of an identified `surface` (§forc-identification) as one dict.

    ``grid_floor`` repeats the validation runs with the reference wire tabulated exactly on the
    identified grid and stresses (a perfect identification): the part of the error that comes
    from the model's grid (bilinear in 5 C cells, linear in stress), not from the identification.
    """
    from musclesim.components.sma.reference_wire import ReferenceWire

    exact = ReferenceWire().hypersurface(surface.temps, surface.stresses)
    return {"surface_error": surface_error(surface),
            "validation_runs": validation_runs(surface),
            "grid_floor": validation_runs(exact),
            "memory_checks": memory_checks()}


def format_report(rep: dict[str, Any]) -> str:
    """Human-readable text of a `report` `rep`."""
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
