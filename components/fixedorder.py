"""Small dense linear algebra in a fixed order of operations: the same bits on every CPU.

numpy's ``@`` and scipy's ``expm`` hand even a 4x4 product to BLAS, whose kernel is chosen per CPU
(OpenBLAS: Haswell, SkylakeX, Sandybridge, ...) and sums in its own order, with or without fused
multiply-adds; a stick-slip run amplifies those last digits into different sticks and slips. Here
every product is written out in Python: each operation is rounded as IEEE 754 prescribes, and
every sum runs in the order `matvec` states (the halves in pairs, then left to right), on any
CPU. Matrices are sequences of rows of floats (numpy arrays work as well); results are lists of
lists. `least_squares` fits long columns: its sums are `math.fsum`'s, exactly rounded whatever
their order. Python's own floats carry no fused multiply-add, so nothing here depends on the CPU.

The matrix products and the exponential are written once, on float64 arrays, as functions that
`musclesim.fmu.compiled.jit` compiles (numba adds no fused multiply-add either): a compiled core
(the crawler body's, a weight's link) calls them per step; the list functions below call them too.
"""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from musclesim.fmu.compiled import jit

Matrix = Sequence[Sequence[float]]  # rows of floats (numpy arrays work as well)


def matvec(a: Matrix, x: Sequence[float]) -> list[float]:
    """The product `a` `x`. Each row's terms t_k are summed in a fixed order: for an even length n,
    first t_k + t_(k + n/2) (the two halves in pairs), then those left to right; for an odd n
    left to right. A mirror that swaps the halves (the crawler's two blocks) leaves these sums
    alone, so mirrored inputs give mirrored bits."""
    out = np.empty(np.shape(a)[0])
    matvec_into(np.asarray(a, dtype=float), np.asarray(x, dtype=float), out)
    return out.tolist()


def matmul(a: Matrix, b: Matrix) -> list[list[float]]:
    """The product `a` `b`, each element summed over the inner index as `matvec` sums."""
    a_, b_ = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    out = np.empty((a_.shape[0], b_.shape[1]))
    matmul_into(a_, b_, out)
    return out.tolist()


@jit
def _row_dot(a, i, x):
    """Row `i` of `a` times the vector `x`, summed as `matvec` states."""
    n = x.shape[0]
    if n % 2 == 0:
        m = n // 2
        s = a[i, 0] * x[0] + a[i, m] * x[m]
        for k in range(1, m):
            s += a[i, k] * x[k] + a[i, k + m] * x[k + m]
        return s
    s = a[i, 0] * x[0]
    for k in range(1, n):
        s += a[i, k] * x[k]
    return s


@jit
def matvec_into(a, x, out):
    """`out` = `a` `x` (float64 arrays), each row summed as `matvec` states."""
    for i in range(a.shape[0]):
        out[i] = _row_dot(a, i, x)


@jit
def matmul_into(a, b, out):
    """`out` = `a` `b` (float64 arrays, `out` neither), each element summed as `matvec` states."""
    bt = np.ascontiguousarray(b.T)
    for i in range(a.shape[0]):
        row = a[i]
        for j in range(b.shape[1]):
            out[i, j] = _row_dot(bt, j, row)


@jit
def fsum(x):
    """The exactly rounded sum of the float64 array `x`: Shewchuk's algorithm as Python's
    ``math.fsum`` runs it (the same result, infinities and NaN included; an overflow of finite
    terms gives an infinity where math.fsum raises)."""
    partials = np.empty(x.shape[0] + 1)
    n = 0
    special = 0.0
    inf_sum = 0.0
    for k in range(x.shape[0]):
        v = x[k]
        saved = v
        i = 0
        for j in range(n):
            y = partials[j]
            if abs(v) < abs(y):
                v, y = y, v
            hi = v + y
            lo = y - (hi - v)
            if lo != 0.0:
                partials[i] = lo
                i += 1
            v = hi
        n = i
        if v != 0.0:
            if not math.isfinite(v):
                if math.isinf(saved):
                    inf_sum += saved
                special += saved
                n = 0
            else:
                partials[n] = v
                n += 1
    if special != 0.0:
        return special if not math.isnan(inf_sum) else math.nan
    hi = 0.0
    lo = 0.0
    if n > 0:
        n -= 1
        hi = partials[n]
        while n > 0:
            v = hi
            n -= 1
            y = partials[n]
            hi = v + y
            lo = y - (hi - v)
            if lo != 0.0:
                break
        if n > 0 and ((lo < 0.0 and partials[n - 1] < 0.0) or (lo > 0.0 and partials[n - 1] > 0.0)):
            y = lo * 2.0
            v = hi + y
            if y == v - hi:
                hi = v
    return hi


@jit
def _norm1(a):
    """The 1-norm: the largest column sum of magnitudes (each sum exactly rounded)."""
    best = 0.0
    for j in range(a.shape[1]):
        column = np.empty(a.shape[0])
        for i in range(a.shape[0]):
            column[i] = abs(a[i, j])
        c = fsum(column)
        if j == 0 or c > best:
            best = c
    return best


@jit
def _off_diagonal_sum(a, i, column):
    """Exactly rounded sum of the magnitudes off the diagonal in row or `column` `i` of `a`."""
    n = a.shape[0]
    t = np.empty(n - 1)
    m = 0
    for j in range(n):
        if j != i:
            t[m] = abs(a[j, i]) if column else abs(a[i, j])
            m += 1
    return fsum(t)


@jit
def _balance(a):
    """Powers of two d with B = diag(d)^-1 A diag(d) of rows and columns of like size (Parlett and
    Reinsch's balancing, radix 2, as EISPACK's BALANC without its permutations). Scaling by powers
    of two commutes with the rounding of every product, so working on B gives diag(d)^-1 (what A
    would give) diag(d) bit for bit, but for the number of squarings (B's smaller norm asks fewer)
    and the doubling at which exp - I turns to exp. Returns (B, d)."""
    n = a.shape[0]
    a = _scaled(a, 1.0)
    d = np.ones(n)
    changed = True  # (an infinity would not settle)
    for i in range(n):
        for j in range(n):
            changed = changed and math.isfinite(a[i, j])
    while changed:
        changed = False
        for i in range(n):
            c = _off_diagonal_sum(a, i, True)
            r = _off_diagonal_sum(a, i, False)
            if c == 0.0 or r == 0.0:
                continue
            f, total = 1.0, c + r
            while c < r / 2.0:
                f, c = f * 2.0, c * 4.0
            while c >= r * 2.0:
                f, c = f / 2.0, c / 4.0
            if (c + r) / f < 0.95 * total:
                changed = True
                d[i] *= f
                for j in range(n):
                    a[i, j] /= f
                    a[j, i] *= f
    return a, d


def identity(n: int) -> list[list[float]]:
    """The `n` x `n` identity matrix."""
    return [[1.0 if i == j else 0.0 for j in range(n)] for i in range(n)]


TAYLOR_TERMS = 13  # E^13 / 14! is the last term kept: the next is below 5e-17 at |E| <= 1/2


@jit
def _scaled(a, f):
    """A new array `f` `a` (written as loops: array expressions take numba long to compile)."""
    out = np.empty_like(a)
    for i in range(a.shape[0]):
        for j in range(a.shape[1]):
            out[i, j] = f * a[i, j]
    return out


@jit
def _plus_identity(a):
    """A new array `a` + I."""
    out = _scaled(a, 1.0)
    for i in range(a.shape[0]):
        out[i, i] += 1.0
    return out


@jit
def _fused(alpha, c, a, b, d):
    """alpha c + (a b) / d, element by element, the product as `matmul` sums it."""
    out = np.empty((a.shape[0], b.shape[1]))
    matmul_into(a, b, out)
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            out[i, j] = alpha * c[i, j] + out[i, j] / d
    return out


@jit
def exp_and_integral_into(A, h, X_out, Phi_out):
    """`X_out` = exp(`A` `h`), `Phi_out` = its integral over the step (float64 arrays): the
    algorithm of `exp_and_integral`."""
    A, d = _balance(A)
    n = A.shape[0]
    norm = _norm1(A) * abs(h)
    s = max(0, math.frexp(norm)[1] + 1)  # norm < 2^e, so |A tau| < 2^(e - s) <= 1/2
    tau = math.ldexp(h, -s)  # exact: a power of two
    E = _scaled(A, tau)
    eye = np.eye(n)
    P = _scaled(eye, 1.0)
    for j in range(TAYLOR_TERMS + 1, 1, -1):  # P = I + E/2 (I + E/3 (... (I + E/14)))
        P = _fused(1.0, eye, E, P, float(j))
    D = np.empty((n, n))
    matmul_into(E, P, D)
    Phi = _scaled(P, tau)
    X = np.empty((n, n))
    have_x = False  # exp itself, once it has decayed below D
    for _ in range(s):
        if not have_x:
            candidate = _plus_identity(D)
            if _norm1(candidate) < 0.5 * _norm1(D):
                X, have_x = candidate, True
        if not have_x:
            D, Phi = _fused(2.0, D, D, D, 1.0), _fused(2.0, Phi, D, Phi, 1.0)
        else:
            X2 = np.empty((n, n))
            matmul_into(X, X, X2)
            X, Phi = X2, _fused(1.0, Phi, X, Phi, 1.0)
    if not have_x:
        X = _plus_identity(D)
    for i in range(n):
        for j in range(n):
            X_out[i, j] = X[i, j] * d[i] / d[j]
            Phi_out[i, j] = Phi[i, j] * d[i] / d[j]


def exp_and_integral(A: Matrix, h: float) -> tuple[list[list[float]], list[list[float]]]:
    """(exp(A h), integral_0^h exp(A t) dt) of a square matrix `A` over the step `h`.

    Scaling and squaring (Moler and Van Loan's method 3, for the pair): with tau = h / 2^s small
    enough that |A tau| <= 1/2 (1-norm), Phi(tau) = tau P, P = sum_k (A tau)^k / (k + 1)! summed by
    Horner's rule, and D(tau) = exp(A tau) - I = A tau P; then s doublings
    Phi(2 t) = 2 Phi(t) + D(t) Phi(t), D(2 t) = 2 D(t) + D(t) D(t) (exp - I rather than exp
    keeps the digits of a short step), until exp = I + D has decayed below half of D; from then
    on Phi(2 t) = Phi(t) + exp(A t) Phi(t), exp(2 A t) = exp(A t)^2 (squaring exp itself keeps the
    digits of a response that dies out over the step, which 2 D + D D would cancel).

    Examples
    --------
    >>> exp_and_integral([[0.0, 1.0], [0.0, 0.0]], 0.5)  # a free mass: exact
    ([[1.0, 0.5], [0.0, 1.0]], [[0.5, 0.125], [0.0, 0.5]])
    """
    a = np.asarray(A, dtype=float)
    X, Phi = np.empty_like(a), np.empty_like(a)
    exp_and_integral_into(a, float(h), X, Phi)
    return X.tolist(), Phi.tolist()


@jit
def zoh_into(A, B, h, Ad, Bd):
    """`Ad`, `Bd` = the zero-order hold of (`A`, `B`) over `h` (float64 arrays): `zoh`."""
    Phi = np.empty_like(A)
    exp_and_integral_into(A, h, Ad, Phi)
    matmul_into(Phi, B, Bd)


def zoh(A: Matrix, B: Matrix, h: float) -> tuple[list[list[float]], list[list[float]]]:
    """Zero-order-hold discretisation of dx/dt = `A` x + `B` u over a step `h`: (Ad, Bd) with
    Ad = exp(A h) and Bd = integral_0^h exp(A t) dt B, so that x[k+1] = Ad x[k] + Bd u[k] is
    exact for u held over the step: the pair scipy's ``cont2discrete(..., method="zoh")`` computes
    through LAPACK and BLAS, here in a fixed order (`exp_and_integral`).

    Examples
    --------
    >>> zoh([[0.0, 1.0], [0.0, 0.0]], [[0.0], [1.0]], 0.5)  # a free mass pushed by u: exact
    ([[1.0, 0.5], [0.0, 1.0]], [[0.125], [0.5]])
    """
    a, b = np.asarray(A, dtype=float), np.asarray(B, dtype=float)
    Ad, Bd = np.empty_like(a), np.empty((a.shape[0], b.shape[1]))
    zoh_into(a, b, float(h), Ad, Bd)
    return Ad.tolist(), Bd.tolist()


def _dot(a, b):
    """Exactly rounded a . b of two float vectors (the products rounded first)."""
    return math.fsum([p * q for p, q in zip(a, b)])


def least_squares(columns: Sequence[Sequence[float] | np.ndarray],
                  y: Sequence[float] | np.ndarray) -> list[float]:
    """The coefficients c minimising |sum_j c_j `columns`[j] - `y`| (columns of one length, at least
    as long as there are columns, independent), by Householder QR: what numpy's lstsq gives to
    rounding, in a fixed order of operations.

    Examples
    --------
    >>> least_squares([[1.0, 1.0, 1.0], [0.0, 1.0, 2.0]], [1.0, 3.0, 5.0])  # y = 1 + 2 x
    [1.0, 2.0]
    """
    A = [[float(v) for v in col] for col in columns]
    b = [float(v) for v in y]
    n = len(A)
    R = [[0.0] * n for _ in range(n)]
    for k in range(n):
        x = A[k][k:]
        alpha = math.sqrt(_dot(x, x))
        if x[0] > 0:
            alpha = -alpha  # reflect away from x, no cancellation in v[0]
        v = [x[0] - alpha] + x[1:]
        vv = _dot(v, v)
        if vv == 0.0 or alpha == 0.0:
            raise ValueError("least_squares: the columns are not independent")
        for col in A[k + 1:] + [b]:
            g = 2.0 * _dot(v, col[k:]) / vv
            col[k:] = [c - g * vi for c, vi in zip(col[k:], v)]
        R[k][k] = alpha
        for j in range(k + 1, n):
            R[k][j] = A[j][k]
    c = [0.0] * n
    for k in range(n - 1, -1, -1):
        s = b[k]
        for j in range(k + 1, n):
            s -= R[k][j] * c[j]
        c[k] = s / R[k][k]
    return c
