"""Stopping cleanly on SIGINT and SIGTERM: the run stops at its next step, nothing is left behind.

Inside `interruptible` (the command line wraps every command in it) both signals are caught. While
a master steps FMUs (`polled`), the handler only records the signal: raising there would unwind
through an FMU's own Python code, which pythonfmu reports as a failed step. The master checks
`requested` at every communication step and at each phase, and raises `Interrupted` with the
results so far. Outside such a section the handler raises `Interrupted` at once, so waiting on a
Dask cluster or writing a report ends the same way, through every ``finally``: temporary folders
are removed and clusters closed.
"""
from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import contextlib
import signal
import threading

_SIGNALS = (signal.SIGINT, signal.SIGTERM)
STATE: dict[str, Any] = {"signum": None, "polled": 0}


class Interrupted(BaseException):
    """The user stopped the work with a signal; ``results`` holds a run's rows so far, if any.

    A `BaseException`, like KeyboardInterrupt: handlers that record a failed case or a failed fit
    (``except Exception``) let it through.
    """

    def __init__(self, signum: int, results: Any = None) -> None:
        """Stopped by signal number `signum`; `results`: the run's `Results` so far, or None."""
        self.signum, self.results = signum, results
        self.exit_code = 128 + signum  # the shell's convention: 130 for SIGINT, 143 for SIGTERM
        super().__init__(f"interrupted by {signal.Signals(signum).name}")


def requested() -> int | None:
    """The signal received inside `interruptible` and not yet acted on, else None."""
    return STATE["signum"]


def _handle(signum: int, frame: Any) -> None:
    STATE["signum"] = signum
    if not STATE["polled"]:
        raise Interrupted(signum)


@contextlib.contextmanager
def polled() -> Iterator[None]:
    """A section that checks `requested` itself and raises `Interrupted` when it is set (a master
    stepping FMUs): in it, a signal is only recorded."""
    STATE["polled"] += 1
    try:
        yield
    finally:
        STATE["polled"] -= 1


@contextlib.contextmanager
def interruptible() -> Iterator[None]:
    """Catch SIGINT and SIGTERM for the duration (main thread only; elsewhere a no-op)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.signal(s, _handle) for s in _SIGNALS}
    STATE["signum"] = None
    try:
        yield
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
        STATE["signum"] = None
