"""Reading three limits as a student writes them (exercise 1.4): a dict keyed 'lambda < 1', 'lambda = 1' and
'lambda > 1' (also 'λ<1', 'lam < 1' ...), a list of three in that order, or text such as 'inf, 1, 0'; each limit
exact ('about 1' and 0.99999999999999999999 are not 1).
"""

from __future__ import annotations

import math
import re

import numpy as np

from .parsing import _DOUBT, _HEDGED, ALONE, Unreadable, _compact, _number, _text, alone, exactly
from .sentences import _one_slip, said_in_words
from .wording import shown

__all__ = ["read_limits"]


def _exact(given, value: float, what: str) -> float:
    """``value`` where ``given`` is exactly it: a limit of 0 or 1 written as 0.99999999999999999999 (text, a
    Fraction, a Decimal) rounds to 1 as a float but is not 1, and 1e400 overflows to infinity but is not it; and a
    limit is not hedged ('about 1')."""
    text = _text(given)
    if text is not None and not math.isnan(value) and _HEDGED.search(text):  # a limit is an exact number
        raise Unreadable(f"Could not read {shown(given)} as {what}: a limit is exact, not about a value.")
    return exactly(given, value, what)


def _limit_key(key) -> str | None:
    """'lambda < 1', 'λ<1', 'lam < 1', '< 1' ... as '<1'; None for anything else."""
    text = _text(key)
    if text is None:
        return None
    compact = re.sub(r"^0<(?=lambda|lam|l)", "", _compact(text))  # '0 < lambda < 1': the question's own range
    compact = re.sub(r"in[(\[]1,(?:inf|infinity|oo)[)\]]$", ">1", compact)  # 'lambda in (1, inf)'
    compact = re.sub(r"in[(\[]0,1[)\]]$", "<1", compact)  # 'lambda in (0, 1)'
    for name in ("lambda", "lam", "l"):
        if compact.startswith(name):
            compact = compact[len(name):]
            break
    compact = re.sub(r"(?<=[<=>])1\.0*$", "1", compact)  # 'lambda < 1.0'
    compact = _SIDE_WORDS.get(re.sub(r"(?:1(?:\.0*)?|one)$", "", compact), compact)  # 'lambda smaller than 1'
    return compact if compact in ("<1", "=1", ">1") else None


#: a key's comparison said in words ('lambda smaller than 1', 'lambda equal to 1', 'lambda above one')
_SIDE_WORDS = {**dict.fromkeys(("<", "lessthan", "smallerthan", "below", "under", "islessthan", "issmallerthan",
                                "isbelow"), "<1"),
               **dict.fromkeys(("=", "equalto", "equals", "is", "isequalto", "exactly"), "=1"),
               **dict.fromkeys((">", "greaterthan", "largerthan", "biggerthan", "morethan", "above", "over",
                                "isgreaterthan", "isabove"), ">1")}


#: a limit said as a sentence ('it goes to infinity', 'it stays at 1', 'exactly 1', 'tends to 0'): the value read
_SAID = re.compile(r"^\s*(?:(?:it|the\s+ratio|the\s+limit)\s+)?(?:(?:goes|tends|converges|approaches|heads|"
                   r"blows\s+up|shoots\s+up|grows|diverges|falls|drops|decays|stays|remains|is|equals|becomes)"
                   r"(?:\s+(?:to|at|towards?))?\s+)?(?:exactly\s+)?(?=\S)", re.IGNORECASE)


#: the question's own words around three limits: the Gaussian's ratio, x growing, the order of the three sides
_LAMBDA = r"(?:lambda|\u03bb|lam)"
_THREE_SIDES = (rf"{_LAMBDA}\s*<\s*1\s*,\s*(?:{_LAMBDA}\s*)?=\s*1\s*,?\s*(?:and\s+)?(?:{_LAMBDA}\s*)?>\s*1")
_QUESTIONS_OWN = re.compile(
    r"^\s*(?:the\s+)?gaussian(?:'s)?(?:\s+ratio)?\s*:\s*|\s+for\s+the\s+gaussian(?:'s)?(?:\s+ratio)?\s*$|"
    rf"\s+for\s+{_THREE_SIDES}\s*$|^\s*for\s+{_THREE_SIDES}\s*:\s*|"
    r"\s+as\s+x\s*(?:->|\u2192|goes\s+to|tends\s+to|grows)\s*(?:inf|infinity|\u221e)?\s*$|"
    rf"\s*\(\s*{_THREE_SIDES}\s*\)\s*$", re.IGNORECASE)


def read_limits(answer) -> dict:
    """A dict of the three limits, keyed '<1', '=1', '>1' (floats, inf allowed); raises :class:`Unreadable`.

    Three limits in the question's order (lambda < 1, = 1, > 1) are read too: a list, a tuple or text such as
    'inf, 1, 0'."""
    text = _text(answer)
    if text is not None and _DOUBT.search(text):
        raise Unreadable(f"Could not read {shown(answer)} as a dict of three limits: it doubts its own answer.")
    if text is not None:  # Python's spellings of infinity, a closing 'respectively', a preface ('The limits are')
        text = re.sub(r"float\(\s*['\"](?:inf|infinity)['\"]\s*\)", "inf", text, flags=re.I)
        text = _QUESTIONS_OWN.sub("", text)  # 'Gaussian: inf, 1, 0', 'inf, 1, 0 (lambda < 1, = 1, > 1)'
        printed = re.fullmatch(r"\s*\{(.*)\}\s*", text)
        if printed:  # "{'lambda < 1': inf, ...}": the dict as Python prints it
            text = re.sub(r"['\"]", "", printed.group(1))
        text = re.sub(r"^\s*(?:the\s+)?limits\s+are\s*:?\s*|\s*,?\s+respectively\s*\.?\s*$", "", text, flags=re.I)
        text = re.sub(r"^\s*(?:np\.|numpy\.)?array\(\s*(\[[^\[\]]*\])\s*(?:,\s*dtype=\w+)?\)\s*$", r"\1",
                      text)  # numpy's printed form
        pairs = re.findall(rf"(?:^|,|;)\s*({_LAMBDA}\s*(?:<|=|>|<=|>=)\s*1)(?:\s*(?::|->|=>|\u2192)\s*|\s+)([^,;]+)",
                           text, flags=re.I)  # 'lambda < 1: inf', 'λ<1 ∞'
        pairs = pairs if len(pairs) == 3 else [(key, value) for value, key in re.findall(
            rf"(?:^|,|;)\s*([^,;]+?)\s+for\s+({_LAMBDA}\s*(?:<|=|>)\s*1)\s*(?=,|;|$)", text, flags=re.I)]
        if len(pairs) == 3:  # 'lambda < 1: inf, ...' as a dict written out; 'inf for lambda < 1, ...'
            answer = dict(pairs)
            text = None
    elif isinstance(answer, np.ndarray) and answer.ndim == 1 and len(answer) == 3:
        answer = list(answer)
    whole = None if text is None else re.fullmatch(r"\s*[\[(]([^\[\]()]*)[\])]\s*", text)
    if whole:  # '[inf, 1, 0]', '(inf, 1, 0)': a list or a tuple as Python prints it
        text = whole.group(1)
    if text is not None:  # 'math.inf', 'np.inf': infinity as Python spells it
        text = re.sub(r"\b(?:math|np|numpy)\.(inf|infty)\b", r"\1", text)
    if text is not None and re.search(r"[()]|\bbecause\b", text):
        raise Unreadable(f"Could not read {shown(answer)} as a dict of three limits: {ALONE}.")
    parts = [] if text is None else [part.strip() for part in re.split(r"[,;]|\band\b", text) if part.strip()]
    if len(parts) == 1 and len(parts[0].split()) == 3:  # 'inf 1 0': three limits apart, none a number of two
        parts = parts[0].split()
    if len(parts) == 3:  # 'inf, 1, 0', 'inf, 1 and 0'
        answer = parts
    if isinstance(answer, (list, tuple)) and len(answer) == 3:
        answer = dict(zip(("lambda < 1", "lambda = 1", "lambda > 1"), answer))
    if not isinstance(answer, dict):
        raise Unreadable(f"Could not read {shown(answer)} as a dict of three limits.")
    limits = {}
    for key, value in answer.items():
        side = _limit_key(key)
        if side is None:
            raise Unreadable(f"Could not read the key {shown(key)} as one of lambda < 1, lambda = 1, lambda > 1.")
        if side in limits:
            raise Unreadable(f"The key {shown(key)} names lambda {side[0]} 1 a second time.")
        what = f"the limit for lambda {side[0]} 1"
        if _text(value) is not None:
            value = _SAID.sub("", alone(_text(value), value, what))  # '0 (1 for small x)', '0, probably': not read
            value = "infinity" if _one_slip(value.strip().lower(), "infinity") else value  # 'infinty'
            value = said_in_words(value)  # 'zero point zero'
            value = re.sub(r"^\s*(?:math|np|numpy)\.(inf|infty)\s*$", r"\1", value)  # 'math.inf' as text
        limits[side] = _exact(value, _number(value, what), what)
    missing = [f"lambda {side[0]} 1" for side in ("<1", "=1", ">1") if side not in limits]
    if missing:
        raise Unreadable(f"Your dict has no key for {' and '.join(missing)}.")
    return limits
