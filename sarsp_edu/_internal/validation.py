"""Argument checks shared by every module: each error names the parameter,
the value that arrived and what is valid."""

from __future__ import annotations

import math
import numbers

import numpy as np


def _as_float(value) -> float:
    """``float(value)`` for a number, NaN for anything else.

    Text is refused although ``float("0.2")`` would work: a string that
    passed validation would stay a string in the object and fail far from
    here.  Booleans are refused too (``True`` is not a magnitude).
    """
    if isinstance(value, (str, bytes, bool)):
        return math.nan
    try:
        return float(value)
    except (TypeError, ValueError):
        return math.nan


def check_positive(name: str, value, maximum: float | None = None, why: str = "") -> float:
    """A positive finite float, at most ``maximum`` if given (``why`` gives the bound's reason)."""
    number = _as_float(value)
    if not (math.isfinite(number) and number > 0):
        raise ValueError(f"{name} must be a positive finite number, got {name}={value!r}")
    if maximum is not None and number > maximum:
        reason = f" ({why})" if why else ""
        raise ValueError(f"{name} must be a positive number of at most {maximum:g}{reason}, got {name}={value!r}")
    return number


def check_int(name: str, value, minimum: int | None = None, maximum: int | None = None, *, allow_none=False,
              why: str = ""):
    """An integer in ``[minimum, maximum]`` (bools refused), or None if allowed; ``why`` gives the bound's reason."""
    if value is None and allow_none:
        return None
    ok = not isinstance(value, bool) and isinstance(value, numbers.Integral)
    ok = ok and (minimum is None or value >= minimum) and (maximum is None or value <= maximum)
    if not ok:
        if minimum is not None and maximum is not None:
            valid = f"an integer from {minimum} to {maximum}"
        elif minimum is not None:
            valid = f"an integer >= {minimum}"
        else:
            valid = "an integer"
        if allow_none:
            valid += " or None"
        if why:
            valid += f" ({why})"
        raise ValueError(f"{name} must be {valid}, got {name}={value!r}")
    return int(value)


def check_bool(name: str, value) -> bool:
    """True or False (numpy's bool too)."""
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be True or False, got {name}={value!r}")
    return bool(value)


def check_choice(name: str, value, choices):
    """One of ``choices``."""
    if value not in choices:
        listed = ", ".join(repr(c) for c in choices)
        raise ValueError(f"{name} must be one of {listed}, got {name}={value!r}")
    return value


def check_range(name: str, value, low: float, high: float, what: str = "") -> float:
    """A float in ``[low, high]``; ``what`` says what the number is, for the message."""
    number = _as_float(value)
    if not (low <= number <= high):
        detail = f" ({what})" if what else ""
        raise ValueError(f"{name} must lie in [{low:g}, {high:g}]{detail}, got {name}={value!r}")
    return number


def check_fraction(name: str, value) -> float:
    """A float in [0, 1]."""
    return check_range(name, value, 0.0, 1.0)


#: the largest nu whose log marginal likelihood float64 still computes to many digits (at 10^15 and beyond
#: the (nu - 2) terms swallow the data's: the value is wrong in its first digit)
LARGEST_NU = 1e12


def check_nu(nu) -> float:
    """The Student-t degrees of freedom: finite, > 2 and at most ``LARGEST_NU``."""
    number = _as_float(nu)
    if not (math.isfinite(number) and number > 2):
        raise ValueError(
            f"nu must be a finite number > 2 (the covariance is infinite for nu <= 2), "
            f"got nu={nu!r}; for nu -> infinity use GaussianProcess"
        )
    if number > LARGEST_NU:
        raise ValueError(
            f"nu must be at most {LARGEST_NU:g} (beyond it float64 loses the likelihood's digits, and the TP "
            f"is a GP to every digit shown), got nu={nu!r}; for nu -> infinity use GaussianProcess"
        )
    return number


def check_switch_states(n_switch_states, n_unsafe: int) -> int:
    """The number of unsafe states a shift moves: 0 to ``n_unsafe``."""
    if (
        isinstance(n_switch_states, bool)
        or not isinstance(n_switch_states, numbers.Integral)
        or not 0 <= n_switch_states <= n_unsafe
    ):
        raise ValueError(
            f"n_switch_states must be an integer from 0 to n_unsafe={n_unsafe}, "
            f"got n_switch_states={n_switch_states!r}"
        )
    return int(n_switch_states)


# -- model data (numpy is imported inside: config, which loads no numerical library, imports this module) --
#: |values| beyond this overflow float64 in a fit: squared in distances and y^T K^-1 y, and squared again in the
#: optimiser's second moments of the likelihood's gradient (1e75^4 = 1e300)
LARGEST = 1e75


def check_X(X, name="X", n_features=None):
    """A finite 2-D float array of model inputs (rows are samples)."""
    X = np.asarray(X, dtype=float)
    if X.ndim != 2:
        hint = (" (Reshape your data: X.reshape(-1, 1) for a single feature, X.reshape(1, -1) for a single sample)"
                if X.ndim == 1 else "")
        raise ValueError(
            f"{name} must be a 2-D array of shape (n_samples, n_features), "
            f"got an array of shape {X.shape}{hint}"
        )
    if X.shape[0] == 0 or X.shape[1] == 0:
        raise ValueError(f"{name} must hold at least one sample and one feature, got shape {X.shape}")
    if n_features is not None and X.shape[1] != n_features:
        raise ValueError(
            f"{name} has {X.shape[1]} features but the model was fitted on {n_features}"
        )
    if not np.all(np.isfinite(X)):
        bad = np.argwhere(~np.isfinite(X))[0]
        raise ValueError(
            f"{name} must be finite (no NaN or inf), got {X[tuple(bad)]} at row {bad[0]}, column {bad[1]}"
        )
    check_scale(name, X)
    return X


def check_scale(name: str, values) -> None:
    """Refuse data whose squares would overflow float64."""
    import numpy as np

    largest = float(np.max(np.abs(values)))
    if largest > LARGEST:
        raise ValueError(
            f"{name} holds values as large as {largest:.3g}, beyond {LARGEST:g}: their squares (and the "
            f"fit's squared gradients) overflow float64; rescale {name} (divide it by its standard deviation, say)"
        )


def check_training(X, y):
    """Training inputs and targets, checked against each other."""
    import numpy as np

    X = check_X(X)
    y = np.asarray(y, dtype=float)
    if y.ndim == 2 and y.shape[1] == 1:
        y = y[:, 0]
    if y.ndim != 1:
        raise ValueError(f"y must be a 1-D array of shape (n_samples,), got shape {y.shape}")
    if y.shape[0] != X.shape[0]:
        raise ValueError(
            f"X and y must have the same number of samples, got {X.shape[0]} rows in X "
            f"and {y.shape[0]} values in y"
        )
    if not np.all(np.isfinite(y)):
        i = int(np.flatnonzero(~np.isfinite(y))[0])
        raise ValueError(f"y must be finite (no NaN or inf), got y[{i}]={y[i]}")
    check_scale("y", y)
    return X, y


def check_positive_pair(name: str, value) -> tuple:
    """A pair ``(low, high)`` of finite numbers with ``0 < low < high`` (a box of hyperparameters)."""
    try:
        low, high = (float(b) for b in value)
    except (TypeError, ValueError):
        low = high = math.nan
    if not (0 < low < high < math.inf):
        raise ValueError(f"{name} must be a pair (low, high) with 0 < low < high, got {name}={value!r}")
    return low, high
