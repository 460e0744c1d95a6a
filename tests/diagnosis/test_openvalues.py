"""`musclesim calibrate` (musclesim.diagnosis.openvalues): the open values a scalar-only data set
names, fitted to its training metrics with intervals from their uncertainties; the held-out
metrics predicted."""
import json
from contextlib import nullcontext

import pytest

from musclesim.cosim import ParamRef
from musclesim import batch
from musclesim.cli import main
from musclesim.cosim import Master, compute_metrics, load_scenario
from musclesim.diagnosis import calibrate, calibration_markdown, dataset
from musclesim.diagnosis.fitting import Free, values_of
from musclesim.errors import UserError

from conftest import SCENARIOS


def test_a_free_value_may_set_parameters_of_other_names_alike():
    free = [Free(("wire", "mult"), "hysteresis_shift", -5, 15, 0,
                 also=(ParamRef("other", "composition_shift"),)), Free(("tc",), "tau", 0, 1, 0)]
    assert values_of(free, [4.0, 0.1]) == {
        ParamRef("wire", "hysteresis_shift"): 4.0, ParamRef("mult", "hysteresis_shift"): 4.0,
        ParamRef("other", "composition_shift"): 4.0, ParamRef("tc", "tau"): 0.1}


@pytest.fixture(scope="module")
def bias_set(fmu_dir, tmp_path_factory):
    """The stress bench, 3 s at two drive levels, its thermocouple reading 3 K high: the peak
    reading of each as a metric (0.1 K uncertainty); one level trains, the other is held out."""
    d = tmp_path_factory.mktemp("calibrate")
    text = (SCENARIOS / "sma-bench-stress.toml").read_text().replace(
        "stop_time = 60.0", "stop_time = 3.0").replace("from = 10.0", "from = 0.5")
    text = text.replace("[metrics]\n", '[metrics]\nT_max = { signal = "thermocouple.T_meas", '
                        'op = "max" }\n')
    lines = []
    for name, amplitude in (("low", 0.4), ("high", 0.5)):
        (d / f"bench-{name}.toml").write_text(text.replace("amplitude = 0.5,",
                                                           f"amplitude = {amplitude},"))
        s = load_scenario(d / f"bench-{name}.toml", ["thermocouple.bias=3.0"])
        measured = compute_metrics(Master(s, fmu_dir).run(), s.metrics)["T_max"]
        lines.append(f'[experiments.{name}]\nscenario = "../bench-{name}.toml"\n'
                     f'conditions = {{ "drive.amplitude" = {amplitude} }}\n'
                     f'metrics.T_max = {{ value = {measured!r}, unit = "K", uncertainty = 0.1 }}\n')
    (d / "set").mkdir()
    (d / "set" / "manifest.toml").write_text(
        "".join(lines) + '[split]\nheld_out = ["high"]\n[[calibrate]]\n'
        'set = ["thermocouple.bias"]\nbounds = [-10.0, 10.0]\nwhy = "the reading\'s offset"\n')
    return d / "set"


def test_the_open_value_is_found_within_its_interval_and_the_held_out_metric_predicted(
        bias_set, fmu_dir):
    report = calibrate(dataset.load(bias_set), fmu_dir)
    value, = report["open_values"]
    assert value["set"] == ["thermocouple.bias"] and value["why"] == "the reading's offset"
    assert value["value"] == pytest.approx(3.0, abs=0.02)
    lo, hi = value["interval95"]
    # one metric of 0.1 K uncertainty pins a bias that moves it one for one: +-0.196 K
    assert lo < 3.0 < hi and hi - lo == pytest.approx(2 * 1.96 * 0.1, rel=0.05)
    rows = {r["experiment"]: r for r in report["metrics"]}
    assert rows["low"]["part"] == "train" and rows["high"]["part"] == "held_out"
    assert rows["high"]["nominal_error"] == pytest.approx(-3.0 / rows["high"]["measured"],
                                                          rel=0.05)
    assert abs(rows["high"]["fitted"] - rows["high"]["measured"]) < 0.05
    assert report["open_values"][0]["unit"] == "K"  # the thermocouple's bias, a temperature
    assert "| thermocouple.bias | K | 3" in calibration_markdown(report)


def test_cli_writes_the_report(bias_set, fmu_dir, tmp_path, capsys, monkeypatch):
    # the fits' runs here, not on a local cluster (whose start alone takes seconds)
    monkeypatch.setattr(batch, "dask_client", lambda scheduler, workers: nullcontext())
    monkeypatch.setattr(batch, "dask_map", lambda client: batch.serial_map)
    assert main(["calibrate", str(bias_set), "--out", str(tmp_path / "out"), "--fmus",
                 str(fmu_dir), "--workers", "1"]) == 0
    assert "| high | T_max | held_out |" in capsys.readouterr().out
    report = json.loads((tmp_path / "out" / "calibration.json").read_text())
    assert report["open_values"][0]["value"] == pytest.approx(3.0, abs=0.02)


def test_a_set_without_open_values_or_with_an_unknown_instance_is_refused(bias_set, fmu_dir,
                                                                           tmp_path):
    manifest = (bias_set / "manifest.toml").read_text()
    for name, text, message in (
            ("none", manifest.split("[[calibrate]]")[0], "names no open value"),
            ("unknown", manifest.replace('"thermocouple.bias"', '"magnet.bias"'),
             "no scenario of the data set has an instance 'magnet'"),
            ("no-parameter", manifest.replace('"thermocouple.bias"',
                                              '"thermocouple.bias", "wire.bias"'),
             "SmaWire has no parameter 'bias'")):
        d = tmp_path / name
        d.mkdir()
        (d / "manifest.toml").write_text(text.replace("../bench-", f"{bias_set.parent}/bench-"))
        with pytest.raises(UserError, match=message):
            calibrate(dataset.load(d), fmu_dir)
