"""Loop explorer: steady strain loops of temperature bands cycled at constant stress
(§forc-identification, §capstan-multiplier).

A band T_lo:T_hi is cycled along a cosine from T_lo a few times through the Preisach forward model
(§preisach); from the second cycle on the loop repeats, and its peak-to-peak strain equals the FORC
increment F(T_hi, T_lo; sigma). The model is the reference wire (tabulated on a 1 C grid at the
given stress) or an identified FORC data set.
"""
from __future__ import annotations

import math
import warnings
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from musclesim.components.sma.preisach import Hypersurface, PreisachModel, RangeWarning
from musclesim.components.sma.reference_wire import DEFAULT_PARAMS, ReferenceWire
from musclesim.cosim import save_figure
from musclesim.errors import UserError


def tabulate(source: ReferenceWire, stress: float, step: float = 1.0) -> Hypersurface:
    """Single-stress Hypersurface at `stress` [Pa] of a `ReferenceWire` `source` on a `step` [C]
    grid over its saturation range.

    Examples
    --------
    >>> h = tabulate(ReferenceWire(), 155e6, step=5.0)
    >>> round(h.F(85.0, 60.0, 155e6), 4)
    0.0204
    """
    return source.hypersurface(source.grid(step), [stress])


def parse_band(text: str) -> tuple[float, float]:
    """`text` 'T_lo:T_hi' [C] -> (T_lo, T_hi); raises ValueError unless T_lo < T_hi.

    Examples
    --------
    >>> parse_band("50:100")
    (50.0, 100.0)
    """
    try:
        lo, hi = (float(x) for x in str(text).split(":"))
    except ValueError:
        raise ValueError(f"band {text!r} must be T_lo:T_hi in C, e.g. 50:100") from None
    if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
        raise ValueError(f"band {text!r} needs finite temperatures with T_lo < T_hi")
    return lo, hi


def loops(model: Hypersurface | ReferenceWire, stress: float,
          bands: Sequence[tuple[float, float] | str], cycles: int = 3,
          points: int = 200) -> list[dict[str, Any]]:
    """Cycle each temperature band at constant stress and return its steady loop.

    Parameters
    ----------
    model : Hypersurface or ReferenceWire
        An identified FORC data set, or a FORC source that `tabulate` turns into one.
    stress : float
        Constant stress [Pa].
    bands : sequence of (float, float) or str
        (T_lo, T_hi) [C] or 'T_lo:T_hi', each within the model's temperature range.
    cycles : int
        Cycles per band (>= 2); the last one is returned.
    points : int
        Samples per cycle.

    Returns
    -------
    list of dict
        Per band: ``band`` (T_lo, T_hi) [C], ``peak_to_peak`` strain [-] of the last cycle and
        ``curve`` (temperature [C], strain [-]) arrays of the last cycle.

    Raises
    ------
    ValueError
        A malformed band or one outside the model's range.

    Examples
    --------
    >>> [round(r["peak_to_peak"], 4) for r in loops(ReferenceWire(), 155e6, ["60:85"])]
    [0.0204]
    """
    if cycles < 2 or points < 4:
        raise ValueError(f"need cycles >= 2 and points >= 4 (got {cycles}, {points})")
    surface = model if isinstance(model, Hypersurface) else tabulate(model, stress)
    phase = np.linspace(0.0, 2 * math.pi, points + 1)
    results = []
    for band in bands:
        lo, hi = parse_band(band) if isinstance(band, str) else (float(band[0]), float(band[1]))
        if not surface.t_lo <= lo < hi <= surface.t_hi:
            raise ValueError(f"band {lo:g}:{hi:g} C must lie within the model's "
                             f"{surface.t_lo:g}..{surface.t_hi:g} C with T_lo < T_hi")
        temps = lo + (hi - lo) * (1 - np.cos(phase)) / 2
        m = PreisachModel(surface)
        m.reset(lo, stress)
        for _ in range(cycles - 1):
            for T in temps:
                m.step(T, stress)
        strain = np.array([m.step(T, stress) for T in temps])
        results.append({"band": (lo, hi), "peak_to_peak": float(strain.max() - strain.min()),
                        "curve": (temps, strain)})
    return results


def plot_loops(results: list[dict[str, Any]], path: str | Path, title: str = "") -> None:
    """Save strain [%] over temperature [C] of each band's steady loop in `results` (`loops`') to
    `path`, titled `title`."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for r in results:
        temps, strain = r["curve"]
        lo, hi = r["band"]
        ax.plot(temps, 100 * strain, lw=1.2,
                label=f"{lo:g}-{hi:g} C: {100 * r['peak_to_peak']:.2f} %")
    ax.set_xlabel("temperature [C]")
    ax.set_ylabel("strain [%]")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def load_model(path: str | Path | None = None) -> tuple[Hypersurface | ReferenceWire, str]:
    """The model behind ``--model`` `path`, and its name: None -> the reference wire; a .toml file
    -> a reference wire with those parameters; anything else -> a FORC data set. Raises UserError
    when unreadable."""
    if path is None:
        return ReferenceWire(), f"reference wire ({Path(DEFAULT_PARAMS).name})"
    try:
        if Path(path).suffix == ".toml":
            return ReferenceWire(path), f"reference wire ({path})"
        return Hypersurface.load(path), f"FORC data set ({path})"
    except ValueError as exc:
        raise UserError(str(exc)) from None


def loops_main(stress: float, bands: Sequence[tuple[float, float] | str],
               model_path: str | Path | None = None, as_json: bool = False,
               plot_path: str | Path | None = None) -> str | dict[str, Any]:
    """What ``musclesim loops`` does: cycle the bands, optionally plot, and report.

    Parameters
    ----------
    stress : float
        Constant stress [Pa].
    bands : sequence of str or (float, float)
        'T_lo:T_hi' [C] as given on the command line, or pairs.
    model_path : path-like, optional
        FORC data file or wire parameter file (.toml); default: the reference wire.
    as_json : bool
        Return a JSON-ready dict instead of text.
    plot_path : path-like, optional
        Where to save the plot of the loops (no plot when None).

    Returns
    -------
    str or dict
        Text with one line per band, or ``{"model", "stress_Pa", "loops": [{"band_C",
        "peak_to_peak"}], "warnings", "plot"}``. Out-of-range stresses are clamped by the FORC
        data set's policy; its warnings are reported, not hidden.

    Raises
    ------
    UserError
        Unreadable model, malformed band, band outside the model, non-finite or negative stress.

    Examples
    --------
    >>> print(loops_main(155e6, ["30:130", "60:85"]))
    loops at 155 MPa, reference wire (flexinol-127um-90C.toml)
      30-130 C: peak-to-peak strain 0.04003 (4.00 %)
      60-85 C: peak-to-peak strain 0.02044 (2.04 %)
    """
    if not (math.isfinite(stress) and stress >= 0):
        raise UserError(f"stress must be a finite, non-negative number in Pa (got {stress!r})")
    model, name = load_model(model_path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RangeWarning)
        try:
            results = loops(model, stress, bands)
        except ValueError as exc:
            raise UserError(str(exc)) from None
    notes = sorted({str(w.message) for w in caught if issubclass(w.category, RangeWarning)})
    if plot_path is not None:
        plot_loops(results, plot_path, f"steady loops at {stress / 1e6:g} MPa, {name}")
    if as_json:
        return {"model": name, "stress_Pa": stress, "warnings": notes,
                "plot": None if plot_path is None else str(plot_path),
                "loops": [{"band_C": list(r["band"]), "peak_to_peak": r["peak_to_peak"]}
                          for r in results]}
    lines = [f"loops at {stress / 1e6:g} MPa, {name}"]
    lines += [f"  {r['band'][0]:g}-{r['band'][1]:g} C: peak-to-peak strain "
              f"{r['peak_to_peak']:.5f} ({100 * r['peak_to_peak']:.2f} %)" for r in results]
    lines += [f"  warning: {n}" for n in notes]
    if plot_path is not None:
        lines.append(f"  plot: {plot_path}")
    return "\n".join(lines)
