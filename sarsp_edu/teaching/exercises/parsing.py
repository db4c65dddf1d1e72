"""Reading a short answer as a student would write it.

A prediction may be written in many ways: ``"Narrower."``, ``"smaller"``,
``"<"``, ``"below 1"``, ``50``, ``"50"``, ``np.int64(50)``, a dict keyed
``"λ < 1"`` or ``"lambda<1"`` with ``"infinity"`` as a value.  Each reader
returns the answer in one canonical form, or raises :class:`Unreadable`
saying what it could not read; the check then lists the accepted forms
instead of a hint meant for a wrong idea.

Examples
--------
>>> read_word("Above 1.", {"above": ABOVE, "below": BELOW})
'above'
>>> read_word("it has grown narrower", {"wider": WIDER, "narrower": NARROWER})
'narrower'
>>> read_word("it rose below 1", {"above": ABOVE, "below": BELOW})  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
sarsp_edu.teaching.exercises.parsing.Unreadable: Could not read 'it rose below 1' as 'above' or 'below'.
"""

from __future__ import annotations

import math
import re
from decimal import Decimal
from fractions import Fraction

import numpy as np

from .sentences import parse, spelled
from .wording import shown

__all__ = ["ABOVE", "BELOW", "NARROWER", "Unreadable", "WIDER", "alone", "exactly", "read_word"]


class Unreadable(ValueError):
    """An answer that cannot be read as any of the accepted forms; its message says what was not read."""


def _compact(text: str) -> str:
    """Lower case, spaces, quotes and a final full stop dropped, symbols spelt one way ('λ ≤ 1' -> 'lambda<=1')."""
    text = text.strip().lower()
    for symbol, spelt in (("λ", "lambda"), ("≤", "<="), ("≥", ">="), ("∞", "inf"), ("==", "=")):
        text = text.replace(symbol, spelt)
    text = re.sub(r"[\s\"'`\u2018\u2019\u201c\u201d]+", "", text)  # curly quotes too, as a notebook's text has them
    return re.sub(r"[.!]+$", "", text)


def _words(*spellings: str) -> frozenset:
    return frozenset(_compact(s) for s in spellings)


def _compared(words, *others: str) -> frozenset:
    """Each word alone and compared with 1, as a student spells it ('below', 'below 1.0', 'less than one' ...)."""
    ones = [f"{than}{one}" for than in ("", "than ", "then ") for one in ("1", "1.0", "one", "unity")]  # 'then': a typo
    return _words(*others, *words, *(f"{word} {one}" for word in words for one in ones))


#: the spellings of each side, for the predictions that ask 'above' or 'below' 1, 'wider' or 'narrower'
#: a direction said as a change ('it goes down', 'decreases', 'less than before'): each the same side
_UP = ("goes up", "increases", "increased", "grows", "rises", "more than before", "larger than before",
       "bigger than before", "higher than before", "up", "exceeds", "climbs", "climb", "past", "beyond", "grow",
       "increase", "rise", "go up", "grew", "rose", "went up", "climbed")
_DOWN = ("goes down", "decreases", "decreased", "reduced", "reduces", "shrinks", "falls", "drops", "less than before",
         "smaller than before", "lower than before", "down", "shrink", "decrease", "fall", "drop", "go down",
         "shrank", "shrunk", "fell", "dropped", "went down")


def _bands(*words):
    """Each comparative alone, of the band, and against before or nu = 3 ('smaller band', 'narrower than at nu = 3')."""
    return (*words, *(f"{word} {tail}" for word in words for tail in ("band", "than before", "than at nu = 3",
                                                                       "than at nu=3", "than with nu = 3")))
ABOVE = _compared(("above", "over", "greater", "larger", "bigger", "higher", "more"), ">", "> 1", "> 1.0", "> one",
                  "factor > 1",
                  "1 < factor", "beta > n", *_UP)
BELOW = _compared(("below", "under", "beneath", "less", "smaller", "lower", "fewer"), "<", "< 1", "< 1.0", "< one",
                  "sub-1", "sub 1", "sub-one",
                  "factor < 1", "1 > factor", "between 0 and 1", "between zero and one",
                  "beta < n",
                  *_DOWN)
WIDER = _words(*_bands("wider", "broader", "larger", "bigger", "higher"), "wide", "widens", "widened", "broadens",
               "broadened", "more", ">", "more wide", "more broad", "less narrow", "not as narrow", "less tight",
               "getting wider", "getting broader", "wider and wider",
               *_UP)
NARROWER = _words(*_bands("narrower", "tighter", "thinner", "slimmer", "skinnier", "smaller", "lower"), "narrow",
                  "narrows", "narrowed", "tightens", "tightened", "less", "<", "more narrow", "less wide",
                  "not as wide", "less broad", "not as broad", "getting narrower", "getting tighter",
                  "narrower and narrower", *_DOWN)  # not 'beta > n': why the band narrows, not the prediction
#: numbers written as words, as a student may ('one', 'zero', 'fifty', 'forty-two')
_UNITS = ("zero one two three four five six seven eight nine ten eleven twelve thirteen fourteen fifteen sixteen "
          "seventeen eighteen nineteen").split()
_TENS = dict(zip("twenty thirty forty fifty sixty seventy eighty ninety".split(), range(20, 100, 10)))


def _number_word(compact: str) -> float | None:
    """A whole number from 0 to 100 written in words ('fifty', 'fortytwo' once compacted), else None."""
    compact = compact.replace("-", "")
    if compact in _UNITS:
        return float(_UNITS.index(compact))
    if compact in ("nought", "naught"):  # 0 as British English says it
        return 0.0
    if compact in ("onehundred", "ahundred", "hundred"):
        return 100.0
    for word, tens in _TENS.items():
        if compact == word:
            return float(tens)
        if compact.startswith(word) and compact[len(word):] in _UNITS[1:10]:
            return float(tens + _UNITS.index(compact[len(word):]))
    return None


def _text(answer) -> str | None:
    """``answer`` as text when it is one (a str, numpy's str, bytes), else None: full-width characters as ASCII, a
    lead-in (:data:`_LEAD_IN`) and the sentence's end (spaces, full stops, '!') dropped, but an ellipsis."""
    if isinstance(answer, bytes):
        try:
            answer = answer.decode()
        except UnicodeDecodeError:
            return None
    if isinstance(answer, np.ndarray) and answer.ndim == 0 and answer.dtype.kind in "US":
        answer = answer.item()
    if not isinstance(answer, str):
        return None
    # full-width forms (U+FF01 to U+FF5E: letters, digits and '<' as an East Asian keyboard types them) as ASCII
    text = answer.translate(_FULL_WIDTH)
    for _ in range(2):  # 'Answer: my prediction is ...': one lead-in after another
        text = _LEAD_IN.sub("", text, count=1)
    if re.search(r"(?:\.\.|\u2026)[\s.!]*$", text):  # an ellipsis: a sentence left open, read as it is
        return text.rstrip()
    # 'Below!', '0, 1, 2 (not 3)!', 'array(50).', an ideographic stop, '50 is my answer'
    return re.sub(r"(?:\s+is\s+(?:my|our)\s+(?:answer|prediction))?[\s.!\u3002]*$", "", text, flags=re.I)


_FULL_WIDTH = {code: code - 0xFEE0 for code in range(0xFF01, 0xFF5F)}


def read_word(answer, options: dict, tails=None) -> str:
    """The option (a key of ``options``) whose spellings include ``answer``; raises :class:`Unreadable`.

    A prediction is read alone: an answer that doubts itself ('narrower, probably'), or says more than the
    prediction (a reason, a condition, an aside: 'narrower, because ...', 'narrower when nu = 3'), is not read,
    and its reply asks for the prediction alone (the reason belongs in the written answer, which no check
    grades).  Reading reasons word by word accepted wrong predictions and refused right ones.

    Parameters
    ----------
    answer : object
        The student's answer; only text (str, numpy's str, bytes) can be read.
    options : dict
        ``{option: spellings}``, the spellings a set of compacted forms such as :data:`ABOVE`.
    tails : tuple of str, optional
        Patterns of endings that leave the prediction as it is, dropped; default: exercise 2.6's (the
        question's own nu = 30 and its own change of nu, 'than before', 'towards the GP').
    """
    names = " or ".join(repr(option) for option in options)
    own_thirty = tails is None  # exercise 2.6's: its own nu = 30 may be said first ('At nu = 30 the band is narrower')
    tails = _TAILS if tails is None else tails
    text = _text(answer)
    if text is not None:
        text = spelled(text)  # 'beloww', 'narower': one slip from one direction word
        if own_thirty:
            text = re.sub(r"^\s*(?:(?:at|with)\s+)?(?:nu|\u03bd)\s*=\s*30\s*[,:]?\s*", "", text, count=1, flags=re.I)
        text = re.sub(r"^\s*not\s+([^,;]+?)\s*[,;]\s*(?:but\s+)?([^,;]+)$", r"\2, not \1", text,
                      flags=re.I)  # 'not wider, narrower': the other option denied first
        try:
            text = alone(text, answer, names)
        except Unreadable as refused:
            text = _restated(text, answer, refused, options, tails)
        found = _read_clause(text, options, tails)
        if found is not None:
            return found
        if _DENIES.search(text):  # 'not above', "it won't exceed 1": the other side, or 1 itself
            raise Unreadable(f"Could not read {shown(answer)} as {names}: it says what the answer is not; write "
                             "what it is.")
    raise Unreadable(f"Could not read {shown(answer)} as {names}.")


#: a prediction said by what it is not ('not above', 'no longer wider', "can't be above 1", 'anything but above')
_DENIES = re.compile(r"\b(?:not|never|no\s+longer|anything\s+but)\b|n't\b", re.IGNORECASE)


def _restated(text: str, answer, refused: Unreadable, options: dict, tails) -> str:
    """The first clause of an answer whose asides only deny the other options ('narrower, not wider'); an answer
    whose clauses name two options is refused as naming both ('above, below'); any other is ``refused``."""
    if ALONE not in str(refused):
        raise refused
    first, asides = _clauses(text.strip().rstrip(".!"))
    main = _read_clause(first, options, tails)
    for aside in asides:
        denied = re.fullmatch(r"(?:and\s+|but\s+)?not\s+(.+)", aside.strip(), flags=re.I)
        said = _read_clause(denied.group(1) if denied else aside, options, tails)
        if said is not None and main is not None and (said == main) == bool(denied):
            raise Unreadable(f"Could not read {shown(answer)} as {' or '.join(map(repr, options))}: it names "
                             "both.") from None
        if not denied or said is None:
            raise refused
    return first


#: a word that negates what follows it, or a doubt: an aside holding one is not read past
_NEGATION = re.compile(r"(^|[^a-z])(not|no|never|hardly|or|maybe|perhaps)([^a-z]|$)|n't|\?")
#: a doubt or a hedge anywhere in an answer: it is not read
_DOUBT = re.compile(r"(^|[^a-z])(or|maybe|perhaps|unsure|guess|probably|possibly|likely|think|believe|suppose|"
                    r"not sure|not certain|uncertain|don'?t know|no idea|reckon)([^a-z]|$)|\?", re.IGNORECASE)
#: an approximate value, said as one ('about 1', '~1', 'roughly infinity'): a limit and a count are exact
_HEDGED = re.compile(r"\b(?:about|around|roughly|approximately|approx|nearly|almost|close\s+to|rounded|estimated?)\b|"
                     r"[~\u2248]", re.IGNORECASE)
_LEAD = (r"(?:(?:my|our|the|final)\s+)*(?:prediction|answer)\s*(?::|=|->|\u2192|\s[-\u2013\u2014]|(?:is|would\s+be|"
         r"will\s+be)\b\s*:?)(?:\s*that\s+(?:it|they)\s+(?:is|are|will\s+be|would\s+be)\b)?|"
         r"(?:a|ans|final|result|predicted|my\s+pick)\s*:|(?:so|hence|thus|therefore)\b\s*,?|"
         r"(?:i|we)(?:\s+would|\s+will|'d|\u2019d|'ll|\u2019ll|'m|\u2019m|\s+am)?\s+(?:predict(?:ed|ing)?|expect(?:ed|ing)?|"
         r"say(?:ing)?|answer(?:ed|ing)?|choose|go\s+with|going\s+with|pick)\b(?:\s+that)?"
         r"(?:\s+(?:it|they)\s+(?:is|are|will\s+be|would\s+be)\b)?\s*:?|they\s+are\b\s*:?|"
         r"(?:the\s+)?(?:largest|maximum|max|greatest)(?:\s+(?:possible\s+)?(?:number|count))?(?:\s+of\s+(?:unsafe\s+)?"
         r"(?:cells|states|squares))?\s*(?:is\b|:|=)|(?:the\s+)?(?:tp(?:'?s)?\s+)?band\s+(?:is|gets|becomes|will\s+be)\b\s*:?|"
         r"(?:the\s+)?(?:tp(?:'?s)?\s+)?(?:fitted\s+)?(?:variance\s+)?factor\s+(?:is|will\s+be|gets|becomes)\b\s*:?|"
         r"(?:the\s+)?safe\s+(?:actions|set)\s*(?:(?:are|is)\b\s*:?|:|=>|->|\u2192|=)")
#: what a student may write before the prediction, dropped ('My prediction: narrower', 'I predict below', 'A: 50')
_LEAD_IN = re.compile(rf"^\s*(?:{_LEAD})\s*", re.IGNORECASE)
#: a Python call anywhere in an answer ('range(50)'), and an answer that is one call ('math.exp(0)')
_CALL = re.compile(r"\b[A-Za-z_][\w.]*\(")
_ONE_CALL = re.compile(r"\s*[A-Za-z_][\w.]*\(.*\)\s*")
#: a number as numpy prints it ('np.int64(50)', 'array(50)'), not a call, its value group 1; an answer that is one
_NUMPY_NUMBER = re.compile(r"\b(?:(?:np|numpy)\.(?:u?int|float)\d*|array)\(\s*([^()]+?)\s*\)")
_NUMPY_PRINTED = re.compile(rf"^\s*{_NUMPY_NUMBER.pattern}\s*$")
#: the reply to an answer that says more than its prediction
ALONE = ("write the prediction alone, as the question asks; anything more (a reason, another condition, an aside) "
         "belongs in the written answer below, which no check grades")


def _is_arithmetic(text: str) -> bool:
    """Whether ``text`` is one sum, difference, product or quotient of numbers ('(10*10)/2'; not '50 (100 / 2)')."""
    import ast

    if not re.fullmatch(r"[\d\s()*x\u00d7/.]+", text, flags=re.I) or not re.search(r"[*x\u00d7/]", text, flags=re.I):
        return False  # a product or a quotient: '0 - 5' is two numbers, not a working
    try:
        tree = ast.parse(re.sub(r"[x\u00d7]", "*", text, flags=re.I).strip(), mode="eval")
    except SyntaxError:
        return False
    return all(isinstance(node, (ast.Expression, ast.BinOp, ast.Constant, ast.operator, ast.UnaryOp, ast.unaryop))
               for node in ast.walk(tree))


def alone(text: str, answer, what: str) -> str:
    """``text``, its preface dropped, if it is a prediction alone; else :class:`Unreadable` saying why (a doubt,
    or more than the prediction: a reason, a condition, an aside).

    Parameters
    ----------
    text : str
        The answer as text.
    answer : object
        The answer as given (quoted in the reply).
    what : str
        What the answer is read as, for the reply ('a whole number', "'wider' or 'narrower'").
    """
    if _DOUBT.search(text):
        raise Unreadable(f"Could not read {shown(answer)} as {what}: it doubts its own answer.")
    text = re.sub(r"\s*[.!\u2026;:,]+\s*$|\s+[-\u2013\u2014]\s*$", "",  # 'Narrower.', 'below,', 'Narrower - '
                  _LEAD_IN.sub("", text.replace("\u2019", "'"), count=1).strip()).strip()
    whole = re.fullmatch(r"\(([^()]*)\)", text)  # '(0.4)', '(50)': the value in brackets
    if whole:
        text = whole.group(1).strip()
    sides = text.split("=")
    plain = r"\s*\d+(?:\.\d+)?\s*|\s*[a-z]+(?:-[a-z]+)?\s*"  # a number, in digits or a word
    if all(_is_arithmetic(side.strip()) or re.fullmatch(plain, side, flags=re.I) for side in sides) and any(
            _is_arithmetic(side.strip()) for side in sides):
        return text  # a working in brackets, '(10*10)/2', '50 = (10*10)/2': no aside
    if _clauses(text)[1]:
        raise Unreadable(f"Could not read {shown(answer)} as {what}: {ALONE}.")
    return text


def _clauses(text: str) -> tuple:
    """The answer's first clause, and its asides: what stands in brackets, and each clause after a colon, a
    semicolon, a comma or a dash ('Narrower: the factor falls' -> 'Narrower', ['the factor falls'])."""
    asides = re.findall(r"\(([^()]*)\)", text)
    bare = re.sub(r"\s*\([^()]*\)\s*", " ", text).strip()
    bare = re.sub(r"(?<=[A-Za-z0-9])\.\s+(?=[A-Z])", "; ", bare)  # 'Below. Without outliers ...': a second sentence
    # not '1,000'; 'below 1 because ...': the reason is an aside too
    first, *others = re.split(r"\s*(?:[:;\u2013\u2014]|,(?!\d))\s*|\s+-\s+|\s+(?:because|since)\s+", bare)
    return first.strip(), [*asides, *(clause for clause in others if clause.strip())]


#: what a student may add after the prediction without changing it, dropped: a comparison with before or with
#: nu = 3, the question's own nu = 30 and its own change ('as nu grows'), where the band heads ('towards the GP's
#: band'); any other condition ('when nu = 3', 'as nu decreases') leaves the answer unread
_TAILS = (r"\s+than\s+(before|((at|with|for)\s+)?((the\s+)?(band|one|tp('s\s+band)?)\s+(at|with|for)\s+)?(nu|\u03bd)"
          r"\s*=\s*3(?![\d.])|(at|with|for)\s+3(?![\d.]))\s*$",
          r"\s+(as|when|while)\s+(nu|\u03bd)\s+(goes|grows|increases|rises|moves)\s+from\s+3\s+to\s+30(?![\d.])\s*$",
          r"\s*,?\s+(at\s+|with\s+)?((nu|\u03bd)\s*=\s*)?30\s+(vs\.?|versus|against|compared\s+(with|to)|instead\s+of)"
          r"\s+(at\s+)?((nu|\u03bd)\s*=\s*)?3(?![\d.])\s*$",
          r"\s+(with|for|using)\s+(section\s+2'?s\s+)?(the\s+)?(fixed\s+)?(hyperparameters|tp)\s*$",
          r"\s+than\s+(the\s+)?(nu|\u03bd)\s*=\s*3(?![\d.])\s+(band|one)\s*$",
          r"\s+at\s+((nu|\u03bd)\s*=\s*)?30\s+than\s+at\s+((nu|\u03bd)\s*=\s*)?3(?![\d.])\s*$",
          r"\s+(at|for|with|when|if)\s+(nu|\u03bd)\s*(=|is|of)\s*30(?![\d.])\s*$",
          r"\s+(as|when|while|if|once)\s+(nu|\u03bd)\s+(grows|increases|rises|goes\s+up|gets\s+(larger|bigger))\s*$",
          r"\s+towards?\s+(the\s+)?(gp|gaussian)('s)?(\s+(band|process|one))?\s*$",
          r"\s+(for|with)\s+(larger|bigger|higher)\s+(nu|\u03bd)\s*$", r"\s+at\s+(nu\s*=\s*)?30(\.0+)?\s*$")
def _read_clause(text: str, options: dict, tails=_TAILS) -> str | None:
    """The option one clause names, read as a sentence (:func:`.sentences.parse`; ``tails`` dropped), or None:
    none or two options named, or a verb that moves against its complement ('it rose below 1')."""
    for _ in range(3):  # 'narrower as nu grows towards the GP': one ending after another
        for tail in tails:
            text = re.sub(tail, "", text, flags=re.IGNORECASE)
    ways = {way: next((option for option, spellings in options.items() if _compact(spelt) in spellings), None)
            for way, spelt in (("up", "goes up"), ("down", "goes down"), ("narrows", "narrows"), ("widens", "widens"))}
    named, against = set(), False
    for way, complement in parse(text):
        option = ways[way] if not complement else next(
            (option for option, spellings in options.items() if _compact(complement) in spellings), None)
        if option is None:
            continue
        if way is not None and option != ways[way]:
            against = True
        else:
            named.add(option)
    return named.pop() if len(named) == 1 and not against else None


def _number(answer, what: str, single: bool = False) -> float:
    """A finite or infinite real number from any numeric type or text; raises :class:`Unreadable`."""
    if isinstance(answer, (bool, np.bool_)) or answer is None:
        raise Unreadable(f"Could not read {shown(answer)} as {what}.")
    text = _text(answer)
    if text is not None:
        if re.search(r"\d\s+\d", text):  # '5 0' is two numbers, not 50
            raise Unreadable(f"Could not read {shown(answer)} as {what}.")
        leading_zero(text, answer, what)
        main, asides = _clauses(text)
        if _NEGATION.search(" ".join(asides).lower()):  # '50 (or 25)', '50 (not 50)': refused
            raise Unreadable(f"Could not read {shown(answer)} as {what}.")
        numbered = [clause for clause in (main, *asides) if re.search(r"\d", clause) or _number_word(
            _compact(clause)) is not None]
        # '50 (a checkerboard)', '50, half the grid': the first clause; 'half the grid: 50': the one with a number
        text = main if re.search(r"\d", main) or _number_word(_compact(main)) is not None or len(numbered) != 1 \
            else numbered[0]
        if "%" in text:  # a share, not a count or a value
            raise Unreadable(f"Could not read {shown(answer)} as {what}: it is a percentage.")
        others = {float(n) for clause in numbered if clause is not text
                  for n in re.findall(r"(?<!of )(?<!of the )(?<![\w.])(\d+(?:\.\d+)?)", clause)}
        mine = re.findall(r"(?<!of )(?<!of the )(?<![\w.])(\d+(?:\.\d+)?)", text)  # 'of 100' is a total
        if single and others and mine and others - {float(mine[0])}:  # '50, i.e. 25 per row': two counts
            raise Unreadable(f"Could not read {shown(answer)} as {what}: it gives two numbers.")
        compact = _compact(text)
        for lead in ("theansweris", "answer:", "itis", "its", "it\u2019s", "thereare", "about", "around", "roughly",
                     "approximately", "\u2248", "~"):  # a hedge: 'about 1' is 1
            if compact.startswith(lead):
                compact = compact[len(lead):]
        compact = {"infinity": "inf", "+infinity": "inf", "positiveinfinity": "inf", "plusinfinity": "inf",
                   "oo": "inf", "-infinity": "-inf", "-oo": "-inf",
                   "infinite": "inf", "diverges": "inf", "itdiverges": "inf"}.get(compact, compact)
        compact = re.sub(r"(unsafecells|cells|unsafestates|states|squares)$", "", compact)  # '50 cells'
        fraction = re.fullmatch(r"(-?\d+)/(\d+)", compact)  # '1/3'
        if fraction and int(fraction.group(2)):
            return int(fraction.group(1)) / int(fraction.group(2))
        try:
            value = float(compact)
            mantissa = compact.split("e")[0]
            if (math.isinf(value) and "inf" not in compact) or (value == 0 and re.search(r"[1-9]", mantissa)):
                raise Unreadable(f"Could not read {shown(answer)} as {what}: it is beyond a float's range.")
            return value
        except ValueError:
            word = _number_word(compact)
            if word is None:
                raise Unreadable(f"Could not read {shown(answer)} as {what}.") from None
            return word
    try:
        array = np.asarray(answer)
        if isinstance(answer, np.ndarray) and array.size == 1:  # np.array([0.37]): one value, as numpy holds it
            array = answer = array.reshape(())
        if array.ndim != 0 or array.dtype.kind == "b":
            raise ValueError
        return float(answer)
    except (TypeError, ValueError, OverflowError, ArithmeticError):
        raise Unreadable(f"Could not read {shown(answer)} as {what}.") from None


def leading_zero(text: str, answer, what: str) -> None:
    """Raise :class:`Unreadable` where a number in ``text`` begins with 0 ('050', '01', '00.37'): Python refuses
    such a number, and so does a reader (but 0 itself, and 0.5).

    Parameters
    ----------
    text : str
        The answer as text, as far as it has been read.
    answer : object
        The answer as given (quoted in the reply).
    what : str
        What the answer is read as, for the reply ('a whole number').
    """
    if re.search(r"(?<![\w.])0\d", text):
        raise Unreadable(f"Could not read {shown(answer)} as {what}: a number in digits does not begin with 0 "
                         "(but 0 itself, or 0.5).")


def exactly(given, value: float, what: str) -> float:
    """``value`` where ``given`` is exactly it, for a whole or infinite ``value`` read from ``given`` (its digits
    as written, a Decimal, a Fraction, a sympy number): 49.99999999999999999 rounds to 50.0 as a float but is not
    50; raises :class:`Unreadable`.  NaN and values that are neither whole nor infinite are returned as they are.

    Parameters
    ----------
    given : object
        The student's answer as written (text, a Decimal, a Fraction, a sympy or numpy number).
    value : float
        What was read from it.
    what : str
        What it is read as, for the refusal ('a whole number', 'an action number').
    """
    if math.isnan(value) or not (math.isinf(value) or value == int(value)) or 2**53 < abs(value) < math.inf:
        return value  # beyond 2**53 every float is whole: 1e300 is read as the float it is
    text = _text(given)
    if text is not None:  # a number written in digits must be the value exactly; a word is ('one', 'infinite')
        quotient = re.fullmatch(r"\s*([+-]?\d+)\s*/\s*(\d+)\s*", text)
        digits = re.search(r"[+-]?\d+(?:\.\d*)?(?:e[+-]?\d+)?", re.sub(r"(?<=\d)_(?=\d)", "", text),
                           flags=re.I)  # '1_0' is Python's 10
        if quotient and int(quotient.group(2)):
            exact = Fraction(int(quotient.group(1)), int(quotient.group(2))) == value
        else:
            exact = digits is None or (not math.isinf(value) and Decimal(digits.group(0)) == Decimal(value))
    else:
        try:
            exact = Decimal(str(given)) == Decimal(value)  # sympy's Float(1), a Decimal, a numpy float
        except Exception:  # noqa: BLE001 - any object's str(): one that cannot be read as a Decimal is compared
            try:
                exact = bool(given == value if math.isinf(value) else given == int(value))  # a Fraction, a Rational
            except Exception:  # noqa: BLE001 - nor compared: not exactly the value
                exact = False
    if not exact:
        raise Unreadable(f"Could not read {shown(given)} as {what}: it is not exactly {value:g}.")
    return value


#: readers moved to modules of their own (0.4; read_side in 0.5): importable from here for one release, with a warning
_MOVED_READERS = {"read_actions": "action_lists", "read_count": "counts", "read_limits": "limits", "read_side": "sides"}


def __getattr__(name: str):
    if name in _MOVED_READERS:
        import importlib
        import warnings

        module = f"{__package__}.{_MOVED_READERS[name]}"
        warnings.warn(f"{__name__}.{name} moved to {module}.{name}", DeprecationWarning, stacklevel=2)
        return getattr(importlib.import_module(module), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
