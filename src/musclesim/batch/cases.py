"""Case folders: one run of a scenario per folder, on Dask, resumable.

An output folder ``out`` holds ``out/sweep.json`` (what its cases come from, written by `claim`)
and one folder per case, ``out/cases/<id>/``, with the run's results and its ``summary.json``
(``"completed": true`` and the metrics, or ``"completed": false`` and the ``"error"``). A case
whose summary says it completed is `finished` and is not run again; `run_cases` runs the others
on a Dask cluster. Sweeps (`sweep.run`) and the study's tables (``musclesim.analysis``) use them.
"""
import hashlib
import json
from pathlib import Path

from musclesim.batch.cluster import dask_client
from musclesim.cosim import replace_file
from musclesim.errors import UserError


def write_failure(case_dir, error):
    """Record in case_dir/summary.json that the case failed with `error`; return that summary."""
    summary = {"completed": False, "error": error}
    Path(case_dir).mkdir(parents=True, exist_ok=True)
    replace_file(Path(case_dir) / "summary.json", json.dumps(summary, indent=2) + "\n")
    return summary


def run_case(scenario_path, case_dir, fmu_dir, overrides, stop_time):
    """Run one case into `case_dir` (on a Dask worker); return its summary, failed or not."""
    from musclesim.cosim import run_scenario

    try:
        # no per-case plot: drawing it costs about a third of a 60 s case; sweep.png summarises
        summary, _ = run_scenario(scenario_path, case_dir, fmu_dir, overrides, stop_time,
                                  with_plot=False)
    except UserError as exc:
        return write_failure(case_dir, str(exc))
    except Exception as exc:  # whatever breaks one case is recorded; the sweep goes on
        return write_failure(case_dir, f"{type(exc).__name__}: {exc}")
    return summary


def case_summary(case_dir):
    """The summary of a case that ran (completed or failed), else None (no summary.json, or not
    a JSON object)."""
    try:
        summary = json.loads((Path(case_dir) / "summary.json").read_text())
    except (OSError, ValueError):
        return None
    return summary if isinstance(summary, dict) else None


def finished(case_dir):
    """The summary of a case that completed (``"completed": true``), else None."""
    summary = case_summary(case_dir)
    return summary if summary is not None and summary.get("completed") is True else None


def claim(out, scenario_path, **settings):
    """Record in out/sweep.json what the cases come from (the scenario file and its hash, the
    FMUs' sources, `settings`), refusing a folder whose cases came from something else.

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


def run_cases(todo, submit, scheduler, workers, record):
    """Run the cases `todo` on Dask (a LocalCluster unless `scheduler` is given), recording each
    as it finishes.

    Parameters
    ----------
    todo : list of (case id, point)
        The cases to run; `point` is whatever `submit` and `record` need.
    submit : callable
        ``submit(case id, point)`` -> the arguments of `run_case` (its case folder second).
    scheduler : str or None
        Address of a running Dask scheduler.
    workers : int or None
        Worker processes of the local cluster (default: the cores, at most one per case).
    record : callable
        ``record(case id, point, summary)``, called in this process as each case ends (a case
        whose worker died gets a failure summary written into its folder).
    """
    from distributed import as_completed
    from tqdm import tqdm

    with dask_client(scheduler, workers, len(todo)) as client:
        futures = {client.submit(run_case, *submit(cid, point), pure=False): (cid, point)
                   for cid, point in todo}
        for fut in tqdm(as_completed(futures), total=len(futures), desc="sweep", unit="case"):
            cid, point = futures.pop(fut)
            try:
                summary = fut.result()
            except Exception as exc:  # the worker itself died (e.g. KilledWorker)
                summary = write_failure(submit(cid, point)[1], f"{type(exc).__name__}: {exc}")
            record(cid, point, summary)
