"""One co-simulation run: build the FMUs, host them in this process, read and check a scenario
file (or one shipped with musclesim, found by its name: ``locate_scenario``), step it with the master algorithm, write its results, read time series. Addresses are
typed: a `Signal` (instance, variable) and a `ParamRef` (instance, parameter), parsed once from
the files' ``"instance.name"`` strings; a scenario's data flow (`Scenario.graph`, a `Graph` of
`Link`\\ s: which instance feeds which) serves the master and the diagnosis; `with_values` is the
one way parameter values reach a scenario, `implausible` says which of them a component declares
implausible (a temperature in Celsius), and `unknown_instance` answers a name no instance has
with the nearest one. Exporting a scenario for other tools (SSP, one FMU)
is the layer above, ``musclesim.export``.

The data path of a run is ``load_scenario`` -> ``Master(...).run()`` (`Results`) ->
``write_results``; where every instance is one of our compiled kernels on the direct host the
master runs its steps fused, in one compiled loop written for the scenario's wiring
(``musclesim.cosim.fused``), and ``run_cases`` runs many parameter sets of one scenario in one
such pass, one thread per case; ``run_scenario`` does all three (with the freshness check of the FMUs) for the
command line and for every case of a sweep, writing the rows as the run goes. What every layer's
outputs rely on lives here too: output paths checked before the work (``check_output_dir``,
``check_output_file``, ``check_archive``), files replaced whole (``replace_file``,
``replace_zip``, ``save_figure``), long signals reduced for plotting (``envelope``), a run's
outputs removed together (``clear_run_outputs``), and
stopping on SIGINT or SIGTERM at the next step with what was written kept (``interruptible``,
raising ``Interrupted``).
"""
from musclesim.cosim.adapters import KINDS
from musclesim.cosim.address import ParamRef, Signal
from musclesim.cosim.build import build_all, check_fresh, source_digest
from musclesim.cosim.graph import Graph, Link
from musclesim.cosim.host import forget_fmu_resource_paths, read_fmu, reuse_fmus
from musclesim.cosim.interrupt import Interrupted, interruptible
from musclesim.cosim.interrupt import requested as interrupt_requested
from musclesim.cosim.loader import compile_loader, loader_unavailable
from musclesim.cosim.cases import run_cases
from musclesim.cosim.master import Master, signal_units
from musclesim.cosim.outputs import (check_archive, check_output_dir, check_output_file,
                                     envelope, replace_file, replace_zip, save_figure)
from musclesim.cosim.results import (Results, clear_run_outputs, compute_metrics, csv_rows,
                                     metric_unit)
from musclesim.cosim.results import write_all as write_results
from musclesim.cosim.run import run_scenario
from musclesim.cosim.scenario import (Instance, Metric, Panel, Scenario, apply_overrides,
                                      implausible, unknown_instance, with_values)
from musclesim.cosim.scenario import load as load_scenario
from musclesim.cosim.scenario_files import FORMAT, format_problem, renamed_signals
from musclesim.cosim.scenario_files import locate as locate_scenario
from musclesim.cosim.scenario_files import shipped_dir as shipped_scenarios
from musclesim.cosim.timeseries import read_time_series

__all__ = ["Signal", "ParamRef", "with_values",
           "build_all", "check_fresh", "source_digest", "loader_unavailable", "compile_loader",
           "forget_fmu_resource_paths", "read_fmu", "reuse_fmus",
           "FORMAT", "Instance", "Metric", "Panel", "Scenario", "load_scenario", "apply_overrides",
           "locate_scenario", "shipped_scenarios", "implausible", "unknown_instance",
           "format_problem", "renamed_signals", "Graph", "Link",
           "Master", "Results", "KINDS", "run_scenario", "run_cases",
           "compute_metrics", "metric_unit", "signal_units", "write_results", "csv_rows",
           "clear_run_outputs", "read_time_series", "Interrupted", "interruptible", "interrupt_requested",
           "check_output_dir", "check_output_file", "check_archive", "replace_file", "replace_zip",
           "save_figure", "envelope"]
