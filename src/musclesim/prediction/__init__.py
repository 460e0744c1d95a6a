"""Predictions with 90 % intervals of the scenarios' outcomes (§predictions): what the model
predicts for each metric of a declared set of scenarios, with an interval from the shipped fit's
uncertainty and the spread of the diagnosis's alternative models, shipped as data.

The data path is a declaration (``load_declaration``: scenarios/predictions/<name>.toml, the fit
the scenarios ship, the alternative models, the scenarios, the study's values) -> ``predict``
(the document: the fit's covariance, the models, per scenario and metric the value, its
interval and the study's) -> scenarios/predictions/<name>.json, which ``summary_entry`` reads
into a run's summary.json when the run is the one the predictions were made for.
``fingerprint`` is of the predictions' inputs (a shipped set made from others is stale; a test
checks it).

The layer sits above the diagnosis, whose fits it uses, beside the benchmark; modules:
declaration (the file and the fingerprint), propagate (the arithmetic: covariance, linearised
propagation, admission of a model, the interval), compute (``predict``: the runs), shipped (the
shipped files as a run's summary reads them; it imports nothing above `musclesim.cosim`).
"""
from musclesim.prediction.compute import predict
from musclesim.prediction.declaration import Declaration, fingerprint
from musclesim.prediction.declaration import load as load_declaration
from musclesim.prediction.propagate import (ADMIT, LEVEL, STEP, Z, admitted, covariance,
                                            interval, outcome_sd, points)
from musclesim.prediction.shipped import SUMMARY_KEY, describe, folder, made_for, summary_entry

__all__ = ["predict", "Declaration", "load_declaration", "fingerprint", "LEVEL", "Z", "ADMIT",
           "STEP", "covariance", "outcome_sd", "points", "admitted", "interval", "SUMMARY_KEY",
           "summary_entry", "describe", "made_for", "folder"]
