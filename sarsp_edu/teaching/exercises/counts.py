"""Reading a count as a student writes it (exercise 3.4): ``50``, ``"fifty"``, ``"The grid can hold 50 unsafe
cells"``, ``"50 = 10*10/2"``, ``"at most 50"``, ``"50 (half the grid)"``; not ``"less than 50"``, ``"about 50"``,
``"50 percent"``, ``"50 of 64"`` or a count with another number beside it (``"50, 5 per row"``).

Examples
--------
>>> read_count("12"), read_count(12.0), read_count("fifty"), read_count("50 = 10 x 10 / 2")
(12, 12, 50, 50)
>>> read_count("a few")
Traceback (most recent call last):
...
sarsp_edu.teaching.exercises.parsing.Unreadable: Could not read 'a few' as a whole number.
"""

from __future__ import annotations

import ast
import math
import re

from .parsing import (
    _CALL,
    _HEDGED,
    _NEGATION,
    _NUMPY_PRINTED,
    ALONE,
    Unreadable,
    _clauses,
    _compact,
    _number,
    _number_word,
    _text,
    alone,
    exactly,
)
from .sentences import number_spelled
from .wording import shown

__all__ = ["arithmetic", "read_count"]

#: a bound, an estimate or a share where a count is asked ('less than 50', 'nearly 50', '50 is too many', '50
#: percent', '50+'): not the count ('at most 50' is: the question's own bound)
_NOT_A_COUNT = re.compile(r"\b(?:less|more|fewer|over|under|below|above|nearly|almost|close\s+to|slightly|a\s+bit|"
                          r"at\s+least|exceed\w*|beyond|too\s+(?:many|few)|percent|per\s*cent|or\s+so|minimum|"
                          r"min)\b|\d\s*\+(?!\s*\d)|[<>\u2265]", re.IGNORECASE)
#: the question's own bound, said as the answer's ('no more than 50', 'up to 50', 'a maximum of 50'): dropped
_AT_MOST = re.compile(r"\b(?:no|not)\s+more\s+than\b|\bup\s+to\b|\b(?:a\s+)?maximum\s+of\b|\bat\s+most\b|<=|\u2264",
                      re.IGNORECASE)
#: the question's own conditions, said with the count: its grid ('on a 10 x 10 grid, 50'), its rule ('50 with no
#: two 4-adjacent'), 'of them': dropped
_RULE = (r"(?:no\s+two(?:\s+of\s+them)?(?:\s+cells)?\s+(?:(?:4|four)-?\s*)?(?:adjacent|touching|neighbou?ring|"
         r"shar(?:ing|e)\s+an\s+edge)(?:\s+cells)?|(?:4|four)-?\s*adjacency)")
_GRID = r"(?:a\s+|the\s+)?(?:10|ten)\s*(?:x|\u00d7|by|-by-)\s*(?:10|ten)(?:\s+grid)?"
_QUESTIONS_OWN = re.compile(
    rf"^\s*(?:(?:on|for|in)\s+)?{_GRID}\s*(?:[,:]|->|=>|\u2192)?\s*(?=(?:it\s+is|it'?s|there\s+are|\d|[a-z]+\s*$))|"
    rf"\s*,?\s+(?:on|in)\s+{_GRID}\s*$|"
    rf"\s+(?:with|if|when)\s+{_RULE}\s*$|\s+of\s+them\s*$|\s*(?:,|\()\s*(?:with\s+|if\s+)?{_RULE}\s*\)?\s*$|"
    rf"\s*\(\s*(?:(?:on|for|in)\s+)?{_GRID}\s*\)\s*$",  # '50 (10 x 10)', '50 (for a 10 x 10 grid)'
    re.IGNORECASE)
#: a grid's size ('10 x 10', '10x10', '10-by-10'): given by the question, not a count
_GRID_SIZE = re.compile(r"\b10\s*(?:x|\u00d7|\*|-?by-?)\s*10\b(?!\s*/)", re.IGNORECASE)  # the question's grid
#: an answer with its working: '50 = 10*10/2', '10 * 10 / 2 = 50'
_WORKING = re.compile(r"^\s*(?:(\d+)\s*=\s*([\d\s*x\u00d7/+().-]+)|([\d\s*x\u00d7/+().-]+)=\s*(\d+))\s*$",
                      re.IGNORECASE)


_OPERATIONS = {ast.Add: lambda a, b: a + b, ast.Sub: lambda a, b: a - b, ast.Mult: lambda a, b: a * b,
               ast.Div: lambda a, b: a / b, ast.FloorDiv: lambda a, b: a // b,
               ast.Pow: lambda a, b: a ** b}  # '10**2//2' (the sizes are bounded in _arithmetic)


def arithmetic(text: str) -> float | None:
    """The value of ``text`` where it is one sum, difference, product, quotient or power of numbers ('1 / 2.7',
    '10**2//2', '10 x 10 / 2'), else None.

    >>> arithmetic("10**2 // 2"), arithmetic("1 / 4"), arithmetic("50"), arithmetic("50 cells")
    (50.0, 0.25, None, None)
    """
    if not re.fullmatch(r"[\d\s().*x\u00d7/+-]*\d[\d\s().*x\u00d7/+-]*", text, flags=re.I) or not re.search(
            r"\d\s*[)]?\s*[*x\u00d7/+-]", text, flags=re.I):
        return None
    try:
        value = _arithmetic(ast.parse(re.sub(r"[x\u00d7]", "*", text, flags=re.I).strip(), mode="eval").body)
    except (SyntaxError, ZeroDivisionError, ValueError, OverflowError):
        return None
    return value if math.isfinite(value) else None


def _arithmetic(node) -> float:
    """The value of a sum, difference, product or quotient of numbers ('100//2', '0.5 * 100'; ValueError for
    anything else)."""
    if isinstance(node, ast.Constant) and type(node.value) in (int, float):
        return float(node.value)
    if isinstance(node, ast.BinOp) and type(node.op) in _OPERATIONS:
        left, right = _arithmetic(node.left), _arithmetic(node.right)
        if isinstance(node.op, ast.Pow) and (abs(right) > 64 or abs(left) > 1e4):  # no 10**10**10
            raise ValueError("a power too large to be a working")
        value = _OPERATIONS[type(node.op)](left, right)
        if not math.isfinite(value) or abs(value) > 2**53:
            raise ValueError("beyond a whole float")
        return value
    raise ValueError("not arithmetic of whole numbers")


#: a count's unit, closing it ('50 cells', 'fifty unsafe states')
_UNIT = re.compile(r"\s+(?:unsafe\s+)?(?:cells?|states?|squares?)\s*$", re.IGNORECASE)


def _worked(text: str) -> str:
    """``text`` with its unit dropped and a number word before '=' in digits ('fifty = 100/2 cells' ->
    '50 = 100/2'), then its working checked (:func:`_checked_working`)."""
    text = _UNIT.sub("", text)
    word = re.match(r"^\s*([a-z]+(?:-[a-z]+)?)\s*=", text, flags=re.I)
    value = None if word is None else _number_word(word.group(1).lower().replace("-", ""))
    if value is not None:
        text = str(int(value)) + text[word.end() - 1:]
    return _checked_working(text)


def _checked_working(text: str) -> str:
    """``text`` with its working checked and dropped ('50 = 10*10/2' -> '50'); raises :class:`Unreadable` where
    the working does not give the number."""
    if re.fullmatch(r"[\d\s().]*[\d)]\s*[*x\u00d7/+-][\d\s*x\u00d7/+().-]*", text, flags=re.IGNORECASE):  # '(100)/2'
        value = arithmetic(text)
        return str(int(value)) if value is not None and value == int(value) else text
    match = _WORKING.match(text)
    if not match:
        return text
    number, working = (match.group(1), match.group(2)) if match.group(1) else (match.group(4), match.group(3))
    expression = re.sub(r"[x\u00d7]", "*", working, flags=re.IGNORECASE)
    try:
        value = _arithmetic(ast.parse(expression.strip(), mode="eval").body)
    except (SyntaxError, ZeroDivisionError, ValueError):
        return text
    if value != float(number):
        raise Unreadable(f"Could not read {shown(text)} as a whole number: its working does not give {number}.")
    return number


def read_count(answer) -> int:
    """A whole number (int, float, numpy scalar, 0-d array or text such as '50'), alone (as
    :func:`~sarsp_edu.teaching.exercises.parsing.alone` reads it); raises :class:`Unreadable`."""
    text = _text(answer)
    if text is None:
        return _read_count(answer)
    for _ in range(3):  # '50 cells, no two 4-adjacent, on a 10 x 10 grid': one after another
        text = _QUESTIONS_OWN.sub("", text)
    word = _UNIT.sub("", text)
    mended = number_spelled(word)  # 'fity', 'fity cells': the number word, mended (a sentence as it is)
    text = _said_plainly(mended if mended != word else text)
    text = _NUMPY_PRINTED.sub(r"\1", text)  # 'np.int64(50)', 'array(50)': numpy's printed forms ('int(50)' is a call)
    if _CALL.search(text):  # 'range(50)', 'len(range(50))': a call, not its value
        raise Unreadable(f"Could not read {shown(answer)} as a whole number: it is a Python call, not a count; write "
                         "the number itself.")
    _other_grid_or_range(text, answer)
    if re.fullmatch(r"\s*(?:not|never)\s+[^,;:()]+", text, flags=re.I):  # 'not 49': what the count is not
        raise Unreadable(f"Could not read {shown(answer)} as a whole number: it says what the count is not; write "
                         "what it is.")
    text = _alone(text, answer)
    if _HEDGED.search(text):
        raise Unreadable(f"Could not read {shown(answer)} as a whole number: a count is exact; write the number "
                         "alone.")
    if _NOT_A_COUNT.search(_AT_MOST.sub(" ", text)):
        raise Unreadable(f"Could not read {shown(answer)} as a whole number: it gives a bound, an estimate or a "
                         "share, not the number.")
    try:
        return _read_count(_GRID_SIZE.sub(" gridsize ", _worked(_AT_MOST.sub(" ", text))))
    except Unreadable as refused:  # said of the student's words, not of what was read from them
        why = str(refused).rpartition(" as a whole number")[2] or "."
        raise Unreadable(f"Could not read {shown(answer)} as a whole number{why}") from None


def _other_grid_or_range(text: str, answer) -> None:
    """Raise :class:`Unreadable` where ``text`` is a range ('49-50', '45 to 50'), a list of numbers ('[50, 50]')
    or a count on another grid than the question's ('50 on a 9 x 9 grid'), each with its own reason."""
    spanned = re.fullmatch(r"\s*(\d+)\s*(?:-|\u2013|\u2014|to)\s*(\d+)\s*(?:cells|states|squares)?\s*", text,
                           flags=re.I)
    if spanned and int(spanned.group(1)) < int(spanned.group(2)):  # not '100-50', a working
        raise Unreadable(f"Could not read {shown(answer)} as a whole number: it gives a range; a count is one "
                         "number.")
    if re.fullmatch(r"\s*(?:[\[({][^\[\](){}]*[,;][^\[\](){}]*[\])}]|\[[^\[\]]*\])\s*", text):  # not '(50)'
        raise Unreadable(f"Could not read {shown(answer)} as a whole number: it is a list; write the count alone.")
    grid = re.search(r"\b(\d+)\s*(?:x|\u00d7|\*|-?by-?)\s*(\d+)\b(?:\s+grid\b)", text, flags=re.I)
    if grid and grid.group(1, 2) != ("10", "10"):
        raise Unreadable(f"Could not read {shown(answer)} as a whole number: the question's grid is 10 x 10, not "
                         f"{grid.group(1)} x {grid.group(2)}.")


def _said_plainly(text: str) -> str:
    """``text`` with what only restates the count said as the count: Python's literals ('0x32' -> '50'), 'half of
    100' as '100/2', a sum said whole ('100 - 50', not read as a dash), another number denied ('50 not 19', 'not
    19 but 50' -> '50')."""
    text = text.replace("\u00bd", " 1/2 ").replace("\u00b7", "*").replace("\u00b2", "**2").strip()  # '½ · 100', '10²/2'
    text = re.sub(r"^\s*(?:a\s+total\s+of|all)\s+(?=\d)|(?<=\d)\s+(?:in\s+total|total|in\s+all)\s*$", "", text,
                  flags=re.I)  # '50 in total', 'all 50'
    literal = re.fullmatch(r"\s*(0[xob][0-9a-f_]+|\d+(?:_\d+)+)(\s+(?:unsafe\s+)?(?:cells|states|squares))?\s*", text,
                           flags=re.IGNORECASE)
    if literal:  # '0x32', '5_0', '0x32 cells'
        try:
            return str(int(literal.group(1), 0 if literal.group(1)[:2].lower() in ("0x", "0o", "0b") else 10))
        except ValueError:
            return text
    text = re.sub(r"^\s*=\s*", "", text)  # '= 50'
    text = re.sub(r"\bn\s*(?:\^|\*\*|\u00b2)\s*2?(?=\s*/\s*2)", "10**2", text)  # '50 (n^2/2)': the question's n = 10
    text = re.sub(r"(?<![\w.])\d+(?:\.\d+)?e[+-]?\d+(?![\w.])", lambda m: repr(float(m.group(0))), text,
                  flags=re.IGNORECASE) if re.search(r"[*/+-]", text) else text  # '1e2/2': a working in floats
    # '50 = fifty', 'fifty, i.e. 50': one number said twice
    said_twice = re.fullmatch(r"\s*([a-z]+(?:-[a-z]+)?|\d+)\s*(?:=|,\s*(?:i\.\s*e\.?|that\s+is)\s*,?)\s*"
                              r"([a-z]+(?:-[a-z]+)?|\d+)\s*", text, flags=re.IGNORECASE)
    if said_twice:
        values = [_number_word(part.lower().replace("-", "")) if not part.isdigit() else float(part)
                  for part in said_twice.groups()]
        if None not in values and values[0] == values[1]:
            return str(int(values[0]))
    text = re.sub(r"\b(?:(?:one|a)\s+half|half|1\s*/\s*2)\s+(?:of\s+)?(?:the\s+)?(\d+)\b", r"\1/2", text,
                  flags=re.IGNORECASE)  # 'half of 100', 'one half of 100'
    text = re.sub(r"^\s*half\s+(?:of\s+)?the\s+(?:cells|squares|grid|board)\s*$", "100/2", text, flags=re.IGNORECASE)
    text = re.sub(r"^\s*(\d+)\s+or\s+(?:fewer|less)(?:\s+(?:unsafe\s+)?(?:cells|states|squares))?\s*$", r"at most \1",
                  text, flags=re.IGNORECASE)  # the bound, '50 or fewer cells'
    text = re.sub(r"^\s*(\d+)\s+or\s+(?:more|greater)\s*$", r"at least \1", text, flags=re.IGNORECASE)  # not it
    if re.fullmatch(r"\s*\d+(?:\.\d+)?\s+-\s+\d+(?:\.\d+)?\s*", text):  # '100 - 50': a difference
        return _checked_working(text.replace(" - ", "-"))
    worded = re.fullmatch(r"\s*([a-z]+(?:-[a-z]+)?|\d+)\s*(,?\s+(?:but\s+)?not\s+)([a-z]+(?:-[a-z]+)?|\d+)\s*", text,
                          flags=re.IGNORECASE)  # 'fifty, not forty-nine': the denial in words
    if worded:
        said = [part if part.isdigit() else _number_word(part.lower().replace("-", "")) for part in worded.group(1, 3)]
        if None not in said:
            text = f"{int(float(said[0]))}{worded.group(2)}{int(float(said[1]))}"
    denied = (re.fullmatch(r"\s*(\d+)\s*,?\s+(?:but\s+)?not\s+(\d+)\s*", text, flags=re.IGNORECASE),
              re.fullmatch(r"\s*not\s+(\d+)\s*(?:,?\s*but|[,;:])\s*(\d+)\s*", text, flags=re.IGNORECASE))
    for match, said in zip(denied, (1, 2)):  # 'not 49 but 50', 'not 49, 50'
        if match and match.group(1) != match.group(2):
            return match.group(said)
    return text


def _alone(text: str, answer) -> str:
    """``text`` as :func:`~.parsing.alone` reads it; or, where it says more than the count, the one clause that
    gives the count when every other clause gives the same number or none, and none of them bounds, doubts or
    negates it ('50 (half the grid)', 'half the grid: 50', 'fifty (50)'; not '50 (or 25)', '50, 5 per row')."""
    try:
        return alone(text, answer, "a whole number")
    except Unreadable as refused:
        if ALONE not in str(refused):
            raise
        if re.search(r"\b(?:because|since|as|so)\b", text, flags=re.I):  # a reason: read alone, as elsewhere
            raise
        main, asides = _clauses(text.strip().rstrip(".!"))
        if any(re.fullmatch(rf"\s*(?:but\s+)?not\s+{re.escape(main.strip())}\s*", aside, flags=re.I)
               for aside in asides):  # '50, not 50'
            raise Unreadable(f"Could not read {shown(answer)} as a whole number: it denies its own answer.") from None
        asides = [re.sub(r"^\s*=\s*", "", aside) for aside in asides  # '50 (= 100/2)': its working
                  if not _denies_another(aside, main)]  # '50, not 25': emphasis
        if any(_NEGATION.search(aside.lower()) or _NOT_A_COUNT.search(aside) or _HEDGED.search(aside) or "%" in aside
               for aside in asides):
            raise
        numbered = [clause for clause in (main, *asides) if re.search(r"\d", clause) or _number_word(_compact(
            _UNIT.sub("", clause))) is not None]  # 'fifty cells, a checkerboard'
        if any(aside not in numbered and not _DESCRIBES_THE_COUNT.fullmatch(aside.strip()) for aside in asides):
            raise  # '50 (closer to the edge)', '50 (every cell)': an aside that states no count, or another one
        try:
            counts = {_read_count(_worked(clause)) for clause in numbered}
        except Unreadable:
            counts = set()
        if len(counts) != 1 and numbered:
            raise Unreadable(f"Could not read {shown(answer)} as a whole number: it gives another number beside the "
                             "count; write the count alone.") from None
        if not numbered:
            raise
        return numbered[0]


#: the count described in words, as an aside may say it ('a checkerboard', 'one colour of a chessboard', 'half the
#: grid', 'every other cell'): any other aside without a number names no count, or another one ('every cell')
_DESCRIBES_THE_COUNT = re.compile(
    r"(?:i\.\s*e\.?\s*|that\s+is\s*,?\s*|so\s+|=\s*)?(?:(?:a|the|one|either)\s+)?(?:exactly|"
    r"(?:chess|checker)[\s-]?board'?s\s+half|"
    r"(?:(?:colou?r|half)\s+of\s+(?:a|the)\s+)?(?:gridsize\s+)?(?:chess|checker)[\s-]?board(?:\s+(?:pattern|colou?ring|layout))?|"
    r"(?:checker|chess)[\s-]?board(?:\s+(?:pattern|colou?ring|colou?r|layout))?|colou?r(?:\s+of\s+(?:a|the)\s+(?:chess|checker)board)?|"
    r"(?:all\s+(?:the\s+)?)?(?:black|white|dark|light)\s+(?:squares|cells)(?:\s+of\s+(?:a|the)\s+(?:chess|checker)board)?|"
    r"(?:(?:a|the)\s+)?(?:chess|checker)[\s-]?board'?s\s+(?:black|white|dark|light)\s+(?:squares|cells)|half|"
    r"half\s+(?:of\s+)?(?:the\s+)?(?:grid|cells|board|squares|grid'?s\s+cells)|every\s+(?:other|second)\s+(?:cell|square|one)|"
    r"(?:the\s+)?max(?:imum)?|"
    r"alternat(?:e|ing)\s+(?:cells|squares))", re.IGNORECASE)


def _denies_another(aside: str, main: str) -> bool:
    """Whether ``aside`` only denies another number than ``main`` gives ('50, not 25')."""
    denied = re.fullmatch(r"\s*(?:but\s+)?not\s+(\d+)\s*", aside, flags=re.I)
    given = re.fullmatch(r"\s*(\d+)\s*", main)
    return bool(denied and given and denied.group(1) != given.group(1))


def _read_count(answer) -> int:
    try:
        value = _number(answer, "a whole number", single=True)
    except Unreadable as refused:
        if any(why in str(refused) for why in ("two numbers", "percentage", "begin with 0")):
            raise
        value = _count_in_words(answer)
    if not math.isfinite(value) or value != int(value):
        raise Unreadable(f"Could not read {shown(answer)} as a whole number.")
    return int(exactly(answer, value, "a whole number"))  # 49.99999999999999999 is no whole number


_NUMBER = r"(?:\d+(?:\.\d+)?|[a-z]+(?:-[a-z]+)?)"
_STATES_A_COUNT = re.compile(
    r"^(?:(?:(?:the|a)\s+(?:gridsize\s+)?(?:grid|board|world)|it)\s+(?:can\s+)?(?:hold|holds|fit|fits|take|takes|"
    r"has|have)\s+|(?:it'?s\s+|it\s+is\s+)?exactly\s+|it'?s\s+|it\s+is\s+|there\s+can\s+be\s+|"
    r"it(?:'d|\s+would|'ll|\s+will)\s+be\s+|it\s+was\s+|they\s+(?:can\s+)?(?:hold|fit|take)\s+|"
    r"the\s+(?:max(?:imum)?|most|largest|upper\s+limit)(?:\s+(?:number|count))?(?:\s+(?:of\s+)?(?:unsafe\s+)?"
    r"(?:cells|states|squares))?(?:\s+(?:it|the\s+grid)\s+can\s+hold)?\s+is\s+|max(?:imum)?\.?\s+)?"
    rf"(?:at\s+most\s+)?{_NUMBER}(?:\s+(?:unsafe\s+)?(?:cells|states|squares))?"
    r"(?:\s+(?:at\s+(?:the\s+)?most|max|exactly|is\s+(?:the|my)\s+(?:answer|prediction|maximum|max|most)|"
    r"on\s+the\s+board|"
    r"out\s+of\s+(?:the\s+)?\d+|"
    r"(?:on|in)\s+(?:a|the)\s+(?:gridsize\s+)?grid|of\s+(?:the\s+)?\d+(?:\s+(?:cells|states|squares))?))?$",
    re.IGNORECASE)


def _count_in_words(answer) -> float:
    """The one number a sentence gives as its count ('The grid can hold 50 unsafe cells', 'at most 50', '50 of
    the 100 cells': a number after 'of' is a total, not the count); raises :class:`Unreadable`."""
    text = _text(answer)
    if text is None or _NEGATION.search(text.lower()):
        raise Unreadable(f"Could not read {shown(answer)} as a whole number.")
    # only a sentence that states the count ('The grid can hold 50 unsafe cells', '50 unsafe cells', '50 of the
    # 100 cells'): not one that judges it ('50 is wrong', '50 is too high', '50 cannot fit')
    if not _STATES_A_COUNT.match(text.strip().rstrip(".!")):
        raise Unreadable(f"Could not read {shown(answer)} as a whole number.")
    if "%" in text:
        raise Unreadable(f"Could not read {shown(answer)} as a whole number: it is a percentage.")
    counts = [float(m.group(2)) for m in re.finditer(r"(\bof\s+(?:the\s+)?)?(?<![\w.])(\d+(?:\.\d+)?)(?![\w.]*\d)",
                                                       text) if m.group(1) is None]
    counts += [word for word in (_number_word(token.replace("-", "")) for token in re.findall(
        r"(?<!of )(?<!of the )\b[a-z]+(?:-[a-z]+)?\b", text.lower())) if word is not None]  # 'It can hold fifty'
    if len(set(counts)) != 1:
        raise Unreadable(f"Could not read {shown(answer)} as a whole number.")
    totals = {int(total) for total in re.findall(r"\bof\s+(?:the\s+)?(\d+)", text)} - {100}
    if totals:  # '50 of the 100 cells' is a count; '50 of 64' counts another grid
        raise Unreadable(f"Could not read {shown(answer)} as a whole number: a 10 x 10 grid has 100 cells, not "
                         f"{min(totals)}.")
    return counts[0]
