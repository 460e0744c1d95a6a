"""Reference strain and loading profiles (components/sma/profiles.py, §reference-profiles): the
closed forms by hand, every profile within its range, seeded random peaks, copies that rebuild."""
import copy
import math
import pickle

import numpy as np
import pytest

from musclesim.components.sma import profiles
from musclesim.components.sma.profiles import (EPS_MAX, LOADING_PROFILES, STRAIN_PROFILES,
                                               loading_profile, random_peaks, strain_profile)

T = np.linspace(0.0, 550.0, 5501)


def test_closed_forms_by_hand():
    w = 2 * math.pi / 17
    sp1, sp3 = strain_profile("SP I"), strain_profile("SP III")
    for t in (0.0, 3.0, 8.5, 100.0):
        assert sp1(t) == pytest.approx(EPS_MAX / 2 - EPS_MAX / 2 * math.cos(w * t), abs=1e-15)
        assert sp3(t) == pytest.approx(EPS_MAX / 2 - EPS_MAX / 2 * t / 550 * math.cos(w * t),
                                       abs=1e-15)
    lp2 = loading_profile("LP II")
    assert lp2(47 / 4) == pytest.approx(145e6) and lp2(0.0) == pytest.approx(125e6)
    assert loading_profile("LP IV")(275.0) == pytest.approx(125e6)


@pytest.mark.parametrize("name", STRAIN_PROFILES + LOADING_PROFILES)
def test_every_profile_stays_within_its_range_and_takes_arrays(name):
    p = strain_profile(name) if name.startswith("SP") else loading_profile(name)
    values = p(T)
    assert values.shape == T.shape and np.all(values >= p.lo) and np.all(values <= p.hi)
    assert p(T[17]) == values[17] and isinstance(p(1.0), float)
    assert values.max() - values.min() > 0.5 * (p.hi - p.lo)  # it sweeps the range


def test_random_peaks_alternate_far_enough_and_repeat_with_their_seed():
    fn = random_peaks(0.0, 1.0, 100.0, seed=3)
    x = fn(np.linspace(0.0, 100.0, 100001))
    assert np.array_equal(x, random_peaks(0.0, 1.0, 100.0, seed=3)(np.linspace(0.0, 100.0,
                                                                              100001)))
    assert not np.array_equal(x, random_peaks(0.0, 1.0, 100.0, seed=4)(np.linspace(0.0, 100.0,
                                                                                  100001)))
    assert x[0] == 0.0 and np.max(np.abs(np.diff(x))) < 1e-3  # starts at lo, smooth
    turns = np.flatnonzero(np.diff(np.sign(np.diff(x))) != 0)
    swings = np.abs(np.diff(x[turns]))
    assert len(turns) > 5 and np.all(swings[swings > 1e-9] >= 0.1 - 1e-9)


def test_copies_rebuild_the_same_profile_and_unknown_names_are_refused():
    sp = strain_profile("SP IV", seed=7)
    for other in (copy.deepcopy(sp), pickle.loads(pickle.dumps(sp))):
        assert np.array_equal(other(T), sp(T)) and repr(other) == repr(sp)
    with pytest.raises(ValueError, match="unknown profile 'SP V'; choose one of SP I"):
        strain_profile("SP V")
    assert profiles.DURATION == 550.0
