"""Many runs: the Dask cluster and maps, case folders, parameter sweeps.

The layer above a single co-simulation run (``musclesim.cosim``) and below the studies that need
many of them (``musclesim.analysis``, ``musclesim.hysteresis``, ``musclesim.diagnosis``):

- `cluster`: the one place for Dask: `dask_client` (a local cluster or a running scheduler,
  whose workers keep FMUs unpacked: `plugins`), `dask_map` (a ``pmap(fn, items)`` over it,
  callable from several threads) and `serial_map` (the same, in this process), `cluster_map`
  (either, as the command line's options ask: `in_process` for one worker); `ship_fmus`
  sends the workers an FMU folder as bytes (`shipped`: the `FmuFolder` tasks carry in its
  place), so that they need none of the client's files;
- `cases`: case folders, one run per folder, resumable: `claim` an output folder for one set of
  settings, `run_cases` on Dask (its cases cut into `chunks`, each a `run_chunk` on a worker:
  one compiled pass where they fuse; every case's `Outcome` written here by `write_case`), read
  back a `case_summary`, skip the `finished` ones;
- `sweep`: `musclesim sweep`: sweep files (`load_sweep`), grid axes (`parse_axis`,
  `grid_cases`), `run_sweep` with its CSV and plot.
"""
from musclesim.batch.cases import (Outcome, case_summary, chunks, claim, finished, run_case,
                                   run_cases, run_chunk, write_case, write_failure)
from musclesim.batch.cluster import (cluster_map, dask_client, dask_map, in_process, serial_map,
                                     ship_fmus)
from musclesim.batch.shipped import FmuFolder
from musclesim.batch.sweep import Sweep, grid_cases, parse_axis
from musclesim.batch.sweep import load as load_sweep
from musclesim.batch.sweep import run as run_sweep

__all__ = ["dask_client", "dask_map", "serial_map", "cluster_map", "in_process", "ship_fmus",
           "FmuFolder",
           "claim", "case_summary", "finished", "write_failure", "Outcome", "run_case",
           "run_chunk", "chunks", "write_case", "run_cases",
           "Sweep", "load_sweep", "parse_axis", "grid_cases", "run_sweep"]
