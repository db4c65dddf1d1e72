"""No hidden state: the package's uses of ``__dict__``, of ``id(`` and of module-level mutable state are the
documented few below, each with its reason; a new one fails here until it is documented (or removed).

Mutable module-level state is a module-level name that a function of its module changes (an item set, a
mutating method called, a ``global`` statement) or a ``ContextVar``.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import sarsp_edu

PACKAGE = Path(sarsp_edu.__file__).parent

#: module -> the module-level names it changes at run time, and why each must be module-level
MODULE_STATE = {
    "_internal/parallel.py": {"_WORKER": "a pool worker process's own per-process state (its initializer's)"},
    "_internal/threads.py": {"_STATE": "BLAS has one thread pool per process: one count of its users"},
    "teaching/dashboards/projector.py": {"_DASHBOARDS": "the dashboards alive, which one switch resizes",
                                         "_SWITCH": "the projector switch, one per kernel"},
    "teaching/dashboards/tutorials.py": {"_T_LIMIT": "a sympy limit computed once per process"},
    "teaching/exercises/capstone.py": {"_LAST": "the last capstone check's runs, for its diagnosis"},
    "teaching/live/fitcache.py": {"_warned": "one warning per kind of problem and process"},
    "teaching/live/fitting.py": {"_ALL": "every fitting process alive, ended at the interpreter's exit"},
    "_internal/owner.py": {"_OWNERS": "every owner whose thread was started, closed at the interpreter's exit"},
}
#: module -> its uses of ``__dict__`` (lines' text, stripped) and why
DICT_USES = {
    "teaching/exercises/capstone.py": "a student's agent takes the package's fitted models whole (a deep copy "
                                      "of their state), so that both sides decide from the same fit",
}
#: module -> why it keys a mapping by ``id(``
ID_USES = {
    "agent/priors.py": "the strategic priors' caches of a buffer (each entry keeps the buffer itself, so the id "
                       "cannot be reused while it is cached)",
    "teaching/dashboards/framework.py": "a widget's name, found from the widget an ipywidgets change names",
    "teaching/live/fitcache.py": "a fitted model's name, found from the model the agent's fit hands over",
}

_MUTATORS = {"append", "add", "update", "pop", "clear", "setdefault", "remove", "discard", "extend", "insert",
             "popitem", "set"}


def _module_state(tree) -> set:
    top = set()
    for node in tree.body:
        if isinstance(node, ast.Assign):
            top |= {t.id for t in node.targets if isinstance(t, ast.Name)}
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name) and node.value is not None:
            top.add(node.target.id)
    found = set()
    for function in ast.walk(tree):
        if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        for node in ast.walk(function):
            if isinstance(node, ast.Global):
                found |= set(node.names)
            targets = node.targets if isinstance(node, ast.Assign) else [node.target] if isinstance(
                node, ast.AugAssign) else []
            found |= {t.value.id for t in targets if isinstance(t, ast.Subscript) and isinstance(t.value, ast.Name)
                      and t.value.id in top}
            if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
                    and isinstance(node.func.value, ast.Name) and node.func.value.id in top
                    and node.func.attr in _MUTATORS):
                found.add(node.func.value.id)
    for node in tree.body:
        if (isinstance(node, ast.Assign) and isinstance(node.value, ast.Call)
                and getattr(node.value.func, "attr", getattr(node.value.func, "id", None)) == "ContextVar"):
            found |= {t.id for t in node.targets if isinstance(t, ast.Name)}
    return found


def _modules():
    for path in sorted(PACKAGE.rglob("*.py")):
        yield path.relative_to(PACKAGE).as_posix(), path.read_text(encoding="utf-8")


def _code_lines(text: str) -> list:
    """The module's lines without comments and docstrings' prose (a line that mentions __dict__ in words)."""
    return [line.split("#")[0] for line in text.splitlines() if not line.strip().startswith(("#", '"', "'"))]


def test_module_level_state_is_the_documented_few():
    found = {}
    for name, text in _modules():
        names = _module_state(ast.parse(text))
        if names:
            found[name] = names
    assert found == {module: set(names) for module, names in MODULE_STATE.items()}


def test_uses_of_dict_and_id_are_the_documented_few():
    dict_uses, id_uses = set(), set()
    for name, text in _modules():
        lines = _code_lines(text)
        if any("__dict__" in line for line in lines):
            dict_uses.add(name)
        if any(re.search(r"(?<![\w.])id\(", line) for line in lines):
            id_uses.add(name)
    assert dict_uses == set(DICT_USES)
    assert id_uses == set(ID_USES)


def test_the_scan_finds_what_it_looks_for():
    """The scan itself: each kind it looks for is found in a module written here."""
    source = ("import contextvars\nCACHE = {}\nSEEN = []\nCOUNT = 0\nHOOK = contextvars.ContextVar('h')\n"
              "FIXED = {'a': 1}\n"
              "def f(k):\n    CACHE[k] = 1\n    SEEN.append(k)\n    global COUNT\n    COUNT += 1\n"
              "    return FIXED[k]\n")
    assert _module_state(ast.parse(source)) == {"CACHE", "SEEN", "COUNT", "HOOK"}


def test_the_agents_settings_by_name_are_declared_one_by_one_and_are_exactly_agentsettings():
    """No forwarding by ``__getattr__``: each of Algorithm 1's settings is a declared attribute of the agent class
    (visible to ``dir``, ``help`` and editors), and they are the fields of ``AgentSettings``, no more, no less."""
    import dataclasses

    from sarsp_edu import SARSPAgent
    from sarsp_edu.agent import sarsp
    from sarsp_edu.config import AgentSettings

    declared = {name for name, value in vars(SARSPAgent).items() if isinstance(value, sarsp._Setting)}
    assert declared == {field.name for field in dataclasses.fields(AgentSettings)}
    assert "__getattr__" not in vars(SARSPAgent) and "__setattr__" not in vars(SARSPAgent)


def test_the_refit_hook_is_a_checked_argument_of_the_agent():
    import pytest

    from sarsp_edu import RBF, GaussianProcess, SARSPAgent

    from .test_sarsp import tiny_data

    calls = []
    agent = SARSPAgent(GaussianProcess(RBF()), GaussianProcess(RBF()), tiny_data(5.0),
                       refit_model=lambda model, X, y: calls.append(len(y)))
    assert agent.refit_model is not None and calls == []
    with pytest.raises(TypeError, match="refit_model must be a function"):
        SARSPAgent(GaussianProcess(RBF()), GaussianProcess(RBF()), tiny_data(5.0), refit_model=42)
