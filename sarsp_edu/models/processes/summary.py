"""A fitted model's hyperparameters as plain numbers: what a stored run records of its fits."""

from __future__ import annotations

import math

__all__ = ["fit_summary"]


def _number(value) -> float | None:
    """A float, or None where it is not finite (JSON has no NaN that every reader takes)."""
    value = float(value)
    return value if math.isfinite(value) else None


def fit_summary(model) -> dict:
    """The fitted hyperparameters of a GaussianProcess, StudentTProcess or StudentTLikelihoodGP.

    Returns
    -------
    dict
        ``kind`` ("gp", "tp" or "t-likelihood"), ``amplitude``, ``length_scale``, ``noise_variance`` (the
        Student-t noise's ``s^2 nu / (nu - 2)`` for the t-likelihood GP), its ``scale`` and ``nu`` (the TP's
        ``nu`` too), the search's ``gradient_norm`` where it ended (None without a search) and the final
        ``objective`` of each start (``start_objectives``, the first from the constructor's values).
    """
    from .laplace import noise_variance
    from .likelihood import StudentTLikelihoodGP
    from .tp import StudentTProcess

    out = {"amplitude": _number(model.kernel_.amplitude), "length_scale": _number(model.kernel_.length_scale)}
    if isinstance(model, StudentTLikelihoodGP):
        out = {"kind": "t-likelihood", **out, "scale": _number(model.scale_), "nu": _number(model.nu_),
               "noise_variance": _number(noise_variance(model.nu_, model.scale_))}
    else:
        out = {"kind": "tp" if isinstance(model, StudentTProcess) else "gp", **out,
               "noise_variance": _number(model.noise_variance_)}
        if isinstance(model, StudentTProcess):
            out["nu"] = _number(model.nu_)
    out["gradient_norm"] = _number(getattr(model, "gradient_norm_", math.nan))
    out["start_objectives"] = [_number(v) for v in getattr(model, "start_objectives_", [])]
    return out
