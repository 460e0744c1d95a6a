"""Hand-made stand-ins for the diagnosis's tests (no FMU): a unit of one run whose first half
trains and second is held out, noise, a library effect placed as a candidate, a fit result."""
import math
from dataclasses import replace
from types import SimpleNamespace

import numpy as np

from musclesim.cosim import Instance, Scenario, Signal
from musclesim.diagnosis import effects
from musclesim.diagnosis.candidates import Candidate
from musclesim.diagnosis.fitting import FitResult, Free
from musclesim.diagnosis.stats import HELD_OUT, gap

FLOOR = 0.01
N = 400
TC, STRAIN = Signal("thermocouple", "T_meas"), Signal("wire", "strain")


def fake_unit(observed=(TC, STRAIN)):
    """One run: the first half trains, the second is held out; the wire feeds the
    thermocouple."""
    part = np.r_[np.zeros(N // 2, np.int8), np.ones(N // 2, np.int8)]
    scenario = Scenario("bench", None, {"wire": Instance("wire", "SmaWire"),
                                        "thermocouple": Instance("thermocouple", "Thermocouple")},
                        ((Signal("wire", "T"), Signal("thermocouple", "T")),), 0.02, 8.0)
    return SimpleNamespace(observed=observed, noise={c: FLOOR / 3 for c in observed},
                           instances=("thermocouple", "wire"),
                           runs=[SimpleNamespace(part=part, time=0.02 * np.arange(N),
                                                 scenario=scenario)])


def noise(seed):
    return 0.003 * np.random.default_rng(seed).standard_normal(N)


def candidate(name, instance):
    e = effects.find(name)
    return Candidate(e, (instance,), [Free((instance,), p.name, p.lower, p.upper, p.off)
                                      for p in e.parameters])


def fitted(unit, res, x=3.0, **changed):
    """A `FitResult` of one parameter at `x` with residuals `res` (fields `changed`)."""
    interval = [(x - 0.1, x + 0.1)] if isinstance(x, float) else []
    f = FitResult(x if isinstance(x, list) else [x], interval, res, math.inf,
                  gap(unit, res, HELD_OUT), True, 1, None, {})
    return replace(f, **changed)
