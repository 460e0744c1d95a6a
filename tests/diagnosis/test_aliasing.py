"""The aliasing of an effect by the calibration, on synthetic sensitivities (no FMU)."""
import numpy as np
import pytest

from musclesim.diagnosis.fitting import Free
from musclesim.diagnosis.scoring import score
from musclesim.diagnosis.aliasing import aliasing
from musclesim.diagnosis.stats import gap

from diagnosis_fakes import N, TC, candidate, fake_unit, fitted, noise


def test_aliasing_of_an_effect_by_the_calibration_on_synthetic_sensitivities():
    """A thermocouple's bias changes only its channel; a room warmer by as much moves the wire
    and so both channels, the transformation temperatures shifted with it give the strain back:
    together they make the bias exactly, unless the strain's sensitivity differs."""
    rng = np.random.default_rng(5)
    dstrain = rng.standard_normal(N)  # the strain's sensitivity to the wire's temperature
    tc, strain = np.r_[np.ones(N), np.zeros(N)], np.r_[np.zeros(N), dstrain]
    ambient, shift = tc + strain, -strain
    jac = np.column_stack([tc, ambient, shift, rng.standard_normal(2 * N)])
    names = ["wire.T_amb", "wire.hysteresis_shift", "wire.h"]
    a = aliasing(jac, 1, names)
    assert a["share"] == pytest.approx(1.0) and a["index"] > 1e3
    assert set(a["with"]) == {"wire.T_amb", "wire.hysteresis_shift"}
    # with the room stated (not calibrated) the ambient's column is gone: no stand-in
    b = aliasing(np.delete(jac, 1, axis=1), 1, names[1:])
    assert b["share"] < 0.01 and b["index"] < 1.1
    assert aliasing(None, 1, names) is None and aliasing(jac[:, :1], 1, []) is None
    assert aliasing(np.zeros_like(jac), 1, names) is None  # an effect that changes nothing
    # in a scored fit, a calibration parameter that ended at its bound cannot stand in: left out
    unit = fake_unit((TC,))
    res = {TC: [noise(9)]}
    base = {"residuals": res, "heldout_gap": gap(unit, res, 1)}
    calib = [Free(("wire",), n, 0.0, 1.0, 0.5) for n in ("T_amb", "hysteresis_shift", "h")]
    f = fitted(unit, res, x=[1.0, 0.5, 0.5, 0.5], jac=jac,
               interval=[(0.9, 1.1)] + [(0.4, 0.6)] * 3)
    e = score(unit, base, candidate("thermocouple bias", "thermocouple"), f, {}, calib)
    assert e["aliasing"]["share"] == pytest.approx(1.0)
    f.x[1] = 1.0  # the ambient at its upper bound
    e = score(unit, base, candidate("thermocouple bias", "thermocouple"), f, {}, calib)
    assert e["aliasing"]["share"] < 0.01 and "wire.T_amb" not in e["aliasing"]["with"]
