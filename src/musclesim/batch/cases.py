"""Case folders: one run of a scenario per folder, on Dask, resumable.

An output folder ``out`` holds ``out/sweep.json`` (what its cases come from, written by `claim`)
and one folder per case, ``out/cases/<id>/``, with the run's results and its ``summary.json``
(``"completed": true`` and the metrics, or ``"completed": false`` and the ``"error"``). A case
whose summary says it completed is `finished` and is not run again; `run_cases` runs the others
on a Dask cluster. Sweeps (`sweep.run`) and the study's tables (``musclesim.analysis``) use them.

Cases run on a worker in chunks (`chunks`, `run_chunk`: one compiled pass where they fuse) and
write nothing there: their results come back to this process, results.csv's rows formatted by
the worker, and this process alone writes each case's folder (`write_case`) with the run's
writers, so that the workers need no access to the output folder, and the folder's guarantees
are those of one run (`musclesim.cosim.write_results`).
"""
from __future__ import annotations

import hashlib
import json
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from musclesim.batch.cluster import dask_client, in_process, ship_fmus
from musclesim.batch.shipped import FmuFolder
from musclesim.cosim import (Master, Results, Scenario, Signal, apply_overrides, clear_run_outputs,
                             csv_rows, replace_file, reuse_fmus, signal_units)
from musclesim.cosim import run_cases as run_together
from musclesim.errors import UserError


def write_failure(case_dir: str | Path, error: str | None) -> dict[str, Any]:
    """Record in `case_dir`/summary.json that the case failed with `error`; return that summary.

    An earlier run's outputs there (its results.csv, plot, summary) are removed first, the
    summary first: the folder then holds this failure alone, never an old run's rows beside it.
    """
    summary = {"completed": False, "error": error}
    Path(case_dir).mkdir(parents=True, exist_ok=True)
    clear_run_outputs(case_dir)
    replace_file(Path(case_dir) / "summary.json", json.dumps(summary, indent=2) + "\n")
    return summary


@dataclass(frozen=True)
class Outcome:
    """What a case's run hands back (`run_case`, `run_chunk`): the case's `scenario`, the
    master's `results` (failed or not: ``results.error``) with the recorded signals' `units`, the
    `hosts` that ran each instance (``Master.hosts``) and results.csv's `rows` formatted
    (``musclesim.cosim.csv_rows``, encoded); or only the `error` of a run that could not start."""

    scenario: Scenario | None = None
    results: Results | None = None
    units: dict[Signal, str] | None = None
    hosts: dict[str, str] | None = None
    error: str | None = None
    rows: bytes | None = None


def run_case(scenario: Scenario, fmu_dir: str | Path | FmuFolder, overrides: Iterable[str] = ()
             ) -> Outcome:
    """Run one case, the loaded `scenario` with `overrides` (``"inst.param=value"``) on the FMUs
    in `fmu_dir`; return its `Outcome`, failed or not. Writes nothing."""
    try:
        m = _master(scenario, fmu_dir, overrides)
        return _outcome(m, m.run())
    except Exception as exc:  # whatever breaks one case is recorded; the sweep goes on
        return _failed(exc)


def run_chunk(scenario: Scenario, fmu_dir: str | Path | FmuFolder,
              chunk: Sequence[Sequence[str]]) -> list[Outcome]:
    """Run the cases `chunk` (each its overrides of the loaded `scenario`) on the FMUs in
    `fmu_dir` (a Dask worker's task): in one compiled pass where they fuse
    (`musclesim.cosim.run_cases`), else one after the other; each case's `Outcome`, failed or
    not, in `chunk`'s order. A case that breaks the pass (a bug) is run again alone, as are the
    others, so that its error stays its own. Writes nothing."""
    made: list[Master | Outcome] = []
    for overrides in chunk:
        try:
            made.append(_master(scenario, fmu_dir, overrides))
        except Exception as exc:
            made.append(_failed(exc))
    masters = [m for m in made if isinstance(m, Master)]
    try:
        results = iter(run_together(masters))
    except Exception:
        return [run_case(scenario, fmu_dir, overrides) for overrides in chunk]
    return [m if isinstance(m, Outcome) else _outcome(m, next(results)) for m in made]


def _master(scenario: Scenario, fmu_dir: str | Path | FmuFolder, overrides: Iterable[str]
            ) -> Master:
    """The `Master` of `scenario` with `overrides` on the FMUs in `fmu_dir`."""
    problems: list[str] = []
    s = apply_overrides(scenario, overrides, problems)
    if problems:
        raise UserError(f"scenario {scenario.path} has {len(problems)} problem(s): "
                        + "; ".join(problems))
    return Master(s, fmu_dir)


def _outcome(m: Master, res: Results) -> Outcome:
    """The `Outcome` of master `m`'s run `res`, its rows formatted for results.csv here: on a
    worker, the formatting (most of a long case's writing) runs beside the other workers'."""
    return Outcome(m.scenario, res, signal_units(m), dict(m.hosts),
                   rows=csv_rows(res.time, res.data).encode())


def _failed(exc: Exception) -> Outcome:
    """The `Outcome` of a case that could not run: a user's error as it is, a bug named."""
    return Outcome(error=str(exc) if isinstance(exc, UserError) else f"{type(exc).__name__}: {exc}")


def write_case(case_dir: str | Path, outcome: Outcome) -> dict[str, Any]:
    """Write a case's `outcome` (an `Outcome`) into `case_dir` (results.csv and summary.json, no
    plot: drawing it costs about a third of a 60 s case, and sweep.png summarises); return its
    summary."""
    from musclesim.cosim import write_results

    if outcome.results is None:
        return write_failure(case_dir, outcome.error)
    assert outcome.scenario is not None and outcome.units is not None  # set with results
    return write_results(case_dir, outcome.scenario, outcome.results, outcome.units,
                         with_plot=False, rows=outcome.rows)


def case_summary(case_dir: str | Path) -> dict[str, Any] | None:
    """The summary of the case in `case_dir` if it ran (completed or failed), else None (no
    summary.json, or not a JSON object)."""
    try:
        summary = json.loads((Path(case_dir) / "summary.json").read_text())
    except (OSError, ValueError):
        return None
    return summary if isinstance(summary, dict) else None


def finished(case_dir: str | Path) -> dict[str, Any] | None:
    """The summary of the case in `case_dir` if it completed (``"completed": true``), else None."""
    summary = case_summary(case_dir)
    return summary if summary is not None and summary.get("completed") is True else None


def claim(out: str | Path, scenario_path: str | Path, **settings: Any) -> None:
    """Record in `out`/sweep.json what the cases come from (the scenario file `scenario_path` and
    its hash, the FMUs' sources, `**settings`), refusing a folder whose cases came from something
    else.

    Raises
    ------
    UserError
        When out/sweep.json names other settings (another scenario file or content, other FMU
        sources, or another value of one of `settings`).
    """
    from musclesim.cosim import source_digest

    out = Path(out)
    config = {"scenario": str(scenario_path),
              "scenario_sha256": hashlib.sha256(Path(scenario_path).read_bytes()).hexdigest(),
              **settings, "fmu_sources": source_digest()}
    path = out / "sweep.json"
    if path.is_file():
        try:
            old = json.loads(path.read_text())
        except ValueError:
            old = {}
        differ = [k for k in config if not isinstance(old, dict) or old.get(k) != config[k]]
        if differ:
            raise UserError(f"{out} holds the cases of a run with other settings "
                            f"({', '.join(differ)}); choose another --out or delete that folder")
    out.mkdir(parents=True, exist_ok=True)
    replace_file(path, json.dumps(config, indent=2) + "\n")


def run_cases(out: str | Path, todo: Sequence[tuple[str, Sequence[str]]], scenario: Scenario,
              fmu_dir: str | Path, scheduler: str | None = None, workers: int | None = None,
              record: Callable[[str, dict[str, Any], Results | None], None] | None = None
              ) -> None:
    """Run the cases `todo` of `scenario` on Dask (a LocalCluster unless `scheduler` is given;
    in this process for one worker, `in_process`), writing each into out/cases/<id>/ in this
    process as it finishes.

    The workers get the FMUs (`ship_fmus`) and the scenario once each, and send every case's
    results back: they need no access to this machine's files. Each task is a chunk of cases
    (`chunks`) run in one compiled pass where they fuse (`run_chunk`).

    Parameters
    ----------
    out : str or Path
        The output folder (claimed: `claim`).
    todo : list of (case id, overrides)
        The cases to run, each with its ``"inst.param=value"`` overrides of `scenario`.
    scenario : musclesim.cosim.Scenario
        The loaded scenario every case starts from.
    fmu_dir : str or Path
        Folder of built FMUs, read here.
    scheduler : str or None
        Address of a running Dask scheduler.
    workers : int or None
        Worker processes of the local cluster (default: the cores, at most one per case); 1
        runs the cases in this process, no cluster (`in_process`).
    record : callable, optional
        ``record(case id, summary, results)``, called as each case has been written, with the
        run's `Results` (None for a case that did not start, or whose worker died: it gets a
        failure summary).
    """
    from tqdm import tqdm

    with tqdm(total=len(todo), desc="sweep", unit="case") as bar:
        for cids, outcomes in _outcomes(todo, scenario, fmu_dir, scheduler, workers):
            for cid, outcome in zip(cids, outcomes):
                summary = write_case(Path(out) / "cases" / cid, outcome)
                if record is not None:
                    record(cid, summary, outcome.results)
                bar.update()


def _outcomes(todo: Sequence[tuple[str, Sequence[str]]], scenario: Scenario, fmu_dir: str | Path,
              scheduler: str | None, workers: int | None
              ) -> Iterator[tuple[list[str], list[Outcome]]]:
    """(case ids, their outcomes) of each chunk of `todo` as it ends: in this process where the
    options ask it (`in_process`), else on Dask."""
    from distributed import as_completed

    if in_process(scheduler, workers):
        with reuse_fmus():  # each FMU unpacked once, as a worker keeps it
            for part in chunks(todo, scenario, 1):
                yield [cid for cid, _ in part], run_chunk(scenario, fmu_dir, [o for _, o in part])
        return
    components = {i.component for i in scenario.instances.values()}
    with dask_client(scheduler, workers, len(todo)) as client:
        fmus = ship_fmus(client, fmu_dir, components)
        sent = client.scatter(scenario, broadcast=True, hash=False)
        parts = chunks(todo, scenario, len(client.scheduler_info()["workers"]))
        futures = {client.submit(run_chunk, sent, fmus, [list(o) for _, o in part], pure=False):
                   [cid for cid, _ in part] for part in parts}
        for fut in as_completed(futures):
            cids = futures.pop(fut)
            try:
                yield cids, fut.result()
            except Exception as exc:  # the worker itself died (e.g. KilledWorker)
                yield cids, [Outcome(error=f"{type(exc).__name__}: {exc}")] * len(cids)


CHUNK_VALUES = 20_000_000  # recorded values a task's chunk of cases holds at most (160 MB)
PER_WORKER = 8  # chunks per worker: results come back while the others run (measured best)


def chunks(todo: Sequence[tuple[str, Sequence[str]]], scenario: Scenario, workers: int
           ) -> list[list[tuple[str, Sequence[str]]]]:
    """The cases `todo` of `scenario` cut into chunks, a task each: about `PER_WORKER` chunks per
    worker of `workers` (so that results come back, and are written, while the workers run the
    next chunks, and a slow chunk does not hold the others back), each holding at most
    `CHUNK_VALUES` recorded values (rows x recorded signals: the case's results, and their rows
    as text, wait on the worker until sent)."""
    per_case = (scenario.n_steps + 1) * (len(scenario.recorded()) + 1)
    size = max(1, min(-(-len(todo) // (PER_WORKER * max(1, workers))), CHUNK_VALUES // per_case))
    return [list(todo[k:k + size]) for k in range(0, len(todo), size)]
