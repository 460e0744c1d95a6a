"""Case folders (musclesim.batch.cases): a folder is claimed for one set of settings, a case is
finished only when its summary.json says it completed. No FMU is run."""
import json

import pytest

from musclesim.batch import case_summary, claim, finished, write_failure
from musclesim.errors import UserError


@pytest.fixture
def scenario_file(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text("# a scenario: claim only hashes it\n")
    return path


def test_claim_records_the_settings_and_refuses_other_ones(tmp_path, scenario_file):
    out = tmp_path / "out"
    claim(out, scenario_file, stop_time=1.0, overrides=["a.b=1"])
    config = json.loads((out / "sweep.json").read_text())
    assert config["scenario"] == str(scenario_file) and config["stop_time"] == 1.0
    assert config["overrides"] == ["a.b=1"] and len(config["scenario_sha256"]) == 64
    assert config["fmu_sources"]
    claim(out, scenario_file, stop_time=1.0, overrides=["a.b=1"])  # the same settings: fine
    with pytest.raises(UserError, match=r"other settings \(stop_time\)"):
        claim(out, scenario_file, stop_time=2.0, overrides=["a.b=1"])
    scenario_file.write_text("# edited\n")
    with pytest.raises(UserError, match=r"other settings \(scenario_sha256\)"):
        claim(out, scenario_file, stop_time=1.0, overrides=["a.b=1"])
    assert json.loads((out / "sweep.json").read_text()) == config  # a refusal writes nothing


def test_claim_refuses_a_folder_whose_record_is_unreadable(tmp_path, scenario_file):
    out = tmp_path / "out"
    out.mkdir()
    (out / "sweep.json").write_text("not json")
    with pytest.raises(UserError, match="choose another --out"):
        claim(out, scenario_file)


@pytest.mark.parametrize("content, ran, completed", [
    ('{"completed": true, "x1_final": 0.5}', True, True),
    ('{"completed": false, "error": "boom"}', True, False),
    ('{"completed": "yes"}', True, False),  # only a JSON true is a completed case
    (None, False, False),  # no summary.json: the case has not run
    ('{"completed": tru', False, False),  # cut short: not run
    ("[1, 2]", False, False),  # not an object
], ids=["completed", "failed", "not-true", "missing", "garbage", "not-an-object"])
def test_finished_and_case_summary(tmp_path, content, ran, completed):
    case = tmp_path / "case"
    case.mkdir()
    if content is not None:
        (case / "summary.json").write_text(content)
    summary = case_summary(case)
    assert (summary is not None) == ran
    assert finished(case) == (summary if completed else None)
    assert case_summary(str(case)) == summary  # a str path works as well


def test_write_failure_is_a_case_that_ran_and_failed(tmp_path):
    case = tmp_path / "cases" / "a=1"
    assert write_failure(case, "it broke") == {"completed": False, "error": "it broke"}
    assert case_summary(case) == {"completed": False, "error": "it broke"}
    assert finished(case) is None


def test_a_failure_removes_an_earlier_runs_results(tmp_path):
    """A case that ran before (its results.csv, plot and summary there) and fails now keeps no
    row of the earlier run beside the failure's summary."""
    case = tmp_path / "cases" / "a=1"
    case.mkdir(parents=True)
    for name in ("results.csv", "results.csv.part", "results.png"):
        (case / name).write_text("an earlier run's\n")
    (case / "summary.json").write_text('{"completed": true, "error": null}\n')
    write_failure(case, "it broke")
    assert sorted(p.name for p in case.iterdir()) == ["summary.json"]
    assert case_summary(case) == {"completed": False, "error": "it broke"}
