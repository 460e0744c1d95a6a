"""Small dense linear algebra in a fixed order of operations: the same bits on every CPU.

numpy's ``@`` and scipy's ``expm`` hand even a 4x4 product to BLAS, whose kernel is chosen per CPU
(OpenBLAS: Haswell, SkylakeX, Sandybridge, ...) and sums in its own order, with or without fused
multiply-adds; a stick-slip run amplifies those last digits into different sticks and slips. Here
every product is written out in Python: each operation is rounded as IEEE 754 prescribes, and
every sum runs in the order `matvec` states (the halves in pairs, then left to right), on any
CPU. Matrices are sequences of rows of floats (numpy arrays work as well); results are lists of
lists. `least_squares` fits long columns: its sums are `math.fsum`'s, exactly rounded whatever
their order. Python's own floats carry no fused multiply-add, so nothing here depends on the CPU.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # arrays work as well as sequences; nothing here calls numpy
    import numpy as np

Matrix = Sequence[Sequence[float]]  # rows of floats (numpy arrays work as well)


def matvec(a: Matrix, x: Sequence[float]) -> list[float]:
    """The product `a` `x`. Each row's terms t_k are summed in a fixed order: for an even length n,
    first t_k + t_(k + n/2) (the two halves in pairs), then those left to right; for an odd n
    left to right. A mirror that swaps the halves (the crawler's two blocks) leaves these sums
    alone, so mirrored inputs give mirrored bits."""
    n = len(x)
    out = []
    for row in a:
        t = [p * q for p, q in zip(row, x)]
        if n % 2 == 0:
            t = [t[k] + t[k + n // 2] for k in range(n // 2)]
        s = t[0]
        for v in t[1:]:
            s += v
        out.append(s)
    return out


def matmul(a: Matrix, b: Matrix) -> list[list[float]]:
    """The product `a` `b`, each element summed over the inner index as `matvec` sums."""
    cols = list(zip(*b))
    if len(cols[0]) == 4:  # the crawler body's size, written out: the same sums, twice as fast
        return [[(r0 * c0 + r2 * c2) + (r1 * c1 + r3 * c3) for c0, c1, c2, c3 in cols]
                for r0, r1, r2, r3 in a]
    return [matvec(cols, row) for row in a]


def _fused(alpha, c, a, b, d):
    """alpha c + (a b) / d, element by element, the product as `matmul` sums it."""
    return [[alpha * q + p / d for p, q in zip(rp, rc)] for rp, rc in zip(matmul(a, b), c)]


def _norm1(a):
    """The 1-norm: the largest column sum of magnitudes (each sum exactly rounded)."""
    return max((math.fsum(abs(row[j]) for row in a) for j in range(len(a[0]))), default=0.0)


def _balance(a):
    """Powers of two d with B = diag(d)^-1 A diag(d) of rows and columns of like size (Parlett and
    Reinsch's balancing, radix 2, as EISPACK's BALANC without its permutations). Scaling by powers
    of two commutes with the rounding of every product, so working on B gives diag(d)^-1 (what A
    would give) diag(d) bit for bit, but for the number of squarings (B's smaller norm asks fewer)
    and the doubling at which exp - I turns to exp. Returns (B, d)."""
    n = len(a)
    a = [[float(v) for v in row] for row in a]
    d = [1.0] * n
    changed = all(math.isfinite(v) for row in a for v in row)  # (an infinity would not settle)
    while changed:
        changed = False
        for i in range(n):
            c = math.fsum(abs(a[j][i]) for j in range(n) if j != i)
            r = math.fsum(abs(a[i][j]) for j in range(n) if j != i)
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
                    a[i][j] /= f
                    a[j][i] *= f
    return a, d


def identity(n: int) -> list[list[float]]:
    """The `n` x `n` identity matrix."""
    return [[1.0 if i == j else 0.0 for j in range(n)] for i in range(n)]


TAYLOR_TERMS = 13  # E^13 / 14! is the last term kept: the next is below 5e-17 at |E| <= 1/2


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
    A, d = _balance(A)
    n = len(A)
    norm = _norm1(A) * abs(h)
    s = max(0, math.frexp(norm)[1] + 1)  # norm < 2^e, so |A tau| < 2^(e - s) <= 1/2
    tau = math.ldexp(h, -s)  # exact: a power of two
    E = [[float(v) * tau for v in row] for row in A]
    eye = identity(n)
    P = eye
    for j in range(TAYLOR_TERMS + 1, 1, -1):  # P = I + E/2 (I + E/3 (... (I + E/14)))
        P = _fused(1.0, eye, E, P, j)
    D, Phi = matmul(E, P), [[tau * v for v in row] for row in P]
    X = None  # exp itself, once it has decayed below D
    for _ in range(s):
        if X is None:
            candidate = [[p + q for p, q in zip(rd, ri)] for rd, ri in zip(D, eye)]
            if _norm1(candidate) < 0.5 * _norm1(D):
                X = candidate
        if X is None:
            D, Phi = _fused(2.0, D, D, D, 1.0), _fused(2.0, Phi, D, Phi, 1.0)
        else:
            X, Phi = matmul(X, X), _fused(1.0, Phi, X, Phi, 1.0)
    if X is None:
        X = [[p + q for p, q in zip(rd, ri)] for rd, ri in zip(D, eye)]
    return [[v * d[i] / d[j] for j, v in enumerate(row)] for i, row in enumerate(X)], \
        [[v * d[i] / d[j] for j, v in enumerate(row)] for i, row in enumerate(Phi)]


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
    Ad, Phi = exp_and_integral(A, h)
    return Ad, matmul(Phi, B)


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
