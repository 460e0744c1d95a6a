"""The conformal statistics on synthetic arrays (no FMU): Mondrian thresholds and prediction sets,
their coverage, agreement with crepes, conformal p-values, the conditional logit, reliability bins,
the outlyingness score and the errors."""
import doctest
import json
import math

import numpy as np
import pytest
from scipy import stats as sps

from musclesim.diagnosis import conformal
from musclesim.diagnosis.conformal import (Outlyingness, choice_probabilities, choose_ridge,
                                           conformal_p_value, fit_choice, mondrian_thresholds,
                                           prediction_set, reliability)


def test_the_docstring_examples_run():
    result = doctest.testmod(conformal)
    assert result.attempted >= 15 and result.failed == 0


def test_all_names_the_public_functions():
    assert all(callable(getattr(conformal, name)) for name in conformal.__all__)


# ---- the threshold rule by hand ------------------------------------------------------------------

def test_nineteen_cases_at_five_percent_give_the_largest_score():
    scores = np.random.default_rng(0).permutation(np.arange(1.0, 20.0))
    # ceil(20 * 0.95) = 19: the 19th smallest of 19
    assert mondrian_thresholds(scores, ["k"] * 19, alpha=0.05) == {"k": 19.0}
    # one more case and the rank is ceil(21 * 0.95) = 20 of 20: still the largest
    assert mondrian_thresholds(np.append(scores, 0.5), ["k"] * 20, 0.05) == {"k": 19.0}


def test_ten_cases_at_five_percent_cannot_cover_and_give_inf():
    # ceil(11 * 0.95) = 11 > 10
    assert mondrian_thresholds(np.arange(10.0), ["k"] * 10, alpha=0.05) == {"k": math.inf}
    # at 10 %: ceil(11 * 0.9) = 10, the largest
    assert mondrian_thresholds(np.arange(10.0), ["k"] * 10, alpha=0.1) == {"k": 9.0}


def test_the_rank_is_ceil_of_n_plus_one_times_one_minus_alpha():
    scores = np.arange(1.0, 10.0)  # 9 cases: the k-th smallest is k
    for alpha, rank in [(0.5, 5), (0.45, 6), (0.3, 7), (0.25, 8), (0.2, 8), (0.15, 9), (0.7, 3)]:
        assert mondrian_thresholds(scores, ["k"] * 9, alpha) == {"k": float(rank)}, alpha
    # 10 * (1 - 0.7) is 3.0000000000000004 in floating point and 100 * (1 - 0.45)
    # 55.00000000000001: ranks 3 and 55, not 4 and 56
    assert (10 * (1 - 0.7), 100 * (1 - 0.45)) == (3.0000000000000004, 55.00000000000001)
    assert mondrian_thresholds(np.arange(1.0, 100.0), ["k"] * 99, 0.45) == {"k": 55.0}


def test_ties_count_once_each_and_a_label_at_the_threshold_is_kept():
    scores = np.array([5.0] * 9 + [1.0])
    # ceil(11 * 0.8) = 9: sorted, 1 then nine 5s, the 9th is a 5
    assert mondrian_thresholds(scores, ["k"] * 10, 0.2) == {"k": 5.0}
    scores = np.array([2.0, 1.0, 2.0, 3.0, 2.0])
    q = mondrian_thresholds(scores, ["k"] * 5, 0.5)  # ceil(6 * 0.5) = 3: 1, 2, [2], 2, 3
    assert q == {"k": 2.0}
    assert prediction_set(np.array([2.0, np.nextafter(2.0, 3.0), 1.0]), ["k"] * 3, q) == [0, 2]


def test_each_category_has_its_own_threshold_and_an_unknown_category_keeps_its_labels():
    scores = np.array([1.0, 2.0, 3.0, 4.0, 10.0, 20.0, 30.0, 40.0, 7.0])
    cats = ["a"] * 4 + ["b"] * 4 + ["c"]
    q = mondrian_thresholds(scores, np.array(cats), alpha=0.4)  # ceil(5 * 0.6) = 3; c: 2 > 1
    assert q == {"a": 3.0, "b": 30.0, "c": math.inf}
    assert list(q) == ["a", "b", "c"]
    assert prediction_set(np.array([3.0, 3.5, 25.0, 31.0, 1e9, 1e9]),
                          ["a", "a", "b", "b", "c", "unseen"], q) == [0, 2, 4, 5]
    assert prediction_set(np.zeros(0), [], q) == []


# ---- coverage ------------------------------------------------------------------------------------

ALPHA = 0.1
CALIBRATION = {"a": 40, "b": 14}  # cases per category in each repetition
SCALE = {"a": 1.0, "b": 3.0}      # category b's true labels look stranger: one pooled
LABELS = ["a", "a", "b", "b"]     # threshold would under-cover it
TESTS, REPETITIONS = 50, 200      # test cases per category per repetition


def expected_coverage(n):
    """(mean, standard deviation) of the empirical coverage of one category over the
    repetitions.

    With continuous scores and n calibration cases the coverage of one calibration set is
    C = F(q) = U_(m), the m-th smallest of n uniforms, m = ceil((n + 1)(1 - alpha)):
    C ~ Beta(m, n + 1 - m) (the law Angelopoulos & Bates 2021 give), E C = m / (n + 1)
    (>= 1 - alpha).
    Each repetition draws T test cases, hits ~ Binomial(T, C); the R repetitions are
    independent, so the pooled frequency has variance (Var C + E[C (1 - C)] / T) / R, where
    E[C (1 - C)] = E C - E C^2 = E C (1 - E C) - Var C.
    """
    m = math.ceil((n + 1) * (1 - ALPHA))
    beta = sps.beta(m, n + 1 - m)
    mean, var = beta.mean(), beta.var()
    within = mean * (1 - mean) - var
    return mean, math.sqrt((var + within / TESTS) / REPETITIONS)


def draw_scores(rng, category, size):
    """Nonconformity of true labels of `category`: |N(0, 1)| scaled."""
    return SCALE[category] * np.abs(rng.standard_normal(size))


def coverage_run(pooled=False):
    """{category: (hits, total)} of the true labels, and the mean set size, over the
    repetitions."""
    rng = np.random.default_rng(20260529)
    hits = {k: 0 for k in CALIBRATION}
    sizes = []
    for _ in range(REPETITIONS):
        cats = [k for k, n in CALIBRATION.items() for _ in range(n)]
        scores = np.concatenate([draw_scores(rng, k, n) for k, n in CALIBRATION.items()])
        q = mondrian_thresholds(scores, ["all"] * len(cats) if pooled else cats, ALPHA)
        if pooled:
            q = {k: q["all"] for k in CALIBRATION}
        for k in CALIBRATION:
            truths = rng.choice([i for i, c in enumerate(LABELS) if c == k], size=TESTS)
            # wrong labels: clearly stranger than true ones of their category, though not always
            label_scores = 1.5 * np.array([SCALE[c] for c in LABELS]) \
                + np.abs(rng.standard_normal((TESTS, len(LABELS)))) * [SCALE[c] for c in LABELS]
            label_scores[np.arange(TESTS), truths] = draw_scores(rng, k, TESTS)
            for row, truth in zip(label_scores, truths):
                kept = prediction_set(row, LABELS, q)
                hits[k] += truth in kept
                sizes.append(len(kept))
    return {k: (hits[k], TESTS * REPETITIONS) for k in CALIBRATION}, float(np.mean(sizes))


def test_mondrian_sets_cover_each_category_at_least_one_minus_alpha():
    found, mean_size = coverage_run()
    for k, (hit, total) in found.items():
        rate = hit / total
        mean, sd = expected_coverage(CALIBRATION[k])
        # 4 standard deviations: a correct rule fails this with probability about 6e-5
        assert rate >= 1 - ALPHA - 4 * sd, (k, rate)
        assert abs(rate - mean) <= 4 * sd, (k, rate, mean)
        # not trivially 1: the guarantee's upper side, 1 - alpha + 1 / (n + 1)
        assert rate <= 1 - ALPHA + 1 / (CALIBRATION[k] + 1) + 4 * sd, (k, rate)
    # the sets are not everything: on average well under the four labels
    assert 1.0 < mean_size < 2.0


def test_one_pooled_threshold_under_covers_the_harder_category():
    """What the Mondrian calibration is for; also shows the coverage test can fail."""
    found, _ = coverage_run(pooled=True)
    hit, total = found["b"]
    _, sd = expected_coverage(CALIBRATION["b"])
    assert hit / total < 1 - ALPHA - 4 * sd


# ---- conformal p-values --------------------------------------------------------------------------

def test_p_values_by_hand_with_ties():
    calibration = np.array([1.0, 1.0, 1.0, 2.0])
    assert conformal_p_value(calibration, 1.0) == 1.0      # (1 + 4) / 5
    assert conformal_p_value(calibration, 1.5) == 0.4      # (1 + 1) / 5
    assert conformal_p_value(calibration, 2.0) == 0.4      # a tie counts as at least as strange
    assert conformal_p_value(calibration, 3.0) == 0.2      # stranger than all: 1 / (n + 1)
    assert conformal_p_value(np.zeros(0), 3.0) == 1.0      # no calibration: no evidence
    assert isinstance(conformal_p_value(calibration, 1.5), float)
    vector = conformal_p_value(calibration, np.array([[1.0, 1.5], [2.0, 3.0]]))
    assert vector.shape == (2, 2) and vector.tolist() == [[1.0, 0.4], [0.4, 0.2]]


def test_p_values_are_super_uniform_on_exchangeable_data():
    rng = np.random.default_rng(7)
    n, R = 19, 4000
    data = rng.exponential(size=(R, n + 1))
    p = np.array([conformal_p_value(row[:n], row[n]) for row in data])
    # continuous scores: p is uniform on {1/20, ..., 20/20}, P(p <= k / 20) = k / 20 exactly;
    # the frequency of R independent draws has sd sqrt(t (1 - t) / R), 4 of them allowed
    for t in (0.05, 0.1, 0.25, 0.5):
        assert abs(np.mean(p <= t) - t) <= 4 * math.sqrt(t * (1 - t) / R), t
    # an outlier: the test score shifted far out gets the smallest p-value there is
    assert conformal_p_value(data[0, :n], data[0, :n].max() + 1) == 1 / (n + 1)


def test_a_label_is_in_the_set_exactly_when_its_p_value_exceeds_alpha():
    rng = np.random.default_rng(3)
    cats = np.array(["a"] * 19 + ["b"] * 9 + ["c"] * 3)
    scores = np.round(rng.gamma(2.0, size=cats.size), 1)  # rounded: ties
    labels = ["a", "b", "c", "a", "b", "c"]
    tests = np.round(rng.gamma(2.0, size=(200, len(labels))), 1)
    for alpha in (0.05, 0.1, 0.2, 0.25, 0.3, 0.5, 0.01):  # 0.05 * 20, 0.1 * 10, 0.25 * 4: boundary
        q = mondrian_thresholds(scores, cats, alpha)
        for row in tests:
            p = [conformal_p_value(scores[cats == k], s) for s, k in zip(row, labels)]
            assert prediction_set(row, labels, q) == [i for i, v in enumerate(p) if v > alpha]


# ---- agreement with crepes -----------------------------------------------------------------------

def test_sets_and_p_values_agree_with_crepes_mondrian_classifier():
    """crepes' non-smoothed p-value is ours, (1 + #{s_i >= s}) / (n + 1); its default (smoothed)
    one replaces the 1 + #{s_i == s} by U (1 + #{s_i == s}), U uniform. Its Mondrian `bins`
    give one category per test object, for all its labels; here a category belongs to a label,
    so crepes is asked label by label (column by column), each column's bins that label's
    category. crepes keeps a label when p >= 1 - confidence, we when p > alpha: they differ
    only at p == alpha, impossible at the alphas here (alpha (n_k + 1) is no integer)."""
    crepes = pytest.importorskip("crepes")
    rng = np.random.default_rng(11)
    sizes = {"a": 37, "b": 23, "c": 11}
    cats = np.array([k for k, n in sizes.items() for _ in range(n)])
    shape = {"a": 1.0, "b": 2.0, "c": 4.0}
    scores = np.round(np.array([rng.gamma(shape[k]) for k in cats]), 1)  # rounded: ties
    labels = np.array(["a", "a", "b", "b", "c", "c"])
    tests = np.round(rng.gamma(2.0, size=(300, labels.size)), 1)
    classifier = crepes.ConformalClassifier().fit(scores, bins=cats)
    for alpha in (0.1, 0.2, 0.3):
        q = mondrian_thresholds(scores, cats, alpha)
        ours = np.zeros(tests.shape, dtype=int)
        for i, row in enumerate(tests):
            ours[i, prediction_set(row, labels, q)] = 1
        for j, k in enumerate(labels):
            bins = np.full(len(tests), k)
            theirs_p = classifier.predict_p(tests[:, j], bins=bins, smoothing=False)
            np.testing.assert_allclose(conformal_p_value(scores[cats == k], tests[:, j]),
                                       theirs_p, rtol=0, atol=1e-15)
            theirs = classifier.predict_set(tests[:, j], bins=bins, confidence=1 - alpha,
                                            smoothing=False)
            np.testing.assert_array_equal(ours[:, j], theirs)
        assert 0 < ours.mean() < 1  # neither empty nor everything


# ---- conditional logit ---------------------------------------------------------------------------

def logit_data(rng, weights, n=4000, alternatives=5):
    """Features (NaN where not available), availability and truths drawn from the model."""
    features = rng.standard_normal((n, alternatives, len(weights)))
    available = rng.random((n, alternatives)) < 0.7
    available[np.arange(n), rng.integers(alternatives, size=n)] = True  # at least one
    features[~available] = np.nan
    p = choice_probabilities(features, available, weights)
    truth = (rng.random((n, 1)) > p.cumsum(axis=1)).sum(axis=1)
    return features, available, truth


def standard_errors(features, available, weights):
    """sqrt(diag(I^-1)) of the maximum likelihood weights: I = sum over cases of the covariance
    of the features under the case's probabilities (the observed = expected information)."""
    x = np.where(available[..., None], features, 0.0)
    p = choice_probabilities(features, available, weights)
    mean = np.einsum("nj,njf->nf", p, x)
    d = x - mean[:, None, :]
    info = np.einsum("nj,njf,njg->fg", p, d, d)
    return np.sqrt(np.diag(np.linalg.inv(info)))


def nll(features, available, truth, weights, l2):
    p = choice_probabilities(features, available, weights)
    return -np.mean(np.log(p[np.arange(len(truth)), truth])) + l2 * weights @ weights


def test_fit_choice_recovers_known_weights_within_their_standard_errors():
    rng = np.random.default_rng(5)
    true = np.array([1.0, -0.5, 0.25])
    features, available, truth = logit_data(rng, true)
    assert available[np.arange(len(truth)), truth].all()
    w = fit_choice(features, available, truth, l2=0.0)
    se = standard_errors(features, available, w)
    assert np.all(se < 0.05)  # informative data: the tolerance below means something
    assert np.all(np.abs(w - true) <= 4 * se), (w, se)
    # deterministic
    np.testing.assert_array_equal(fit_choice(features, available, truth, l2=0.0), w)


def test_fit_choice_is_the_penalised_optimum():
    rng = np.random.default_rng(6)
    features, available, truth = logit_data(rng, np.array([2.0, -1.0]), n=500, alternatives=3)
    for l2 in (0.0, 0.01, 1.0):
        w = fit_choice(features, available, truth, l2=l2)
        # central differences of the objective written independently: zero at the optimum
        h = 1e-5
        grad = [(nll(features, available, truth, w + h * e, l2)
                 - nll(features, available, truth, w - h * e, l2)) / (2 * h) for e in np.eye(2)]
        assert np.abs(grad).max() < 1e-6, (l2, grad)
    # the ridge shrinks
    assert np.linalg.norm(fit_choice(features, available, truth, l2=1.0)) < \
        np.linalg.norm(fit_choice(features, available, truth, l2=0.0))


def test_choose_ridge_takes_the_least_held_out_log_loss_of_folds_dealt_by_its_seed():
    rng = np.random.default_rng(9)
    features, available, truth = logit_data(rng, np.array([1.0, 0.0, 0.0]), n=60)
    features = np.where(available[..., None], features, 0.0)  # plain loops below need numbers
    l2, losses = choose_ridge(features, available, truth, [10.0, 1e-2, 0.0], folds=3, seed=4)
    # the deal, and the held-out loss, by hand
    fold = np.random.default_rng(4).permutation(60) % 3
    for ridge, got in losses.items():
        total = 0.0
        for k in range(3):
            w = fit_choice(features[fold != k], available[fold != k], truth[fold != k], ridge)
            for i in np.flatnonzero(fold == k):
                u = np.where(available[i], features[i] @ w, -np.inf)
                total -= u[truth[i]] - np.log(np.exp(u).sum())
        assert got == pytest.approx(total / 60, rel=1e-9)
    assert l2 == min(losses, key=losses.get)
    # a feature that predicts nothing: the strongest ridge (weights near zero) does best
    noise = rng.standard_normal((60, 5, 3))
    pure_chance = rng.integers(5, size=60)
    assert choose_ridge(noise, np.ones((60, 5), bool), pure_chance, [0.0, 100.0])[0] == 100.0
    with pytest.raises(ValueError, match="folds"):
        choose_ridge(noise, np.ones((60, 5), bool), pure_chance, [1.0], folds=61)
    with pytest.raises(ValueError, match="grid"):
        choose_ridge(noise, np.ones((60, 5), bool), pure_chance, [])


def test_choice_probabilities_sum_to_one_with_unavailable_alternatives_at_zero():
    rng = np.random.default_rng(8)
    features = 1e3 * rng.standard_normal((50, 4, 2))  # utilities far beyond exp's range
    available = rng.random((50, 4)) < 0.6
    available[:, 0] = True
    features[~available] = np.nan
    p = choice_probabilities(features, available, np.array([1.0, -2.0]))
    assert np.isfinite(p).all()
    np.testing.assert_allclose(p.sum(axis=1), 1.0, rtol=0, atol=1e-12)
    assert np.all(p[~available] == 0.0)
    # by hand: utilities 0, log 2, log 3 (1 : 2 : 3), one not available
    x = np.log(np.array([[[1.0], [2.0], [3.0], [4.0]]]))
    p = choice_probabilities(x, np.array([[True, True, True, False]]), np.array([1.0]))
    np.testing.assert_allclose(p, [[1 / 6, 2 / 6, 3 / 6, 0.0]], rtol=1e-12)


# ---- reliability ---------------------------------------------------------------------------------

def test_reliability_by_hand():
    probs = np.array([0.05, 0.1, 0.15, 0.3, 0.95, 1.0])
    hits = np.array([False, True, False, False, True, True])
    table = reliability(probs, hits)
    assert [b["lower"] for b in table] == [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]
    assert [b["upper"] for b in table] == [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]
    assert [b["count"] for b in table] == [1, 2, 0, 1, 0, 0, 0, 0, 0, 2]  # 0.1 and 0.3: upper bin
    assert table[0] == {"lower": 0.0, "upper": 0.1, "count": 1, "stated": 0.05, "observed": 0.0}
    assert table[1]["stated"] == pytest.approx(0.125) and table[1]["observed"] == 0.5
    assert table[2] == {"lower": 0.2, "upper": 0.3, "count": 0, "stated": None, "observed": None}
    assert table[9]["stated"] == pytest.approx(0.975) and table[9]["observed"] == 1.0  # 1.0 in
    table = reliability(np.array([0.0, 0.5, 0.5]), np.array([1, 0, 1]), edges=[0.0, 0.5, 1.0])
    assert [(b["count"], b["observed"]) for b in table] == [(1, 1.0), (2, 0.5)]


# ---- outlyingness --------------------------------------------------------------------------------

def test_outlyingness_is_the_mahalanobis_distance_about_the_median():
    rng = np.random.default_rng(9)
    cov = np.array([[4.0, 1.9], [1.9, 1.0]])  # strongly correlated
    X = rng.multivariate_normal([10.0, -3.0], cov, size=500)
    model = Outlyingness.fit(X)
    np.testing.assert_array_equal(model.centre, np.median(X, axis=0))
    d = X - model.centre
    S = d.T @ d / len(X)
    np.testing.assert_allclose(model.scale, S + 1e-6 * np.trace(S) / 2 * np.eye(2), rtol=1e-12)
    points = rng.normal(size=(5, 2)) * 3 + model.centre
    diff = points - model.centre
    by_hand = np.sqrt(np.einsum("nf,fg,ng->n", diff, np.linalg.inv(model.scale), diff))
    np.testing.assert_allclose(model.score(points), by_hand, rtol=1e-10)
    # across the correlation 2 away in Euclidean terms is stranger than 3 away along it, and
    # than every row of the data
    across = model.centre + 2 * np.array([0.45, -0.9]) / np.linalg.norm([0.45, -0.9])
    along = model.centre + 3 * np.array([0.9, 0.45]) / np.linalg.norm([0.9, 0.45])
    far_across, near_along = model.score(np.array([across, along]))
    assert far_across > near_along
    assert far_across > model.score(X).max()


def test_outlyingness_json_round_trip_and_collinear_columns():
    rng = np.random.default_rng(10)
    x = rng.standard_normal(40)
    X = np.column_stack([x, 2 * x, rng.standard_normal(40)])  # collinear: the ridge inverts it
    model = Outlyingness.fit(X)
    assert np.isfinite(model.score(X)).all()
    document = json.loads(json.dumps(model.to_json()))
    assert set(document) == {"centre", "scale"} and isinstance(document["scale"][0], list)
    again = Outlyingness.from_json(document)
    np.testing.assert_array_equal(again.centre, model.centre)
    np.testing.assert_array_equal(again.scale, model.scale)
    np.testing.assert_array_equal(again.score(X), model.score(X))
    # far from the data off the line the columns keep: the strangest
    off = model.centre + np.array([1.0, -0.5, 0.0])
    assert model.score(off[None, :])[0] > 10 * model.score(X).max()


# ---- errors --------------------------------------------------------------------------------------

F3 = np.zeros((2, 3, 1))
ALL = np.ones((2, 3), bool)


@pytest.mark.parametrize("call, message", [
    (lambda: fit_choice(np.zeros((2, 3)), ALL, np.array([0, 0])),
     r"features must have shape \(n_cases, n_alternatives, n_features\), not \(2, 3\)\."),
    (lambda: fit_choice(F3, np.ones((2, 2), bool), np.array([0, 0])),
     r"available has shape \(2, 2\), but features has \(2, 3\) cases and alternatives\."),
    (lambda: fit_choice(F3, np.ones((2, 3)), np.array([0, 0])),
     r"available must be a bool array, not float64\."),
    (lambda: fit_choice(F3, np.array([[True] * 3, [True, False, True]]), np.array([0, 1])),
     r"truth 1 of case 1 is not an available alternative\."),
    (lambda: fit_choice(F3, ALL, np.array([0, 3])),
     r"truth 3 of case 1 is not an alternative index \(0 to 2\)\."),
    (lambda: fit_choice(F3, ALL, np.array([0, 0, 0])),
     r"truth has shape \(3,\), but features has 2 cases\."),
    (lambda: fit_choice(F3, ALL, np.array([0.0, 1.0])),
     r"truth must hold integer indices, not float64\."),
    (lambda: fit_choice(F3, ALL, np.array([0, 0]), l2=-1.0),
     r"l2 must be finite and non-negative, not -1\.0\."),
    (lambda: fit_choice(np.full((2, 3, 1), np.nan), ALL, np.array([0, 0])),
     r"features must be finite for every available alternative\."),
    (lambda: choice_probabilities(F3, np.array([[True] * 3, [False] * 3]), np.zeros(1)),
     r"case 1 has no available alternative\."),
    (lambda: choice_probabilities(F3, ALL, np.zeros(2)),
     r"weights has shape \(2,\), but features has 1 features\."),
    (lambda: mondrian_thresholds(np.zeros(3), ["a"] * 3, alpha=1.0),
     r"alpha must lie strictly between 0 and 1, not 1\.0\."),
    (lambda: mondrian_thresholds(np.zeros(3), ["a"] * 2, alpha=0.1),
     r"scores has 3 values but categories has 2\."),
    (lambda: mondrian_thresholds(np.array([np.nan]), ["a"], alpha=0.1),
     r"scores must not be NaN\."),
    (lambda: prediction_set(np.zeros(3), ["a"], {}),
     r"label_scores has 3 values but label_categories has 1\."),
    (lambda: conformal_p_value(np.zeros((2, 2)), 1.0),
     r"calibration_scores must be one-dimensional, not of shape \(2, 2\)\."),
    (lambda: conformal_p_value(np.zeros(2), math.nan), r"scores must not be NaN\."),
    (lambda: reliability(np.array([1.2]), np.array([1])),
     r"probabilities must lie within the edges, \[0\.0, 1\.0\]\."),
    (lambda: reliability(np.array([0.2]), np.array([2])), r"hits must be bools \(or 0 and 1\)\."),
    (lambda: reliability(np.array([0.2]), np.array([1]), edges=[0.0, 0.5, 0.5, 1.0]),
     r"edges must be at least two strictly increasing values\."),
    (lambda: Outlyingness.fit(np.ones((4, 2))),
     r"X has no spread about its median: every row equals it\."),
    (lambda: Outlyingness.fit(np.ones(4)), r"X must be a non-empty \(n, d\) array, not of shape"),
    (lambda: Outlyingness.fit(np.eye(3)).score(np.zeros((1, 2))),
     r"X must have shape \(n, 3\), not \(1, 2\)\."),
    (lambda: Outlyingness.from_json({"centre": [0.0]}),
     r"an Outlyingness document needs \['scale'\]\."),
    (lambda: Outlyingness(np.zeros(2), -np.eye(2)),
     r"scale must be symmetric positive definite\."),
])
def test_errors_say_what_is_wrong(call, message):
    with pytest.raises(ValueError, match=message):
        call()
