"""The calibrated sets applied to a report (musclesim.diagnosis.confidence): the alternatives and
their features read from report.json documents, the set by its thresholds, the gate."""
import math

import numpy as np
import pytest

from musclesim.diagnosis import (ANOTHER_PAIR, CALIBRATION_ONLY, FEATURES, OUTSIDE_LIBRARY,
                                 TWO_EFFECTS, Confidence, Outlyingness, alternatives,
                                 case_features, confidence_features, load_confidence)

SINGLES = ["thermocouple bias", "latent heat"]
SIGNALS = ["tc.T", "wire.strain"]


def doc_with_evidence():
    cand = lambda name, logz, p, gap: {  # noqa: E731
        "name": name, "log_evidence": logz, "probability": p, "heldout_gap_all": gap,
        "heldout_gap": {"tc.T": gap, "wire.strain": gap * 2},
        "parameters": {"tc.bias": {"value": 10.0, "lower": -10.0, "upper": 10.0}}}
    return {"verdict": "thermocouple bias", "noise_floor": 0.002, "complete": False,
            "gap": {"heldout_gap": 0.02, "noise_floor": 0.002,
                    "signals": {"tc.T": {"noise": 0.002}, "wire.strain": {"noise": 0.002}}},
            "calibration": {"heldout_gap_after": 0.01, "parameters": {}},
            "effects": [{"name": "latent heat", "shrinkage": 0.2,
                         "judged": {"significant": True}, "signature": {"consistent": True},
                         "per_signal": {"tc.T": {"before": 0.01, "after": 0.005}}},
                        {"name": "stress dependence ignored"}],
            "evidence": {"candidates": [cand(CALIBRATION_ONLY, 100.0, 0.0, 0.01),
                                        cand("thermocouple bias", 110.0, 1.0, 0.005),
                                        cand("thermocouple bias + latent heat", 104.0, 0.0,
                                             0.004)],
                         "symmetries": [{"candidates": ["thermocouple bias",
                                                        CALIBRATION_ONLY]}],
                         "discrepancy": {"tc.T": {"sigma": 0.004}}},
            "shrinkage": {"all": {"after": 0.005}},
            "regimes": {"by_regime": {"all": {"gap": 0.01}, "hot": {"gap": 0.02}}}}


def test_the_alternatives_of_a_report_and_their_features():
    alts = alternatives(doc_with_evidence(), SINGLES, SIGNALS)
    names = [a[0] for a in alts]
    assert names == [CALIBRATION_ONLY, "thermocouple bias", "latent heat",
                     "stress dependence ignored", "thermocouple bias + latent heat",
                     ANOTHER_PAIR, OUTSIDE_LIBRARY]
    causes = [a[1] for a in alts]
    assert causes[4:] == [TWO_EFFECTS, TWO_EFFECTS, OUTSIDE_LIBRARY]
    assert all(len(a[2]) == len(confidence_features(SINGLES, SIGNALS)) for a in alts)
    f = {name: dict(zip(confidence_features(SINGLES, SIGNALS), a[2])) for name, _, a in
         [(a[0], None, a) for a in alts]}
    bias = f["thermocouple bias"]
    assert bias["most probable"] == 1 and bias["log evidence to best"] == 0
    assert bias["mimicked by calibration"] == 1 and bias["on a bound"] == 1
    assert bias["held-out gain"] == pytest.approx(math.log(2))
    assert bias["gain on tc.T"] == pytest.approx(math.log(2))
    assert bias["is thermocouple bias"] == 1 and bias["is latent heat"] == 0
    assert bias["held-out gain if thermocouple bias"] == pytest.approx(math.log(2))
    hot = dict(zip(confidence_features(SINGLES, SIGNALS, ["hot"]),
                   alternatives(doc_with_evidence(), SINGLES, SIGNALS, ["hot"])[1][2]))
    assert hot["gap hot if thermocouple bias"] == pytest.approx(math.log(2))
    assert hot["gap hot if latent heat"] == 0
    assert f[CALIBRATION_ONLY]["log evidence to best"] == pytest.approx(-math.log1p(10))
    latent = f["latent heat"]  # not weighed: its own fit describes it
    assert latent["fitted"] == 0 and latent["effect's gain"] == 0.2
    assert latent["gains clearly"] == 1 and latent["gain on tc.T"] == pytest.approx(math.log(2))
    assert f[OUTSIDE_LIBRARY]["gap left"] == pytest.approx(math.log(2.5))
    assert f[OUTSIDE_LIBRARY]["structured gap left"] == 1
    # a cause the calibration does not know has no cause's features
    assert not any(v for k, v in f["stress dependence ignored"].items() if " if " in k
                   or k.startswith("is "))


def test_an_effect_fitted_per_instance_is_an_alternative_per_instance():
    """The crawler's anchoring slip is fitted on each block apart: each fit is a candidate named
    by its label, and each is an alternative with that candidate's evidence."""
    doc = doc_with_evidence()
    doc["effects"] = [{"name": "anchoring slip", "label": f"anchoring slip ({b})",
                       "shrinkage": 0.1} for b in ("friction1", "friction2")]
    cands = doc["evidence"]["candidates"]
    cands.append({**cands[1], "name": "anchoring slip (friction2)", "probability": 0.5})
    alts = {a[0]: dict(zip(confidence_features(SINGLES, SIGNALS), a[2]))
            for a in alternatives(doc, SINGLES, SIGNALS)}
    assert "anchoring slip" not in alts
    assert alts["anchoring slip (friction2)"]["posterior"] == 0.5
    assert alts["anchoring slip (friction2)"]["effect's gain"] == 0.1
    assert alts["anchoring slip (friction1)"]["fitted"] == 0  # no candidate of its own here
    assert alts["anchoring slip (friction1)"]["effect's gain"] == 0.1


def test_an_effect_whose_fit_failed_gains_nothing_and_leaves_every_feature_finite():
    """A fit whose run failed leaves an infinite held-out gap, its shrinkage -inf in
    report.json (a crawler pool case had one): the features stay finite."""
    doc = doc_with_evidence()
    doc["effects"][0].update(shrinkage=-math.inf, judged=None)
    alts = {a[0]: a[2] for a in alternatives(doc, SINGLES, SIGNALS)}
    assert all(np.isfinite(f).all() for f in alts.values())
    assert dict(zip(confidence_features(SINGLES, SIGNALS),
                    alts["latent heat"]))["effect's gain"] == 0


def test_a_report_that_stopped_early_has_calibration_only_alone_weighed():
    doc = {"verdict": "recalibration", "noise_floor": 0.002,
           "gap": {"heldout_gap": 0.004, "noise_floor": 0.002},
           "calibration": {"heldout_gap_after": 0.002, "parameters": {}}, "effects": []}
    alts = alternatives(doc, SINGLES, SIGNALS)
    f = dict(zip(FEATURES, alts[0][2]))
    assert alts[0][0] == CALIBRATION_ONLY and f["stopped early"] == 1
    assert all(dict(zip(FEATURES, a[2]))["fitted"] == 0 for a in alts)
    assert case_features(doc)[:2] == [pytest.approx(math.log(2)), 0.0]


def calibration_doc(thresholds, gate_scores):
    n = len(confidence_features(SINGLES, SIGNALS))
    weights = np.zeros(n)
    weights[list(confidence_features(SINGLES, SIGNALS)).index("most probable")] = 3.0
    scale = Outlyingness.fit(np.array([[0, 0, 0, 0, 0, 0], [1, 1, 1, 1, 1, 1],
                                       [2, 0, 1, 0, 1, 0.5]], float))
    return {"name": "test", "fingerprint": "x", "family": {"cases": 3}, "cases": 3,
            "created": "2026-11-29", "alpha": 0.05, "singles": SINGLES, "signals": SIGNALS,
            "causes": [CALIBRATION_ONLY, *SINGLES, TWO_EFFECTS, OUTSIDE_LIBRARY], "regimes": [],
            "weights": weights.tolist(), "thresholds": thresholds,
            "gate": {"alpha": 0.3, "outlyingness": scale.to_json(), "scores": gate_scores}}


def test_the_set_holds_each_cause_whose_score_is_within_its_threshold():
    conf = Confidence(calibration_doc({}, [0.0]))
    probs = conf.assess(doc_with_evidence())["probabilities"]
    assert sum(probs.values()) == pytest.approx(1 - conf.probabilities(doc_with_evidence())[1][
        "stress dependence ignored"])
    top = max(probs, key=probs.get)
    assert top == "thermocouple bias"
    q = {k: 1 - probs[k] + 1e-12 for k in probs}  # each cause just in
    q["latent heat"] = 1 - probs["latent heat"] - 1e-9  # this one just out
    got = Confidence(calibration_doc(q, [0.0])).assess(doc_with_evidence())
    assert got["set"] == [k for k in conf.causes if k != "latent heat"]
    assert got["level"] == 0.95 and got["calibration"]["name"] == "test"


def test_the_gate_is_a_conformal_p_value_of_the_case_against_the_family():
    far = Confidence(calibration_doc({}, [0.1, 0.2, 0.3])).assess(doc_with_evidence())["gate"]
    assert far == {"outside": True, "p_value": 0.25, "alpha": 0.3}  # stranger than all three
    near = Confidence(calibration_doc({}, [1e9] * 3)).assess(doc_with_evidence())["gate"]
    assert near["outside"] is False and near["p_value"] == 1.0


def test_a_scenario_without_a_calibration_has_none():
    assert load_confidence("no-such-scenario") is None
