"""Conformal statistics on plain arrays: prediction sets, p-values and recalibrated probabilities.

What this is for: the diagnosis names candidate explanations of a sim-to-real gap and weighs them.
These functions turn such weights into statements with a stated error rate, calibrated on cases
whose answer is known (the blind benchmark's), and need no model, FMU or file:

- split-conformal prediction with Mondrian (per-category) calibration, `mondrian_thresholds` and
  `prediction_set`: a set of candidates that holds the true one with probability at least
  1 - alpha within each category of true answer (Vovk, Gammerman & Shafer 2005, *Algorithmic
  Learning in a Random World*, their Mondrian conformal predictors; Romano, Sesia & Candès 2020,
  "Classification with valid and adaptive coverage", NeurIPS; Angelopoulos & Bates 2021,
  "A gentle introduction to conformal prediction and distribution-free uncertainty
  quantification", arXiv:2107.07511);
- conformal p-values for outlier testing, `conformal_p_value` (Bates, Candès, Lei, Romano &
  Sesia 2023, "Testing for outliers with conformal p-values", Ann. Statist. 51(1)), with a
  nonconformity score for feature vectors, `Outlyingness` (a Mahalanobis distance);
- a conditional-logit recalibration of the candidates' probabilities, `fit_choice` and
  `choice_probabilities` (McFadden 1974, "Conditional logit analysis of qualitative choice
  behavior", in Zarembka (ed.), *Frontiers in Econometrics*), fitted by log loss with a ridge
  `choose_ridge` picks by cross-validation, and
  `reliability`, the table of a reliability diagram to judge the probabilities it gives.

The guarantees assume that the calibration cases and the case judged are exchangeable (drawn
alike); they are marginal over calibration sets, and hold per category only for the Mondrian
thresholds. A label is in `prediction_set` exactly when its conformal p-value against its
category's calibration scores exceeds alpha.

>>> import numpy as np
>>> scores = np.arange(1.0, 20.0)                  # 19 calibration cases of category "a"
>>> thresholds = mondrian_thresholds(scores, ["a"] * 19, alpha=0.1)
>>> thresholds                                     # the ceil(20 * 0.9) = 18th smallest
{'a': 18.0}
>>> prediction_set(np.array([2.5, 18.0, 18.5]), ["a", "a", "b"], thresholds)  # "b": no data
[0, 1, 2]
>>> conformal_p_value(scores, 18.5)                # (1 + 1) / 20 > 0.1: in the set
0.1
"""
from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, TypedDict, overload

import numpy as np
from scipy import linalg, optimize

__all__ = ["fit_choice", "choose_ridge", "choice_probabilities", "mondrian_thresholds",
           "prediction_set", "conformal_p_value", "reliability", "ReliabilityBin", "Outlyingness"]

# (n + 1)(1 - alpha) is an integer for the usual pairs (n = 19, alpha = 0.05), but in floating
# point it may land just above it (10 * (1 - 0.7) is 3.0000000000000004): this much is rounding
_RANK_ROUNDING = 1e-9
_TENTHS = tuple(round(i / 10, 1) for i in range(11))


# ---- conditional logit ---------------------------------------------------------------------------

def _checked_choices(features: np.ndarray, available: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(features with zeros where not available, available as bool), or ValueError."""
    features = np.asarray(features, dtype=float)
    available = np.asarray(available)
    if features.ndim != 3:
        raise ValueError(f"features must have shape (n_cases, n_alternatives, n_features), "
                         f"not {features.shape}.")
    if available.shape != features.shape[:2]:
        raise ValueError(f"available has shape {available.shape}, but features has "
                         f"{features.shape[:2]} cases and alternatives.")
    if available.dtype != bool:
        raise ValueError(f"available must be a bool array, not {available.dtype}.")
    if not available.any(axis=1).all():
        raise ValueError(f"case {int(np.argmin(available.any(axis=1)))} has no available "
                         f"alternative.")
    masked = np.where(available[..., None], features, 0.0)
    if not np.isfinite(masked).all():
        raise ValueError("features must be finite for every available alternative.")
    return masked, available


def _log_probabilities(features: np.ndarray, available: np.ndarray,
                       weights: np.ndarray) -> np.ndarray:
    """log p of each alternative (-inf where not available), by a shifted log-sum-exp."""
    utility = np.where(available, features @ weights, -np.inf)
    top = utility.max(axis=1, keepdims=True)
    return utility - top - np.log(np.exp(utility - top).sum(axis=1, keepdims=True))


def choice_probabilities(features: np.ndarray, available: np.ndarray,
                         weights: np.ndarray) -> np.ndarray:
    """Conditional-logit probabilities of the alternatives of each case.

    The utility of alternative j of case i is ``features[i, j] @ weights``; the probabilities
    are their softmax over the case's available alternatives (the largest utility subtracted
    first, so that none overflows).

    Parameters
    ----------
    features : ndarray, shape (n_cases, n_alternatives, n_features)
        The alternatives' features; only those of available alternatives are read (the others
        may be NaN).
    available : ndarray of bool, shape (n_cases, n_alternatives)
        Which alternatives exist in each case; each case needs at least one.
    weights : ndarray, shape (n_features,)
        The weights of the features in the utility, e.g. from `fit_choice`.

    Returns
    -------
    ndarray, shape (n_cases, n_alternatives)
        Probabilities: zero where not available, each row summing to 1.

    Raises
    ------
    ValueError
        On a shape mismatch, a case without available alternatives or a non-finite value.

    Examples
    --------
    >>> features = np.array([[[0.0], [1.0], [np.nan]]])   # one case, the third alternative absent
    >>> p = choice_probabilities(features, np.array([[True, True, False]]), np.array([np.log(3)]))
    >>> p.round(6).tolist()
    [[0.25, 0.75, 0.0]]
    """
    masked, available = _checked_choices(features, available)
    weights = np.asarray(weights, dtype=float)
    if weights.shape != masked.shape[2:]:
        raise ValueError(f"weights has shape {weights.shape}, but features has "
                         f"{masked.shape[2]} features.")
    if not np.isfinite(weights).all():
        raise ValueError("weights must be finite.")
    return np.exp(_log_probabilities(masked, available, weights))


def fit_choice(features: np.ndarray, available: np.ndarray, truth: np.ndarray,
               l2: float = 1e-2) -> np.ndarray:
    """Weights of a conditional logit fitted to known answers by penalised log loss.

    Minimises ``-mean_i log p_i(truth_i) + l2 * |w|^2`` over the weights w, where p is
    `choice_probabilities` (McFadden 1974), with scipy's L-BFGS-B from w = 0 and the analytic
    gradient ``mean_i (sum_j p_ij x_ij - x_i,truth_i) + 2 l2 w``. The loss is convex (strictly
    for l2 > 0), so the result does not depend on a start; the fit is deterministic. A feature
    equal for all the alternatives of every case is not identified (it cancels in the
    softmax): its weight is 0 with l2 > 0. With l2 = 0 and answers that a weight separates
    perfectly the weights grow until the optimiser stops.

    Parameters
    ----------
    features : ndarray, shape (n_cases, n_alternatives, n_features)
        The alternatives' features; only those of available alternatives are read.
    available : ndarray of bool, shape (n_cases, n_alternatives)
        Which alternatives exist in each case.
    truth : ndarray of int, shape (n_cases,)
        The index of each case's true alternative, which must be available.
    l2 : float, default 1e-2
        The ridge penalty on the squared norm of the weights (>= 0).

    Returns
    -------
    ndarray, shape (n_features,)
        The fitted weights.

    Raises
    ------
    ValueError
        On a shape mismatch, a truth that is not an available alternative, a non-finite
        feature or a negative `l2`.

    Examples
    --------
    >>> features = np.array([[[1.0], [0.0]], [[1.0], [0.0]], [[0.0], [1.0]]])
    >>> w = fit_choice(features, np.ones((3, 2), bool), np.array([0, 0, 0]), l2=0.0)
    >>> round(float(w[0]), 4)                     # 2 of 3 chose the feature: e^w / (1 + e^w) = 2/3
    0.6931
    """
    masked, available = _checked_choices(features, available)
    truth = np.asarray(truth)
    n = masked.shape[0]
    if truth.shape != (n,):
        raise ValueError(f"truth has shape {truth.shape}, but features has {n} cases.")
    if n == 0:
        raise ValueError("there are no cases to fit.")
    if not np.issubdtype(truth.dtype, np.integer):
        raise ValueError(f"truth must hold integer indices, not {truth.dtype}.")
    outside = (truth < 0) | (truth >= masked.shape[1])
    if outside.any():
        i = int(np.argmax(outside))
        raise ValueError(f"truth {int(truth[i])} of case {i} is not an alternative index "
                         f"(0 to {masked.shape[1] - 1}).")
    rows = np.arange(n)
    if not available[rows, truth].all():
        i = int(np.argmin(available[rows, truth]))
        raise ValueError(f"truth {int(truth[i])} of case {i} is not an available alternative.")
    if not (math.isfinite(l2) and l2 >= 0):
        raise ValueError(f"l2 must be finite and non-negative, not {l2}.")
    chosen = masked[rows, truth]  # (n, n_features)

    def loss(w: np.ndarray) -> tuple[float, np.ndarray]:
        logp = _log_probabilities(masked, available, w)
        p = np.exp(logp)
        expected = np.einsum("nj,njf->nf", p, masked)
        value = -logp[rows, truth].mean() + l2 * w @ w
        return float(value), (expected - chosen).mean(axis=0) + 2 * l2 * w

    result = optimize.minimize(loss, np.zeros(masked.shape[2]), jac=True, method="L-BFGS-B",
                               options={"gtol": 1e-10, "ftol": 1e-15, "maxiter": 10_000})
    return np.asarray(result.x, dtype=float)


def choose_ridge(features: np.ndarray, available: np.ndarray, truth: np.ndarray,
                 grid: Sequence[float], folds: int = 5,
                 seed: int = 0) -> tuple[float, dict[float, float]]:
    """The ridge of `fit_choice` with the least cross-validated log loss.

    The cases are dealt at random (numpy's generator of `seed`) into `folds` folds of sizes
    differing by at most one; for each ridge of `grid` the weights are fitted on all folds but
    one and the mean ``-log p(truth)`` is taken on the one left out, over every case.

    Parameters
    ----------
    features, available, truth
        As for `fit_choice`.
    grid : sequence of float
        The ridges to try (each >= 0); on a tie the first.
    folds : int, default 5
        The number of folds (2 to the number of cases).
    seed : int, default 0
        The seed of the deal.

    Returns
    -------
    (float, dict)
        The chosen ridge, and each ridge's cross-validated log loss.

    Raises
    ------
    ValueError
        On an empty grid, a fold count out of range, or as `fit_choice` does.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> x = rng.normal(size=(40, 2, 1))
    >>> truth = (x[:, 1, 0] > x[:, 0, 0]).astype(int)    # separable: the weakest ridge fits best
    >>> choose_ridge(x, np.ones((40, 2), bool), truth, [1.0, 1e-3])[0]
    0.001
    """
    truth = np.asarray(truth)
    n = len(truth)
    if not grid:
        raise ValueError("the grid of ridges is empty.")
    if not 2 <= folds <= n:
        raise ValueError(f"folds must lie between 2 and the {n} cases, not {folds}.")
    fold = np.random.default_rng(seed).permutation(n) % folds
    losses: dict[float, float] = {}
    for l2 in grid:
        total = 0.0
        for k in range(folds):
            out = fold == k
            w = fit_choice(features[~out], available[~out], truth[~out], float(l2))
            p = choice_probabilities(features[out], available[out], w)
            total -= float(np.log(np.maximum(p[np.arange(out.sum()), truth[out]],
                                             1e-300)).sum())
        losses[float(l2)] = total / n
    return min(losses, key=losses.__getitem__), losses


# ---- split-conformal prediction ------------------------------------------------------------------

def _checked_alpha(alpha: float) -> None:
    if not 0 < alpha < 1:
        raise ValueError(f"alpha must lie strictly between 0 and 1, not {alpha}.")


def mondrian_thresholds(scores: np.ndarray, categories: Sequence[str] | np.ndarray,
                        alpha: float) -> dict[str, float]:
    """Split-conformal thresholds of nonconformity, one per category (Mondrian calibration).

    For category k with n_k calibration cases, the threshold q_k is the
    ceil((n_k + 1)(1 - alpha))-th smallest of their scores, or +inf when that rank exceeds n_k
    (alpha < 1 / (n_k + 1)). A test case exchangeable with category k's calibration cases then
    has P(score <= q_k | category k) >= 1 - alpha (Vovk et al. 2005; Angelopoulos & Bates 2021,
    sect. 1, applied to each category's cases alone), and, when q_k is finite and the scores
    have no ties, less than 1 - alpha + 1 / (n_k + 1).
    A product (n_k + 1)(1 - alpha) within 1e-9 above an integer counts as that integer (the
    rounding of alpha in floating point).

    Parameters
    ----------
    scores : ndarray, shape (n,)
        The nonconformity of each calibration case's true label (larger: stranger).
    categories : sequence of str, length n
        The category of each calibration case's true label.
    alpha : float
        The error rate allowed, in (0, 1).

    Returns
    -------
    dict of str to float
        {category: q_k} for the categories in `categories`, sorted by name. A category without
        calibration cases is absent: callers treat it as +inf (every label of it is kept).

    Raises
    ------
    ValueError
        When `scores` is not one-dimensional, holds NaN, or its length differs from that of
        `categories`, or when alpha is outside (0, 1).

    Examples
    --------
    >>> mondrian_thresholds(np.array([3.0, 1.0, 2.0, 5.0]), ["a", "a", "a", "b"], alpha=0.4)
    {'a': 3.0, 'b': inf}
    >>> mondrian_thresholds(np.array([3.0, 1.0, 2.0, 5.0]), ["a", "a", "a", "b"], alpha=0.5)
    {'a': 2.0, 'b': 5.0}
    """
    scores = np.asarray(scores, dtype=float)
    labels = np.asarray(categories).astype(str)
    _checked_alpha(alpha)
    if scores.ndim != 1:
        raise ValueError(f"scores must be one-dimensional, not of shape {scores.shape}.")
    if labels.shape != scores.shape:
        raise ValueError(f"scores has {scores.size} values but categories has {labels.size}.")
    if np.isnan(scores).any():
        raise ValueError("scores must not be NaN.")
    out: dict[str, float] = {}
    for category in sorted(set(labels.tolist())):
        ranked = np.sort(scores[labels == category])
        rank = math.ceil((ranked.size + 1) * (1 - alpha) - _RANK_ROUNDING)
        out[category] = float(ranked[rank - 1]) if rank <= ranked.size else math.inf
    return out


def prediction_set(label_scores: np.ndarray, label_categories: Sequence[str] | np.ndarray,
                   thresholds: Mapping[str, float]) -> list[int]:
    """The labels of one test case whose nonconformity is within their category's threshold.

    Parameters
    ----------
    label_scores : ndarray, shape (n_labels,)
        The nonconformity of each candidate label of the case.
    label_categories : sequence of str, length n_labels
        The category of each label (the category it would have as the true label).
    thresholds : mapping of str to float
        {category: threshold} from `mondrian_thresholds`; a category missing from it counts as
        +inf (its labels are kept).

    Returns
    -------
    list of int
        The indices of the labels kept, ascending: ``score <= threshold`` (ties kept).

    Raises
    ------
    ValueError
        When `label_scores` is not one-dimensional, holds NaN, or its length differs from
        that of `label_categories`.

    Examples
    --------
    >>> prediction_set(np.array([0.5, 2.0, 9.0]), ["a", "a", "c"], {"a": 2.0, "c": 3.0})
    [0, 1]
    """
    label_scores = np.asarray(label_scores, dtype=float)
    labels = np.asarray(label_categories).astype(str)
    if label_scores.ndim != 1:
        raise ValueError(f"label_scores must be one-dimensional, not of shape "
                         f"{label_scores.shape}.")
    if labels.shape != label_scores.shape:
        raise ValueError(f"label_scores has {label_scores.size} values but label_categories "
                         f"has {labels.size}.")
    if np.isnan(label_scores).any():
        raise ValueError("label_scores must not be NaN.")
    return [i for i, (s, k) in enumerate(zip(label_scores.tolist(), labels.tolist()))
            if s <= thresholds.get(k, math.inf)]


@overload
def conformal_p_value(calibration_scores: np.ndarray, score: float) -> float: ...


@overload
def conformal_p_value(calibration_scores: np.ndarray, score: np.ndarray) -> np.ndarray: ...


def conformal_p_value(calibration_scores: np.ndarray,
                      score: float | np.ndarray) -> float | np.ndarray:
    """The conformal p-value of a score among calibration scores (larger score: stranger).

    ``p = (1 + #{i : s_i >= score}) / (n + 1)``, the (marginal, not smoothed) conformal p-value
    of Bates et al. (2023). If the score is exchangeable with the n calibration scores,
    P(p <= t) <= t for every t in [0, 1] (super-uniform), whatever the scores' distribution;
    with no calibration scores p = 1. For a category's calibration scores, p > alpha exactly when
    ``score <= mondrian_thresholds(...)[category]``.

    Parameters
    ----------
    calibration_scores : ndarray, shape (n,)
        The nonconformity scores of the calibration cases.
    score : float or ndarray
        The test score, or an array of test scores (each judged on its own).

    Returns
    -------
    float or ndarray
        The p-value, or an array of them shaped as `score`.

    Raises
    ------
    ValueError
        When `calibration_scores` is not one-dimensional or a score is NaN.

    Examples
    --------
    >>> conformal_p_value(np.array([1.0, 2.0, 3.0, 4.0]), 3.0)   # (1 + 2) / 5
    0.6
    >>> conformal_p_value(np.array([1.0, 2.0, 3.0, 4.0]), np.array([0.0, 9.0])).tolist()
    [1.0, 0.2]
    """
    calibration = np.asarray(calibration_scores, dtype=float)
    if calibration.ndim != 1:
        raise ValueError(f"calibration_scores must be one-dimensional, not of shape "
                         f"{calibration.shape}.")
    tests = np.asarray(score, dtype=float)
    if np.isnan(calibration).any() or np.isnan(tests).any():
        raise ValueError("scores must not be NaN.")
    ranked = np.sort(calibration)
    at_least = ranked.size - np.searchsorted(ranked, tests, side="left")
    p = (1.0 + at_least) / (ranked.size + 1.0)
    if isinstance(score, np.ndarray):
        return np.asarray(p, dtype=float)
    return float(p)


# ---- probabilities judged ------------------------------------------------------------------------

class ReliabilityBin(TypedDict):
    """One bin of `reliability`: its probability interval, how many cases fell in it, their mean
    stated probability and how often they were right (None for both in an empty bin)."""

    lower: float
    upper: float
    count: int
    stated: float | None
    observed: float | None


def reliability(probabilities: np.ndarray, hits: np.ndarray,
                edges: Sequence[float] = _TENTHS) -> list[ReliabilityBin]:
    """The table of a reliability diagram: stated probability against observed frequency.

    Each bin is ``[lower, upper)``, the last ``[lower, upper]``. Probabilities that are right
    say, in each bin, about as often as they state (``observed`` near ``stated``, within the
    binomial spread of ``count`` cases).

    Parameters
    ----------
    probabilities : ndarray, shape (n,)
        The stated probability of each prediction, within the edges.
    hits : ndarray of bool, shape (n,)
        Whether each prediction came true (bools, or 0 and 1).
    edges : sequence of float, default (0, 0.1, ..., 1)
        The bins' edges, strictly increasing, at least two.

    Returns
    -------
    list of ReliabilityBin
        Per bin: {"lower", "upper", "count", "stated" (the mean probability), "observed" (the
        frequency of hits)}; an empty bin has count 0 and None for both.

    Raises
    ------
    ValueError
        On lengths that differ, hits that are not 0 or 1, edges that do not increase, or a
        probability outside the edges.

    Examples
    --------
    >>> table = reliability(np.array([0.2, 0.25, 0.9, 1.0]), np.array([0, 1, 1, 1]),
    ...                     edges=(0.0, 0.5, 1.0))
    >>> [(b["count"], b["stated"], b["observed"]) for b in table]
    [(2, 0.225, 0.5), (2, 0.95, 1.0)]
    """
    p = np.asarray(probabilities, dtype=float)
    h = np.asarray(hits)
    cuts = np.asarray(edges, dtype=float)
    if p.ndim != 1 or h.shape != p.shape:
        raise ValueError(f"probabilities and hits must be one-dimensional of one length, not "
                         f"of shapes {p.shape} and {h.shape}.")
    if not np.isin(h, (0, 1)).all():
        raise ValueError("hits must be bools (or 0 and 1).")
    if cuts.ndim != 1 or cuts.size < 2 or not (np.diff(cuts) > 0).all():
        raise ValueError("edges must be at least two strictly increasing values.")
    if not ((p >= cuts[0]) & (p <= cuts[-1])).all():  # NaN fails this too
        raise ValueError(f"probabilities must lie within the edges, [{cuts[0]}, {cuts[-1]}].")
    which = np.minimum(np.searchsorted(cuts, p, side="right") - 1, cuts.size - 2)
    out: list[ReliabilityBin] = []
    for b in range(cuts.size - 1):
        inside = which == b
        count = int(inside.sum())
        out.append(ReliabilityBin(
            lower=float(cuts[b]), upper=float(cuts[b + 1]), count=count,
            stated=float(p[inside].mean()) if count else None,
            observed=float(h[inside].astype(float).mean()) if count else None))
    return out


# ---- outlyingness of feature vectors -------------------------------------------------------------

@dataclass(frozen=True, eq=False)
class Outlyingness:
    """A nonconformity score for feature vectors: the Mahalanobis distance from a centre.

    `fit` takes the centre as the median of each column (robust: a few far rows do not move
    it) and the scale as the covariance of the columns about that median,
    ``S = (X - m)' (X - m) / n``, plus a ridge ``1e-6 * trace(S) / d`` on the diagonal so that
    it inverts when columns are collinear or fewer rows than columns are given. The scale is
    not robust (a far row inflates it); it needs no iteration and suits calibration sets
    without gross outliers. Scores of exchangeable rows give valid `conformal_p_value`s.
    Compared by identity (the arrays have no single truth value); `to_json` gives the values.

    Parameters
    ----------
    centre : ndarray, shape (d,)
        The centre m.
    scale : ndarray, shape (d, d)
        The symmetric positive-definite scale S (the ridge included).

    Examples
    --------
    >>> model = Outlyingness.fit(np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [2.0, 2.0],
    ...                                    [1.0, 1.0]]))
    >>> model.centre.tolist()
    [1.0, 1.0]
    >>> model.score(np.array([[1.0, 1.0], [1.0, 9.0]])).round(3).tolist()
    [0.0, 8.944]
    """

    centre: np.ndarray
    scale: np.ndarray
    _factor: np.ndarray = field(init=False, repr=False)  # the Cholesky factor of scale

    def __post_init__(self) -> None:
        centre = np.asarray(self.centre, dtype=float)
        scale = np.asarray(self.scale, dtype=float)
        if centre.ndim != 1 or scale.shape != (centre.size, centre.size):
            raise ValueError(f"centre must have shape (d,) and scale (d, d), not {centre.shape} "
                             f"and {scale.shape}.")
        if not (np.isfinite(centre).all() and np.isfinite(scale).all()):
            raise ValueError("centre and scale must be finite.")
        try:
            factor = linalg.cholesky(scale, lower=True)
        except linalg.LinAlgError:
            raise ValueError("scale must be symmetric positive definite.") from None
        object.__setattr__(self, "centre", centre)
        object.__setattr__(self, "scale", scale)
        object.__setattr__(self, "_factor", factor)

    @classmethod
    def fit(cls, X: np.ndarray) -> Outlyingness:
        """The centre and scale of the rows of `X` (see the class docstring).

        Parameters
        ----------
        X : ndarray, shape (n, d)
            Feature vectors, one a row, finite; at least one row that differs from the median.

        Returns
        -------
        Outlyingness
            The fitted score.

        Raises
        ------
        ValueError
            When `X` is not a non-empty finite 2-D array or all its rows equal the median.
        """
        X = np.asarray(X, dtype=float)
        if X.ndim != 2 or X.shape[0] == 0 or X.shape[1] == 0:
            raise ValueError(f"X must be a non-empty (n, d) array, not of shape {X.shape}.")
        if not np.isfinite(X).all():
            raise ValueError("X must be finite.")
        centre = np.median(X, axis=0)
        deviations = X - centre
        scale = deviations.T @ deviations / X.shape[0]
        spread = float(np.trace(scale))
        if spread <= 0:
            raise ValueError("X has no spread about its median: every row equals it.")
        scale = (scale + scale.T) / 2 + 1e-6 * spread / X.shape[1] * np.eye(X.shape[1])
        return cls(centre, scale)

    def score(self, X: np.ndarray) -> np.ndarray:
        """The Mahalanobis distance ``sqrt((x - m)' S^-1 (x - m))`` of each row of `X`.

        Parameters
        ----------
        X : ndarray, shape (n, d)
            Feature vectors, one a row.

        Returns
        -------
        ndarray, shape (n,)
            Their distances (larger: stranger).

        Raises
        ------
        ValueError
            When `X` is not an (n, d) array of this score's d columns.
        """
        X = np.asarray(X, dtype=float)
        d = self.centre.size
        if X.ndim != 2 or X.shape[1] != d:
            raise ValueError(f"X must have shape (n, {d}), not {X.shape}.")
        z = linalg.solve_triangular(self._factor, (X - self.centre).T, lower=True)
        return np.asarray(np.sqrt((z * z).sum(axis=0)), dtype=float)

    def to_json(self) -> dict[str, Any]:
        """{"centre": [d floats], "scale": [d lists of d floats]}: plain lists for JSON.

        Returns
        -------
        dict
            The document `from_json` reads back.
        """
        return {"centre": self.centre.tolist(), "scale": self.scale.tolist()}

    @classmethod
    def from_json(cls, document: Mapping[str, Any]) -> Outlyingness:
        """The score `to_json` wrote.

        Parameters
        ----------
        document : mapping
            {"centre": [...], "scale": [[...], ...]}.

        Returns
        -------
        Outlyingness
            The same centre and scale.

        Raises
        ------
        ValueError
            When a key is missing or the values do not make a valid score.
        """
        missing = {"centre", "scale"} - set(document)
        if missing:
            raise ValueError(f"an Outlyingness document needs {sorted(missing)}.")
        return cls(np.asarray(document["centre"], dtype=float),
                   np.asarray(document["scale"], dtype=float))
