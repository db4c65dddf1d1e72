"""Saying values, inputs and results in words, for the replies of the checks.

Small values are said in full, so that a student can redo a case by hand;
larger arrays by their shape; anything else by a short description, never a
traceback or a page of digits.
"""

from __future__ import annotations

import numpy as np

__all__ = ["SMALL", "describe", "said", "several", "parts", "shape_problem", "shown", "which_differ"]

#: inputs and results with at most this many numbers are said in full, so a student can redo the case by hand
SMALL = 8
#: a value's repr longer than this is shortened
_LONGEST = 40
#: the longest answer in words quoted whole
_LONGEST_TEXT = 80


def shown(value) -> str:
    """Any value in a few words: its repr when short ('fifty', 3.5), else what it is ('an int of 401 digits')."""
    if isinstance(value, int) and not isinstance(value, bool) and abs(value) >= 10**_LONGEST:
        return f"an int of {len(str(abs(value)))} digits"
    try:
        text = repr(value)
    except Exception:  # a student's object may fail to print itself
        text = ""
    if text and len(text) <= _LONGEST and "\n" not in text:
        return text
    if isinstance(value, str):  # a student's words are shown, the start of them where they run long
        line = " ".join(value.split())
        if len(line) <= _LONGEST_TEXT:
            return repr(line)
        return f"{line[:_LONGEST_TEXT - 20]!r}... ({len(value)} characters)"
    if isinstance(value, np.ndarray):
        return f"an array of shape {value.shape}"
    return f"a {type(value).__name__}"


def several(value) -> bool:
    """Whether a reference result is several results (a tuple), not one array."""
    return isinstance(value, tuple)


def parts(value, many: bool) -> list:
    """A result as a list of arrays: several parts where the reference returns a tuple, else one array.

    A part that numpy cannot read as an array (ragged lists, say) becomes an array of one object.

    Parameters
    ----------
    value : object
        The result.
    many : bool
        Split a tuple or list into its parts (:func:`several` of the reference).
    """
    values = list(value) if many and isinstance(value, (tuple, list)) else [value]
    return [_array(v) for v in values]


def _array(value) -> np.ndarray:
    """One part as an array: numbers held as objects (sympy's Floats, say) as floats; else an array of one object."""
    try:
        array = np.asarray(value)
    except Exception:  # ragged lists, or a student's object that fails to convert itself
        array = None
    if array is not None and array.dtype == object and array.size:
        items = array.ravel().tolist()
        if not any(item is None or isinstance(item, (str, bytes)) for item in items):
            try:
                return np.array([float(item) for item in items]).reshape(array.shape)
            except Exception:  # not numbers: said as such
                pass
    if array is None:
        array = np.empty((), dtype=object)
        array[()] = value
    return array


def said(value) -> str | None:
    """A value in words: small ones in full ('[0.2, 0.5]', 'True', '3.5'), else None."""
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, (int, np.integer)):
        return str(value) if abs(int(value)) < 10**15 else None
    if isinstance(value, (float, np.floating)):
        short = f"{float(value):.6g}"
        if float(short) != float(value) and len(short.lstrip("-").replace(".", "").strip("0")) <= 3:
            longer = f"{float(value):.10g}"  # a hair from a round number (1 - 1e-7) is not shown as the round one
            return longer if float(longer) == float(value) or longer != short else repr(float(value))
        return short
    if isinstance(value, dict):
        items = [(key, said(item)) for key, item in value.items()]
        return "{" + ", ".join(f"{key}: {text}" for key, text in items) + "}" if all(t for _, t in items) else None
    if isinstance(value, tuple):
        items = [said(item) for item in value]
        return "(" + ", ".join(items) + ")" if items and all(items) else None
    try:
        array = np.asarray(value)
    except Exception:  # a student's object may fail to convert itself
        return None
    if array.dtype.kind in "biuf" and array.ndim == 1 and array.size <= SMALL:
        items = [said(item.item()) for item in array]
        return "[" + ", ".join(items) + "]" if all(items) else None
    return None


def describe(case: dict) -> str:
    """An input in words: small values in full, larger arrays by their shape ('X of shape (7, 2), nu = 3.5')."""
    out = []
    for name, value in case.items():
        text = said(value)
        if text is not None:
            out.append(f"{name} = {text}")
        elif isinstance(value, np.ndarray):
            out.append(f"{name} of shape {value.shape}")
    return ", ".join(out)


def shape_problem(got, expected) -> str | None:
    """A sentence about a result of the wrong structure or shape, or None.

    Parameters
    ----------
    got : object
        The student's result.
    expected : object
        The reference result; a tuple is several results.
    """
    got_parts, expected_parts = parts(got, several(expected)), parts(expected, several(expected))
    if len(expected_parts) > 1 and len(got_parts) != len(expected_parts):
        if isinstance(got, np.ndarray) and got.ndim and len(got) == len(expected_parts):
            return (f"it should return {len(expected_parts)} things (a tuple), but returns one array of shape "
                    f"{got.shape}: return them as a tuple, not stacked into one array.")
        return f"it should return {len(expected_parts)} things (a tuple), but returns {len(got_parts)}."
    for i, (g, e) in enumerate(zip(got_parts, expected_parts)):
        if g.shape != e.shape:
            which = f"its result number {i + 1}" if len(expected_parts) > 1 else "its result"
            if e.ndim == 0:
                return f"{which} should be a single number, but has shape {g.shape}."
            return f"{which} has shape {g.shape} where {e.shape} is expected."
    return None


def which_differ(got, expected, same) -> str:
    """'it gives other values than the package', naming which results differ where there are several.

    Parameters
    ----------
    got : object
        The student's result.
    expected : object
        The reference result; a tuple is several results.
    same : callable
        ``same(got_part, expected_part) -> bool``, as :func:`~sarsp_edu.teaching.exercises.grading.same`.
    """
    if not several(expected):
        return "it gives other values than the package"
    pairs = list(zip(parts(got, True), parts(expected, True)))
    wrong = [i + 1 for i, (g, e) in enumerate(pairs) if not same(g, e)]
    if len(wrong) == len(pairs):
        return ("both of its results differ" if len(pairs) == 2 else f"all {len(pairs)} of its results differ") + \
            " from the package's"
    named = " and ".join(f"number {i}" for i in wrong)
    verb = "differs" if len(wrong) == 1 else "differ"
    rest = "the other is right" if len(pairs) - len(wrong) == 1 else "the others are right"
    return f"its result {named} (of {len(pairs)}) {verb} from the package's; {rest}"
