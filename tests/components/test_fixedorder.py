"""Fixed-order arithmetic (components/fixedorder.py): products summed in their stated order,
least squares as numpy's lstsq."""
import numpy as np
import pytest

from musclesim.components import fixedorder


def _in_pairs(t):
    """Terms summed as fixedorder does: an even count's halves in pairs, then left to right."""
    if len(t) % 2 == 0:
        t = [t[k] + t[k + len(t) // 2] for k in range(len(t) // 2)]
    return float(sum(t[1:], t[0]))


def test_fixed_order_products_sum_in_their_stated_order():
    """The 4x4 product written out sums as the general loop does, bit for bit, in the order the
    docstring states; the series gives scipy's expm to rounding (a reference through LAPACK)."""
    from scipy.linalg import expm

    rng = np.random.default_rng(3)
    for n in (2, 3, 4, 5, 6):
        a, b = rng.standard_normal((n, n)), rng.standard_normal((n, n))
        by_hand = [[_in_pairs([a[i, j] * b[j, l] for j in range(n)]) for l in range(n)]
                   for i in range(n)]
        assert fixedorder.matmul(a.tolist(), b.tolist()) == by_hand
        np.testing.assert_allclose(fixedorder.exp_and_integral(a.tolist(), 0.7)[0],
                                   expm(0.7 * a), rtol=1e-13, atol=1e-13)


def test_fixed_order_least_squares_is_numpys_lstsq():
    """Householder QR with exactly rounded sums gives numpy's lstsq (LAPACK) to rounding, on a fit
    as ill-conditioned as the pressure loops' (a nearly constant column beside the ones)."""
    rng = np.random.default_rng(4)
    p = 12e3 + np.cumsum(rng.standard_normal(2001))
    X = np.column_stack([p[:-1], rng.choice([-0.5, 0.5], 2000), np.ones(2000)])
    y = X @ [0.999, 30.0, 12.0] + 0.1 * rng.standard_normal(2000)
    expected = np.linalg.lstsq(X, y, rcond=None)[0]
    np.testing.assert_allclose(fixedorder.least_squares(X.T, y), expected, rtol=1e-10)
    assert fixedorder.least_squares([[1.0, 1.0, 1.0], [0.0, 1.0, 2.0]], [1.0, 3.0, 5.0]) \
        == [1.0, 2.0]
    with pytest.raises(ValueError, match="not independent"):
        fixedorder.least_squares([[1.0, 2.0], [2.0, 4.0]], [1.0, 2.0])
