"""The linear algebra of the GP and the TP: Cholesky factors, solves, grouped rows.

Every factorisation in the package goes through :func:`cholesky` (one
LAPACK call, no checks: the fast path) or :func:`cholesky_with_jitter` (the
safe path, which tries :func:`cholesky` first).  LAPACK is called directly
because on the agent's 110 x 110 matrices scipy's wrappers cost more than the
factorisation itself.

:func:`group_rows` folds repeated inputs together exactly, so that a
likelihood over thousands of rows with a few hundred distinct inputs costs a
factorisation of the distinct inputs' size.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg import lapack

__all__ = [
    "GroupedRows",
    "cholesky",
    "cholesky_with_jitter",
    "group_rows",
    "inverse_from_cholesky",
    "solve_cholesky",
    "solve_lower",
    "trace_of_product",
]


def cholesky(K: np.ndarray, overwrite: bool = False):
    """Lower Cholesky factor of ``K``, or None if ``K`` is not positive definite (the fast path).

    With ``overwrite`` a C-ordered ``K`` is factorised in its own memory (its
    transpose is the same symmetric matrix in Fortran order, LAPACK's), and
    ``K`` is lost whether or not the factorisation succeeds.

    Parameters
    ----------
    K : ndarray of shape (n, n)
        A symmetric matrix (only its lower triangle is read).
    overwrite : bool, default False
        Factorise in ``K``'s memory.
    """
    if overwrite:
        L, info = lapack.dpotrf(K.T, lower=1, clean=1, overwrite_a=1)
    else:
        L, info = lapack.dpotrf(K, lower=1, clean=1)
    return L if info == 0 else None


def cholesky_with_jitter(K: np.ndarray, max_tries: int = 6):
    """Lower Cholesky factor of ``K``, adding diagonal jitter if needed (the safe path).

    Tries ``K`` as it is, then ``K + j I`` with ``j`` = 1e-10, 1e-9, ... times
    the mean of the diagonal, ``max_tries`` times.  Returns ``(L, jitter)``;
    raises ``numpy.linalg.LinAlgError`` with advice when every try fails.

    Parameters
    ----------
    K : ndarray of shape (n, n)
        A symmetric covariance matrix; it is not changed.
    max_tries : int, default 6
        How many jitters to try after ``K`` itself (the largest is 1e-10 x 10^(max_tries - 1) of the diagonal).
    """
    if not np.all(np.isfinite(np.diag(K))):
        raise np.linalg.LinAlgError(
            "the covariance matrix has a non-finite diagonal; check the hyperparameters and the data for overflow"
        )
    L = cholesky(K)
    if L is not None:
        return L, 0.0
    scale = float(np.mean(np.diag(K)))
    if not scale > 0:
        raise np.linalg.LinAlgError(
            f"the covariance matrix has a non-positive diagonal (mean {scale}); check the hyperparameters"
        )
    jitter = 0.0
    for k in range(max_tries):
        jitter = scale * 10.0 ** (k - 10)
        Kj = K.copy()
        Kj.flat[:: K.shape[0] + 1] += jitter
        L = cholesky(Kj)
        if L is not None:
            return L, jitter
    raise np.linalg.LinAlgError(
        f"the covariance matrix is not positive definite even with a diagonal jitter of "
        f"{jitter:.3g}: increase noise_variance, or remove duplicated inputs with "
        "conflicting targets"
    )


def solve_cholesky(L: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Solve ``K x = b`` given the lower Cholesky factor ``L`` of ``K``.

    (scipy's ``cho_solve`` takes ``(L, lower)`` as a pair; this takes ``L``.)

    Parameters
    ----------
    L : ndarray of shape (n, n)
        The lower Cholesky factor of ``K``.
    b : ndarray of shape (n,) or (n, k)
        The right-hand side(s).
    """
    x, info = lapack.dpotrs(L, b, lower=1)
    if info != 0:
        raise np.linalg.LinAlgError(f"LAPACK dpotrs failed with info={info}")
    return x


def solve_lower(L: np.ndarray, B: np.ndarray) -> np.ndarray:
    """Solve ``L X = B`` for lower-triangular ``L``.

    Parameters
    ----------
    L : ndarray of shape (n, n)
        Lower triangular.
    B : ndarray of shape (n,) or (n, k)
        The right-hand side(s).
    """
    X, info = lapack.dtrtrs(L, B, lower=1)
    if info != 0:
        raise np.linalg.LinAlgError(f"LAPACK dtrtrs failed with info={info}")
    return X


def inverse_from_cholesky(L: np.ndarray, overwrite: bool = False) -> np.ndarray:
    """The lower triangle of ``K^-1`` (zeros above) from the lower Cholesky factor of ``K``.

    LAPACK potri: about three times cheaper than solving against the
    identity.  ``L`` comes from :func:`cholesky` with zeros above the
    diagonal, and potri keeps them, so no triangle needs clearing or
    mirroring.  With ``overwrite`` the inverse replaces ``L`` in its memory.

    Parameters
    ----------
    L : ndarray of shape (n, n)
        The lower Cholesky factor of ``K``, zeros above the diagonal.
    overwrite : bool, default False
        Write the inverse into ``L``'s memory.
    """
    K_inv, info = lapack.dpotri(L, lower=1, overwrite_c=1 if overwrite else 0)
    if info != 0:
        raise np.linalg.LinAlgError(f"LAPACK dpotri failed with info={info}")
    return K_inv


def trace_of_product(lower: np.ndarray, S: np.ndarray) -> float:
    """``tr(A S) = sum(A * S)`` for symmetric ``A`` given as its lower triangle, symmetric ``S``.

    Parameters
    ----------
    lower : ndarray of shape (n, n)
        The lower triangle of ``A``, zeros above the diagonal (as :func:`inverse_from_cholesky` gives).
    S : ndarray of shape (n, n)
        Symmetric, both triangles filled.
    """
    return 2.0 * float(np.vdot(lower, S)) - float(np.dot(np.diag(lower), np.diag(S)))


class GroupedRows:
    """Training data with repeated inputs folded together (exact, see :func:`group_rows`).

    Attributes: ``X`` the distinct inputs (G, d) in order of first
    appearance, ``counts`` (G,), ``mean`` the mean target of each distinct
    input (G,), ``rss`` the sum of squared deviations of the targets from
    their input's mean, ``n`` the number of rows.
    """

    __slots__ = ("X", "counts", "mean", "rss", "n")

    def __init__(self, X, counts, mean, rss, n):
        self.X, self.counts, self.mean, self.rss, self.n = X, counts, mean, rss, n

    @classmethod
    def ungrouped(cls, X: np.ndarray, y: np.ndarray) -> "GroupedRows":
        """Every row its own group: the textbook computation, for comparisons.

        Parameters
        ----------
        X : ndarray of shape (n, d)
        y : ndarray of shape (n,)
        """
        return cls(X, np.ones(len(X)), y, 0.0, len(X))

    def beta_and_log_det(self, L: np.ndarray, alpha: np.ndarray, s2: float) -> tuple:
        """``y^T K^-1 y`` and ``log|K|`` of all the rows, from the factor ``L`` of ``A`` and ``alpha = A^-1 ybar``.

        Parameters
        ----------
        L : ndarray of shape (G, G)
            The lower Cholesky factor of ``A = K(U, U) + s2 N^-1`` (see :func:`group_rows`).
        alpha : ndarray of shape (G,)
            ``A^-1 ybar``, with ``ybar`` the groups' mean targets.
        s2 : float
            The noise variance.

        Returns
        -------
        tuple of float
            ``(beta, log_det)``.
        """
        G = self.counts.shape[0]
        beta = self.rss / s2 + float(self.mean @ alpha)
        log_det = (2.0 * float(np.sum(np.log(np.diag(L)))) + (self.n - G) * math.log(s2)
                   + float(np.sum(np.log(self.counts))))
        return beta, log_det


def distinct_rows(X: np.ndarray) -> tuple:
    """The distinct rows of ``X`` in order of first appearance: ``(first, group)``.

    ``X[first]`` are the distinct rows and ``group[i]`` the index into them of
    row ``i``; rows are equal when every entry is (``-0.0`` equals ``0.0``).

    Parameters
    ----------
    X : ndarray of shape (n, d)

    Examples
    --------
    >>> first, group = distinct_rows(np.array([[1.0, 2.0], [0.0, 0.0], [1.0, 2.0], [-0.0, 0.0]]))
    >>> first.tolist(), group.tolist()
    ([0, 1], [0, 1, 0, 1])
    """
    keyed = np.ascontiguousarray(X + 0.0)  # + 0.0 folds -0.0 into 0.0
    keys = keyed.view(np.dtype((np.void, keyed.dtype.itemsize * keyed.shape[1]))).ravel()
    _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    order = np.argsort(first)  # groups in order of first appearance
    rank = np.empty_like(order)
    rank[order] = np.arange(order.shape[0])
    return first[order], rank[inverse.reshape(-1)]


def group_rows(X: np.ndarray, y: np.ndarray) -> GroupedRows:
    """Fold rows with equal inputs into (distinct input, count, mean target) and a residual sum.

    With ``n_g`` copies of input ``u_g``, ``K = Z K(U, U) Z^T + s2 I`` (``Z``
    the n x G indicator matrix).  On the span of ``Z``'s columns the
    covariance is ``N^1/2 K(U, U) N^1/2 + s2 I`` (``N = diag(n_g)``), and on
    its orthogonal complement ``s2 I``.  Hence, exactly,

    - ``y^T K^-1 y = rss / s2 + ybar^T A^-1 ybar`` and
    - ``log|K| = (n - G) log s2 + sum log n_g + log|A|``,

    with ``A = K(U, U) + s2 N^-1``, a G x G matrix: the likelihood of all
    n rows costs a factorisation of the distinct inputs' size.  The
    predictive distribution is that of the group means with noise
    ``s2 / n_g``.  With distinct inputs ``A = K`` and nothing changes.

    Parameters
    ----------
    X : ndarray of shape (n, d)
        The inputs; rows are equal when every entry is (``-0.0`` equals ``0.0``).
    y : ndarray of shape (n,)
        The targets.
    """
    n = X.shape[0]
    first, group_of_row = distinct_rows(X)
    if first.shape[0] == n:
        return GroupedRows(X, np.ones(n), y, 0.0, n)
    counts = np.bincount(group_of_row, minlength=first.shape[0]).astype(float)
    mean = np.bincount(group_of_row, weights=y, minlength=first.shape[0]) / counts
    rss = float(np.sum((y - mean[group_of_row]) ** 2))
    return GroupedRows(X[first], counts, mean, rss, n)
