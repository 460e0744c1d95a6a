"""What the diagnosis's stages hand each other: frozen values; an isolation unit's report entry."""
import dataclasses
from types import SimpleNamespace

import pytest

from musclesim.diagnosis.stages import Calibration, FitUnit, Isolation


def test_an_isolation_units_entry_and_its_calibration_frozen():
    cal = Calibration([], {}, {}, None, {}, None, {"tc.T_meas": 1}, 0.05)
    unit = SimpleNamespace(instances=("tc", "wire"), observed=("tc.T_meas",))
    iso = Isolation(unit, cal, 0.01, 0.002, True, 0.05)
    assert iso.section() == {"instances": ["tc", "wire"], "observed": ["tc.T_meas"],
                             "heldout_gap_nominal": 0.05, "heldout_gap": 0.01,
                             "noise_floor": 0.002, "deviates": True}
    for value, field in ((cal, "nominal_gap"), (iso, "gap"),
                         (FitUnit(unit, cal, frozenset({"tc"})), "suspects")):
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(value, field, None)
