"""The sim-to-real gap diagnosis: why does a model not match its bench?

The data path is a measured data set (``load_dataset``: data.csv + manifest.toml, checked against
its scenario; ``write_data_set`` writes one) -> ``diagnose`` (where the model misses, which
unmodelled effect of ``EFFECTS`` explains it, how far the held-out gap shrinks), giving a
``Report`` (frozen sections; ``Report.to_json()`` is report.json's document) ->
``write_report`` (report.json, report.md, plots). ``calibrate`` fits the open values a
scalar-only set names to its training metrics and predicts the held-out ones (module
openvalues).

Modules: dataset (measured data sets), effects (the effect library and the per-component
knowledge the diagnosis uses), thresholds (every threshold, documented), problem (the units
simulated against the data), simulate, stats, regimes, fitting, parameters (the calibration
parameters), candidates, judging, aliasing, scoring and consistency (the candidates and their
fits described), evidence and weigh (the candidates' evidence, probabilities and the verdict),
stages (what the stages hand each other), which (section 4), sections (the `Report`), pipeline
(`diagnose`), report (the files); conformal (split-conformal sets, conformal p-values, a
conditional logit: statistics on arrays) and confidence (the sets, probabilities and gate of a
calibration on a family of benches, applied to a report; ``load_confidence`` reads the one
shipped for a scenario).

The stages' building blocks are public too, for the blind benchmark above this layer
(`musclesim.benchmark`), which records cases, fits its oracle and scores the diagnosis with them:
``Problem`` (the units simulated against data), ``simulate_unit`` (parameter values applied by
`musclesim.cosim.with_values`),
``residuals`` and ``Failed`` (runs), ``gap`` (the normalised RMS gap of a ``Part``, ``TRAIN`` or
``HELD_OUT``), ``fit``, ``Free`` and ``values_of`` (bounded least squares of free parameters),
``calibration`` (the calibration parameters of a unit) and ``find_effect``.
"""
from musclesim.diagnosis.openvalues import bound_sentence as calibration_bound_sentence
from musclesim.diagnosis.openvalues import calibrate
from musclesim.diagnosis.openvalues import markdown as calibration_markdown
from musclesim.diagnosis.dataset import DataSet
from musclesim.diagnosis.dataset import load as load_dataset
from musclesim.diagnosis.dataset import write as write_data_set
from musclesim.diagnosis.effects import EFFECTS, REGIMES, Effect
from musclesim.diagnosis.effects import find as find_effect
from musclesim.diagnosis.fitting import Free, fit, values_of
from musclesim.diagnosis.pipeline import diagnose
from musclesim.diagnosis.problem import Problem
from musclesim.diagnosis.report import write as write_report
from musclesim.diagnosis.sections import Report
from musclesim.diagnosis.parameters import calibration
from musclesim.diagnosis.simulate import Failed, Simulated, residuals
from musclesim.diagnosis.simulate import simulate as simulate_unit
from musclesim.diagnosis.stats import HELD_OUT, TRAIN, Part, gap
from musclesim.diagnosis.weigh import CALIBRATION_ONLY
from musclesim.diagnosis.confidence import (ANOTHER_PAIR, FEATURES, OUTSIDE_LIBRARY, TWO_EFFECTS,
                                            Confidence, alternatives, case_features)
from musclesim.diagnosis.confidence import features as confidence_features
from musclesim.diagnosis.confidence import load as load_confidence
from musclesim.diagnosis.conformal import (Outlyingness, choice_probabilities, choose_ridge,
                                           conformal_p_value, fit_choice, mondrian_thresholds,
                                           prediction_set, reliability)

__all__ = ["load_dataset", "DataSet", "write_data_set", "diagnose", "Report", "write_report",
           "calibrate",
           "calibration_markdown", "calibration_bound_sentence", "EFFECTS",
           "REGIMES", "Effect", "find_effect", "Problem", "simulate_unit",
           "residuals", "Failed", "Simulated", "gap", "fit", "Free", "values_of", "calibration", "Part",
           "TRAIN", "HELD_OUT", "CALIBRATION_ONLY", "TWO_EFFECTS", "OUTSIDE_LIBRARY",
           "ANOTHER_PAIR", "FEATURES", "confidence_features", "Confidence", "alternatives", "case_features",
           "load_confidence", "Outlyingness", "choice_probabilities", "conformal_p_value",
           "choose_ridge", "fit_choice", "mondrian_thresholds", "prediction_set", "reliability"]
