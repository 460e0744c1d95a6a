"""Judging an effect's fit against calibration alone on the signals it can change: its gain with
a block-bootstrap interval (`judge`), where it gains (`signature`, `gain_signature`), and whether
a gap left is unstructured (`explained`).

>>> explained(0.02, 1.0, 0.01)  # within STRUCTURED (3) noise floors
True
>>> explained(0.05, 1.0, 0.01), explained(0.05, 0.5, 0.01)  # ... or RESIDUAL_SHARE (0.1) of before
(True, True)
>>> explained(0.2, 1.0, 0.01)
False
"""
import numpy as np

from musclesim.diagnosis.stats import HELD_OUT, bootstrap, gap, interval95, part_rows, row_squares
from musclesim.diagnosis.thresholds import (DEVIATES, MIN_SHRINKAGE, RESIDUAL_SHARE,
                                            SIGNATURE_MIN, STRUCTURED)

__all__ = ["NO_GAP", "explained", "gain_signature", "signature", "judge"]

NO_GAP = ("the model matches the data within the noise on the held-out part: there is no gap to "
          "explain")


def explained(after, before, floor):
    """Whether a held-out gap left `after` is unstructured: within STRUCTURED noise floors, or
    at most RESIDUAL_SHARE of the gap `before`."""
    return after <= STRUCTURED * floor or after <= RESIDUAL_SHARE * before


def gain_signature(gain, mask):
    """(ratio, consistent) from per-sample gains (squared residual before - after) and the
    regime's mask of the same samples (None: the effect predicts no regime, it is consistent when
    it gains at all). The ratio is the mean gain in the regime over the mean gain overall."""
    if mask is None:
        return None, gain.sum() > 0
    if not mask.any() or gain.sum() <= 0:
        return None, False
    ratio = float(gain[mask].mean() / gain.mean())
    return ratio, ratio >= SIGNATURE_MIN


def signature(unit, res_before, res_after, regime_masks, columns=None):
    """Gain per held-out sample (of `columns`) in the effect's regime vs overall: (ratio,
    consistent)."""
    rows = part_rows(unit, HELD_OUT)
    gain = np.concatenate([a - b for a, b in zip(row_squares(unit, res_before, HELD_OUT, columns),
                                                 row_squares(unit, res_after, HELD_OUT, columns))])
    mask = None if regime_masks is None else \
        np.concatenate([m[r] for m, r in zip(regime_masks, rows)])
    return gain_signature(gain, mask)


def judge(unit, res_before, res_after, columns, regime, masks):
    """An effect's held-out gain over `res_before` on the signals it can change (`columns`): the
    gap there before and after, the gain 1 - after / before with its 95 % block-bootstrap
    interval, its signature in `regime`, and whether it counts: the gap there is material (one
    of those signals deviates, above DEVIATES times its own noise), the gain is at least
    MIN_SHRINKAGE,
    its interval lies above zero and it shows in the regime."""
    before = gap(unit, res_before, HELD_OUT, columns)
    after = gap(unit, res_after, HELD_OUT, columns)
    boot = bootstrap(unit, [res_before, res_after], columns)
    interval = interval95(1 - boot[:, 1] / boot[:, 0])
    ratio, consistent = signature(unit, res_before, res_after,
                                  masks.get(regime) if regime != "all" else None, columns)
    gain = 1 - after / before if before else 0.0
    material = any(gap(unit, res_before, HELD_OUT, [c]) > DEVIATES * unit.noise[c] for c in columns)
    return {"signals": list(columns), "before": before, "after": after, "gain": gain,
            "interval": interval, "significant": bool(interval[0] > 0),
            "material": bool(material),
            "signature": {"regime": regime, "gain_ratio": ratio, "consistent": bool(consistent)},
            "counts": bool(material and gain >= MIN_SHRINKAGE and interval[0] > 0
                           and consistent)}
