"""A synthetic twin of the study's fast-actuation fit (§study-outcomes, §pulse-gap): the pulse
experiment's outcomes computed on our own model with an effect of the pulse gap hidden at a known
value; then `musclesim calibrate`'s fit (musclesim.diagnosis.openvalues) of each effect in turn,
as `musclesim predict` fits its alternative models, recovers which effect it was and its value:
the hidden one's fit meets the twin and ends within its interval at the hidden value, and every
other effect misses it by more than the spread admits (`musclesim.prediction.ADMIT`)."""
import pytest

from musclesim.cosim import Master, compute_metrics, load_scenario
from musclesim.diagnosis import calibrate, dataset
from musclesim.prediction import ADMIT

from conftest import SCENARIOS

STOP = 1.0  # s of the study's 20 Hz pulses: the wire heating, so its temperature moves
# the twin's outcomes from 0.5 s, with a thermocouple's and a laser's uncertainties
OUTCOMES = {"temperature_mean": ("K", 0.1), "temperature_p2p": ("K", 0.05),
            "displacement_mean": ("m", 2e-6), "p2p_first_second": ("m", 2e-6)}
# the effects of the pulse gap, each with its bounds as scenarios/predictions/fast-actuation.toml
# opens them (the tubes' contact conductance, which the scenario sets to 2 mW/K, up to 10 mW/K)
EFFECTS = {"supply resistance": ("mult.source_resistance", 0.0, 3.0, "Ohm"),
           "capstan heat loss": ("mult.contact_conductance", 0.0, 0.01, "W/K"),
           "hysteresis above 200 MPa": ("mult.stress_rise", 7.1e-8, 1.43e-7, "K/Pa"),
           "peg board": ("mult.h", 100.0, 200.0, "W/(m2.K)")}
HIDDEN = {"supply resistance": 1.2, "capstan heat loss": 5e-3, "hysteresis above 200 MPa": 1e-7,
          "peg board": 160.0}


@pytest.fixture(scope="module")
def pulse(tmp_path_factory):
    """A folder holding the pulse scenario with its metrics taken from 0.5 s."""
    d = tmp_path_factory.mktemp("twin")
    text = (SCENARIOS / "sma-multiplier-pulse.toml").read_text()
    (d / "pulse.toml").write_text(text.replace('from = 5.0 }', 'from = 0.5 }'))
    return d


def outcomes(folder, fmu_dir, overrides):
    """The twin's outcomes (`OUTCOMES`) of the cut pulse scenario in `folder` run with
    `overrides`."""
    s = load_scenario(folder / "pulse.toml", overrides, stop_time=STOP)
    got = compute_metrics(Master(s, fmu_dir).run(), s.metrics)
    return {k: got[k] for k in OUTCOMES}


def fitted(folder, fmu_dir, twin, effect, name):
    """(the open value's report, chi-square) of `effect`'s parameter fitted to the `twin`'s
    outcomes, as a scalar-only data set `name` beside the scenario in `folder`."""
    ref, lo, hi, _ = EFFECTS[effect]
    d = folder / name.replace(" ", "-")
    d.mkdir()
    metrics = "".join(f'metrics.{k} = {{ value = {v!r}, unit = "{OUTCOMES[k][0]}", '
                      f'uncertainty = {OUTCOMES[k][1]!r} }}\n' for k, v in twin.items())
    (d / "manifest.toml").write_text(
        f'[experiments.pulse]\nscenario = "../pulse.toml"\nstop_time = {STOP!r}\n{metrics}'
        f'[split]\nheld_out = []\n[[calibrate]]\nset = ["{ref}"]\n'
        f'bounds = [{lo!r}, {hi!r}]\nwhy = "{effect}"\n')
    report = calibrate(dataset.load(d), fmu_dir)
    chi2 = sum(((m["fitted"] - m["measured"]) / m["uncertainty"]) ** 2 for m in report["metrics"])
    value, = report["open_values"]
    return value, chi2


@pytest.mark.parametrize("hidden", list(HIDDEN))
def test_the_hidden_effect_and_its_value_are_recovered_and_the_others_left_out(pulse, fmu_dir,
                                                                              hidden):
    ref, _, _, unit = EFFECTS[hidden]
    twin = outcomes(pulse, fmu_dir, [f"{ref}={HIDDEN[hidden]!r}"])
    nominal = outcomes(pulse, fmu_dir, [])
    assert sum(((twin[k] - nominal[k]) / OUTCOMES[k][1]) ** 2 for k in OUTCOMES) > 100 * ADMIT
    fits = {effect: fitted(pulse, fmu_dir, twin, effect, f"{hidden} twin, {effect} fitted")
            for effect in EFFECTS}
    value, chi2 = fits[hidden]
    lo, hi = value["interval95"]
    assert chi2 < 1e-3 and value["status"] == "fitted" and value["unit"] == unit
    assert lo <= HIDDEN[hidden] <= hi
    assert value["value"] == pytest.approx(HIDDEN[hidden], rel=1e-3)
    left_out = {effect for effect, (_, c) in fits.items() if c > chi2 + ADMIT}
    assert left_out == set(EFFECTS) - {hidden}
