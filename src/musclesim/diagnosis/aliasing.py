"""How far the calibration parameters stand in for an effect on these data (`aliasing`, from a
fit's Jacobian; `aliasing_in`, by those that ended inside their bounds)."""
import math

import numpy as np

__all__ = ["aliasing", "aliasing_in"]


def aliasing(jac, k, names):
    """How far the calibration parameters can stand in for an effect on these data, to first
    order: {"share", "index", "with"} from a fit's Jacobian `jac` (training residuals, the
    effect's `k` columns first, then the calibration parameters `names`), or None (no
    Jacobian, no calibration, an effect that changes nothing).

    ``share`` is the squared cosine of the largest principal angle between the effect's columns
    and the calibration's (for one parameter: the R^2 of its column regressed on theirs): the
    part of the effect's least aliased signature calibration makes too. ``index`` is
    1 / sqrt(1 - share), read as Brun et al.'s (2001) collinearity index is: the change of the
    outputs the effect makes can be compensated by the calibration parameters down to 1 / index
    of it (its norm). ``with`` names the two calibration parameters that carry most of that
    compensation.

    >>> J = np.array([[1.0, 1.0, 0.0], [1.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    >>> a = aliasing(J, 1, ["T_amb", "shift"])  # (1, 1, 0) projects to (1, .5, .5): 1.5 of 2
    >>> round(a["share"], 3), a["with"]
    (0.75, ['T_amb', 'shift'])
    >>> J[:, 0] = J[:, 1] - J[:, 2]  # a bias that an ambient and a shift make together
    >>> round(aliasing(J, 1, ["T_amb", "shift"])["share"], 6)
    1.0
    """
    if jac is None or jac.shape[1] <= k:
        return None
    E, C = jac[:, :k], jac[:, k:]
    if not np.any(E):
        return None

    def basis(A):
        u, sv, _ = np.linalg.svd(A, full_matrices=False)
        return u[:, sv > sv[0] * 1e-9]

    qe = basis(E)
    cosines = np.linalg.svd(basis(C).T @ qe, compute_uv=False)
    share = float(min(cosines) ** 2) if len(cosines) == qe.shape[1] else 0.0
    beta = np.linalg.lstsq(C, E, rcond=None)[0]
    carried = np.abs(beta).sum(axis=1) * np.linalg.norm(C, axis=0)
    order = np.argsort(-carried)[:2]
    return {"share": share, "index": 1 / math.sqrt(max(1 - share, 1e-12)),
            "with": [names[i] for i in order if carried[i] > 0]}


def aliasing_in(f, k, calib):
    """`aliasing` of fit `f`'s first `k` parameters by the calibration parameters `calib` that
    ended inside their bounds: one at a bound cannot move on (the thermocouple's gain at its
    tolerance cannot stand in for a larger bias)."""
    inside = [i for i, (fr, x) in enumerate(zip(calib, f.x[k:]))
              if fr.lower + 1e-3 * (fr.upper - fr.lower) < x
              < fr.upper - 1e-3 * (fr.upper - fr.lower)]
    jac = f.jac
    return aliasing(None if jac is None else jac[:, list(range(k)) + [k + i for i in inside]],
                    k, [calib[i].key for i in inside])
