"""On-demand speed measurements (`musclesim bench`): the Preisach core per step vs a plain call."""
from __future__ import annotations

import gc
import platform
import statistics
import time
from typing import Any, Callable, Sequence

GOAL_FORWARD_US = 2.0  # us per forward step on this machine (issue 3, item 7)
GOAL_INVERSE_US = 3.0  # us per inverse step; the study quotes 8.6 us (§preisach-inverse)
CHUNK = 1000  # steps timed together; the median is taken over chunks


def preisach(n: int = 20000, repeat: int = 5) -> dict[str, Any]:
    """Median time per step of the pure Preisach core, forward and inverse, in one process, over
    `repeat` runs of `n` steps.

    The inverse follows SP IV (random peaks and troughs) under LP V (random stress) at 25 Hz on
    the SMA-shaped analytic surface of the §preisach grid; the forward model is fed the inverse's
    temperatures. Steps are timed in chunks of `CHUNK` (garbage collector off); each figure is
    the median over all chunks of `repeat` runs of `n` steps. ``call_us`` times a trivial
    two-argument Python function in the same loop, so the ratios compare with the interpreter's
    own call cost on this machine.

    Returns
    -------
    dict
        ``forward_us``, ``inverse_us``, ``call_us`` [us per step], ``forward_ratio`` and
        ``inverse_ratio`` (per call), the goals in us, ``n``, ``repeat``, ``python``.
    """
    if n < CHUNK or repeat < 1:
        raise ValueError(f"n must be at least {CHUNK} and repeat at least 1 (got {n}, {repeat})")
    from musclesim.components.sma.analytic import sma_like_surface
    from musclesim.components.sma.inverse import PreisachInverse
    from musclesim.components.sma.preisach import PreisachModel
    from musclesim.components.sma.profiles import loading_profile, strain_profile

    surface = sma_like_surface()
    times = [k / 25.0 for k in range(n)]
    eps = strain_profile("SP IV", duration=times[-1] + 1)(times).tolist()
    sigma = loading_profile("LP V", duration=times[-1] + 1)(times).tolist()
    inverse = PreisachInverse(surface)
    forward = PreisachModel(surface)
    temps = [inverse.step(e, s) for e, s in zip(eps, sigma)]
    result: dict[str, Any] = {
        "inverse_us": _median_us(inverse.step, eps, sigma, repeat,
                                 lambda: inverse.reset(0.0, sigma[0])),
        "forward_us": _median_us(forward.step, temps, sigma, repeat,
                                 lambda: forward.reset(30.0, sigma[0])),
        "call_us": _median_us(_trivial, temps, sigma, repeat, lambda: None),
    }
    result["forward_ratio"] = result["forward_us"] / result["call_us"]
    result["inverse_ratio"] = result["inverse_us"] / result["call_us"]
    result.update(goal_forward_us=GOAL_FORWARD_US, goal_inverse_us=GOAL_INVERSE_US, n=n,
                  repeat=repeat, python=platform.python_version())
    return result


def format_preisach(report: dict[str, Any]) -> str:
    """The `preisach` report `report` as text, one line per figure."""
    lines = []
    for key in ("forward", "inverse"):
        goal = report[f"goal_{key}_us"]
        us = report[f"{key}_us"]
        verdict = "meets" if us <= goal else "misses"
        lines.append(f"{key:8s} {us:6.3f} us/step  = {report[f'{key}_ratio']:5.1f} calls  "
                     f"({verdict} the goal of {goal:g} us)")
    lines.append(f"call     {report['call_us']:6.3f} us  (trivial Python function call, same run)")
    lines.append(f"median over chunks of {CHUNK} steps; {report['repeat']} runs of "
                 f"{report['n']} steps; Python {report['python']}")
    return "\n".join(lines)


def _trivial(x: float, y: float) -> float:
    return x


def _median_us(step: Callable[[float, float], Any], xs: Sequence[float], ys: Sequence[float],
               repeat: int, reset: Callable[[], Any]) -> float:
    """Median over chunks of the time per call of step(x, y) [us]."""
    per_step = []
    enabled = gc.isenabled()
    gc.disable()
    try:
        for _ in range(repeat):
            reset()
            for start in range(0, len(xs) - CHUNK + 1, CHUNK):
                chunk = list(zip(xs[start:start + CHUNK], ys[start:start + CHUNK]))
                t0 = time.perf_counter()
                for x, y in chunk:
                    step(x, y)
                per_step.append((time.perf_counter() - t0) / CHUNK * 1e6)
    finally:
        if enabled:
            gc.enable()
    return statistics.median(per_step)
