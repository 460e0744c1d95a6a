"""Synthetic family cases and report.json documents for the calibration's tests (no FMU): a
pipeline that puts the truth's log evidence ahead most of the time, a look-alike ahead
otherwise, and stops early on most cases without an effect."""
import numpy as np

from musclesim.benchmark import family
from musclesim.diagnosis import CALIBRATION_ONLY, OUTSIDE_LIBRARY, TWO_EFFECTS


def _doc(cause, pair, rng):
    floor = 0.002
    singles = list(family.LIBRARY)
    if cause == CALIBRATION_ONLY and rng.random() < 0.7:
        return {"verdict": "recalibration", "noise_floor": floor, "complete": True,
                "gap": {"heldout_gap": floor * rng.uniform(2, 4), "noise_floor": floor},
                "calibration": {"heldout_gap_after": floor * rng.uniform(0.9, 1.2),
                                "parameters": {}},
                "effects": [], "shrinkage": {"all": {"after": floor * 1.1}}}
    names = [CALIBRATION_ONLY] + singles
    lead = cause
    if cause == TWO_EFFECTS:
        names.append(" + ".join(pair))
        lead = names[-1] if rng.random() < 0.6 else pair[0]
    elif cause == OUTSIDE_LIBRARY:
        lead = str(rng.choice(names))
    if rng.random() < 0.25:  # a look-alike wins
        lead = str(rng.choice(names))
    logz = {n: 1000 + rng.normal(0, 3) for n in names}
    logz[lead] += rng.uniform(5, 60)
    best = max(logz.values())
    post = {n: float(np.exp(v - best)) for n, v in logz.items()}
    total = sum(post.values())
    left = floor * (rng.uniform(3, 6) if cause == OUTSIDE_LIBRARY else rng.uniform(1, 2))
    cands = [{"name": n, "probability": post[n] / total, "log_evidence": logz[n],
              "heldout_gap_all": left * (1.5 if n == CALIBRATION_ONLY else
                                         1.0 if n == lead else 1.3),
              "heldout_gap": {"thermocouple.T_meas": left, "wire.strain": left},
              "parameters": {}} for n in names]
    return {"verdict": lead, "noise_floor": floor, "complete": cause != OUTSIDE_LIBRARY,
            "gap": {"heldout_gap": floor * rng.uniform(5, 20), "noise_floor": floor},
            "calibration": {"heldout_gap_after": left * 1.5, "parameters": {}},
            "effects": [{"name": n} for n in singles],
            "evidence": {"candidates": cands, "symmetries": []},
            "shrinkage": {"all": {"after": left}},
            "regimes": {"by_regime": {"all": {"gap": left}, "hot": {"gap": left * 1.2}}}}


def pool(per_cause, seed):
    """(case, report document) of `per_cause` synthetic cases of every family cause."""
    rng = np.random.default_rng(seed)
    rows = []
    for i in range(per_cause * len(family.CAUSES)):
        cause = family.CAUSES[i % len(family.CAUSES)]
        pair = [str(e) for e in rng.choice(family.LIBRARY, 2, replace=False)]
        forms = {sub: sorted(o)[int(rng.integers(len(o)))] for sub, o in family.FORMS.items()}
        case = {"case": f"case-f{i:03d}", "cause": cause, "forms": forms,
                **({"pair": pair} if cause == TWO_EFFECTS else {})}
        rows.append((case, _doc(cause, pair, rng)))
    return rows
