"""Reading the two direction predictions (exercises 2.5 and 2.6) as a student writes them.

Exercise 2.5 asks on which side of 1 a variance factor lies ('above' or
'below'); exercise 2.6 whether a band at nu = 30 is 'wider' or 'narrower'
than at nu = 3.  Both are read as one sentence (:mod:`.sentences`), and
each adds what its own question makes unambiguous:

- 2.5 (:func:`read_side`): a number on a side of 1 ('0.37', 'it drops to
  0.37', '0.37 < 1'), never one at or below 0 (a variance factor is
  positive); the question's own condition ('below, without outliers');
- 2.6 (:func:`read_band`): the question's own nu = 30 ('the nu = 30 band
  is narrower', 'narrower (nu = 30)'), and the band at nu = 3 said instead
  ('wider at nu = 3', 'the band at nu = 3 is wider'), read as the other side.

Examples
--------
>>> read_side("it drops to 0.37"), read_side("Below, without outliers")
('below', 'below')
>>> read_band("wider at nu = 3"), read_band("the nu = 30 band is narrower")
('narrower', 'narrower')
"""

from __future__ import annotations

import math
import re
from decimal import Decimal

from .counts import arithmetic
from .parsing import (
    _HEDGED,
    _LEAD_IN,
    _ONE_CALL,
    ABOVE,
    BELOW,
    NARROWER,
    WIDER,
    Unreadable,
    _clauses,
    _number,
    _text,
    alone,
    leading_zero,
    read_word,
)
from .sentences import parse, said_in_words
from .wording import shown

__all__ = ["read_band", "read_side"]

_NU = r"(?:nu|\u03bd)\s*=?\s*"
#: 2.5's own condition, said after the side or before it ('below 1 without outliers', 'on clean data, below')
_CLEAN = (r"(?:without\s+(?:the\s+|any\s+)?outliers|(?:(?:with|when|if)\s+(?:there\s+are\s+)?)?no\s+outliers|"
          r"(?:at|with|for)\s+(?:p|proportion)\s*=\s*0(?:\.0+)?(?![\d.])|(?:the\s+)?clean\s+(?:data|targets)|"
          r"(?:on|for|with)\s+(?:the\s+)?clean\s+(?:data|targets)|"
          r"(?:with|for|in|at|using)\s+(?:(?:the\s+)?tp\s+fitted\s+as\s+in\s+section\s+3|section\s+3'?s\s+fit|"
          r"(?:nu|\u03bd)\s*=\s*3(?:\.0+)?(?![\d.]))|(?:nu|\u03bd)\s*=\s*3(?:\.0+)?(?![\d.]))")  # and the question's
# own fit: section 3's, at nu = 3 ('below (nu = 3)')
_FACTOR = r"(?:the\s+)?(?:tp(?:'?s)?\s+)?(?:fitted\s+)?(?:variance\s+)?(?:factor|variance_scale_)"
_WITHOUT_OUTLIERS = (rf"\s*(?:,|\u2014|\u2013|\s-)?\s+{_CLEAN}\s*$|\s*\(\s*{_CLEAN}\s*\)\s*$|"
                     rf"^\s*(?:{_CLEAN}|clean|(?:p|proportion)\s*=\s*0(?:\.0+)?)\s*[,:]?\s*|\s*\(\s*{_FACTOR}(?:,?\s+{_CLEAN})?\s*\)\s*$|"
                     r"\s*\(\s*(?:proportion|p)\s*=\s*0(?:\.0+)?\s*\)\s*$")  # '(the fitted factor)'
#: the question's own subject said before the answer ('TP below 1', 'the TP: narrower', "the TP's band: narrower")
_THE_TP = (r"^\s*(?:the\s+)?tp(?:'s)?(?:\s+band)?(?:\s*[:,\u2013\u2014]\s*|\s+is\s+|\s+)"
           r"(?!(?:fitted\s+|variance\s+)*factor|(?:at|with|for)\s+(?:nu|\u03bd)|band)(?=[a-z0-9.])")
def _denial_said_plainly(text: str) -> str:
    """'not wider but narrower' ('not above 1 but below') and 'narrower and not wider' said as 'narrower, not
    wider'."""
    word = r"([a-z]+(?:\s+(?:1|one))?)"
    text = re.sub(rf"^\s*not\s+{word}\s*,?\s+but\s+{word}\s*$", r"\2, not \1", text, flags=re.I)
    return re.sub(r"^\s*([a-z]+)\s*,?\s+and\s+not\s+([a-z]+)\s*$", r"\1, not \2", text, flags=re.I)


#: the question's own subject in brackets after the answer ('narrower (TP)', 'below (the TP)')
_TP_ASIDE = r"\s*\(\s*(?:the\s+)?tp(?:'s\s+(?:band|factor))?\s*\)\s*$"
#: 1 said against the factor ('1 is above it'): the factor is on the other side
_ONE_IS = re.compile(r"^\s*(?:1|one)\s+is\s+(?:(above|over|(?:larger|greater|bigger|more|higher)\s+than)|"
                     r"(below|under|(?:less|smaller|lower)\s+than))\s+(?:it|the\s+(?:variance\s+)?factor)\s*$", re.I)
#: the factor named before its value ('The factor is 0.4', 'variance_scale_ = 0.4', "It's 0.4", 'beta/n = 0.67')
_FACTOR_IS = re.compile(r"^\s*(?:the\s+(?:tp'?s\s+)?(?:fitted\s+)?(?:variance\s+)?factor|variance_scale_|"
                        r"beta_?\s*/\s*n|it'?s|it\s+is)\s*(?:is|=)?\s*", re.IGNORECASE)
#: a number compared with 1 ('0.37 < 1'): the number and the comparison must agree
_COMPARED = re.compile(r"^\s*(\d+(?:\.\d+)?)\s*(<|>)\s*(?:1(?:\.0*)?|one)\s*$", re.IGNORECASE)
#: 1 compared with a number ('1 > 0.37'): said as the number compared with 1
_ONE_COMPARED = re.compile(r"^\s*(?:1(?:\.0*)?|one)\s*(<|>)\s*(\d+(?:\.\d+)?)\s*$", re.IGNORECASE)
_A_NUMBER = re.compile(r"\d+(?:\.\d+)?|\.\d+")


def _side_of(value: float, answer) -> str:
    if math.isnan(value) or value == 1:
        raise Unreadable(f"Could not read {shown(answer)} as 'above' or 'below': it is on neither side of 1.")
    if value <= 0 or math.isinf(value):
        raise Unreadable(f"Could not read {shown(answer)} as 'above' or 'below': a variance factor is a positive, "
                         "finite number.")
    return "above" if value > 1 else "below"


def read_side(answer) -> str:
    """'above' or 'below' 1: a word (:func:`~.parsing.read_word` with :data:`~.parsing.ABOVE` and
    :data:`~.parsing.BELOW`), a sentence, or a number on that side of 1 (0.37 is 'below'), alone (as
    :func:`~.parsing.alone` reads it); raises :class:`~.parsing.Unreadable`, for 1 itself and for a number
    at or below 0 too."""
    text = _text(answer)
    if text is None:
        try:
            value = _number(answer, "a number")
        except Unreadable:
            raise Unreadable(f"Could not read {shown(answer)} as 'above' or 'below'.") from None
        return _side_of(value, answer)
    _other_setting(text, answer, "'above' or 'below'", _NU_IS, (3.0,), "about section 3's fit at nu = 3")
    _other_setting(text, answer, "'above' or 'below'", _P_IS, (0.0,),  # 'below 1 (p = 0.1)': with outliers
                   "about the data without outliers")
    bare = re.sub(r"\s*[.!\u2026,;:]+\s*$", "", text)  # 'below.', 'below 1,'
    bare = _denial_said_plainly(bare.replace("\u03b2", "beta"))  # 'below 1 (β < n)', 'not above but below'
    if _ONE_CALL.fullmatch(bare) and not re.fullmatch(
            r"\s*(?:(?:np\.|numpy\.)float\d*|array)\(\s*[\d.]+\s*\)\s*", bare):  # 'math.exp(-1)', 'float(0.37)': calls
        raise Unreadable(f"Could not read {shown(answer)} as 'above' or 'below': it is a Python call; write the side, "
                         "or the number itself.")
    bare = re.sub(r"^\s*(?:(?:np\.|numpy\.)float\d*|array)\(\s*([\d.]+)\s*\)\s*$", r"\1", bare)  # 'array(0.37)'
    bare = re.sub(rf"^\s*{_FACTOR}\s*:\s*", "", bare, count=1, flags=re.I)  # "the TP's factor: below 1"
    bare = re.sub(_THE_TP, "", bare, count=1, flags=re.I)  # 'TP below 1', 'the TP: below'
    bare = re.sub(_TP_ASIDE, "", bare, flags=re.I)  # 'below (TP)'
    for _ in range(2):  # 'below 1 without outliers at nu = 3': one after another
        bare = re.sub(_WITHOUT_OUTLIERS, "", bare, flags=re.I)
    bare = said_in_words(bare)
    leading_zero(bare, answer, "'above' or 'below'")  # '00.37', '03'
    written = re.fullmatch(r"\s*(\d+\.\d+)\s*", bare)
    if written:  # a number is on the side its digits put it: '0.9999999999999999999' is below 1, as written
        exact = Decimal(written.group(1))
        return _side_of(float(exact), answer) if exact in (0, 1) else "above" if exact > 1 else "below"
    worked = arithmetic(bare)
    if worked is not None:  # '1 - 0.63': a working, read by its value
        return _side_of(worked, answer)
    one_compared = _ONE_COMPARED.match(bare)
    if one_compared:
        bare = f"{one_compared.group(2)} {'<' if one_compared.group(1) == '>' else '>'} 1"
    one_is = _ONE_IS.match(bare)
    if one_is:
        return "below" if one_is.group(1) else "above"
    try:
        alone(bare, answer, "'above' or 'below'")  # 'below 1 (3.3)', '0.4 (above 1)', 'below, probably': unread
    except Unreadable as refused:  # unless its asides only deny the other side ('below 1, not above')
        agreed = _clauses_agree(bare, read_side, "because|since|as|so")
        if agreed is not None:  # '0.37, below 1': the number and its side, each alone, agree
            return agreed
        try:
            return read_word(bare, {"above": ABOVE, "below": BELOW}, tails=())
        except Unreadable as again:
            raise Unreadable(str(again if "names both" in str(again) else refused).replace(
                shown(bare), shown(answer), 1)) from None
    if _HEDGED.search(bare):  # 'about 0.37', 'roughly below 1': a prediction is said as it is
        raise Unreadable(f"Could not read {shown(answer)} as 'above' or 'below': write the side, or the number, "
                         "without a hedge.")
    try:
        side, unread = read_word(bare, {"above": ABOVE, "below": BELOW}, tails=()), None
    except Unreadable as refused:  # its reply may say why ('not above': what the factor is not)
        side, unread = None, str(refused).replace(shown(bare), shown(answer), 1)
    bare = _FACTOR_IS.sub("", _LEAD_IN.sub("", bare, count=1), count=1)
    compared = _COMPARED.match(bare)
    values = [float(compared.group(1))] if compared else []
    moved = [(way, float(complement.removeprefix("to "))) for way, complement in parse(bare)
             if _A_NUMBER.fullmatch(complement.removeprefix("to "))]  # 'it drops to 0.37'
    for way, value in moved:  # 'it rises to 0.37': the verb says above, the number below
        if way in ("up", "down") and _side_of(value, answer) != {"up": "above", "down": "below"}[way]:
            raise Unreadable(f"Could not read {shown(answer)} as 'above' or 'below': its verb and its number "
                             "point to different sides.")
    values += [value for _, value in moved]
    if not values:
        try:
            values = [arithmetic(bare) or _number(bare, "a number")]  # '1 / 2.7': by its value
        except Unreadable:
            if side is None:
                raise Unreadable(unread) from None
    sides = {_side_of(value, answer) for value in values} | ({side} if side else set())
    if compared and sides != {"below" if compared.group(2) == "<" else "above"}:
        raise Unreadable(f"Could not read {shown(answer)} as 'above' or 'below': {compared.group(1)} is not "
                         f"{compared.group(2)} 1.")
    if len(sides) != 1:
        raise Unreadable(f"Could not read {shown(answer)} as 'above' or 'below': it names both sides.")
    return sides.pop()


#: a setting named with its value: nu ('nu = 30', '1e5' one value) and the outliers' share ('p = 0.1')
_NU_IS = re.compile(r"(\bnu|\u03bd)\s*(?:=|is\b|of\b)\s*(\d+(?:\.\d+)?(?:e[+-]?\d+)?)(?![\d.])", re.IGNORECASE)
_P_IS = re.compile(r"(\bp|proportion)\s*=\s*(\d*\.?\d+)", re.IGNORECASE)


def _other_setting(text: str, answer, what: str, named: re.Pattern, own: tuple, asks: str) -> None:
    """Raise :class:`~.parsing.Unreadable` where ``text`` names a setting (``named``) at a value the question does
    not ask ('below at nu = 30' for section 3's fit at nu = 3; 'below 1 (p = 0.1)' for the data without outliers)."""
    for _, value in named.findall(text):
        if float(value) not in own:
            name = "nu" if named is _NU_IS else "p"
            raise Unreadable(f"Could not read {shown(answer)} as {what}: it names another setting ({name} = "
                             f"{value}); the question asks {asks}.")


def _clauses_agree(text: str, reader, reasons: str) -> str | None:
    """The answer every clause of ``text`` gives when read alone by ``reader``, where there are two or more, all
    give the same one, none is a reason (``reasons``) and any that only denies one denies another ('0.37, below 1',
    'below 1 (0.37, not 3.3)', 'narrower at 30, wider at 3'); else None."""
    first, asides = _clauses(text.strip())
    if not asides or re.search(rf"\b(?:{reasons})\b", text, flags=re.I):
        return None
    denied = [re.fullmatch(r"\s*(?:but\s+)?not\s+(.+)", clause, flags=re.I) for clause in (first, *asides)]
    try:
        said = {reader(clause) for clause, denial in zip((first, *asides), denied) if not denial}
        others = {reader(denial.group(1)) for denial in denied if denial}
    except Unreadable:
        return None
    if len(said) == 1 and others & said:  # 'below, not below'
        raise Unreadable(f"Could not read {shown(text)}: it denies its own answer.")
    values = {float(clause) for clause in (first, *asides) if re.fullmatch(r"\s*\d*\.?\d+\s*", clause)}
    if len(values) > 1:  # '0.35 (0.37)': two values, whatever their side
        return None
    return said.pop() if len(said) == 1 else None  # '0.37, above 1': refused


#: the question's own nu = 30, said in the subject or in brackets: dropped
_AT_THIRTY = ((rf"\bthe\s+{_NU}30(?:\.0+)?\s+band\b", "the band"),
              (rf"\s*\(\s*(?:at\s+)?(?:{_NU})?30(?:\.0+)?\s*\)", ""),  # 'narrower (nu = 30)', 'narrower (30)'
              (rf"\s*,\s*(?:at|with|for)\s+{_NU}30(?:\.0+)?\s*$", ""),  # 'narrower, not wider, at nu = 30'
              (r"\s*,\s*(?=towards?\s+(?:the\s+)?(?:gp|gaussian))", " "))
#: the band at nu = 3 said in place of the band at nu = 30 ('wider at nu = 3', 'the band at nu = 3 is wider', 'wider
#: as nu shrinks'); at the end only where no comparison precedes it ('narrower than the band at nu = 3' is the
#: question's own)
_AT_THREE = ((rf"^(?!.*\bthan\b)(.*?)\s*,?\s+(?:at|with|for)\s+{_NU}3(?:\.0+)?(?![\d.])\s*$", r"\1"),
             (r"^(?!.*\bthan\b)(.*?)\s+at\s+3(?:\.0+)?\s*$", r"\1"),
             (rf"^\s*(?:at|with|for)\s+{_NU}3(?:\.0+)?(?![\d.])\s*,?\s+", ""),
             (rf"^(\s*(?:the|its)\s+(?:tp'?s?\s+)?band)\s+(?:at|with|for)\s+{_NU}3(?:\.0+)?(?![\d.])", r"\1"),
             (rf"^(\s*the)\s+{_NU}3(?:\.0+)?(?=\s+band\b)", r"\1"),
             (rf"^(.*?)\s+(?:at|with|for)\s+(?:{_NU})?3(?:\.0+)?(?![\d.])(?=\s+than\s+(?:at\s+|with\s+)?(?:{_NU})?30)",
              r"\1"),  # 'wider at nu = 3 than at nu = 30', 'wider at 3 than at 30'
             (rf"^(.*?)\s+than\s+(?:(?:the\s+band\s+)?(?:at|with|for)\s+)?{_NU}30(?:\.0+)?\s*$",
              r"\1"),  # 'wider than at nu = 30'
             (r"^(?!.*\bthan\b)(.*?)\s*,?\s+(?:as|when|while|once)\s+(?:nu|\u03bd)\s+(?:shrinks|decreases|falls|drops|"
              r"goes\s+down|gets\s+(?:smaller|lower))\s*$", r"\1"))  # 'wider as nu shrinks': the way back to 3
#: the comparison the question makes, said after the band at nu = 3 ('... is wider than at nu = 30'): dropped
_THAN_THIRTY = rf"\s+than\s+(?:the\s+(?:band|one)\s+)?(?:(?:at|with|for)\s+)?(?:{_NU})?30(?:\.0+)?\s*$"


#: 2.6's own comparison in brackets, nu = 30 first ("(section 2's TP at nu = 30 against nu = 3)", '(nu = 30 vs 3)')
_OWN_COMPARISON = (r"\s*\(\s*(?:section\s+2'?s?\s+)?(?:the\s+)?(?:tp'?s?\s+)?(?:band\s+)?(?:at\s+)?"
                   rf"(?:{_NU})?30(?:\.0+)?(?:\s*,?\s*(?:against|vs\.?|versus|than|compared\s+(?:with|to))\s+(?:at\s+)?"
                   rf"(?:{_NU})?3(?:\.0+)?)?\s*\)\s*$|"  # '(nu = 30 against nu = 3)'; '(3 -> 30)': nu's own change
                   rf"\s*\(\s*(?:(?:nu|\u03bd)\s*:?\s*)?(?:from\s+)?(?:{_NU})?3(?:\.0+)?\s*(?:->|\u2192|to)\s*"
                   rf"(?:{_NU})?30(?:\.0+)?\s*\)\s*$")
#: nu's change said the other way round in an aside ('narrower (30 -> 3)')
_NU_BACKWARDS = re.compile(rf"\(\s*(?:(?:nu|\u03bd)\s*:?\s*)?(?:from\s+)?(?:{_NU})?30(?:\.0+)?\s*(?:->|\u2192|to)\s*"
                           rf"(?:{_NU})?3(?:\.0+)?\s*\)", re.IGNORECASE)


#: the factor's way said in words or numbers, from nu = 3 to nu = 30 ('the factor drops to 3.5', 'factor 5.1 to 3.5')
_FACTOR_MOVES = re.compile(r"(?:the\s+)?(?:tp'?s\s+)?factor\s+(?:(drops|falls|decreases|shrinks|goes\s+down)|"
                           r"(rises|grows|increases|goes\s+up))?\s*(?:from\s+)?([\d.]+)?\s*(?:to|->|\u2192)\s*([\d.]+)",
                           re.IGNORECASE)
#: the factor compared without a verb ('smaller factor'; '5.10 -> 3.47', from nu = 3's; '3.47 < 5.10', nu = 30's first)
_FACTOR_WORDED = re.compile(r"(?:a\s+)?(?:(smaller|lower)|(larger|bigger|higher))\s+factor", re.IGNORECASE)
_FACTOR_COMPARED = re.compile(r"(?:(?:the\s+)?factor\s+)?(\d+(?:\.\d+)?)\s*(->|\u2192|<|>)\s*(\d+(?:\.\d+)?)",
                              re.IGNORECASE)


def _the_factors(aside: str) -> bool:
    """Whether every number in ``aside`` is section 2's factor at nu = 3 or at nu = 30, to the digits written
    ('5.1 -> 3.47' is; '9 -> 8' is not)."""
    from ..demos import section2_factor

    factors = [section2_factor(nu) for nu in (3.0, 30.0)]
    for number in re.findall(r"\d+(?:\.\d+)?", aside):
        places = len(number.partition(".")[2])
        if not any(abs(factor - float(number)) <= 0.5 * 10.0 ** -places for factor in factors):
            return False
    return True


def _factor_way(aside: str) -> str | None:
    """'narrower' or 'wider': the band's way that an aside about the TP's factor gives ('the factor drops to 3.5',
    'smaller factor', '5.10 -> 3.47', '3.47 < 5.10'), where its words and numbers agree and the factor stays above 1
    (as it does here); else None."""
    said = _FACTOR_MOVES.fullmatch(aside)
    if said:
        way = "narrower" if said.group(1) else "wider" if said.group(2) else None
        start, end = (float(n) if n and re.fullmatch(r"\d+(?:\.\d+)?", n) else None for n in said.group(3, 4))
        moved = None if start is None or end is None or start == end else "wider" if end > start else "narrower"
        return (way or moved) if (way or moved) and (moved or way) == (way or moved) and end is not None and end > 1 \
            else None
    worded = _FACTOR_WORDED.fullmatch(aside)
    if worded:
        return "narrower" if worded.group(1) else "wider"
    compared = _FACTOR_COMPARED.fullmatch(aside)
    if not compared:
        return None
    first, sign, second = float(compared.group(1)), compared.group(2), float(compared.group(3))
    if first == second or min(first, second) <= 1:
        return None
    if sign in ("<", ">"):  # nu = 30's factor first
        return ("narrower" if first < second else "wider") if (first < second) == (sign == "<") else None
    return "narrower" if second < first else "wider"  # from nu = 3's to nu = 30's


def read_band(answer) -> str:
    """'wider' or 'narrower' for the band at nu = 30 against nu = 3 (exercise 2.6): :func:`~.parsing.read_word`
    with :data:`~.parsing.WIDER` and :data:`~.parsing.NARROWER`, the question's own nu = 30 dropped, and the
    band at nu = 3 said instead read as the other side; raises :class:`~.parsing.Unreadable`."""
    options = {"wider": WIDER, "narrower": NARROWER}
    text = _text(answer)
    if text is None:
        return read_word(answer, options)
    _other_setting(text, answer, "'wider' or 'narrower'", _NU_IS, (3.0, 30.0),
                   "about the band at nu = 30 against nu = 3")
    said = re.sub(r"\s*[.!\u2026,;:]+\s*$", "", text.strip())  # 'wider at nu = 3.', 'narrower,'
    said = re.sub(rf"^\s*(?:(?:at|with|for)\s+)?(?:{_NU})?30(?:\.0+)?\s*(?::|,|->|\u2192|(?=\s[a-z]))\s*"
                  rf"(?!.*\b(?:{_NU})?3(?:\.0+)?\s*:)|"
                  rf"^\s*(?:from\s+)?(?:{_NU})?3(?:\.0+)?\s*(?:->|\u2192|to)\s*(?:{_NU})?30(?:\.0+)?\s*:\s*", "",
                  said, flags=re.I)  # 'At nu = 30: it's narrower', 'at nu = 30 narrower', 'from 3 to 30: narrower'
    said = re.sub(r"^\s*(?:(?:with|using)\s+)?(?:section\s+2'?s\s+)?(?:the\s+)?(?:fixed\s+|same\s+)?"
                  rf"(?:hyperparameters|fit)\s*:\s*|"
                  rf"^\s*(?:the\s+)?tp(?:'?s)?\s+band\s+(?:at\s+)?(?:{_NU})?30(?:\.0+)?\s*:\s*", "", said,
                  flags=re.I)  # "with section 2's hyperparameters: narrower", 'TP band at nu = 30: narrower'
    said = re.sub(rf"(?:^|(?<=,\s))(?:at\s+)?(?:{_NU})?(30|3)(?:\.0+)?\s*:\s*([a-z]+)", r"\2 at nu = \1", said,
                  flags=re.I)  # 'nu = 30: narrower, nu = 3: wider', 'at 30: narrower'
    said = rewritten = _denial_said_plainly(said)  # 'not wider but narrower', 'narrower and not wider'
    said = re.sub(_THE_TP, "", said, count=1, flags=re.I)  # 'TP narrower', "the TP's band: narrower"
    said = re.sub(_TP_ASIDE, "", said, flags=re.I)  # 'narrower (TP)'
    said = re.sub(r"\s*,\s*(?=(?:as|when|while|once)\s+(?:nu|\u03bd)\s+(?:grows|increases|rises|goes\s+up|"
                  r"(?:goes|grows|increases|rises|moves)\s+from\s+3\s+to\s+30)\s*$|than\b)",
                  " ", said, flags=re.I)  # 'narrower, as nu grows', 'narrower at nu = 30, than nu = 3'
    said = re.sub(r"\s*[,(]?\s*(?:with|for|using)?\s*(?:section\s+2'?s\s+)?(?:the\s+)?(?:fixed|same)\s+"
                  r"hyperparameters\s*\)?\s*$", "", said, flags=re.I)  # 'narrower (fixed hyperparameters)'
    said = re.sub(_OWN_COMPARISON, "", said, flags=re.I)  # "narrower (section 2's TP at nu = 30 against nu = 3)"
    said = re.sub(rf"\s*\(\s*(than\s+(?:at\s+)?(?:{_NU})?3(?:\.0+)?)\s*\)\s*$|\s*,\s*(?=(?:at\s+)?{_NU}30(?:\.0+)?\s+"
                  r"(?:vs\.?|versus|against|than|instead\s+of)\s)", lambda m: f" {m.group(1)}" if m.group(1) else " ",
                  said, flags=re.I)  # 'narrower at nu = 30 (than at nu = 3)', 'narrower, nu = 30 vs 3'
    for pattern, replacement in _AT_THIRTY:
        said = re.sub(pattern, replacement, said, flags=re.I)
    flipped = False
    for pattern, replacement in _AT_THREE:
        said, found = re.subn(pattern, replacement, said, flags=re.I)
        flipped = flipped or bool(found)
    if flipped:
        said = re.sub(_THAN_THIRTY, "", said, flags=re.I)
        if re.search(rf"\bthan\s+(?:the\s+band\s+)?(?:(?:at|with|for)\s+)?{_NU}3(?:\.0+)?(?![\d.])", said, flags=re.I):
            raise Unreadable(f"Could not read {shown(answer)} as 'wider' or 'narrower': it compares the band at nu = 3 "
                             "with itself.")
    aside = (re.fullmatch(r"(.*?\S)\s*\(\s*([^()]*?)\s*\)", said)
             or re.fullmatch(r"([a-z]+)\s*[:;,\u2013\u2014]\s*(.*?\bfactor\b.*?)", said, flags=re.I))
    if _NU_BACKWARDS.search(said):
        raise Unreadable(f"Could not read {shown(answer)} as 'wider' or 'narrower': its aside runs nu the other way "
                         "(from 30 to 3); the question goes from nu = 3 to nu = 30.")
    factor_way = None if aside is None else _factor_way(aside.group(2))
    other_value = bool(factor_way) and not _the_factors(aside.group(2))  # 'narrower (the factor drops to 2)'
    if factor_way:  # 'narrower (the factor drops to 3.5)': the factor's way, said again
        said = aside.group(1)
    try:
        side = read_word(said, options)
    except Unreadable as refused:
        both_ends = re.sub(r"\s+and\s+(?=(?:but\s+)?(?:wider|narrower|the\s+band)\b.*\b(?:at|with|for)\s+"
                           r"(?:nu\s*=\s*)?3(?:\.0+)?\.?\s*$)", ", ", rewritten, flags=re.I)  # '... and wider at 3'
        agreed = _clauses_agree(both_ends, read_band, "because|since")  # 'narrower at 30, wider at 3'
        if agreed is not None:
            return agreed
        raise Unreadable(str(refused).replace(shown(said), shown(answer), 1)) from None
    side = {"wider": "narrower", "narrower": "wider"}[side] if flipped else side
    if factor_way and factor_way != side:  # 'narrower (the factor rises to 6)'
        raise Unreadable(f"Could not read {shown(answer)} as 'wider' or 'narrower': its aside moves the factor the "
                         "other way.")
    if other_value:
        raise Unreadable(f"Could not read {shown(answer)} as 'wider' or 'narrower': its aside gives the factor a value "
                         "section 2's fit does not have; write the prediction alone.")
    return side
