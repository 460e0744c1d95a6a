"""The sim-to-real gap diagnosis: why does a model not match its bench?

The data path is a measured data set (``load_dataset``: data.csv + manifest.toml, checked against
its scenario) -> ``diagnose`` (where the model misses, which unmodelled effect of ``EFFECTS``
explains it, how far the held-out gap shrinks) -> ``write_report`` (report.json, report.md,
plots). ``run_blind_benchmark`` checks the diagnosis blind on virtual hardware with hidden
effects, and ``write_data_set`` writes a recorded data set in the format ``load_dataset`` reads.

Modules: dataset (measured data sets), effects (the effect library and the per-component
knowledge the diagnosis uses), thresholds (every threshold, documented), problem (the units
simulated against the data), simulate, stats, regimes, fitting, selection (the stages'
work), pipeline (`diagnose`), report (the files), blind (the benchmark), independent,
independent_crawler and independent_plan (the benchmark's SMA and crawler benches written apart
from the library, and their cases).
"""
from musclesim.diagnosis.blind import run as run_blind_benchmark
from musclesim.diagnosis.blind import write_data_set
from musclesim.diagnosis.dataset import DataSet
from musclesim.diagnosis.dataset import load as load_dataset
from musclesim.diagnosis.effects import EFFECTS, REGIMES, Effect
from musclesim.diagnosis.pipeline import diagnose
from musclesim.diagnosis.report import write as write_report

__all__ = ["load_dataset", "DataSet", "diagnose", "write_report", "run_blind_benchmark",
           "write_data_set", "EFFECTS", "REGIMES", "Effect"]
