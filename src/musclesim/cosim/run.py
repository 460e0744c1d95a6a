"""One scenario run from file to folder: load, check the FMUs are fresh, run, write as it goes."""
from __future__ import annotations

from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np

from musclesim.cosim import build, interrupt, master, results, scenario
from musclesim.errors import UserError


def run_scenario(path: str | Path, out: str | Path, fmu_dir: str | Path = "fmus",
                 overrides: Iterable[str] = (), stop_time: float | None = None,
                 with_plot: bool = True, host: str = "direct", isolate: bool = False,
                 extra: Mapping[str, Any] | None = None
                 ) -> tuple[dict[str, Any], results.Results]:
    """Load the scenario at `path` (with the ``--set`` `overrides` and `stop_time`), run it on
    the FMUs in `fmu_dir` on `host` (`master.HOSTS`; every instance in a child process of its
    own if `isolate`) and write it into `out` (the plot only `with_plot`); return (summary,
    results). `extra` holds entries for the final summary that layers above give (the
    predictions a run's summary carries, `musclesim.prediction`); their keys must not be a
    metric's or one of the summary's own.

    The rows reach `out`/results.csv as the run goes (`results.RunWriter`). When a signal stops
    the run, its rows so far are kept, the summary says ``completed: false`` with the signal and
    time, and `interrupt.Interrupted` is raised again for the caller to exit with. An FMU refused
    or not loadable as the run starts (`musclesim.errors.UserError`) ends it the same way: the
    summary says ``completed: false`` with that sentence, never ``running``.
    """
    s = scenario.load(path, overrides, stop_time)
    build.check_fresh(fmu_dir)
    m = master.Master(s, fmu_dir, host=host, isolate=isolate)
    writer = results.RunWriter(out, s, m.columns, master.signal_units(m), with_plot)
    writer.start()

    def no_rows(error: str) -> results.Results:
        return results.Results(np.empty(0), tuple(m.columns), np.empty((0, len(m.columns))),
                               error)

    try:
        res = m.run(on_rows=writer.rows)
    except interrupt.Interrupted as stop:
        writer.finish(stop.results or no_rows(f"{stop} before the first step"))
        raise
    except UserError as exc:
        writer.finish(no_rows(str(exc)))
        raise
    return writer.finish(res, extra), res
