"""The squared-exponential (RBF) kernel used by both processes.

The paper (section 5.2) and its reference implementation use one kernel for the
Gaussian process and the Student-t process: TensorFlow Probability's
``ExponentiatedQuadratic``, in which the amplitude enters squared,

.. math::

    k(x, x') = a^2 \\exp\\left(-\\frac{\\lVert x - x' \\rVert^2}{2 \\ell^2}\\right),

with one length scale shared by every input dimension.  The observation noise is
*not* part of the kernel here; the processes add it to the diagonal.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.distance import cdist

from .._internal.validation import check_fraction, check_int, check_positive

__all__ = ["DistanceLevels", "KernelTable", "RBF", "squared_distances", "whole_distance_bound"]

# the whole-number lookup of RBF.from_squared_distances: used from this many entries on (below, the checks cost more
# than they save), for squared distances below the table's largest size (8 MB)
_TABLE_MIN_SIZE = 256
_TABLE_MAX_SIZE = 2**20


def squared_distances(X: np.ndarray, Y: np.ndarray | None = None) -> np.ndarray:
    """Pairwise squared Euclidean distances.

    Parameters
    ----------
    X : ndarray of shape (n, d)
    Y : ndarray of shape (m, d), optional
        Defaults to ``X``; the result is then exactly symmetric with a zero
        diagonal, because each entry sums ``(x_ik - x_jk)**2`` and squaring
        gives the same float whichever way the difference is taken.

    Returns
    -------
    ndarray of shape (n, m)
    """
    return cdist(X, X if Y is None else Y, "sqeuclidean")


def whole_distance_bound(*arrays: np.ndarray) -> float | None:
    """An upper bound of the squared distances between the rows of ``arrays`` if every entry is whole, else None.

    Whole-number inputs (the grid world's) have whole-number squared
    distances, each at most the sum over columns of the squared range of the
    column: :meth:`RBF.from_squared_distances` then looks the kernel up in a
    table without checking every distance.

    Parameters
    ----------
    *arrays : ndarrays of shape (n_i, d)
        Rows with the same d columns (empty arrays are skipped).

    Returns
    -------
    float or None
        The bound; None when an entry is not a whole number or the bound
        reaches 2**52, beyond which squared distances are no longer exact.
    """
    low, high = None, None
    for i, X in enumerate(arrays):
        X = np.asarray(X, dtype=float)
        if X.ndim != 2:
            raise ValueError(f"arrays[{i}] must be 2-D (rows of inputs), got shape {X.shape}")
        if X.size == 0:
            continue
        if not np.array_equal(np.rint(X), X):
            return None
        low = X.min(axis=0) if low is None else np.minimum(low, X.min(axis=0))
        high = X.max(axis=0) if high is None else np.maximum(high, X.max(axis=0))
    if low is None:
        return 0.0
    span = high - low
    bound = float(span @ span)
    return bound if bound < 2.0**52 else None


def _floating(D2) -> np.ndarray:
    """``D2`` as an array in its own floating dtype (float32 stays float32, as in ``RBF``'s every-entry path), else
    float64."""
    D2 = np.asarray(D2)
    return D2 if np.issubdtype(D2.dtype, np.floating) else D2.astype(float)


class DistanceLevels:
    """The distinct values of a squared-distance matrix, and for each entry the index of its value.

    A fit evaluates the kernel on one matrix of squared distances at every step.  Among the cost buffer's ~800 distinct
    inputs the 600,000 entries take only about 110,000 distinct values: exponentiating those and gathering costs about a
    third of exponentiating every entry, and gives the same numbers (the same operations on the same doubles, see
    :meth:`RBF.from_squared_distances`).

    Parameters
    ----------
    D2 : ndarray
        Squared distances (kept in their floating dtype; other dtypes as
        float64, as :meth:`RBF.from_squared_distances` computes on them).

    Attributes
    ----------
    values : ndarray of shape (V,)
        The distinct entries of ``D2``, sorted (``np.unique``'s: one 0.0 for
        0.0 and -0.0, NaNs last).
    index : ndarray of D2's shape, of intp
        ``values[index]`` equals ``D2`` (but for NaN entries and the sign of a zero).

    Examples
    --------
    >>> import numpy as np
    >>> from sarsp_edu.models.kernels import DistanceLevels, RBF
    >>> D2 = np.array([[0.0, 2.0], [2.0, 0.0]])
    >>> levels = DistanceLevels(D2)
    >>> levels.values
    array([0., 2.])
    >>> kernel = RBF(length_scale=1.5)
    >>> bool(np.array_equal(kernel.from_squared_distances(D2, levels=levels), kernel.from_squared_distances(D2)))
    True
    """

    def __init__(self, D2: np.ndarray):
        D2 = _floating(D2)
        self.values, index = np.unique(D2, return_inverse=True)
        self.index = index.reshape(D2.shape).astype(np.intp, copy=False)

    @classmethod
    def if_few(cls, D2: np.ndarray, max_fraction: float = 0.25, max_size: int = 2048**2):
        """Levels of ``D2`` if they number at most ``max_fraction`` of its entries, else None.

        Matrices of more than ``max_size`` entries get none (their sort and
        index would cost more time and memory than their steps save: the
        ``reference`` preset's whole-buffer reward fit has 24 million).

        Parameters
        ----------
        D2 : ndarray
            Squared distances, as for the constructor.
        max_fraction : float, default 0.25
            The largest share of distinct values among the entries for which levels are worth keeping.
        max_size : int, default 2048**2
            The most entries a matrix may have.
        """
        max_fraction = check_fraction("max_fraction", max_fraction)
        max_size = check_int("max_size", max_size, 0)
        D2 = _floating(D2)
        if D2.size == 0 or D2.size > max_size:
            return None
        levels = cls(D2)
        return levels if levels.values.size <= max_fraction * D2.size else None


class RBF:
    """Squared-exponential kernel ``k(x, x') = amplitude**2 exp(-|x - x'|**2 / (2 length_scale**2))``.

    Parameters
    ----------
    amplitude : float, default 1.0
        Output scale ``a`` (> 0); the prior variance of the process is ``a**2``.
    length_scale : float, default 1.0
        Length scale ``l`` (> 0), shared by all input dimensions.

    Notes
    -----
    Hyperparameters are optimised in log space: ``theta = [log a, log l]``.
    The gradient returned by ``__call__(..., eval_gradient=True)`` is taken
    with respect to ``theta``:

    - d K / d log a = 2 K
    - d K / d log l = K * |x - x'|**2 / l**2

    Examples
    --------
    >>> import numpy as np
    >>> from sarsp_edu import RBF
    >>> k = RBF(amplitude=2.0, length_scale=0.5)
    >>> round(float(k(np.array([[0.0]]), np.array([[0.5]]))[0, 0]), 6)  # 4 exp(-0.5)
    2.426123
    """

    def __init__(self, amplitude: float = 1.0, length_scale: float = 1.0):
        self.amplitude = check_positive("amplitude", amplitude)
        self.length_scale = check_positive("length_scale", length_scale)

    def get_params(self, deep: bool = True) -> dict:
        """``amplitude`` and ``length_scale``: what scikit-learn's ``clone`` and nested parameters use."""
        return {"amplitude": self.amplitude, "length_scale": self.length_scale}

    def set_params(self, **params) -> "RBF":
        """Set ``amplitude`` or ``length_scale`` (each checked); the model's ``set_params(kernel__...)`` calls it."""
        unknown = sorted(set(params) - {"amplitude", "length_scale"})
        if unknown:
            raise ValueError(f"RBF has no parameters {unknown}; valid parameters are ['amplitude', 'length_scale']")
        for name, value in params.items():
            setattr(self, name, check_positive(name, value))
        return self

    # -- hyperparameters in log space -------------------------------------
    @property
    def theta(self) -> np.ndarray:
        """Log hyperparameters ``[log amplitude, log length_scale]``."""
        return np.log([self.amplitude, self.length_scale])

    def clone_with_theta(self, theta) -> "RBF":
        """A new kernel with hyperparameters ``exp(theta)``."""
        a, l = np.exp(np.asarray(theta, dtype=float))
        return RBF(amplitude=a, length_scale=l)

    # -- evaluation ---------------------------------------------------------
    def from_squared_distances(self, D2: np.ndarray, eval_gradient: bool = False, out=None, *,
                               whole_bound: float | None = None, levels: DistanceLevels | None = None):
        """Kernel matrix (and gradient) from precomputed squared distances.

        The fit evaluates the kernel at many hyperparameters on one training
        set; computing the distances once and reusing them here saves most
        of the cost of each step.

        Parameters
        ----------
        D2 : ndarray of shape (n, m)
        eval_gradient : bool, default False
        out : ndarray of shape (3, n, m), optional
            A workspace to write into (``K`` in ``out[0]``, the gradient in ``out[1:]``) instead of allocating: a fit
            reuses one for all its steps, which spares the page faults of fresh megabyte arrays.
        whole_bound : float, optional
            The caller's guarantee that every entry of ``D2`` is a whole number no larger than this (the squared
            distances of whole-number inputs, see :func:`whole_distance_bound`): the table lookup then skips checking
            the entries, which costs as much as the lookup.  It is not checked: a wrong guarantee gives a wrong
            matrix.  A bound too large for the table leaves the entries checked.
        levels : DistanceLevels, optional
            ``D2``'s distinct values (computed once by a fit for all its
            steps): the kernel is evaluated on them and gathered, bit for bit
            the values of evaluating every entry.  Not checked against ``D2``.

        Returns
        -------
        K : ndarray of shape (n, m)
        K_gradient : ndarray of shape (n, m, 2), only if ``eval_gradient``
            Derivatives with respect to ``theta``.
        """
        inv_l2 = 1.0 / self.length_scale**2
        if out is None and not eval_gradient and D2.size >= _TABLE_MIN_SIZE:
            K = self._from_whole_distances(D2, whole_bound)
            if K is not None:
                return K
        # the same three operations on every entry (in place: this runs once per decision of the agent) or on
        # the distinct values, then gathered
        target = None if out is None else out[0]
        K = np.multiply(D2 if levels is None else levels.values, -0.5 * inv_l2,
                        out=target if levels is None else None)
        np.exp(K, out=K)
        K *= self.amplitude**2
        if levels is not None:
            K = K.take(levels.index, out=target)
        if not eval_gradient:
            return K
        # Two contiguous planes seen as (n, m, 2): writing and contracting them is several times faster than filling a
        # strided last axis.
        planes = np.empty((2,) + K.shape) if out is None else out[1:]
        np.multiply(K, 2.0, out=planes[0])
        np.multiply(K, D2, out=planes[1])
        planes[1] *= inv_l2
        return K, np.moveaxis(planes, 0, -1)

    def _from_whole_distances(self, D2: np.ndarray, whole_bound: float | None = None):
        """``K`` by table lookup when every squared distance is a small whole number, else None.

        The grid world's inputs are whole numbers, so are their squared distances, and an agent's decision evaluates the
        same few hundred distinct values thousands of times.  The table holds
        ``amplitude**2 exp(-i / (2 length_scale**2))`` for ``i = 0, 1, ...``, computed by the very operations of the
        general path on the same doubles, so the result is bit for bit the same; the lookup is about twice as fast as
        the exponential.
        """
        if whole_bound is not None and whole_bound >= _TABLE_MAX_SIZE:
            whole_bound = None  # the bound is too loose to size a table: check the distances themselves
        index = D2.astype(np.intp)
        if whole_bound is None:
            if not np.array_equal(index, D2):
                return None
            top = int(index.max())
            if int(index.min()) < 0 or top >= _TABLE_MAX_SIZE:
                return None
        else:
            top = int(whole_bound)
        key = (self.amplitude, self.length_scale)  # a table is only valid for its hyperparameters
        key_then, table = getattr(self, "_table", (None, None))  # the last table, kept on the kernel
        if key_then != key or table.shape[0] <= top:
            size = min(max(1024, 2 * (top + 1)), _TABLE_MAX_SIZE)
            table = np.multiply(np.arange(size, dtype=float), -0.5 * (1.0 / self.length_scale**2))
            np.exp(table, out=table)
            table *= self.amplitude**2
            self._table = (key, table)
        return table.take(index)

    def __call__(self, X, Y=None, eval_gradient: bool = False):
        """Kernel matrix ``K(X, Y)``.

        Parameters
        ----------
        X : array-like of shape (n, d)
        Y : array-like of shape (m, d), optional
            Defaults to ``X``.  The gradient is only defined for ``Y=None``.
        eval_gradient : bool, default False
            Also return the gradient with respect to the log hyperparameters.

        Returns
        -------
        K : ndarray of shape (n, m)
        K_gradient : ndarray of shape (n, n, 2), only if ``eval_gradient``
        """
        X = np.atleast_2d(np.asarray(X, dtype=float))
        if Y is not None:
            if eval_gradient:
                raise ValueError("eval_gradient=True is only supported when Y is None")
            Y = np.atleast_2d(np.asarray(Y, dtype=float))
            if Y.shape[1] != X.shape[1]:
                raise ValueError(
                    f"X and Y must have the same number of features, got "
                    f"X.shape={X.shape} and Y.shape={Y.shape}"
                )
        return self.from_squared_distances(squared_distances(X, Y), eval_gradient)

    def diag(self, X) -> np.ndarray:
        """The diagonal of ``K(X, X)``: ``amplitude**2`` for every row of ``X``."""
        X = np.atleast_2d(np.asarray(X, dtype=float))
        return np.full(X.shape[0], self.amplitude**2)

    def __repr__(self) -> str:
        return f"RBF(amplitude={self.amplitude:.4g}, length_scale={self.length_scale:.4g})"

    def __eq__(self, other) -> bool:
        return (
            isinstance(other, RBF)
            and self.amplitude == other.amplitude
            and self.length_scale == other.length_scale
        )


class KernelTable:
    """A kernel's values among the distinct rows of an input array, to gather sub-matrices from.

    SARSP builds eight kernel matrices per decision from rows of the same buffer.  The cost buffer holds about 800
    distinct inputs among its ~4,700 rows (the grid is small): the kernel among the distinct inputs, computed once,
    holds every entry of every prior's matrix, and gathering ``K(X[rows], X[rows])`` from it costs less than computing
    the distances and looking the kernel up again.  The entries are the very numbers :meth:`RBF.from_squared_distances`
    gives (the same squared distances, the same evaluation), so predictions are bit for bit unchanged.

    Parameters
    ----------
    kernel : RBF
        The kernel, with its fitted hyperparameters (the table is only valid
        for them).
    X : ndarray of shape (n, d)
        The rows the prior sets are drawn from.
    whole_bound : float, optional
        As in :meth:`RBF.from_squared_distances`, for the distinct rows.

    Attributes
    ----------
    X_unique : ndarray of shape (G, d)
        The distinct rows of ``X``.
    index : ndarray of shape (n,)
        For each row of ``X``, its row of ``X_unique``.
    K : ndarray of shape (G, G)
        ``kernel(X_unique)``.

    Examples
    --------
    >>> import numpy as np
    >>> from sarsp_edu.models.kernels import RBF, KernelTable
    >>> X = np.array([[0.0], [1.0], [0.0], [3.0]])
    >>> kernel = RBF(length_scale=2.0)
    >>> table = KernelTable(kernel, X)
    >>> table.X_unique.shape
    (3, 1)
    >>> rows = np.array([0, 2, 3])
    >>> bool(np.array_equal(table.gram(rows), kernel(X[rows])))
    True
    """

    def __init__(self, kernel: RBF, X: np.ndarray, whole_bound: float | None = None):
        self._build(kernel, *self._distinct(X), whole_bound)

    @classmethod
    def if_small(cls, kernel: RBF, X: np.ndarray, max_distinct: int, whole_bound: float | None = None):
        """A table if ``X`` has at most ``max_distinct`` distinct rows, else None.

        The table takes ``8 G**2`` bytes: the reward buffer's ~5,000 rows are
        all distinct (200 MB), the cost buffer's ~800 distinct rows take 5 MB.

        Parameters
        ----------
        kernel, X, whole_bound
            As for the class.
        max_distinct : int
            The most distinct rows the table may hold.
        """
        unique, index = cls._distinct(X)
        if unique.shape[0] > max_distinct:
            return None
        table = cls.__new__(cls)
        table._build(kernel, unique, index, whole_bound)
        return table

    @staticmethod
    def _distinct(X):
        X = np.asarray(X, dtype=float)
        if X.ndim != 2:
            raise ValueError(f"X must be 2-D (rows of inputs), got shape {X.shape}")
        unique, index = np.unique(X, axis=0, return_inverse=True)
        return unique, index.reshape(-1)

    def _build(self, kernel, unique, index, whole_bound):
        self.kernel, self.X_unique, self.index = kernel, unique, index
        self.K = kernel.from_squared_distances(squared_distances(unique), whole_bound=whole_bound)

    def cross(self, X_query: np.ndarray, whole_bound: float | None = None) -> np.ndarray:
        """``kernel(X_query, X_unique)``, of shape (q, G): gather its columns with :meth:`gather`.

        Parameters
        ----------
        X_query : ndarray of shape (q, d)
        whole_bound : float, optional
            As in :meth:`RBF.from_squared_distances`, for ``X_query`` and the distinct rows together.
        """
        return self.kernel.from_squared_distances(squared_distances(X_query, self.X_unique), whole_bound=whole_bound)

    def gram(self, rows: np.ndarray) -> np.ndarray:
        """``kernel(X[rows])``: a new C-ordered array of shape (len(rows), len(rows))."""
        at = self.index[rows]
        return self.K.take(at, axis=0).take(at, axis=1)

    def gather(self, rows: np.ndarray, cross: np.ndarray):
        """``kernel(X[rows])`` and the columns ``rows`` of a :meth:`cross` result: ``(K, K_star)``.

        Parameters
        ----------
        rows : ndarray of int
            Rows of ``X``.
        cross : ndarray of shape (q, G)
            A :meth:`cross` result.
        """
        return self.gram(rows), cross.take(self.index[rows], axis=1)
