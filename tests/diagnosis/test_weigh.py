"""The symmetry test by profiles and the evidence of a symmetric effect, on synthetic fits (no
FMUs): a profile along which the calibration reproduces the effect is a symmetry, one that
leaves a change is not; a symmetric effect weighs as much as calibration alone."""
from types import SimpleNamespace

import numpy as np
import pytest

from musclesim.cosim import ParamRef
from musclesim.diagnosis import evidence as ev
from musclesim.diagnosis.fitting import Free, FitResult
from musclesim.diagnosis.thresholds import PROFILE_SCALE, SYMMETRY_CHI2
from musclesim.diagnosis.weigh import (CALIBRATION_ONLY, Weighed, profile_jobs, symmetries,
                                       with_symmetries)

N = 500
DISC = {"y": ev.Discrepancy(np.array([0.5]), 0.01)}
FREE = [Free(("tc",), "bias", -10.0, 10.0, 0.0), Free(("wire",), "T_amb", 285.0, 301.0, 293.0),
        Free(("wire",), "h", 50.0, 150.0, 100.0)]
PROBLEM = SimpleNamespace(vars={"wire": {"T_amb": SimpleNamespace(causality="input"),
                                         "h": SimpleNamespace(causality="parameter")}})


def fit(z, train):
    z = np.asarray(z, float)
    x = [f.lower + (f.upper - f.lower) * v for f, v in zip(FREE[-len(z):], z)]
    return FitResult(x, [], None, 0.0, 0.0, True, 1, np.eye(len(z)), {}, z, train)


def candidate(name, z_effect, seed=0):
    residual = np.random.default_rng(seed).standard_normal(N) * 0.01
    w = Weighed(name, fit([z_effect, 0.5, 0.5], {"y": [residual]}), FREE, 1)
    w.evidence = ev.evidence(w.fit.train, np.zeros((N, 3)) + np.eye(N, 3), w.fit.z, DISC)
    return w, residual


def test_the_effect_is_moved_a_tenth_of_its_box_each_way_it_has_room_for():
    w, r = candidate("bias", 0.5)
    # calibration alone fits as well as the effect
    cal = Weighed(CALIBRATION_ONLY, fit([0.5, 0.5], {"y": [r]}), FREE[1:], 0)
    jobs = profile_jobs("unit", [w], cal, DISC, "fmus")
    assert sorted(round(j.fixed[ParamRef("tc", "bias")], 9) for _, _, j in jobs) == [-2.0, 2.0]
    assert all(length == PROFILE_SCALE and j.free == FREE[1:] and j.train_only
               and j.scan == 0 and j.x0 == w.fit.x[1:] for _, length, j in jobs)
    # the calibration's columns of the effect's Jacobian start each profile
    assert all(np.array_equal(j.known[1], w.fit.jac[:, 2]) for _, _, j in jobs)
    near_bound, _ = candidate("bias", 0.05)
    (_, length, job), = profile_jobs("unit", [near_bound], cal, DISC, "fmus")
    assert length == PROFILE_SCALE and job.fixed[ParamRef("tc", "bias")] == pytest.approx(-7.0)
    assert profile_jobs("unit", [], cal, DISC, "fmus") == []
    # an effect that fits better than calibration alone by a noise variance or more is told
    # from a recalibration by its own fit: no profile
    worse = Weighed(CALIBRATION_ONLY, fit([0.5, 0.5], {"y": [r + 0.02]}), FREE[1:], 0)
    assert profile_jobs("unit", [w], worse, DISC, "fmus") == []


def test_a_profile_the_calibration_follows_is_a_symmetry_and_one_it_cannot_is_not():
    sym, r = candidate("bias", 0.5)
    apart, r2 = candidate("lag", 0.5, seed=1)
    # along the bias's profile the calibration (ambient moved) reproduces the residual; along
    # the lag's a change remains: 30 noise sigmas in one sample
    changed = r2.copy()
    changed[100] += 0.3
    profiles = [(sym, PROFILE_SCALE, fit([0.8, 0.5], {"y": [r]})),
                (apart, PROFILE_SCALE, fit([0.5, 0.5], {"y": [changed]}))]
    found = symmetries([sym, apart], profiles, DISC, PROBLEM)
    assert [(s["candidates"], s["test"]) for s in found] == [(["bias", CALIBRATION_ONLY],
                                                              "profile")]
    assert found[0]["chi2"] < SYMMETRY_CHI2 and found[0]["with"] == ["wire.T_amb"]
    assert found[0]["breaks_with"][0].startswith("state wire.T_amb in the data set's")
    # a move shorter than the test's counts as scaled up to it: a chi2 of about 0.4 over a
    # move a tenth as long is about 40 over the whole one
    small = r.copy()
    small[100] += 0.01 * np.sqrt(0.3)
    short = [(sym, PROFILE_SCALE / 10, fit([0.6, 0.5], {"y": [small]}))]
    assert symmetries([sym], short, DISC, PROBLEM) == []
    # a profile that fits better than the effect's own fit tells the two values apart as well
    better = [(sym, PROFILE_SCALE, fit([0.5, 0.5], {"y": [0.1 * r]}))]
    assert symmetries([sym], better, DISC, PROBLEM) == []


def test_a_symmetric_effect_weighs_as_much_as_calibration_alone():
    cal = Weighed(CALIBRATION_ONLY, None, FREE[1:], 0)
    sym, _ = candidate("bias", 0.5)
    other, _ = candidate("lag", 0.5)
    cal.evidence = ev.Evidence(-10.0, -10.0, 0.0, np.zeros(2))
    sym.evidence = ev.Evidence(-14.0, -9.9, -4.1, np.zeros(3))
    other.evidence = ev.Evidence(-30.0, -20.0, -10.0, np.zeros(3))
    for w in (cal, sym, other):
        w.prior = 1 / 3
    weighed = with_symmetries([cal, sym, other], [{"candidates": ["bias", CALIBRATION_ONLY]}])
    p = {w.name: w.probability for w in weighed}
    assert p["bias"] == pytest.approx(p[CALIBRATION_ONLY]) and p["lag"] < 1e-6
    assert sym.evidence.log_evidence == cal.evidence.log_evidence
