"""Predictions conditioned on strategic priors: what a decision asks of a model, and what keeps it quick.

A decision conditions a fitted model on a few rows of its buffer (its
*strategic prior*) and predicts the four actions' inputs.
:class:`PriorPredictor` does that conditioning for the agent, on the package's
models or on a student's parts (:class:`~sarsp_edu.agent.parts.DecisionParts`),
and owns the two things that make it quick without changing a bit of it:

- a *whole-number distance bound*: the buffer's inputs and the queries are
  whole numbers, so squared distances below 2**53 are exact, and the
  kernel can skip the checks a general input needs
  (:func:`~sarsp_edu.models.kernels.whole_distance_bound`);
- a *kernel table* of the buffer's distinct inputs
  (:class:`~sarsp_edu.models.kernels.KernelTable`), from which each prior's
  kernel matrices are gathered instead of computed.

Both are kept per buffer until it grows (rows are only ever added; a
corrective update changes targets, not inputs), the table also until a refit
changes the kernel.  ``kernel_table=False`` switches the table off (the
numbers are the same bits; a benchmark measures what it saves).
"""

from __future__ import annotations

import numpy as np

from ..models.kernels import KernelTable, whole_distance_bound
from ..models.processes.likelihood import StudentTLikelihoodGP

__all__ = ["KERNEL_TABLE_MAX_DISTINCT", "PriorPredictor"]

#: the most distinct inputs a buffer may have for its kernel table to be kept (8 G**2 bytes: 32 MB)
KERNEL_TABLE_MAX_DISTINCT = 2048


class PriorPredictor:
    """A model's predictive moments, each query conditioned on its own strategic prior.

    Parameters
    ----------
    kernel_table : bool, default True
        Gather the priors' kernel matrices from a table of the buffer's
        distinct inputs where it has at most ``max_distinct`` of them.
    max_distinct : int, default KERNEL_TABLE_MAX_DISTINCT
        The most distinct inputs a buffer may have for its table to be kept.
    """

    def __init__(self, kernel_table: bool = True, max_distinct: int = KERNEL_TABLE_MAX_DISTINCT):
        self.kernel_table = bool(kernel_table)
        self.max_distinct = int(max_distinct)
        self._bounds = {}  # id(buffer) -> (buffer, its length, whole-number inputs?, per-column min, max)
        self._tables = {}  # id(buffer) -> (buffer, its length, the kernel's parameters, KernelTable or None)

    def predict(self, model, buffer, prior_rows, query_sets, parts=None, include_noise: bool = True):
        """Mean, variance and degrees of freedom of each query given its prior's rows.

        Parameters
        ----------
        model : GaussianProcess, StudentTProcess or StudentTLikelihoodGP
            Fitted: its kernel and noise are conditioned on, not refitted (the
            Student-t likelihood's by its own Laplace approximation, from the
            package's computation whatever the parts).
        buffer : ObservationBuffer
            The model's training set; ``prior_rows`` index it.
        prior_rows : list of ndarray of int
            One set of row indices per prior.
        query_sets : ndarray of shape (len(prior_rows), q, d)
            The queries each prior predicts.
        parts : DecisionParts, optional
            A student's functions (kernel, GP posterior, TP factor) where
            they replace the package's: assembled per prior.
        include_noise : bool, default True
            The variance of a new observation (the noise included), or of the latent function alone.

        Returns
        -------
        mean, var : ndarray of shape (len(prior_rows), q)
            Predictive mean and variance (with the observation noise where ``include_noise``).
        df : ndarray of shape (len(prior_rows),)
            The predictive's degrees of freedom (inf for the GP).
        """
        X, y = buffer.X, buffer.y
        if isinstance(model, StudentTLikelihoodGP):  # a Student-t likelihood: a Laplace approximation per prior
            return model.predict_batch([X[r] for r in prior_rows], [y[r] for r in prior_rows], query_sets,
                                       include_noise=include_noise)
        steps = None if parts is None else parts.conditioning_steps()
        queries = query_sets.reshape(-1, query_sets.shape[-1])
        bound = self.whole_bound(buffer, queries)
        table = None if steps is not None and steps.kernel is not None else self.table(model, buffer, bound)
        kernels = None
        if table is not None:  # the matrices gathered from the buffer's kernel table: the same numbers, sooner
            cross = table.cross(queries, whole_bound=bound).reshape(*query_sets.shape[:2], -1)
            kernels = [table.gather(rows, cross[i]) for i, rows in enumerate(prior_rows)]
        return model.predict_batch([X[r] for r in prior_rows], [y[r] for r in prior_rows], query_sets,
                                   include_noise=include_noise, whole_bound=bound, kernels=kernels, steps=steps)

    def whole_bound(self, buffer, queries):
        """:func:`~sarsp_edu.models.kernels.whole_distance_bound` of a buffer's inputs and the queries.

        Parameters
        ----------
        buffer : ObservationBuffer
        queries : ndarray of shape (q, d)

        Returns
        -------
        float or None
            A bound on every squared distance among them, None where an input
            is not a whole number (no bound is then claimed).
        """
        kept = self._bounds.get(id(buffer))
        if kept is None or kept[0] is not buffer or kept[1] != len(buffer):
            X = buffer.X
            kept = (buffer, len(buffer), bool(np.array_equal(np.rint(X), X)), X.min(axis=0), X.max(axis=0))
            self._bounds[id(buffer)] = kept
        _, _, whole, low, high = kept
        if not whole:
            return None
        return whole_distance_bound(np.stack([low, high]), queries)

    def table(self, model, buffer, whole_bound):
        """The kernel table of a buffer's inputs under a model's kernel, or None.

        Parameters
        ----------
        model : GaussianProcess or StudentTProcess
            Fitted: ``kernel_`` is tabled.
        buffer : ObservationBuffer
        whole_bound : float or None
            :meth:`whole_bound` of the buffer and the queries (None: no table).

        Returns
        -------
        KernelTable or None
            None where the table is switched off, the inputs are not whole
            numbers or the buffer has more than ``max_distinct`` distinct rows
            (the reward buffer's rows are all distinct).
        """
        if whole_bound is None or not self.kernel_table:
            return None
        kept = self._tables.get(id(buffer))
        params = model.kernel_.get_params()
        if kept is None or kept[0] is not buffer or kept[1] != len(buffer) or kept[2] != params:
            table = KernelTable.if_small(model.kernel_, buffer.X, self.max_distinct, whole_bound=whole_bound)
            kept = (buffer, len(buffer), params, table)
            self._tables[id(buffer)] = kept
        return kept[3]

    def kept_length(self, buffer):
        """The buffer's length when its bound was last computed (None before): a test's view of the cache."""
        kept = self._bounds.get(id(buffer))
        return None if kept is None or kept[0] is not buffer else kept[1]
