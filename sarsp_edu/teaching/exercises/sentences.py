"""A closed grammar for a one-sentence prediction of a direction: ``[subject] [verb] [complement]``.

Exercises 2.5 ('above' or 'below' 1) and 2.6 ('wider' or 'narrower') are
answered in words as often as in one word: 'the variance factor fell below
1', 'the TP band has narrowed', "the band's narrower", 'it has grown
narrower'.  Dropping known words from the front of an answer, one list
after another, read such sentences only where the lists happened to hold
them, and read 'it rose below 1' as 'below'.  Here a sentence is read
whole, against three closed parts:

- a subject (optional): a determiner, an owner, modifiers and a noun ('the
  TP's fitted variance factor', 'its band', 'it', 'beta / n');
- a verb (optional), each form of each verb listed with the way it moves:
  up ('rose', 'has increased'), down ('fell', 'has dropped'), a band's
  ways ('narrows', 'widens': no answer to 'above or below'), or none ('is',
  'will be', 'comes out'); 'grow' is 'become' before a comparative ('grew
  narrower') and up elsewhere; 'stay' and 'remain' take a side or a
  comparative ('stays below 1'), never a state ('it stays narrow': no change);
- a complement (optional): the rest, which the caller looks up among the
  spellings of its options ('below 1', 'narrower than before').

A verb that moves one way with a complement of the other ('rose below 1',
'it shrank wider') is no answer, and a sentence that asks ('is it below
1') is none either: :func:`parse` returns no reading for them.

Examples
--------
>>> ("down", "below 1") in parse("the variance factor fell to below 1")
True
>>> (None, "narrower") in parse("it has grown narrower")
True
>>> parse("is it below 1")
[]
"""

from __future__ import annotations

import re
import unicodedata

__all__ = ["QUESTION", "number_spelled", "parse", "said_in_words", "spelled"]

_DETERMINERS = {"the", "a", "an", "its", "this", "that", "our", "my"}
_OWNERS = {"tp's", "tp", "tps", "student-t", "student-t's", "t", "process's", "model's", "fit's"}
_MODIFIERS = {"fitted", "variance", "predictive", "posterior", "confidence", "uncertainty", "error", "scale"}
_NOUNS = {"band", "bands", "factor", "ratio", "variance_scale_", "beta/n", "it", "width", "variance", "interval",
          "spread"}

#: each verb: its base, third person, past, participle and -ing forms ('_' joins the words of one form), and the
#: way it moves ('-' for none; 'grow' is apart)
_VERB_FORMS = """
be is was been being -             become becomes became become becoming -   get gets got gotten getting -
stay stays stayed stayed staying stay remain remains remained remained remaining stay
end_up ends_up ended_up ended_up ending_up -                     end ends ended ended ending -
come_out comes_out came_out come_out coming_out -                turn_out turns_out turned_out turned_out turning_out -
go goes went gone going -          lie lies lay lain lying -     sit sits sat sat sitting -
land lands landed landed landing -
fall falls fell fallen falling down                  drop drops dropped dropped dropping down
decrease decreases decreased decreased decreasing down
sink sinks sank sunk sinking down                    shrink shrinks shrank shrunk shrinking down
dip dips dipped dipped dipping down                  go_down goes_down went_down gone_down going_down down
reduce reduces reduced reduced reducing down         decline declines declined declined declining down
narrow narrows narrowed narrowed narrowing narrows   tighten tightens tightened tightened tightening narrows
contract contracts contracted contracted contracting narrows
rise rises rose risen rising up                      climb climbs climbed climbed climbing up
increase increases increased increased increasing up go_up goes_up went_up gone_up going_up up
widen widens widened widened widening widens         broaden broadens broadened broadened broadening widens
grow grows grew grown growing grow
"""
_VERBS = [(tuple(form.replace("_", " ") for form in words[i:i + 5]), None if words[i + 5] == "-" else words[i + 5])
          for words in [_VERB_FORMS.split()] for i in range(0, len(words), 6)]
#: what may stand before a verb's form: ('will', base), ('has', participle), ('is', -ing) ...; "'s" and "'ll" as
#: in "it's fallen", "it'll fall"
_BEFORE = {0: ("", "will ", "would ", "should ", "shall ", "'ll ", "is going to ", "'s going to ", "going to ",
               "will then ", "to "),
           1: ("",), 2: ("",), 3: ("has ", "have ", "had ", "has now ", "will have ", "is ", "was ", "will be ",
                                   "has been ", "is being ", "'s "),
           4: ("", "is ", "was ", "will be ", "has been ", "keeps ", "'s ")}  # 'decreasing' alone too
#: what a band or a factor that stays or remains cannot be: its state, not a change ('it stays narrow')
_UNCHANGED = {"narrow", "wide", "broad", "tight", "thin", "the", "same", "unchanged", "as", "constant", "put"}
#: a sentence that asks: it is no prediction ('is it below 1', 'does the band narrow')
QUESTION = re.compile(r"^(is|are|was|does|do|did|will|would|could|can|should|has|have)\s+(it|its|the|this|that|tp)\b")


def _verb_table() -> dict:
    table = {}
    for forms, way in _VERBS:
        for slot, form in enumerate(forms):
            for before in _BEFORE[slot]:
                table.setdefault(tuple((before + form).split()), way)
    for form in ("is", "was", "'s"):  # 'is' alone, and the contraction: "the band's narrower"
        table[(form,)] = None
    return table


_TABLE = _verb_table()
_LONGEST = max(len(words) for words in _TABLE)


def _words(text: str) -> list:
    text = text.strip().lower().replace("\u2019", "'")
    text = re.sub(r"\bbeta_?\s*(?:/|over)\s*n\b", "beta/n", text)
    text = re.sub(r"\b(it|band|factor|variance|beta/n)'(s|ll)\b", r"\1 '\2", text)  # "it's", "the band's", "it'll"
    text = re.sub(r"\bband\s+(?:at|with|for)\s+(?:nu|\u03bd)\s*=\s*30(?![\d.])", "band", text)  # 2.6's own nu
    return text.split()


def _subjects(words: list) -> list:
    """Where a subject may end: 0 (none), and after each reading of a determiner, owners, modifiers, a noun."""
    ends = [0]
    i = 0
    if i < len(words) and words[i] in _DETERMINERS:
        i += 1
        ends.append(i)  # 'a narrower band': a determiner alone
    while i < len(words) and (words[i] in _OWNERS or words[i] in _MODIFIERS):
        i += 1
        if words[i - 1] in _NOUNS:  # 'variance' is a noun too
            ends.append(i)
    if i < len(words) and words[i] in _NOUNS and not (words[i] == "it" and i > 0):
        ends.append(i + 1)
    return sorted(set(ends))


def _comparative(complement: str) -> bool:
    first = complement.split()[0] if complement.split() else ""
    return first in ("more", "less") or (first.endswith("er") and first not in ("over", "under"))


def parse(text: str) -> list:
    """Each reading of ``text`` as ``(way, complement)``: ``way`` the verb's ('up', 'down', 'narrows',
    'widens' or None, also for no verb), ``complement`` the words after it ('' for none); every way of cutting
    the sentence is a reading, and the caller keeps those whose complement it knows and whose verb moves its
    way.  A question has no reading."""
    words = _words(text)
    if QUESTION.match(" ".join(words)):
        return []
    readings = []
    for start in _subjects(words):
        readings.append((None, " ".join(words[start:])))
        for length in range(min(_LONGEST, len(words) - start), 0, -1):
            way = _TABLE.get(tuple(words[start:start + length]), "absent")
            if way == "absent":
                continue
            complement = " ".join(words[start + length:])
            if way == "grow":
                way = None if complement and _comparative(complement) else "up"
            if way == "stay":  # 'stays below 1', 'stays narrower'; not 'stays narrow' (no change)
                if not complement or complement.split()[0] in _UNCHANGED:
                    continue
                way = None
            if way is not None and complement.startswith("to "):  # 'fell to below 1'
                readings.append((way, complement[3:]))
            readings.append((way, complement))
    return [reading for reading in dict.fromkeys(readings) if reading != (None, "")]


#: the words a direction is said in, for :func:`spelled`: the comparatives and the forms of each verb that moves
_DIRECTIONS = frozenset({"above", "below", "under", "beneath", "greater", "larger", "bigger", "higher", "lower",
                         "smaller", "wider", "narrower", "broader", "tighter", "thinner", "slimmer", "narrow",
                         *(word for forms, way in _VERBS if way not in (None, "stay") for form in forms
                           for word in form.split())})
#: the grammar's other words: never taken for a slip ('bands' is not 'lands')
_KNOWN = _DIRECTIONS | _DETERMINERS | _OWNERS | _MODIFIERS | _NOUNS | _UNCHANGED | {
    word for forms, _ in _VERBS for form in forms for word in form.split()}


def _one_slip(word: str, known: str) -> bool:
    """Whether ``word`` is ``known`` with one letter added, dropped, changed, or two neighbours swapped."""
    if abs(len(word) - len(known)) > 1 or word == known:
        return False
    start = next((i for i, (a, b) in enumerate(zip(word, known)) if a != b), min(len(word), len(known)))
    if len(word) == len(known):
        swapped = word[start + 1:start + 2] + word[start:start + 1] == known[start:start + 2]
        return word[start + 1:] == known[start + 1:] or (swapped and word[start + 2:] == known[start + 2:])
    longer, shorter = (word, known) if len(word) > len(known) else (known, word)
    return longer[start + 1:] == shorter[start:]


def spelled(text: str) -> str:
    """``text`` with each word of four letters or more that is one slip from a direction word of five or more (and
    is no word of the grammar itself) spelt as that word: 'beloww', 'Belwo', 'belo' -> 'below'; 'narower' ->
    'narrower'.  A slip that could be two words is mended only where both are forms of one word ('narrowe':
    'narrower' or 'narrowed', both narrowing); else ('lowe': 'lower' or 'lowed') it is left as it is, and so
    unread."""
    def mend(match):
        word = match.group(0)
        if len(word) < 4 or word.lower() in _KNOWN:
            return word
        near = sorted(known for known in _DIRECTIONS if len(known) >= 5 and _one_slip(word.lower(), known))
        one_word = near and all(known[:6] == near[0][:6] and len(known) >= 6 for known in near)
        return near[0] if len(near) == 1 or one_word else word
    return re.sub(r"[A-Za-z]+", mend, text)


_DIGITS = dict(zip("zero nought oh one two three four five six seven eight nine".split(), "000123456789"))
_PARTS = {"half": 2, "third": 3, "quarter": 4, "fifth": 5, "tenth": 10}


def said_in_words(text: str) -> str:
    """A value said in words as the number ('one half', 'two thirds' -> '1/2', '2/3'; 'zero point
    three seven' -> '0.37'), its range ('less than one and more than zero', 'under 1, over 0') as 'between 0 and
    1', 'at 0.37' as '0.37'; else ``text``."""
    words = text.strip().lower()
    if len(words) == 1 and unicodedata.numeric(words, None) is not None and not words.isdigit():  # '½'
        return repr(unicodedata.numeric(words))
    part = re.fullmatch(r"(?:the\s+factor\s+is\s+)?(a|one|two|three|four)(?:\s+|\s*-\s*)(half|third|quarter|fifth|"
                        r"tenth)s?", words)  # 'one third', 'one-third'
    if part:
        return f"{'1' if part.group(1) in ('a', 'one') else _DIGITS[part.group(1)]}/{_PARTS[part.group(2)]}"
    point = re.fullmatch(r"(?:(zero|nought|oh|one|two)\s+)?point((?:\s+(?:zero|nought|oh|one|two|three|four|five|six|"
                         r"seven|eight|nine))+)", words)  # 'zero point three seven', 'point three seven'
    if point:
        return _DIGITS[point.group(1) or "zero"] + "." + "".join(_DIGITS[word] for word in point.group(2).split())
    below_one = r"(?:less\s+than|below|under|smaller\s+than)\s+(?:1|one)"
    above_zero = r"(?:more\s+than|above|over|greater\s+than)\s+(?:0|zero)"
    if re.fullmatch(rf"(?:(?:the\s+factor|it)\s+is\s+)?(?:{below_one}\s*(?:,|and|but)?\s*{above_zero}|"
                    rf"{above_zero}\s*(?:,|and|but)?\s*{below_one})", words):
        return "between 0 and 1"
    return re.sub(r"^\s*at\s+(?=\d)", "", text)  # 'less than 1, at 0.37': its value


#: the words a limit or a count is written with, whose one-letter slips are mended (:func:`number_spelled`)
_NUMBER_WORDS = ("zero one two three four five six seven eight nine ten eleven twelve thirteen fourteen fifteen "
                 "sixteen seventeen eighteen nineteen twenty thirty forty fifty sixty seventy eighty ninety hundred "
                 "infinity").split()


def number_spelled(text: str) -> str:
    """``text``, where it is one word of four letters or more that is no number word but one slip from exactly
    one ('fiftty', 'fity', 'infinty', 'zeor'), spelt as that word ('fourty' -> 'forty'); else as it is (a slip
    inside a sentence is not mended: 'then' is a word, not 'ten')."""
    word = text.strip().lower()
    if not re.fullmatch(r"[a-z]{4,}", word) or word in _NUMBER_WORDS:
        return text
    near = [known for known in _NUMBER_WORDS if _one_slip(word, known)]
    return near[0] if len(near) == 1 else text
