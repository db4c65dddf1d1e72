"""Argument checks shared by every module: each error names the parameter,
the value that arrived and what is valid."""

from __future__ import annotations

import math
import numbers


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


def check_positive(name: str, value) -> float:
    """A positive finite float."""
    number = _as_float(value)
    if not (math.isfinite(number) and number > 0):
        raise ValueError(f"{name} must be a positive finite number, got {name}={value!r}")
    return number


def check_int(name: str, value, minimum: int | None = None, maximum: int | None = None, *, allow_none=False):
    """An integer in ``[minimum, maximum]`` (bools refused), or None if allowed."""
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
        raise ValueError(f"{name} must be {valid}, got {name}={value!r}")
    return int(value)


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


def check_nu(nu) -> float:
    """The Student-t degrees of freedom: finite and > 2."""
    number = _as_float(nu)
    if not (math.isfinite(number) and number > 2):
        raise ValueError(
            f"nu must be a finite number > 2 (the covariance is infinite for nu <= 2), "
            f"got nu={nu!r}; for nu -> infinity use GaussianProcess"
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
