"""Reading three limits as a student writes them (exercise 1.4): a dict keyed 'lambda < 1', 'lambda = 1' and
'lambda > 1' (also 'λ<1', 'lam < 1' ...), a list of three in that order, or text such as 'inf, 1, 0'; each limit
exact ('about 1' and 0.99999999999999999999 are not 1).
"""

from __future__ import annotations

import math
import re
import unicodedata

import numpy as np

from .counts import arithmetic
from .parsing import (
    _CALL,
    _DOUBT,
    _HEDGED,
    _NUMPY_NUMBER,
    _NUMPY_PRINTED,
    _ONE_CALL,
    ALONE,
    Unreadable,
    _compact,
    _number,
    _text,
    alone,
    exactly,
)
from .sentences import number_spelled, said_in_words
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
    compact = compact.replace("\u2208", "in")  # 'λ ∈ (0, 1)'
    # 'lambda in (1, inf)', 'lambda in (0, 1)': not a bracket closed at 1 ('(0, 1]' holds lambda = 1 too)
    compact = re.sub(r"in\(1,(?:inf|infinity|oo|\u221e)[)\]]$", ">1", compact)
    compact = re.sub(r"in[(\[]0,1\)$", "<1", compact)
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
        text = _python_infinity(text)
        first = _DENIED_FIRST.fullmatch(text)
        if first:  # 'not 0, 1, inf, but inf, 1, 0': the other order denied first
            return _without_denial(first.group(2), first.group(1), read_limits, answer)
        ordered = _IN_ITS_ORDER.fullmatch(text)
        if ordered:  # '0, 1, inf for lambda > 1, = 1, < 1': each limit with its own side, in any order
            values = [part.strip() for part in re.split(r"[,;]|\band\b", ordered.group(1)) if part.strip()]
            sides = re.findall(r"[<=>]", ordered.group(2))
            if len(values) == 3 and sorted(sides) == ["<", "=", ">"]:
                answer, text = {f"lambda {side} 1": value for side, value in zip(sides, values)}, None
    if text is not None:
        text = _QUESTIONS_OWN.sub("", text)  # 'Gaussian: inf, 1, 0', 'inf, 1, 0 (lambda < 1, = 1, > 1)'
        printed = re.fullmatch(r"\s*\{(.*)\}\s*", text)
        if printed:  # "{'lambda < 1': inf, ...}": the dict as Python prints it
            text = re.sub(r"['\"]", "", printed.group(1))
        text = re.sub(r"^\s*as\s+x\s*(?:->|\u2192|goes\s+to|tends\s+to|grows)\s*(?:inf|infinity|\u221e)?\s*[:,]\s*|"
                      r"^\s*(?:the\s+)?limits(?:\s+are)?\s*:?\s*|\s*,?\s+respectively\s*\.?\s*$|"
                      r"\s*\(\s*(?:for\s+)?(?:the\s+)?gaussian(?:'s)?(?:\s+ratio)?\s*\)\s*$", "", text,
                      flags=re.I)  # 'The limits are', 'limits:', '(the Gaussian ratio)'
        text = re.sub(r"^\s*(?:np\.|numpy\.)?array\(\s*(\[[^\[\]]*\])\s*(?:,\s*dtype=\w+)?\)\s*$", r"\1",
                      text)  # numpy's printed form
        pairs = re.findall(rf"(?:^|[,;|\s])\s*(?:(?:for|when|if)\s+)?({_LAMBDA}\s*(?:<|=|>|<=|>=)\s*1)"
                           r"(?:\s*(?::|->|=>|\u2192|\u21d2|\u27f9)\s*|\s+)"
                           rf"([^,;|\n]+?)(?=\s*(?:[,;|\n]|$|\s{_LAMBDA}\s*[<=>]))",
                           text, flags=re.I)  # 'lambda < 1: inf', 'λ<1 ∞', 'for lambda<1 inf', 'λ < 1 ⇒ ∞', a line each
        pairs = pairs if len(pairs) == 3 else [(key, value) for value, key in re.findall(
            rf"(?:^|,|;)\s*([^,;]+?)\s+for\s+({_LAMBDA}\s*(?:<|=|>)\s*1)\s*(?=,|;|$)", text, flags=re.I)]
        if len(pairs) == 3:  # 'lambda < 1: inf, ...' as a dict written out; 'inf for lambda < 1, ...'
            answer = dict(pairs)
            text = None
        denied = None if text is None else _DENIAL.fullmatch(text)
        if denied:  # 'inf, 1, 0 (not 0, 1, inf)', 'inf, 1, 0, not 0, 1, inf': the other order denied
            return _without_denial(denied.group(1), denied.group(2) or denied.group(3), read_limits, answer)
        aside = None if text is None else re.fullmatch(r"\s*(.*?\S)\s*\(([^()]+)\)\s*\.?\s*", text)
        if aside:  # 'inf, 1, 0 (inf for lambda < 1)', 'inf, 1, 0 (the first is infinity)': one limit said again
            try:
                limits = read_limits(aside.group(1))
            except Unreadable:
                limits = None
            if limits is not None and _restates(aside.group(2), limits):
                return limits
        if text is not None and re.match(r"^\s*[\[(]\s*[\[(]", text):  # '[[inf, 1, 0]]'
            raise Unreadable(f"Could not read {shown(answer)} as three limits: its brackets do not make one list.")
        text = None if text is None else _NUMPY_NUMBER.sub(r"\1", text)  # 'np.float64(inf), np.float64(1.0), ...'
        if text is not None and _CALL.search(text):  # 'range(3)': a call, not the limits' values
            raise Unreadable(f"Could not read {shown(answer)} as three limits: it is a Python call; write the limits "
                             "themselves ('inf, 1, 0' is how three are written).")
    elif isinstance(answer, np.ndarray) and answer.ndim == 1 and len(answer) == 3:
        answer = list(answer)
    whole = None if text is None else re.fullmatch(r"\s*[\[(]([^\[\]()]*)[\])]\s*", text)
    if whole:  # '[inf, 1, 0]', '(inf, 1, 0)': a list or a tuple as Python prints it
        text = whole.group(1)
    if text is not None:  # 'math.inf', 'np.inf': infinity as Python spells it
        text = re.sub(r"\b(?:math|np|numpy)\.(inf|infty)\b", r"\1", text)
    if text is not None:  # 'inf | 1 | 0', 'inf\u30011\u30010', 'inf / 1 / 0', 'inf, 1 & 0', a limit a line
        text = re.sub(r"\s*(?:[|&\u3001\n]|\s[/\u00b7]\s)\s*", ", ", text.strip())
    items = [] if text is None else re.split(r"[,;]|\band\b", text)
    if len(items) == 3 and "(" in text and all(item.count("(") == item.count(")") for item in items):
        answer, text = [item.strip() for item in items], None  # 'inf (blows up), 1, 0': each limit with its aside
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
        limits[side] = _limit(value, f"the limit for lambda {side[0]} 1")
    missing = [f"lambda {side[0]} 1" for side in ("<1", "=1", ">1") if side not in limits]
    if missing:
        raise Unreadable(f"Your dict has no key for {' and '.join(missing)}.")
    return limits


#: three limits, then their sides in any order ('0, 1, inf for lambda > 1, = 1, < 1')
_IN_ITS_ORDER = re.compile(rf"\s*(.+?)\s+for\s+((?:{_LAMBDA}\s*)?[<=>]\s*1\s*(?:,\s*and|,|and)\s*(?:{_LAMBDA}\s*)?"
                           rf"[<=>]\s*1\s*(?:,\s*and|,|and)\s*(?:{_LAMBDA}\s*)?[<=>]\s*1)\s*\.?\s*", re.IGNORECASE)
#: the other answer denied first ('not 0, 1, inf, but inf, 1, 0'; one limit: 'not 0, inf')
_DENIED_FIRST = re.compile(r"\s*not\s+(.+?)\s*(?:[,;:]\s*but|;|:|\s+but)\s+(.+?)\s*\.?\s*", re.IGNORECASE)
_ONE_DENIED_FIRST = re.compile(r"\s*not\s+([^,;:]+?)\s*[,;:]\s*(?:but\s+)?(.+?)\s*\.?\s*", re.IGNORECASE)
_ORDINALS = {"first": "<1", "second": "=1", "third": ">1", "last": ">1"}


def _restates(aside: str, limits: dict) -> bool:
    """Whether ``aside`` says one of ``limits``, or all three, again: 'inf for lambda < 1', 'lambda = 1: 1', 'the
    first is infinity', 'infinity, one, zero'."""
    try:
        if read_limits(aside) == limits:
            return True
    except Unreadable:
        pass
    glossed = re.fullmatch(r"\s*([^=:]+?)\s*(?:=|:|\bmeans\b)\s*([^=:]+?)\s*", aside, flags=re.I)
    if glossed and not re.search(_LAMBDA, aside, flags=re.I):  # 'inf = blows up': a limit's value glossed
        try:
            value, gloss = (_limit(part, "a limit") for part in glossed.groups())
            if value == gloss and value in limits.values():
                return True
        except Unreadable:
            pass
    said = (re.fullmatch(rf"\s*(.+?)\s+for\s+({_LAMBDA}\s*[<=>]\s*1)\s*", aside, flags=re.I)
            or re.fullmatch(rf"\s*({_LAMBDA}\s*[<=>]\s*1)\s*(?::|=|->|\u2192)\s*(.+?)\s*", aside, flags=re.I))
    if said:
        value, key = said.groups() if "for" in said.group(0).lower().split() else said.groups()[::-1]
        side = _limit_key(key)
    else:
        ordinal = re.fullmatch(r"\s*the\s+(first|second|third|last)(?:\s+one)?\s+(?:is|=)\s+(.+?)\s*", aside,
                               flags=re.I)
        if not ordinal:
            return False
        side, value = _ORDINALS[ordinal.group(1).lower()], ordinal.group(2)
    try:
        return side is not None and _limit(value, "a limit") == limits[side]
    except Unreadable:
        return False


#: an answer, then the other answer denied: in brackets ('inf (not 0)') or after a comma ('inf, 1, 0, not 0, 1, inf')
_DENIAL = re.compile(r"\s*(.*?\S)\s*(?:\(\s*(?:but\s+)?not\s+([^()]+?)\s*\)|[,;]\s*(?:but\s+)?not\s+(.+?))\s*\.?\s*",
                     re.IGNORECASE)


def _without_denial(said: str, denied: str, read, answer, several: bool = False):
    """What ``said`` gives, where ``denied`` gives something else: emphasis ('inf (not 0)'); a denial of the answer
    itself, or one that cannot be read, leaves the answer unread.  ``several``: ``denied`` may name several values
    ('1 (not 0 or inf)')."""
    parts = re.split(r"\s*(?:,|\bor\b|\band\b|&|/)\s*", denied) if several else [denied]
    try:
        given, others = read(said), [read(part) for part in parts if part.strip()]
    except Unreadable:
        raise Unreadable(f"Could not read {shown(answer)} as the limits: {ALONE}.") from None
    if given in others or not others:
        raise Unreadable(f"Could not read {shown(answer)} as the limits: it denies its own answer.")
    return given


def _python_infinity(text: str) -> str:
    """``text`` with Python's spelling of infinity, float('inf'), as 'inf' (the question asks for math.inf)."""
    return re.sub(r"float\(\s*['\"](?:inf|infinity)['\"]\s*\)", "inf", text, flags=re.I)


def _limit(value, what: str) -> float:
    """One limit, exactly: a number, infinity, a working ('3 - 2'), or a word ('one'); said with an aside that
    only restates it ('1 (one)') or denies another value ('inf (not 0)')."""
    text = _text(value)
    if text is None:
        return _exact(value, _number(value, what), what)
    text = _NUMPY_PRINTED.sub(r"\1", _python_infinity(text))  # numpy's printed forms: 'np.float64(1.0)', 'array(1)'
    text = re.sub("[\u00bc-\u00be\u2150-\u215e]", lambda m: f"({unicodedata.numeric(m.group(0))!r})", text)  # '½ + ½'
    if _ONE_CALL.fullmatch(text):  # 'math.exp(0)': a call, not the limit's value
        raise Unreadable(f"Could not read {shown(value)} as {what}: it is a Python call; write the limit itself.")
    first = _ONE_DENIED_FIRST.fullmatch(text)  # 'not 0, inf'
    denied = _DENIAL.fullmatch(text)
    if first or denied:
        said, other = ((first.group(2), first.group(1)) if first
                       else (denied.group(1), denied.group(2) or denied.group(3)))
        return _without_denial(said, other, lambda v: _limit(v, what), value, several=True)
    restated = re.fullmatch(r"\s*([^()]+?)\s*\(\s*([^()]+?)\s*\)\s*", text)
    if restated:  # 'infinity (inf)', '1 (one)': the same value twice
        try:
            first, second = (_limit(part, what) for part in restated.groups())
        except Unreadable:
            first, second = 0.0, 1.0
        if first == second:
            return first
    worked = arithmetic(text.strip().rstrip("."))
    if worked is not None and worked >= 0:  # '3 - 2', '0.5*2': a working, by its value ('0 - 5': two numbers)
        return worked
    text = _SAID.sub("", alone(text, value, what))  # '0 (1 for small x)', '0, probably': not read
    text = said_in_words(number_spelled(text))  # 'zero point zero', 'infinty', 'zeor'
    text = re.sub(r"^\s*(?:math|np|numpy)\.(inf|infty)\s*$", r"\1", text)  # 'math.inf' as text
    verb = _GOES.get(re.sub(r"[^a-z]", "", text.lower()).removeprefix("it"))
    if verb is not None:  # 'blows up', 'it decays': where the ratio goes, said by its verb
        return verb
    return _exact(text, _number(text, what), what)


#: a limit said by its verb alone ('blows up', 'decays')
_GOES = {**dict.fromkeys(("blowsup", "explodes", "divergestoinfinity", "growswithoutbound", "shootsup",
                          "isunbounded", "unbounded"), math.inf),
         **dict.fromkeys(("decays", "vanishes", "diesout", "diesoff", "decaystozero", "vanishestozero", "nothing",
                          "disappears", "fadesaway", "fadesout"), 0.0),  # 'decays to nothing': _SAID drops the verb
         **dict.fromkeys(("unchanged", "stays", "staysthesame", "thesame", "same", "constant", "nochange",
                          "doesnotchange", "doesntchange", "remainsthesame", "staysput"), 1.0)}
