"""A synthetic twin of the study's fast-actuation fit (§study-outcomes, §pulse-gap): the pulse
experiment's outcomes computed on our own model with an effect hidden at a known value, then
`musclesim calibrate`'s fit (musclesim.diagnosis.openvalues) with that effect's parameter open
recovers the value within its interval."""
import pytest

from musclesim.cosim import Master, compute_metrics, load_scenario
from musclesim.diagnosis import calibrate, dataset

from conftest import SCENARIOS

HIDDEN = 1.2  # Ohm: the pulse supply's resistance ("supply resistance"), within its 0-3 bounds
STOP = 1.0    # s of the study's 20 Hz pulses: the wire heating, so its mean temperature moves


@pytest.fixture(scope="module")
def twin(fmu_dir, tmp_path_factory):
    """The pulse scenario cut to its first second, the wire's mean temperature from 0.5 s as the
    twin's outcome (0.1 K uncertainty, a thermocouple's), the source resistance hidden; and the
    nominal model's (no source resistance) value of it."""
    d = tmp_path_factory.mktemp("twin")
    text = (SCENARIOS / "sma-multiplier-pulse.toml").read_text()
    text = text.replace('from = 5.0 }', 'from = 0.5 }')
    (d / "pulse.toml").write_text(text)
    got = {}
    for r in (HIDDEN, 0.0):
        s = load_scenario(d / "pulse.toml", [f"mult.source_resistance={r!r}"], stop_time=STOP)
        got[r] = compute_metrics(Master(s, fmu_dir).run(), s.metrics)["temperature_mean"]
    (d / "set").mkdir()
    (d / "set" / "manifest.toml").write_text(
        '[experiments.pulse]\nscenario = "../pulse.toml"\n'
        f'stop_time = {STOP!r}\n'
        f'metrics.temperature_mean = {{ value = {got[HIDDEN]!r}, unit = "K", '
        'uncertainty = 0.1 }\n'
        '[split]\nheld_out = []\n[[calibrate]]\nset = ["mult.source_resistance"]\n'
        'bounds = [0.0, 3.0]\nwhy = "the pulse supply\'s resistance"\n')
    return d / "set", got


def test_the_hidden_supply_resistance_is_recovered_within_its_interval(twin, fmu_dir):
    folder, got = twin
    assert got[0.0] - got[HIDDEN] > 50 * 0.1  # the nominal model misses the twin: a fit must move
    report = calibrate(dataset.load(folder), fmu_dir)
    value, = report["open_values"]
    lo, hi = value["interval95"]
    assert lo <= HIDDEN <= hi and value["value"] == pytest.approx(HIDDEN, abs=0.05)
    assert value["unit"] == "Ohm" and value["status"] == "fitted"
