"""One co-simulation run: build the FMUs, host them in this process, read and check a scenario
file, step it with the master algorithm, write its results, export it (as SSP, or as one FMU),
read time series. A scenario's data flow (`Graph`: which instance feeds which) serves the master
and the diagnosis.

The data path of a run is ``load_scenario`` -> ``Master(...).run()`` -> ``write_results``;
``run_scenario`` does all three (with the freshness check of the FMUs) for the command line and
for every case of a sweep, writing the rows as the run goes. What every layer's outputs rely on
lives here too: output paths checked before the work (``check_output_dir``,
``check_output_file``), files replaced whole (``replace_file``, ``save_figure``), and stopping on
SIGINT or SIGTERM at the next step with what was written kept (``interruptible``, raising
``Interrupted``).
"""
from musclesim.cosim.address import ParamRef, Signal
from musclesim.cosim.build import build_all, check_fresh, source_digest
from musclesim.cosim.graph import Graph, Link
from musclesim.cosim.host import forget_fmu_resource_paths, read_fmu, reuse_fmus
from musclesim.cosim.interrupt import Interrupted, interruptible
from musclesim.cosim.master import Master
from musclesim.cosim.outputs import (check_output_dir, check_output_file, replace_file,
                                     save_figure)
from musclesim.cosim.results import compute_metrics, metric_unit, signal_units
from musclesim.cosim.results import write_all as write_results
from musclesim.cosim.run import run_scenario
from musclesim.cosim.results import Results, clear_run_outputs
from musclesim.cosim.scenario import (Instance, Metric, Panel, Scenario, apply_overrides,
                                      with_values)
from musclesim.cosim.scenario_files import FORMAT, format_problem, renamed_signals
from musclesim.cosim.scenario import load as load_scenario
from musclesim.cosim.container import export as export_fmu
from musclesim.cosim.ssp import export as export_ssp
from musclesim.cosim.timeseries import read_time_series

__all__ = ["Signal", "ParamRef", "with_values", "build_all", "check_fresh", "source_digest", "forget_fmu_resource_paths", "read_fmu",
           "reuse_fmus",
           "Master", "compute_metrics", "metric_unit", "signal_units", "write_results",
           "run_scenario", "FORMAT", "Instance", "Metric", "Panel", "Scenario", "Results",
           "load_scenario",
           "format_problem", "renamed_signals",
           "apply_overrides", "export_ssp", "export_fmu",
           "Graph", "Link",
           "read_time_series", "Interrupted", "interruptible", "check_output_dir",
           "check_output_file", "replace_file", "save_figure", "clear_run_outputs"]
