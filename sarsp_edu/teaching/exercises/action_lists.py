"""Reading a list of actions as a student writes it (exercise 4.4): ``[0, 2]``, ``"0, 2"``, ``"RIGHT and LEFT"``,
``"0 (RIGHT), 2 (LEFT)"``, ``"all but 3"``, ``"0; 2"``, a boolean mask of the four actions; not a list that
goes on (``"0, 2, ..."``) or a count (``"3 actions"``).

Examples
--------
>>> read_actions("RIGHT (0), LEFT (2)"), read_actions("all but UP"), read_actions("only 0")
([0, 2], [0, 1, 2], [0])
>>> read_actions("0 (DOWN)")  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
sarsp_edu.teaching.exercises.parsing.Unreadable: '0 (DOWN)' names action 0 as DOWN: RIGHT = 0, DOWN = 1, ...
"""

from __future__ import annotations

import re

import numpy as np

from .parsing import _DOUBT, _LEAD_IN, Unreadable, _number, _text, exactly
from .sentences import _one_slip
from .wording import shown

__all__ = ["read_actions"]

#: the actions' names, for answers that name them
_ACTIONS = {"right": 0, "down": 1, "left": 2, "up": 3}
_NAMES = "RIGHT = 0, DOWN = 1, LEFT = 2, UP = 3"
#: an action said with its name beside its number, either way round: 'RIGHT (0)', '0 (RIGHT)', '0 -> RIGHT',
#: 'RIGHT: 0', '0 \u2192 RIGHT'
_PAIRED = r"\s*(?:-->|->|=>|\u2192|\u21d2|\u27f6|:|=)\s*"
#: each as (pattern, name first, read only where the whole answer is such pairs: '0, 1, 2: RIGHT, DOWN, LEFT' is
#: not '2: RIGHT')
_NAMED = ((re.compile(r"\b(right|down|left|up)\s*\(\s*([0-3])\s*\)", re.IGNORECASE), True, False),
          (re.compile(r"\b([0-3])\s*\(\s*(right|down|left|up)\s*\)", re.IGNORECASE), False, False),
          (re.compile(rf"\b(right|down|left|up){_PAIRED}([0-3])(?![\w.])", re.IGNORECASE), True, True),
          (re.compile(rf"(?<![\w.])([0-3]){_PAIRED}(right|down|left|up)\b", re.IGNORECASE), False, True))
#: every action but some: 'all but 3', 'everything except UP', 'all actions except 3'
_ALL_BUT = re.compile(r"^\s*(?:all|any(?:thing)?|every(?:thing|\s+action)?|all\s+(?:the\s+)?actions)\s+"
                      r"(?:but|except)\s+(.+)$",
                      re.IGNORECASE)


def _unnamed(text: str, answer) -> str:
    """``text`` with each 'NAME (n)' or 'n (NAME)' said as its number, once they agree."""
    for pattern, name_first, whole in _NAMED:
        if whole and not re.fullmatch(rf"\s*(?:{pattern.pattern})(?:\s*(?:[,;&]|\band\b)\s*(?:{pattern.pattern}))*\s*",
                                      text, flags=re.IGNORECASE):
            continue
        for match in pattern.finditer(text):
            name, number = match.groups() if name_first else match.groups()[::-1]
            if _ACTIONS[name.lower()] != int(number):
                raise Unreadable(f"{shown(answer)} names action {number} as {name.upper()}: {_NAMES}.")
        text = pattern.sub(lambda m, first=name_first: m.group(2) if first else m.group(1), text)
    return text


def read_actions(answer) -> list[int]:
    """Action numbers 0-3, sorted and once each, from a list, set, array, a 4-long boolean mask or text; raises
    :class:`~sarsp_edu.teaching.exercises.parsing.Unreadable`."""
    text = _text(answer)
    if text is not None:
        return _read_text(text, answer)
    if isinstance(answer, dict) and sorted(answer) == [0, 1, 2, 3] and all(
            isinstance(flag, (bool, np.bool_)) for flag in answer.values()):  # {0: True, 1: False, ...}: a mask
        return [action for action in range(4) if answer[action]]
    if isinstance(answer, (list, tuple, set, frozenset)) and len({isinstance(item, (bool, np.bool_))
                                                                for item in answer}) > 1:
        raise Unreadable(f"Could not read {shown(answer)} as a list of action numbers: it mixes True or False with "
                         "action numbers (True is no action).")  # [True, 3] is not [1, 3]
    if isinstance(answer, (int, np.integer)) and not isinstance(answer, (bool, np.bool_)):
        answer = [answer]
    try:
        array = np.asarray(list(answer) if isinstance(answer, (set, frozenset)) else answer)
    except (TypeError, ValueError, OverflowError):
        array = None
    if array is not None and array.ndim == 1 and array.dtype.kind == "b" and len(array) == 4:
        return [int(a) for a in np.flatnonzero(array)]  # the safe set as a mask of the four actions
    if array is None or array.ndim != 1 or (array.size and array.dtype.kind == "b"):
        raise Unreadable(f"Could not read {shown(answer)} as a list of action numbers.")
    return _numbered(array.tolist())


#: every action, or none: 'all', 'all four', 'every action', 'none of them'
_EVERY = re.compile(r"^\s*(?:all(?:\s+(?:four|4))?(?:\s+(?:of\s+(?:them|the\s+actions))|\s+actions?)?|"
                    r"every(?:\s+action|\s+one|thing)?|0\s*-\s*3|0\s+(?:to|through)\s+3)\s*$", re.IGNORECASE)
_NONE = re.compile(r"^\s*(?:none(?:\s+of\s+(?:them|the\s+four(?:\s+actions)?))?|there\s+are\s+none|nothing|empty|"
                   r"no\s+(?:safe\s+)?actions?|no|\[\s*\]|\u2205|(?:the\s+)?empty\s+set|set\(\))\s*$", re.IGNORECASE)
#: the actions drawn as arrows ('→ and ↑')
_ARROWS = str.maketrans({"\u2192": " right ", "\u2193": " down ", "\u2190": " left ", "\u2191": " up ",
                         "\u27a1": " right ", "\u2b95": " right ", "\u2b07": " down ", "\u2b05": " left ",
                         "\u2b06": " up ", "\ufe0f": ""})  # and as emoji, their variation selector dropped


#: what a list of actions alone does not hold: a clause, an aside, a reason, what is not safe, an addition
_MORE = re.compile(r"[;:\u2013\u2014()]|\s-\s|\b(?:but|because|since|as|not|unsafe|also|too|except|if|when)\b",
                   re.IGNORECASE)


def _read_text(text: str, answer) -> list[int]:
    what = "a list of action numbers"
    spanned = re.fullmatch(r"\s*([0-3])\s*(?:-|\u2013|to|through)\s*([0-3])\s*", text, flags=re.I)
    if spanned and int(spanned.group(1)) < int(spanned.group(2)):  # '0-2', '0 to 2': the actions from one to another
        return list(range(int(spanned.group(1)), int(spanned.group(2)) + 1))
    text = re.sub(r"\s*[\u2013\u2014]\s*(?=not\b)", ", ", text, flags=re.I)  # '0, 1, 2 \u2014 not 3'
    text = re.sub(r"(\bnot\s+\w+)\s+or\s+(?=\w)", r"\1 and ", text, flags=re.I)  # '0 and 3, not 1 or 2': a denial
    for _ in range(2):  # 'not 1 and not 2', 'not 1, not 2': one denial of both
        text = re.sub(r"(\bnot\s+\w+)\s*(?:,|\band\b|&)\s*not\s+", r"\1 and ", text, flags=re.I)
    unsafe = r"(?:(?:(?:is|are)\s+)?(?:unsafe|not\s+safe)|(?:is|are)\s+not)"  # '3 is unsafe', 'UP unsafe', 'UP is not'
    text = re.sub(rf"\(\s*([\w\s,&]+?)\s+{unsafe}\s*\)", r"(not \1)", text, flags=re.I)  # '0, 1, 2 (3 is unsafe)'
    text = re.sub(rf"^\s*([\w\s,&]+?)\s+{unsafe}\s*[:;]\s*(.+)$", r"\2, not \1", text, flags=re.I)  # '3 is unsafe: 0'
    text = re.sub(r"^\s*\(([^()]*)\)\s*(?:,?\s*and\s+|,\s*)(?:but\s+)?not\s+", r"\1, not ", text,
                  flags=re.I)  # '(0, 1) and not 3'
    text = re.sub(rf"^(.*?)\s+(?:(?:is|are)\s+)?safe\s*[,;]\s*(?:and\s+|but\s+)?(.+?)\s+{unsafe}\s*$", r"\1, not \2",
                  text,
                  flags=re.I)  # '0, 1, 2 are safe, 3 is unsafe'
    text = re.sub(r"^(.*?\S)\s*\(\s*((?:but\s+)?not\s+[^()]+?)\s*\)\s*\.?\s*$", r"\1, \2", text,
                  flags=re.I)  # '0, 3 (not 1, 2)'
    text = re.sub(r"^\s*not\s+([^:;]+?)\s*(?:[:;]|\s+but(?=\s))\s*(.+?)\s*$", r"\2, not \1", text,
                  flags=re.I)  # 'not 1, 2; 0, 3', 'not 3 but 0, 1, 2'
    text = re.sub(r"^(.*?)(?:\s+(?:are|is)\s+safe\s*[,;]|\s*;)\s*(?:but\s+|and\s+)?(.*?)\s+(?:are|is)\s+not(?:\s+safe)?"
                  r"\s*$", r"\1, not \2", text, flags=re.I)  # '0, 3; 1 and 2 are not', '0, 3 are safe, 1, 2 are not'
    if not re.search(r"\d|right|down|left|up", text, flags=re.I):  # '→ and ↑' (not 'safe actions → 0, 2')
        text = re.sub(r"<-+(?!>)", " left ", re.sub(r"(?<!<)-+>", " right ", text)).translate(_ARROWS)  # '->', '<-'
    text = _mended(text)
    text = re.sub(r"^\s*none\s+but\s+", "only ", text, flags=re.I)  # 'none but 0 and 3'
    if re.fullmatch(r"\s*(?:not|never)\s+[^:;()]+", text, flags=re.I):  # 'not 3': what the answer is not
        raise Unreadable(f"Could not read {shown(answer)} as {what}: it says which actions are not safe; name those "
                         "that are.")
    unsafe = re.fullmatch(r"\s*(.+?)\s+(?:are|is)\s+(?:unsafe|not\s+safe)\s*\.?\s*", text, flags=re.I)
    if unsafe and not re.search(r"\bsafe\b", unsafe.group(1), flags=re.I):  # '1, 2 are unsafe': the others are safe
        text = f"all but {unsafe.group(1)}"
    if _DOUBT.search(text):
        raise Unreadable(f"Could not read {shown(answer)} as {what}: it doubts its own answer.")
    if re.search(r"\.{2,}|\u2026|\betc\b|\band\s+so\s+on\b", text, flags=re.I):  # '0, 2, ...': the list goes on
        raise Unreadable(f"Could not read {shown(answer)} as {what}: it says the list goes on; name every safe action.")
    if any(text.count(opening) != text.count(closing) for opening, closing in ("[]", "()", "{}")) or re.search(
            r"^\s*[\[({]\s*[\[({]|\[[^\]]*\[|\][\s,;&]*(?:and\s*)?\[", text,
            flags=re.I):  # '[0, 1, 3', '[[0, 1, 3]]', '[0, [1, 2]]', '[0, 1, 2], [3]': not one list
        raise Unreadable(f"Could not read {shown(answer)} as {what}: its brackets do not make one list.")
    # the question's own sigma*^2 = 10 and d = 1, said after the list: dropped (another value is refused below)
    threshold = (r"(?:(?:sigma|\u03c3)(?:_?\*|\u2217)?(?:\^2|\*\*2|\u00b2|\s+squared)|the\s+threshold)\s*=\s*"
                 r"(?:10(?:\.0*)?|1(?:\.0*)?e\+?0*1)(?![\d.])(?:\s+instead\s+of\s+0\.8)?")  # '10', '1e1'
    own = rf"(?:{threshold}|d\s*=\s*1(?:\.0*)?(?![\d.]))"
    text = re.sub(rf"\s*(?:,|\()?\s*(?:with|at|for|when)\s+{own}(?:\s*(?:,|and)\s*{own})?\s*\)?\s*$|"
                  rf"\s*\(\s*{own}(?:\s*(?:,|and)\s*{own})?\s*\)\s*$|\s*,?\s+for\s+the\s+gp(?:'s\s+decision)?\s*$|"
                  r"\s*\(\s*(?:at|with)\s+10(?:\.0*)?\s*\)\s*$",
                  "", text, flags=re.I)  # '0, 3 (sigma*^2 = 10, d = 1)', '0 and 3 for the GP'
    again = re.fullmatch(r"(.*?\S)\s*\(\s*((?:all|every)[^()]*|[\w\s,&]+)\)\s*", text, flags=re.I)
    if again:  # '0, 1, 2 (all but UP)', '0, 1, 2 (RIGHT, DOWN, LEFT)': the same actions said again in brackets
        try:
            first, second = (_read_text(part, answer) for part in again.groups())
        except Unreadable:
            first, second = None, None
        if first is not None and first == second:
            return first
    text = re.sub(rf"^\s*(?:(?:with|at|for|when)\s+)?{own}(?:\s*(?:,|and)\s*{own})?\s*(?:[:,]|->|=>|\u2192|\u21d2)\s*",
                  "", text, flags=re.I)  # 'sigma*^2 = 10: 0, 1, 2', 'σ*^2=10 → 0, 1, 2': the question's own first
    restated = re.fullmatch(r"(.*?)\s*,?\s*(?:i\.\s*e\.?|that\s+is|namely)\s*,?\s*(.*)", text, flags=re.I)
    if restated:  # 'right and up, i.e. 0 and 3': the same actions said twice
        first, second = (_read_text(part, answer) for part in restated.groups())
        if first != second:
            raise Unreadable(f"{shown(answer)} names other actions after 'i.e.' than before it.")
        return first
    text = re.sub(r"(?<=[\d\])}A-Za-z])\s*[,;]\s*$", "", text)  # '0, 2,', '[0, 2],', 'RIGHT, LEFT;': a trailing mark
    if re.search(r",\s*,", text):  # '0,,3': a place with no action in it
        raise Unreadable(f"Could not read {shown(answer)} as {what}: it has an empty place between two commas.")
    if re.search(r"(?:\s(?:with|at|for|when)\s+|\(\s*|^\s*)(?:sigma|\u03c3|d\s*=|the\s+threshold)", text, flags=re.I):
        raise Unreadable(f"Could not read {shown(answer)} as {what}: the question asks for the safe actions with "
                         "sigma*^2 = 10 and d = 1, not another setting.")
    text = _numpy_printed(_LEAD_IN.sub("", text, count=1).strip().rstrip(".!\u2026"))
    if re.search(r"\b(?!set\(\))(?!(?:right|down|left|up)\s*\(\s*[0-3]\s*\))[A-Za-z_][\w.]*\(", text,
                 flags=re.I):  # 'range(0, 4, 3)': a call, not its value ('RIGHT(0)' names an action)
        raise Unreadable(f"Could not read {shown(answer)} as {what}: it is a Python call; write the actions themselves "
                         "('0, 2').")
    if re.fullmatch(r"[\s\[\](),;]*[0-3]{2,}[\s\[\](),;]*", text):  # '03': two actions run together
        raise Unreadable(f"Could not read {shown(answer)} as {what}: write the actions apart ('0, 3').")
    mask = re.fullmatch(r"\[?\s*((?:(?:True|False)\s*,?\s*){4})\]?", text)
    if mask:  # a boolean array of the four actions as numpy prints it: '[ True False  True False]'
        return [a for a, flag in enumerate(re.findall(r"True|False", mask.group(1))) if flag == "True"]
    text = _names_beside(_unnamed(text, answer), answer)
    if re.search(r"(?:,|\band|\bor|&)\s*$", text, flags=re.I):  # '0, 2 and': the list is cut off
        raise Unreadable(f"Could not read {shown(answer)} as {what}: it ends before its last action.")
    text = _LABEL.sub("", text, count=1)  # 'Safe actions: 0, 2'
    if re.fullmatch(r"\s*\(\s*\)\s*", text):  # '()': the empty tuple, as Python prints it
        return []
    text = re.sub(r"^\((.*)\)$", r"\1", text.strip())  # '(0, 2)', a tuple as Python prints it
    text = re.sub(r"\b(right|down|left|up)\s*=\s*([0-3])\b", _named_equals(answer), text, flags=re.I)
    text = re.sub(r"\bboth\s+(?![-=:>\u2192])|\bas\s+well\s+as\b",
                  lambda m: "" if m.group(0).startswith("both") else " and ", text, flags=re.I)
    # 'two actions: 0 and 2', 'the three safe ones 0, 1, 2', '1 safe one: 3', 'both: 0 and 2', 'two actions -> 0, 2':
    # a count before the list, said as one after it ('2: LEFT' may name action 2: a digit is a count only with
    # 'actions' after it)
    before = _COUNT_FIRST.match(text)
    if before:
        listed = re.sub(r"[])}]\s*$", "", before.group("list"))  # '(0, 2)': its closing bracket too
        count = next(group for group in before.group("counted", "bare", "single") if group)
        text = f"{listed} ({'two' if count.lower() == 'both' else count} actions)"
    # '0, 1 and 2 (three actions)': a count of them beside the list, checked against it
    counted = re.search(r"\s*\(\s*(one|two|three|four|[1-4])\s+(?:safe\s+)?actions?\s*\)", text, flags=re.I)
    if counted:
        text = text[:counted.start()] + text[counted.end():]
    said = re.sub(r"\b(actions?|are|is|the|safe|ones|moves?|only|just)\b", " ", text, flags=re.I).strip()
    everything_but = _ALL_BUT.match(said)
    every = [0, 1, 2, 3] if _EVERY.match(text) or _EVERY.match(said) else None
    every = [] if every is None and (_NONE.match(text) or _NONE.match(said)) else every
    if every is not None:
        if counted and _COUNTS[counted.group(1).lower()] != len(every):  # 'all (three actions)'
            raise Unreadable(f"{shown(answer)} counts {counted.group(1)} where it names {len(every)} actions.")
        return every
    count = _COUNTED.search(text)  # '3 actions', 'three safe actions': how many, not which
    if count:
        if count.group(1).lower() in ("0", "zero") and re.fullmatch(r"\s*(?:0|zero)\s*", said, flags=re.I):
            return []  # 'zero actions', 'zero safe actions are safe': none
        raise Unreadable(f"Could not read {shown(answer)} as {what}: it counts the safe actions; name them (for "
                         f"example '0, 2').")
    said = _without_denied(said, answer)  # '0 and 3, not 1': emphasis, when the denied actions are not in the list
    semicolons = re.fullmatch(rf"[\s\[\]()]*{_ITEM}(?:\s*;\s*{_ITEM})+[\s\[\]()]*", said, flags=re.I)  # '0; 2'
    if not semicolons and _MORE.search(everything_but.group(1) if everything_but else said):
        raise Unreadable(f"Could not read {shown(answer)} as {what}: write the safe actions alone (for example "
                         "'0, 2'), as the question asks; anything more (a reason, another condition, an aside) belongs "
                         "in the written answer below.")
    items = [item for item in re.split(_SEPARATORS,
                                       everything_but.group(1) if everything_but else said, flags=re.I) if item]
    if not items:  # '', 'Safe actions:', 'and': no action named, which is not 'none'
        raise Unreadable(f"Could not read {shown(answer)} as {what}: it names no action (write 'none' for none).")
    actions = _numbered(items)
    actions = sorted(set(range(4)) - set(actions)) if everything_but else actions
    if counted and _COUNTS[counted.group(1).lower()] != len(actions):
        plural = "s" if _COUNTS[counted.group(1).lower()] > 1 else ""
        raise Unreadable(f"{shown(answer)} counts {counted.group(1)} action{plural} where its list holds "
                         f"{len(actions)}.")
    return actions


#: a count of actions ('3 actions', 'three safe actions', 'two moves'), where the actions themselves are asked
_COUNTED = re.compile(r"\b(zero|one|two|three|four|\d+)\s+(?:(?:safe\s+)?(?:actions?|moves?|ones)|safe\s+one)\b",
                      re.IGNORECASE)
#: one action, by number or name
_ITEM = r"(?:[0-3]|zero|one|two|three|right|down|left|up)"
_COUNTS = {"one": 1, "two": 2, "three": 3, "four": 4, "1": 1, "2": 2, "3": 3, "4": 4}
#: what stands between a list's actions ('0, 2', '0 and 2', "['RIGHT', 'LEFT']", 'RIGHT or LEFT' once 'or' is
#: not a doubt)
_SEPARATORS = r"(?:[\s,;&+/\[\]{}'\"]|\band\b|\bor\b)+"
#: a count of the actions, then their list: 'two actions: 0, 2', 'the three safe ones 0, 1, 2', '1 safe one: 3',
#: 'both: 0 and 2', "two actions -> ['RIGHT', 'LEFT']"
_COUNT_FIRST = re.compile(
    rf"^\s*(?:the\s+)?(?:(?P<counted>one|two|three|four|[1-4])\s+(?:safe\s+)?(?:actions?|moves?|ones)|"
    rf"(?P<single>one|1)\s+safe\s+one|(?P<bare>one|two|three|four|both)(?=\s*(?::|->|=>|\u2192)))\s*"
    rf"(?::\s*->|-->|->|=>|\u21d2|\u2192|:|=|are|-|\u2013|\u2014)?\s*[\[({{]?\s*['\"]?(?P<list>{_ITEM}\b.*)$",
    re.IGNORECASE)
#: a label before the list ('Safe actions: 0, 2', 'Safe: 0 and 2', 'actions: 0, 2')
_LABEL = re.compile(r"^\s*(?:the\s+)?(?:safe\s+actions?|safe|actions?)(?:\s+are)?\s*"
                    r"(?::\s*->|-->|->|\u2013>|=>|\u21d2|\u27f6|\u2192|:|=|-|\u2013|\u2014)\s*", re.IGNORECASE)


def _mended(text: str) -> str:
    """``text`` with an action's name one slip off spelt right ('RIHGT' -> 'right'), where it is no other name."""
    def mend(match):
        word = match.group(0).lower()
        near = [name for name in ("right", "down", "left", *(("up",) if len(word) == 3 and word[0] == "u" else ()))
                if _one_slip(word, name)]  # 'RIHGT', 'upp'
        return near[0] if len(near) == 1 and word not in _ACTIONS and word not in ("done", "lift", "light") else \
            match.group(0)
    return re.sub(r"[A-Za-z]{3,6}", mend, text)


def _numpy_printed(text: str) -> str:
    """A list as numpy prints it, read as the list: 'array([0, 2])', '(array([0, 2]),)' (np.nonzero's answer),
    '[np.int64(0), np.int64(2)]'."""
    text = re.sub(r"\bnp\.(?:u?int\d*|intp)\(\s*(\d+)\s*\)", r"\1", text)
    inner = re.fullmatch(r"\(?\s*array\((\[[^\[\]]*\])(?:\s*,\s*dtype=\w+)?\)"
                         r"\s*(?:,\s*\))?", text)
    return inner.group(1) if inner else text


def _names_beside(text: str, answer) -> str:
    """``text`` with the actions' names in brackets after their numbers dropped, once they agree ('0 and 2 (RIGHT
    and LEFT)', '[0, 2] (RIGHT, LEFT)')."""
    named_first = re.fullmatch(r"\s*((?:right|down|left|up)(?:\s*(?:,|and|&)?\s*(?:right|down|left|up))*)\s*\(\s*"
                               r"([0-3](?:\s*(?:,|and|&)?\s*[0-3])*)\s*\)\s*", text, flags=re.I)
    if named_first:  # 'RIGHT and LEFT (0 and 2)': the numbers in brackets after the names
        text = f"{named_first.group(2)} ({named_first.group(1)})"
    beside = re.fullmatch(r"(.*?[\d\]])\s*\(\s*((?:right|down|left|up)(?:\s*(?:,|and|&)?\s*(?:right|down|left|up))*)"
                          r"\s*\)", text, flags=re.I)
    if not beside:
        return text
    numbers = [int(n) for n in re.findall(r"(?<![\w.])[0-3](?![\w.])", beside.group(1))]
    names = [_ACTIONS[name.lower()] for name in re.findall(r"right|down|left|up", beside.group(2), flags=re.I)]
    if sorted(numbers) != sorted(names):
        raise Unreadable(f"{shown(answer)} names other actions in its brackets than in its list: {_NAMES}.")
    return beside.group(1)


def _without_denied(said: str, answer) -> str:
    """``said`` without a closing 'not ...' that names only actions its list does not ('0 and 3, not 1', 'RIGHT and
    UP, not DOWN'), or another whole list ('[0, 3] not [0, 1, 3]'); else as it is."""
    found = re.fullmatch(r"(.*?)\s*[,;]?\s+(?:but\s+)?not\s+([\w\s,&\[\]]+)", said, flags=re.I)
    if not found or re.search(r"\bnot\b", found.group(1), flags=re.I):
        return said
    try:
        listed, denied = ([item for item in re.split(_SEPARATORS, found.group(group), flags=re.I) if item]
                          for group in (1, 2))
        listed, denied = _numbered(listed), _numbered(denied)
    except Unreadable:
        return said
    lists = all(re.fullmatch(r"\s*\[[^\[\]]*\]\s*", found.group(group)) for group in (1, 2))
    if listed and denied and not lists and set(listed) & set(denied):  # '0, 1, 2 (not 2)'
        raise Unreadable(f"Could not read {shown(answer)} as a list of action numbers: it denies its own answer.")
    return found.group(1) if listed and denied and (listed != denied if lists else True) else said


def _named_equals(answer):
    """'RIGHT = 0': the number, once the name agrees with it."""
    def number(match):
        if _ACTIONS[match.group(1).lower()] != int(match.group(2)):
            raise Unreadable(f"{shown(answer)} names action {match.group(2)} as {match.group(1).upper()}: {_NAMES}.")
        return match.group(2)
    return number


def _numbered(items) -> list[int]:
    actions = set()
    for item in items:
        item = _ACTIONS.get(item.strip().lower(), item) if isinstance(item, str) else item
        try:
            number = _number(item, "an action number")
        except Unreadable:
            raise Unreadable(f"Could not read {shown(item)} as an action number.") from None
        if number not in (0, 1, 2, 3):
            raise Unreadable(f"{shown(item)} is not an action: they are numbered 0 to 3.")
        number = exactly(item, number, "an action number")  # 1.99999999999999999999 is not action 2
        if int(number) in actions:
            raise Unreadable(f"Your list names action {int(number)} twice: name each safe action once.")
        actions.add(int(number))
    return sorted(actions)
