"""musclesim.analysis.characterise: the gait's pressure references (§gait) from hand-made
results of the characterisation run, and the TOML the gait scenarios read. (The committed
references against a fresh characterisation: tests/analysis/test_linear_pneumatic.py.)"""
import tomllib

import numpy as np
import pytest

from musclesim.analysis import characterise
from musclesim.cosim import Signal
from musclesim.errors import UserError


class FakeResults:
    """What `characterise.references` reads of a `Master` run's results: time and signals by
    Signal (a keyword instance__variable__part names instance.variable.part)."""

    def __init__(self, time, **signals):
        self.time = np.asarray(time, dtype=float)
        self.signals = {}
        for keyword, values in signals.items():
            instance, _, variable = keyword.partition("__")
            self.signals[Signal(instance, variable.replace("__", "."))] = np.asarray(values, float)

    def __getitem__(self, signal):
        return self.signals[signal]


def fake(elongation=None, u1=None, u2=None):
    """One sample a second over 0..40 s: the central ramp to 20 s, the extremal ones after 25 s."""
    t = np.arange(41.0)
    return FakeResults(
        t,
        body__flange_a__s=0.01 + 0.0 * t,  # the back block sits at 10 mm: elongation is relative
        body__flange_b__s=0.01 + (0.003 * t if elongation is None else elongation),
        sensorc__p_meas=100.0 * t ** 2,  # not linear: the interpolation shows
        act1__u=np.clip(t - 29.0, 0.0, 1.0) if u1 is None else u1,  # 0.995 would be at 29.995
        sensor1__p_meas=500.0 * t,
        act2__u=np.where(t >= 32, 0.995, 0.5 * (t >= 31)) if u2 is None else u2,
        sensor2__p_meas=400.0 * t + 7.0)


def test_references_interpolate_the_central_pressure_and_take_first_firm_contact():
    refs = characterise.references(fake())
    # elongation 0.039 m at 13 s, 0.042 m at 14 s: 0.04 m a third of the way, where
    # p = 16900 + (19600 - 16900) / 3 = 17800 Pa
    assert refs["p_central"] == pytest.approx(17800.0, rel=1e-9)
    assert refs["p_firm1"] == 500.0 * 30  # act1.u = 1 >= 0.99 first at 30 s
    assert refs["p_firm2"] == 400.0 * 32 + 7.0  # 0.5 at 31 s is not firm; 0.995 at 32 s is
    for i in (1, 2):  # the references keep a margin above firm contact
        assert refs[f"p_anchor{i}"] == (1 + characterise.ANCHOR_MARGIN) * refs[f"p_firm{i}"]
    assert refs["elongation_at_ramp_end"] == pytest.approx(0.06)  # the last sample at 20 s
    # a target reached at the very first sample takes the first pressure
    assert characterise.references(fake(), elongation_target=-1.0)["p_central"] == 0.0


def test_references_say_what_the_characterisation_did_not_reach():
    with pytest.raises(UserError, match=r"^the central actuator reaches only 0\.03 m of the "
                                        r"0\.04 m elongation target by t = 20 s$"):
        characterise.references(fake(elongation=0.0015 * np.arange(41.0)))
    with pytest.raises(UserError, match=r"^extremal actuator act2 never reaches firm contact "
                                        r"\(indicator >= 0\.99\) in the characterisation$"):
        characterise.references(fake(u2=np.full(41, 0.98)))
    with pytest.raises(UserError, match="act1 never reaches firm contact"):
        characterise.references(fake(u1=np.zeros(41)))


def test_the_references_toml_holds_the_three_references_exactly():
    refs = characterise.references(fake())
    text = characterise.references_toml(refs, "scenarios/crawler-characterisation.toml")
    assert tomllib.loads(text) == {k: refs[k] for k in ("p_central", "p_anchor1", "p_anchor2")}
    assert "from scenarios/crawler-characterisation.toml" in text
    assert "from 15000.0 Pa, + 25%" in text  # p_firm1 = 500 Pa/s x 30 s, the margin
