"""The worked example the docs show (docs/examples/<data set>/report.json, written by `musclesim
diagnose`) is what the diagnosis gives today: a refactoring that changes a result shows here.

Strings, booleans and the report's shape are compared exactly; numbers to 1e-6 relative, since
least squares on another CPU's BLAS kernels rounds the last digits differently."""
import json
import math

import pytest

from musclesim.diagnosis import diagnose, load_dataset

from conftest import ROOT, SCENARIOS

EXAMPLES = ("sma-independent-thermocouple-lag", "sma-independent-thermocouple-bias")


def differences(a, b, where="report"):
    """Where two JSON documents differ (numbers to 1e-6 relative), one sentence each."""
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) != set(b):
            return [f"{where}: keys {sorted(set(a) ^ set(b))} in one only"]
        return [d for k in a for d in differences(a[k], b[k], f"{where}/{k}")]
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [f"{where}: {len(a)} items against {len(b)}"]
        return [d for i, (x, y) in enumerate(zip(a, b)) for d in differences(x, y, f"{where}/{i}")]
    numbers = (int, float)
    if isinstance(a, numbers) and isinstance(b, numbers) and not isinstance(a, bool) \
            and not isinstance(b, bool):
        same = (math.isnan(a) and math.isnan(b)) or math.isclose(a, b, rel_tol=1e-6,
                                                                   abs_tol=1e-12)
        return [] if same else [f"{where}: {a!r} against {b!r}"]
    return [] if a == b else [f"{where}: {a!r} against {b!r}"]


@pytest.mark.parametrize("name", EXAMPLES)
def test_the_worked_example_gives_its_documented_report(name, fmu_dir, cluster_map):
    stored = json.loads((ROOT / "docs" / "examples" / name / "report.json").read_text())
    report = json.loads(json.dumps(
        diagnose(load_dataset(SCENARIOS / "data" / name), fmu_dir, cluster_map).to_json(),
        default=float))
    stored.pop("data_set"), report.pop("data_set")  # where the data set was, as given
    assert differences(stored, report) == []


def test_differences_sees_what_differs():
    a = {"verdict": "x", "gap": [1.0, 2.0], "ok": True}
    assert differences(a, {"verdict": "x", "gap": [1.0, 2.0 + 1e-9], "ok": True}) == []
    assert differences(a, {"verdict": "y", "gap": [1.0, 2.1], "ok": False}) == [
        "report/verdict: 'x' against 'y'", "report/gap/1: 2.0 against 2.1",
        "report/ok: True against False"]
    assert differences(a, {"verdict": "x"}) == ["report: keys ['gap', 'ok'] in one only"]
