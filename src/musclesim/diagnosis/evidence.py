"""Evidence for each candidate cause: a model of the mismatch calibration leaves, the marginal
likelihood of each candidate under it, posterior probabilities, and what the data cannot tell.

A real bench differs from any model in form (its hysteresis, its thermal structure, its sensors),
so the residual the calibrated model leaves is not white noise: it is structured and slow. Taken
as white noise, every candidate that bends the model toward that structure "explains" a share of
it, present or not. Here the residual of each signal is modelled as an autoregressive process
(a discrepancy: Kennedy and O'Hagan's model error term, in its discrete-time, Ornstein-Uhlenbeck
form, with its hyperparameters estimated after calibration, the modular approach of Liu,
Bayarri and Berger): r_t = sum_i phi_i r_(t-i) + e_t, e_t ~ N(0, sigma^2), the order chosen by
BIC, the coefficients and sigma estimated on the calibrated model's training residuals (sigma at
least the signal's noise) and the same for every candidate. A candidate is then scored by its
whitened residuals (the innovations e_t): slow mismatch that a candidate merely bends toward is
whitened away, a signature the data carry is not.

Each candidate's evidence (log marginal likelihood of the training part) is Laplace's
approximation around its fit, in box coordinates (every parameter's bounds mapped to [0, 1], so
the uniform prior over the bounds has density 1): the whitened problem linearised at the fit, its
Gaussian integrated over the box (`gaussian`): exact for a linear model with Gaussian errors, a
direction the data do not constrain counting 1 (a symmetry costs and gains nothing). With prior
probabilities per candidate (`prior`) the posterior probabilities follow; `credible_set` is the
smallest group holding CREDIBLE of them. A candidate's effect that the calibration parameters
reproduce on these data (`symmetry`, and the profiles of `weigh`) cannot be told from
calibration whatever the evidence says: the report lists it.

Everything here works on plain arrays: residual segments (one array per signal and run, in time
order) and Jacobians whose rows follow the same segments.

>>> import numpy as np
>>> rng = np.random.default_rng(1)
>>> e = rng.standard_normal(4000)
>>> r = np.zeros(4000)
>>> for t in range(1, 4000):
...     r[t] = 0.9 * r[t - 1] + e[t]
>>> phi, sigma = ar_fit([r], 1)
>>> round(float(phi[0]), 2), round(float(sigma), 1)
(0.9, 1.0)
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import linalg, special

from musclesim.diagnosis.thresholds import CREDIBLE, MAX_AR_ORDER, PAIR_PRIOR

TINY = 1e-10  # relative eigenvalue below which the data say nothing of a direction


def ar_fit(segments, p):
    """(phi, sigma) of an AR(`p`) model fitted by least squares on `segments` (arrays in time
    order, each at least p + 1 long to count); sigma is the innovations' RMS."""
    rows, target = [], []
    for s in segments:
        if len(s) > p:
            rows.append(np.column_stack([s[p - i - 1:len(s) - i - 1] for i in range(p)])
                        if p else np.empty((len(s), 0)))
            target.append(s[p:])
    if not target:
        return np.zeros(p), 0.0
    X, y = np.vstack(rows), np.concatenate(target)
    phi = np.linalg.lstsq(X, y, rcond=None)[0] if p else np.zeros(0)
    e = y - X @ phi
    return phi, float(np.sqrt(np.mean(e * e)))


def ar_order(segments, max_order=MAX_AR_ORDER):
    """The AR order of `segments` by the Bayesian information criterion, 0..max_order (every
    order fitted on the same samples: those after the first `max_order` of each segment)."""
    n = sum(max(len(s) - max_order, 0) for s in segments)
    if n <= max_order + 1:
        return 0
    best: tuple[float, int] | None = None
    for p in range(max_order + 1):
        _, sigma = ar_fit([s[max_order - p:] for s in segments if len(s) > max_order], p)
        bic = n * math.log(max(sigma, 1e-300) ** 2) + p * math.log(n)
        if best is None or bic < best[0]:
            best = (bic, p)
    assert best is not None  # order 0 at least
    return best[1]


def whiten(segment, phi):
    """The innovations of `segment` (1-D, or 2-D with time along the rows) under AR
    coefficients `phi`: rows p.. of x_t - sum_i phi_i x_(t-i)."""
    p = len(phi)
    x = np.asarray(segment, float)
    out = x[p:].copy()
    for i in range(p):
        out -= phi[i] * x[p - i - 1:len(x) - i - 1]
    return out


@dataclass(frozen=True)
class Discrepancy:
    """One signal's mismatch model: an AR process with coefficients `phi` and innovation std
    `sigma`."""

    phi: np.ndarray
    sigma: float

    @classmethod
    def fit(cls, segments, floor=0.0, order=None):
        """Estimated on `segments` (the calibrated model's training residuals): the order by BIC
        unless given, sigma at least `floor` (the signal's measurement noise)."""
        order = ar_order(segments) if order is None else order
        phi, sigma = ar_fit(segments, order)
        return cls(phi, max(sigma, floor))

    def weighted(self, segments, jac=None):
        """(c, b, A, log-normaliser) of one signal: the quadratic form r'C^-1 r, J'C^-1 r and
        J'C^-1 J of its residual `segments` and the rows `jac` of their Jacobian (None: no
        parameters) under the AR covariance C, and -0.5 (log det C + n log 2 pi) (the
        conditional likelihood: each segment's first p values given)."""
        p, s2 = len(self.phi), self.sigma ** 2
        n, c, b, A, start = 0, 0.0, 0.0, 0.0, 0
        for s in segments:
            if len(s) > p:
                r = whiten(s, self.phi)
                n += r.size
                c += r @ r / s2
                if jac is not None:
                    J = whiten(jac[start:start + len(s)], self.phi)
                    b, A = b + J.T @ r / s2, A + J.T @ J / s2
            start += len(s)
        return c, b, A, -0.5 * n * (math.log(s2) + math.log(2 * math.pi))

    def innovations(self, segments):
        """The standardised innovations of `segments`, concatenated."""
        parts = [whiten(s, self.phi) for s in segments if len(s) > len(self.phi)]
        return np.concatenate(parts) / self.sigma if parts else np.zeros(0)


@dataclass(frozen=True)
class Evidence:
    """A candidate's evidence: the log marginal likelihood of the training part and its parts
    (the log likelihood at the centre of Laplace's Gaussian, the log of its mass in the box),
    that centre in box coordinates (clipped to the box), and the Fisher information J'C^-1 J
    in box coordinates (None for a candidate without parameters)."""

    log_evidence: float
    log_likelihood: float
    occam: float  # the log of the Gaussian's mass in the box: the Occam factor
    z: np.ndarray
    information: np.ndarray | None = None


def evidence(segments, jac, z, discrepancies):
    """Laplace's log evidence of one candidate (see the module docstring).

    Parameters
    ----------
    segments : dict
        {signal: [training residual array per run]} at the fitted values (normalised).
    jac : ndarray or None
        d residuals / d box coordinates, rows in the order of the segments (signal by signal,
        run by run); None for a candidate without parameters.
    z : sequence
        The fitted values in box coordinates.
    discrepancies : dict
        {signal: `Discrepancy`}, the same for every candidate of a comparison.
    """
    z = np.asarray(z, float)
    d = len(z) if jac is not None else 0
    c_all, b_all, A_all, norm, start = 0.0, np.zeros(d), np.zeros((d, d)), 0.0, 0
    for name, segs in segments.items():
        n = sum(len(s) for s in segs)
        c, b, A, lognorm = discrepancies[name].weighted(segs, jac[start:start + n] if d else None)
        c_all, norm = c_all + c, norm + lognorm
        if d:
            b_all, A_all = b_all + b, A_all + A
        start += n
    if not d:
        ll = float(-0.5 * c_all + norm)
        return Evidence(ll, ll, 0.0, z)
    centre, ss, log_volume = gaussian(A_all, b_all, c_all, z)
    ll = float(-0.5 * ss + norm)
    return Evidence(ll + log_volume, ll, log_volume, np.clip(centre, 0, 1), A_all)


def gaussian(A, b, c, z):
    """Laplace's Gaussian of a problem linearised at `z` (box coordinates), given by its
    quadratic form c + 2 b'dz + dz' A dz: (its centre, the form's value there, the log of its
    mass inside the box [0, 1]^d, the uniform prior's density being 1). The centre is the
    unconstrained optimum, outside the box when the data pull a parameter past its bound: the
    mass counts only the box's part. Directions the data do not constrain (eigenvalues of A
    below TINY of the largest) leave the likelihood flat over the box: they count 1. The mass
    of a correlated Gaussian in the box is taken as the product of its marginals' masses."""
    lam, vec = linalg.eigh(A)
    keep = lam > TINY * max(float(lam.max(initial=0.0)), 1.0)
    if not keep.any():
        return np.asarray(z, float), float(c), 0.0
    V, L = vec[:, keep], lam[keep]
    step = -V @ ((V.T @ b) / L)
    centre = np.asarray(z, float) + step
    ss = float(c + b @ step)
    out = float(np.sum(0.5 * np.log(2 * math.pi / L)))
    sd = np.sqrt(np.clip(np.einsum("ij,j,ij->i", V, 1 / L, V), 0, None))
    for mu, s in zip(centre, sd):
        if s > 0:
            out += log_mass(-mu / s, (1 - mu) / s)
    return centre, ss, out


def log_mass(lo, hi):
    """log(Phi(hi) - Phi(lo)) of the standard normal's distribution Phi, accurate far in either
    tail (the two values taken from the tail nearer zero, as log Phi)."""
    if lo > 0:  # both in the upper tail: Phi(-lo) - Phi(-hi)
        lo, hi = -hi, -lo
    a, b = special.log_ndtr(hi), special.log_ndtr(lo)
    return float(a + math.log1p(-math.exp(min(b - a, 0.0)))) if b < a else -math.inf


def prior(names, pairs=()):
    """Prior probabilities of the candidates `names` (singles, calibration only included) and
    of `pairs`: every single equally probable, a pair PAIR_PRIOR times as probable as a single
    (two unmodelled causes at once are rarer than one), normalised."""
    w = np.array([1.0] * len(names) + [PAIR_PRIOR] * len(pairs))
    return w / w.sum()


def posterior(log_evidences, priors):
    """Posterior probabilities from log evidences and prior probabilities."""
    a = np.asarray(log_evidences, float) + np.log(np.asarray(priors, float))
    a -= a.max()
    p = np.exp(a)
    return p / p.sum()


def credible_set(names, probabilities, level=CREDIBLE):
    """The smallest group of `names` whose probabilities sum to at least `level`, most probable
    first."""
    order = np.argsort(-np.asarray(probabilities), kind="stable")
    out, total = [], 0.0
    for i in order:
        out.append(names[i])
        total += probabilities[i]
        if total >= level - 1e-12:
            break
    return out


def symmetry(A, k, scale=0.5):
    """The linear symmetry test of an effect against calibration, from the Fisher information
    `A` (J'C^-1 J in box coordinates) of a candidate whose first `k` parameters are the
    effect's and the rest the calibration's: (chi2, direction, carried). `chi2` is the squared
    norm, in the discrepancy's metric, of what is left of the effect's change at `scale` of its
    box in its most distinguishable `direction` (a unit vector over the effect's parameters)
    after the best change of the calibration parameters (the Schur complement): below 1, a
    linearised model cannot tell the effect from a recalibration. `carried`: each calibration
    parameter's share in reproducing it. Differences taken one parameter at a time can miss a
    symmetry of a model with kinks: `weigh.profile_jobs` also moves the effect along
    `direction` and fits the calibration again there."""
    A = np.asarray(A, float)
    Aee, Aec, Acc = A[:k, :k], A[:k, k:], A[k:, k:]
    coef = np.linalg.pinv(Acc) @ Aec.T if Acc.size else np.zeros((0, k))
    lam, vec = np.linalg.eigh(Aee - Aec @ coef if Acc.size else Aee)
    direction = vec[:, -1] * np.sign(vec[np.argmax(abs(vec[:, -1])), -1])
    carried = np.abs(coef @ direction) * np.sqrt(np.clip(np.diag(Acc), 0, None))
    return scale ** 2 * float(lam[-1]), direction, carried
