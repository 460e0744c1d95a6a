"""Scoring the blind benchmark (musclesim.benchmark.scoring): the scores of hand-made verdicts
against their key, per case and per bench, and their place in scores.json."""
import json

import pytest

from musclesim.benchmark import scoring

from conftest import schema_errors


def evidence(probabilities, credible):
    """A report's evidence section holding only what the scores read."""
    return {"candidates": [{"name": n, "probability": p} for n, p in probabilities.items()],
            "set": credible}


def test_scores_of_the_independent_bench_and_their_place_in_scores_json(tmp_path):
    cases = [{"case": "a", "kind": "none", "bench": "independent", "effect": None, "values": {}},
             {"case": "b", "kind": "outside", "bench": "independent", "effect": "draught",
              "values": {}},
             {"case": "c", "kind": "outside", "bench": "independent", "effect": "two effects",
              "values": {}, "pair": ["latent heat", "thermocouple lag"]},
             {"case": "d", "kind": "effect", "bench": "independent", "effect": "latent heat",
              "values": {}},
             {"case": "e", "kind": "outside", "bench": "independent", "effect": "clamp slip",
              "values": {}},
             {"case": "f", "kind": "effect", "bench": "independent",
              "effect": "thermocouple bias", "values": {}}]
    cal = "calibration only"
    reports = [{"verdict": "recalibration", "complete": True},  # stopped at calibration
               {"verdict": "convection change", "complete": False},  # incomplete: counts
               {"verdict": "latent heat or thermocouple lag", "complete": True,  # both: counts
                "evidence": evidence({"latent heat": 0.6, "thermocouple lag": 0.35, cal: 0.05},
                                     ["latent heat", "thermocouple lag"])},
               {"verdict": "latent heat", "complete": False,
                "evidence": evidence({"latent heat": 0.9, "clamp heat loss": 0.1},
                                     ["latent heat"])},
               {"verdict": "clamp heat loss", "complete": True},  # fully "explained": a miss
               # the bias not told from a recalibration: in the set, not first
               {"verdict": "calibration only or thermocouple bias", "complete": False,
                "evidence": evidence({cal: 0.5, "thermocouple bias": 0.45, "latent heat": 0.05},
                                     [cal, "thermocouple bias"])}]
    gaps = [{"before": 0.1, "oracle": None, "ours": 0.1}] * 3 + [
        {"before": 0.1, "oracle": 0.02, "ours": 0.04},
        {"before": 0.1, "oracle": None, "ours": 0.05},
        {"before": 0.1, "oracle": None, "ours": 0.1}]
    ind = scoring.score(cases, reports, gaps)
    # keyed: a (calibration only, certain), d (in, size 1, top), f (in, size 2, not top)
    assert ind["truth_in_set"] == 1.0 and ind["mean_set_size"] == pytest.approx(4 / 3)
    assert ind["size_weighted_accuracy"] == pytest.approx((1 + 1 + 0.5) / 3)
    assert ind["top1_accuracy"] == 0.5 and ind["false_alarm_rate"] == 0.0
    # Brier: a 0; d (0.9-1)^2 + 0.1^2; f 0.5^2 + (0.45-1)^2 + 0.05^2
    assert ind["brier"] == pytest.approx((0 + 0.02 + 0.25 + 0.3025 + 0.0025) / 3)
    assert ind["unexplained_rate"] == pytest.approx(2 / 3)  # b and c, not e
    assert ind["shrinkage_vs_oracle"] == pytest.approx(0.75)
    assert ind["per_effect"]["thermocouple bias"] == {"cases": 1, "in_set": 1.0, "top1": 0.0}
    assert ind["macro_in_set"] == 1.0 and ind["micro_in_set"] == 1.0
    # every candidate's probability against whether it was the truth, in tenths
    bins = {tuple(b["bin"]): b for b in ind["reliability"]}
    assert bins[(0.9, 1.0)] == {"bin": [0.9, 1.0], "count": 2, "predicted": 0.95,
                                "observed": 1.0}
    assert [b["count"] for b in ind["reliability"]] == [1, 1, 1, 1, 2]  # 0.05 .1 .45 .5 .9 1
    assert bins[(0.4, 0.5)]["observed"] == 1.0 and bins[(0.5, 0.6)]["observed"] == 0.0
    # a case without an effect whose set leaves calibration out is a false alarm
    alarm = scoring.score(cases[:1], [{"verdict": "latent heat", "evidence": evidence(
        {"latent heat": 0.95, cal: 0.05}, ["latent heat"])}], gaps[:1])
    assert alarm["false_alarm_rate"] == 1.0 and alarm["per_case"][0]["brier"] == \
        pytest.approx(2 * 0.95 ** 2)
    path = tmp_path / "scores.json"
    scoring.write_scores(path, alarm, "own")
    scoring.write_scores(path, ind, "independent")
    scoring.write_scores(path, alarm, "own")  # each run keeps the other's part
    written = json.loads(path.read_text())
    assert written["false_alarm_rate"] == 1.0
    assert written["independent"]["bench"] == "independent"
    assert written["independent"]["false_alarm_rate"] == 0.0
    assert schema_errors("scores", written) == []
    assert "by_bench" not in ind  # one bench: no breakdown
    crawler = {"case": "c", "kind": "none", "bench": "independent-crawler", "effect": None,
               "values": {}}
    both = scoring.score(cases + [crawler], reports + [
        {"verdict": "valve delay", "evidence": evidence({"valve delay": 1.0}, ["valve delay"])}],
        gaps + [gaps[0]])
    assert both["false_alarm_rate"] == pytest.approx(0.5)  # pooled over the two benches
    assert both["by_bench"]["independent-crawler"]["false_alarm_rate"] == 1.0
    assert both["by_bench"]["independent"] == {k: v for k, v in ind.items() if k != "per_case"}


def test_the_calibrated_sets_are_judged_by_the_cause_of_each_case(tmp_path):
    """Where a report has the calibrated set of causes beside the posterior's credible set, the
    scores judge it too: a pair outside the library counts as `two effects`, another change
    outside it as `outside the library`, nothing hidden as `calibration only`."""
    kinds = [("none", None, None), ("outside", "two effects", ["latent heat", "thermocouple lag"]),
             ("outside", "draught", None), ("effect", "latent heat", None),
             ("decoy", "thermocouple bias", None)]
    cases = [{"case": str(i), "kind": k, "bench": "independent", "effect": e, "values": {},
              **({"pair": p} if p else {})} for i, (k, e, p) in enumerate(kinds)]
    sets = [["calibration only", "latent heat"], ["two effects"], ["latent heat"],
            ["latent heat", "thermocouple bias", "two effects"], ["thermocouple bias"]]
    reports = [{"verdict": "latent heat", "complete": True,
                "evidence": {**evidence({"latent heat": 1.0}, s), "credible": ["latent heat"],
                             "calibration": {"name": "test"},
                             "gate": {"outside": i == 4, "p_value": 0.5}}}
               for i, s in enumerate(sets)]
    reports.append({"verdict": "recalibration", "complete": True})  # no calibrated set
    cases.append({**cases[0], "case": "uncalibrated"})
    got = scoring.score(cases, reports, [{"before": 0.1, "oracle": None, "ours": 0.1}] * 6)
    assert [t["calibrated"]["in_set"] for t in got["per_case"][:5]] == \
        [True, True, False, True, True]
    assert "calibrated" not in got["per_case"][5]
    assert got["calibrated"] == {"cases": 5, "truth_in_set": 0.8, "mean_set_size": 1.6,
                                 "gate_rate": 0.2}
    # the posterior's credible set is scored as before: latent heat alone in every report
    assert got["per_case"][3]["in_set"] and not got["per_case"][4]["in_set"]
    path = tmp_path / "scores.json"
    scoring.write_scores(path, got, "independent")
    assert schema_errors("scores", json.loads(path.read_text())) == []
