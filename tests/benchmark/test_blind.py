"""The blind benchmark's run (musclesim.benchmark.blind): a few cases diagnosed blind with the key
sealed first, on the own benches and on the independent one."""
import hashlib
import json

import pytest

from musclesim.benchmark import blind

from conftest import ROOT, SCENARIOS, schema_errors


def test_blind_benchmark_on_three_cases(fmu_dir, tmp_path, cluster_map):
    """A null, an out-of-library and a decoy case, diagnosed blind; the key is sealed first."""
    scores = blind.run(3, seed=4, out=tmp_path, fmu_dir=fmu_dir, scenarios_dir=SCENARIOS,
                       pmap=cluster_map)
    key = (tmp_path / "key.json").read_text()
    assert (tmp_path / "key.sha256").read_text() == \
        hashlib.sha256(key.encode()).hexdigest() + "  key.json\n"
    kinds = sorted(row["kind"] for row in scores["per_case"])
    assert kinds == ["decoy", "none", "outside"]
    for case in json.loads(key)["cases"]:  # the data a case holds say nothing of its truth
        manifest = (tmp_path / "cases" / case["case"] / "manifest.toml").read_text()
        assert case["kind"] not in manifest and (case["effect"] or "none") not in manifest
    saved = json.loads((tmp_path / "scores.json").read_text())
    assert schema_errors("scores", saved) == []
    assert saved["top1_accuracy"] == 1.0
    assert saved["false_alarm_rate"] == 0.0
    assert saved["unexplained_rate"] == 1.0
    assert saved["shrinkage_vs_oracle"] > 0.8


def test_a_small_blind_run_on_the_independent_bench(fmu_dir, tmp_path, cluster_map):
    """Seed 102's four cases (20 s each; a seed first run after the evidence method was frozen):
    no hidden effect, a thermocouple offset, a gauge that drifts (outside the library), a coated
    thermocouple posing as latent heat. Measured scores of this diagnosis, asserted."""
    scores = blind.run(4, 102, tmp_path, fmu_dir=fmu_dir, scenarios_dir=ROOT / "scenarios",
                       pmap=cluster_map, bench="independent", duration=20.0)
    kinds = {r["kind"]: r for r in scores["per_case"]}
    assert set(kinds) == {"none", "effect", "decoy", "outside"}
    assert [kinds[k]["truth"] for k in ("effect", "decoy", "outside")] == [
        "thermocouple bias", "thermocouple lag", "gauge drift"]
    # every truth in its set; the lag named alone; the offset among four (calibration the most
    # probable: 20 s leave it close to a recalibration); no false alarm
    assert scores["truth_in_set"] == 1.0 and scores["false_alarm_rate"] == 0.0
    assert kinds["decoy"]["set"] == ["thermocouple lag"] and kinds["decoy"]["top1"]
    assert kinds["effect"]["set"][0] == "calibration only" and len(kinds["effect"]["set"]) == 4
    assert kinds["none"]["set"] == ["training drift", "calibration only"]
    assert scores["mean_set_size"] == pytest.approx(7 / 3)
    assert scores["size_weighted_accuracy"] == pytest.approx((1 / 4 + 1 + 1 / 2) / 3)
    assert scores["top1_accuracy"] == 0.5 and scores["brier"] == pytest.approx(0.419, abs=0.02)
    assert scores["unexplained_rate"] == 1.0 and scores["shrinkage_vs_oracle"] > 0.99
    saved = json.loads((tmp_path / "scores.json").read_text())
    assert schema_errors("scores", saved) == []
    assert saved["independent"]["cases"] == 4


def test_a_small_blind_run_on_the_family_scores_the_calibrated_sets(fmu_dir, tmp_path,
                                                                    cluster_map):
    """Two family cases of 10 s: their reports carry the calibrated set, scored per cause."""
    scores = blind.run(2, 7, tmp_path, fmu_dir=fmu_dir, scenarios_dir=ROOT / "scenarios",
                       pmap=cluster_map, bench="family", duration=10.0)
    saved = json.loads((tmp_path / "scores.json").read_text())
    assert schema_errors("scores", saved) == []
    assert saved["family"]["cases"] == 2 == scores["cases"]
    key = json.loads((tmp_path / "family" / "key.json").read_text())
    for row, case in zip(scores["per_case"], key["cases"]):
        report = json.loads((tmp_path / "family" / "cases" / case["case"]
                             / "report.json").read_text())
        assert row["set"] == report["evidence"]["set"] and report["evidence"]["level"] == 0.95
        assert row["cause"] == case["cause"]
    assert scores["coverage"] == sum(r["cause"] in r["set"] for r in scores["per_case"]) / 2
    # a run that stopped goes on: the case diagnosed before is kept, the other diagnosed again
    kept, lost = (tmp_path / "family" / "cases" / c["case"] / "report.json"
                  for c in key["cases"])
    before, stamp = lost.read_text(), kept.stat().st_mtime_ns
    lost.unlink()
    (tmp_path / "family" / "key.json").unlink()
    again = blind.run(2, 7, tmp_path, fmu_dir=fmu_dir, scenarios_dir=ROOT / "scenarios",
                      pmap=cluster_map, bench="family", duration=10.0, resume=True)
    assert kept.stat().st_mtime_ns == stamp and lost.read_text() == before
    assert again == scores
    from musclesim.errors import UserError
    with pytest.raises(UserError, match="--resume: .* holds no run of these cases"):
        blind.run(2, 8, tmp_path, bench="family", duration=10.0, resume=True)
    # a new run in the same folder stopped while diagnosing: nothing of the last run's reports
    # is left to pass for its own when it is resumed
    def stop(fn, items, *rest):
        if fn is blind._diagnose:
            raise KeyboardInterrupt
        return cluster_map(fn, items, *rest)
    with pytest.raises(KeyboardInterrupt):
        blind.run(2, 8, tmp_path, fmu_dir=fmu_dir, scenarios_dir=ROOT / "scenarios",
                  pmap=stop, bench="family", duration=10.0)
    assert not kept.exists() and not lost.exists()
    assert not (tmp_path / "family" / "key.json").exists()


def test_a_calibration_asked_into_a_missing_folder_is_refused_before_any_work(tmp_path):
    from musclesim.errors import UserError
    with pytest.raises(UserError, match="no-such-folder"):
        blind.run(2, 7, tmp_path / "out", bench="family",
                  calibration=tmp_path / "no-such-folder" / "c.json")
    assert not (tmp_path / "out").exists()
