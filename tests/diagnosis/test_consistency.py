"""The cross-signal sentence on hand-made entries (no FMU)."""
from musclesim.diagnosis.consistency import cross_signal

from diagnosis_fakes import STRAIN, TC, fake_unit


def test_cross_signal_places_the_gap_in_the_sensor_or_in_the_plant():
    unit = fake_unit()
    sensor = {"label": "thermocouple bias", "counts": True,
              "judged": {"signals": [TC]},
              "per_signal": {TC: {"before": 0.04, "after": 0.004},
                             STRAIN: {"before": 0.006, "after": 0.006}}}
    text = cross_signal(unit, [sensor], [sensor])
    assert "depend on the state of wire" in text and "placed in the sensor" in text
    plant = {"label": "latent heat", "counts": True, "judged": {"signals": [TC, STRAIN]},
             "per_signal": {TC: {"before": 0.04, "after": 0.01},
                            STRAIN: {"before": 0.05, "after": 0.01}}}
    assert "placed in wire" in cross_signal(unit, [plant], [plant])
    assert cross_signal(fake_unit((TC,)), [sensor], [sensor]) is None  # one signal: nothing
