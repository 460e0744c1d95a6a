"""Evidence on synthetic arrays (no FMU): the autoregressive discrepancy, Laplace's evidence against
the exact integral and a nested sampler, autocorrelated noise never taken for an effect, a
signature that is there found, symmetries and the credible set."""
import math

import numpy as np
import pytest
from scipy import special

from musclesim.diagnosis import evidence as ev
from musclesim.diagnosis.thresholds import NAME_LEVEL

N = 3000


def ar1(rng, phi, n=N, sigma=1.0):
    """An AR(1) series."""
    e = rng.standard_normal(n) * sigma
    x = np.zeros(n)
    for t in range(1, n):
        x[t] = phi * x[t - 1] + e[t]
    return x


def white(sigma):
    """A discrepancy of white noise with std `sigma` for signal "s"."""
    return {"s": ev.Discrepancy(np.zeros(0), sigma)}


def test_ar_fit_and_order_recover_the_process():
    rng = np.random.default_rng(3)
    x = ar1(rng, 0.8)
    phi, sigma = ev.ar_fit([x], 1)
    assert phi[0] == pytest.approx(0.8, abs=0.03) and sigma == pytest.approx(1.0, abs=0.05)
    assert ev.ar_order([x]) == 1  # BIC: AR(1), not more
    assert ev.ar_order([rng.standard_normal(N)]) == 0  # white noise
    # segments are whitened apart: no term across a segment's start
    w = ev.whiten(np.arange(5.0), np.array([1.0]))
    assert np.array_equal(w, np.ones(4))


def test_laplace_evidence_is_exact_for_a_linear_gaussian_model_in_one_dimension():
    """y = x theta + e, e white with known sigma (the noise floor above the residuals' RMS),
    theta uniform on [0, 1]: the evidence in closed form, the mode inside and at a bound."""
    rng = np.random.default_rng(5)
    x = np.sin(np.linspace(0, 6, 400))
    sigma = 1.0
    for theta in (0.4, 0.0):
        y = x * theta + rng.standard_normal(400) * 0.3
        # the residual r(theta) = x theta - y; at theta_hat its Jacobian is x
        xtx = x @ x
        mu = (x @ y) / xtx
        z = min(max(mu, 0.0), 1.0)
        got = ev.evidence({"s": [x * z - y]}, x[:, None], [z], white(sigma))
        s = sigma / math.sqrt(xtx)
        rss = float((y - x * mu) @ (y - x * mu))
        exact = (-0.5 * rss / sigma ** 2 - 400 * math.log(sigma) - 200 * math.log(2 * math.pi)
                 + math.log(s * math.sqrt(2 * math.pi))
                 + math.log(special.ndtr((1 - mu) / s) - special.ndtr(-mu / s)))
        assert got.log_evidence == pytest.approx(exact, abs=1e-6)


def test_laplace_evidence_agrees_with_a_nested_sampler_in_two_correlated_dimensions():
    """The same in two dimensions with correlated columns, one mode near a bound: dynesty's
    nested sampling integrates the likelihood over the box."""
    dynesty = pytest.importorskip("dynesty")
    rng = np.random.default_rng(7)
    t = np.linspace(0, 4, 300)
    X = np.column_stack([np.sin(t), np.sin(t + 0.4)])
    y = X @ [0.3, 0.05] + rng.standard_normal(300) * 0.5
    sigma = 1.0

    def loglike(theta):
        r = X @ theta - y
        return float(-0.5 * r @ r / sigma ** 2 - 300 * math.log(sigma)
                     - 150 * math.log(2 * math.pi))

    fit = np.clip(np.linalg.lstsq(X, y, rcond=None)[0], 0, 1)
    got = ev.evidence({"s": [X @ fit - y]}, X, fit, white(sigma)).log_evidence
    sampler = dynesty.NestedSampler(loglike, lambda u: u, 2, nlive=400,
                                    rstate=np.random.default_rng(11))
    sampler.run_nested(dlogz=0.01, print_progress=False)
    res = sampler.results
    assert got == pytest.approx(res.logz[-1], abs=max(3 * res.logzerr[-1], 0.15))


def test_a_direction_the_data_do_not_constrain_neither_costs_nor_gains():
    rng = np.random.default_rng(2)
    r = rng.standard_normal(500) * 0.1
    J = np.column_stack([np.zeros(500), np.ones(500) * 1e-9])
    none = ev.evidence({"s": [r]}, None, [], white(1.0))
    idle = ev.evidence({"s": [r]}, J, [0.5, 0.5], white(1.0))
    assert idle.log_evidence == pytest.approx(none.log_evidence, abs=1e-6)


def effect_probability(residual, signature, floor):
    """Posterior probability of 'an effect of this signature' against 'calibration only' for a
    residual: the effect's fit (least squares of the amplitude in [0, 1]) and both evidences
    under the AR discrepancy estimated on the calibration-only residual."""
    amp = float(np.clip((signature @ residual) / (signature @ signature), 0, 1))
    fitted = residual - amp * signature
    disc = {"s": ev.Discrepancy.fit([residual], floor=floor)}
    null = ev.evidence({"s": [residual]}, None, [], disc)
    eff = ev.evidence({"s": [fitted]}, -signature[:, None], [amp], disc)
    return ev.posterior([null.log_evidence, eff.log_evidence], ev.prior(["a", "b"]))[1]


def test_autocorrelated_noise_alone_is_never_an_effect():
    """What calibration leaves on a real bench: slow structured mismatch (AR(1), phi 0.995)
    plus white sensor noise. A candidate whose signature is slow too (a ramp, a slow wave)
    can bend toward it and would 'explain' a share of it as white noise; under the discrepancy
    its probability stays near the prior's even odds, never enough to be named."""
    t = np.linspace(0, 1, N)
    signatures = [t, np.sin(2 * np.pi * 1.5 * t), np.exp(-5 * t)]
    worst = 0.0
    for seed in range(20):
        rng = np.random.default_rng(100 + seed)
        residual = 0.02 * ar1(rng, 0.995) + 0.002 * rng.standard_normal(N)
        for sig in signatures:
            sig = 0.05 * sig / np.max(np.abs(sig))
            amp = float(np.clip((sig @ residual) / (sig @ sig), 0, 1))
            white_gain = 1 - np.mean((residual - amp * sig) ** 2) / np.mean(residual ** 2)
            worst = max(worst, effect_probability(residual, sig, 0.002))
            assert white_gain < 1  # a share it would have 'explained' as white noise
    assert worst < NAME_LEVEL


def test_a_signature_that_is_there_is_found():
    """The same mismatch with a fast, input-driven signature added (what a lag changes in the
    response to a square wave: the edges, ten noise stds there, a tenth of the mismatch's
    size): named every time."""
    t = np.linspace(0, 60, N)
    drive = np.sign(np.sin(2 * np.pi * t / 7.0))
    lagged = np.zeros(N)
    for i in range(1, N):
        lagged[i] = lagged[i - 1] + (drive[i] - lagged[i - 1]) * 0.05
    sig = 0.01 * (drive - lagged)  # what a lag changes: the edges
    found = []
    for seed in range(5):
        rng = np.random.default_rng(200 + seed)
        residual = 0.02 * ar1(rng, 0.995) + 0.002 * rng.standard_normal(N) + 2 * sig
        found.append(effect_probability(residual, sig, 0.002))
    assert min(found) > NAME_LEVEL


def test_the_linear_symmetry_test_and_its_most_distinguishable_direction():
    """From the information J'J: an effect column that is exactly a combination of the
    calibration's leaves nothing (chi2 0); an independent column leaves its own half-box change
    after the best recalibration (the Schur complement); of a two-parameter effect the
    direction the data see best is the Schur complement's leading eigenvector. `carried`: the
    calibration parameter with the larger coefficient carries more of an aliased effect."""
    rng = np.random.default_rng(4)
    cal = rng.standard_normal((400, 2))
    aliased = (cal @ [2.0, -1.0])[:, None] * 1e-2
    apart = rng.standard_normal((400, 1))
    both = np.hstack([aliased, cal])
    chi2, direction, carried = ev.symmetry(both.T @ both, 1)
    assert chi2 < 1e-10 and direction.tolist() == [1.0] and carried[0] > carried[1] > 0
    chi2, _, _ = ev.symmetry(np.hstack([apart, cal]).T @ np.hstack([apart, cal]), 1)
    a = apart[:, 0]
    assert chi2 == pytest.approx(0.25 * (a @ a - a @ cal @ np.linalg.solve(cal.T @ cal, cal.T @ a)))
    assert chi2 > 10
    # two effect parameters: one seen 100 times better than the other, neither in the calibration
    two = np.column_stack([10 * apart[:, 0], rng.standard_normal(400)])
    J = np.hstack([two, cal])
    _, direction, _ = ev.symmetry(J.T @ J, 2)
    assert abs(direction[0]) > 0.99 and direction[np.argmax(abs(direction))] > 0


def test_prior_posterior_and_the_credible_set():
    p = ev.prior(["calibration only", "a", "b"], ["a + b"])
    assert np.allclose(p, np.array([1, 1, 1, 0.1]) / 3.1)
    post = ev.posterior([0.0, 3.0, 2.9, -50.0], p)
    assert post.sum() == pytest.approx(1.0) and post[3] < 1e-20
    assert ev.credible_set(["c", "a", "b", "ab"], post) == ["a", "b"]
    assert ev.credible_set(["x", "y"], [0.95, 0.05]) == ["x"]
