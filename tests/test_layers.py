"""The package's folders are its layers: each module imports only from its own layer and the ones below it.

Also: the paths before the folders (``sarsp_edu.sarsp`` ...) still import, warn, and give the same module; no
module, test, benchmark, notebook or README snippet uses them any more; the names the package's top level lends
lazily are the ones its ``TYPE_CHECKING`` block shows to type checkers.
"""

from __future__ import annotations

import ast
import importlib
import json
import re
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

import sarsp_edu
from sarsp_edu._internal.moved import MOVED, new_path

PACKAGE = Path(sarsp_edu.__file__).parent
REPOSITORY = PACKAGE.parent

#: lowest first; a module may import from its own layer and those before it
LAYERS = ["_internal", "_version", "config", "models", "world", "agent", "experiments", "paper", "teaching", "cli"]


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _layer(module: str) -> int:
    """The layer of ``sarsp_edu.<folder>...``."""
    return LAYERS.index(module.split(".")[1])


def _imports(path: Path):
    """(line, imported module) of every import of a sarsp_edu module in ``path``, relative ones resolved."""
    module = _module_name(path)
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            # "from . import x" names modules: the layer is the module's
            targets = [f"{target}.{alias.name}" if node.module is None else target for alias in node.names]
        else:
            continue
        yield from ((node.lineno, target) for target in targets if target.startswith("sarsp_edu."))


MODULES = sorted(path for path in PACKAGE.rglob("*.py") if path.name != "__init__.py" or path.parent != PACKAGE)


@pytest.mark.parametrize("path", MODULES, ids=lambda path: _module_name(path))
def test_a_module_imports_only_from_its_layer_and_those_below(path):
    own = _layer(_module_name(path))
    upward = [f"line {line}: {target} ({LAYERS[_layer(target)]})" for line, target in _imports(path)
              if _layer(target) > own]
    assert not upward, f"{_module_name(path)} ({LAYERS[own]}) imports from a layer above it: {upward}"


def test_no_module_imports_itself_through_others():
    """No import circle among the package's modules, counting the imports inside functions too (a circle there
    works only while the order of first imports happens to allow it).  ``from . import NAME`` in a package's
    module, NAME defined by the package's ``__init__``, is an edge to the ``__init__``."""
    names = {_module_name(path): path for path in MODULES}
    edges = {}
    for name, path in names.items():
        found = set()
        for _, target in _imports(path):
            while target not in names and "." in target:  # "pkg.module.Name" -> "pkg.module"
                target = target.rpartition(".")[0]
            if target in names and target != name:
                found.add(target)
        edges[name] = found
    circles, done = [], set()

    def visit(name, trail):
        if name in trail:
            circles.append(trail[trail.index(name):] + [name])
            return
        if name in done:
            return
        for other in sorted(edges[name]):
            visit(other, trail + [name])
        done.add(name)

    for name in sorted(edges):
        visit(name, [])
    assert circles == [], "\n".join(" -> ".join(circle) for circle in circles)


def test_the_layers_are_the_package_folders():
    folders = {path.name for path in PACKAGE.iterdir() if path.is_dir() and (path / "__init__.py").exists()}
    files = {path.stem for path in PACKAGE.glob("*.py")} - {"__init__"}
    assert folders | files == set(LAYERS)


def test_the_experiments_layer_does_not_know_the_fit_cache():
    """The live dashboards hand their fit cache in (``cache=``): a run of the experiments layer never reads it."""
    for path in (PACKAGE / "experiments").rglob("*.py"):
        assert "fitcache" not in {target.rpartition(".")[2] for _, target in _imports(path)}, path


@pytest.fixture(scope="module")
def first_warnings():
    """Old path -> the last DeprecationWarning its first import gives, in a fresh process (in this one the test
    modules may have imported the modules already); one process for every path, each imported once."""
    code = ("import importlib, json, sys, warnings\nsaid = {}\nfor old in sys.argv[1:]:\n"
            "    with warnings.catch_warnings(record=True) as seen:\n        warnings.simplefilter('always')\n"
            "        importlib.import_module(old)\n"
            "    said[old] = [str(w.message) for w in seen if w.category is DeprecationWarning][-1:]\n"
            "print(json.dumps(said))")
    # a moved package before its submodules: a submodule's import then warns for itself alone
    paths = sorted(f"sarsp_edu.{old}" for old in MOVED)
    out = subprocess.run([sys.executable, "-c", code, *paths], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout)


@pytest.mark.slow  # a fresh interpreter imports every old path
@pytest.mark.parametrize("old", sorted(MOVED))
def test_an_old_import_path_warns_and_gives_the_module_at_its_new_path(old, first_warnings):
    old_name = f"sarsp_edu.{old}"
    expected = f"{old_name} is now {new_path(old_name)}; the old path works until the next release"
    assert first_warnings[old_name] == [expected]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        module = importlib.import_module(old_name)
    new = importlib.import_module(new_path(old_name))
    assert module is new and module.__name__ == module.__spec__.name == new_path(old_name)


@pytest.mark.slow  # imports the package's models afresh
def test_a_submodule_of_a_moved_package_imports_by_its_old_path_too(monkeypatch):
    for name in [name for name in sys.modules if name.split(".")[:2] == ["sarsp_edu", "processes"]]:
        monkeypatch.delitem(sys.modules, name)  # as in a fresh process, whichever test imported them before
    with pytest.warns(DeprecationWarning) as caught:
        importlib.import_module("sarsp_edu.processes.tp")
    said = [str(warning.message) for warning in caught]
    assert said == ["sarsp_edu.processes is now sarsp_edu.models.processes; the old path works until the next release",
                    "sarsp_edu.processes.tp is now sarsp_edu.models.processes.tp; the old path works until the next "
                    "release"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        old = importlib.import_module("sarsp_edu.processes.tp")
    assert old.StudentTProcess is sarsp_edu.StudentTProcess


def _code_of_the_repository():
    """(where, Python source) of the package, the tests, the benchmarks, the notebooks and the READMEs' snippets."""
    python = [*PACKAGE.rglob("*.py"), *(REPOSITORY / "tests").glob("*.py"), *(REPOSITORY / "benchmarks").glob("*.py")]
    for path in python:
        yield str(path.relative_to(REPOSITORY)), path.read_text()
    for path in (REPOSITORY / "tutorials").rglob("*.ipynb"):
        for number, cell in enumerate(json.loads(path.read_text())["cells"]):
            if cell["cell_type"] == "code":
                source = "".join(cell["source"])
                yield (f"{path.relative_to(REPOSITORY)} cell {number}",
                       "\n".join(line for line in source.splitlines() if not line.lstrip().startswith(("%", "!"))))
    for path in REPOSITORY.glob("*.md"):
        for block in re.findall(r"```python\n(.*?)```", path.read_text(), re.S):
            yield str(path.relative_to(REPOSITORY)), block


@pytest.mark.slow  # reads every notebook and Markdown file
def test_nothing_in_the_repository_imports_an_old_path():
    old = []
    for where, source in _code_of_the_repository():
        for node in ast.walk(ast.parse(source)):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
                names = [node.module, *(f"{node.module}.{alias.name}" for alias in node.names)]
            else:
                continue
            old += [f"{where}:{node.lineno} {name}" for name in names if new_path(name)]
    assert not old, old


def test_the_names_lent_lazily_are_the_names_type_checkers_see():
    tree = ast.parse((PACKAGE / "__init__.py").read_text())
    lazy = next(ast.literal_eval(node.value) for node in tree.body
                if isinstance(node, ast.Assign) and getattr(node.targets[0], "id", None) == "_LAZY")
    checked = next(node for node in tree.body
                   if isinstance(node, ast.If) and getattr(node.test, "id", "") == "TYPE_CHECKING")
    seen = {alias.asname or alias.name: node.module for node in checked.body for alias in node.names}
    assert seen == lazy
    for name, module in lazy.items():
        assert getattr(sarsp_edu, name) is getattr(importlib.import_module(f"sarsp_edu.{module}"), name)


@pytest.mark.slow  # imports every module the table names
def test_the_readmes_module_table_names_only_modules_that_exist():
    """Each row of README's module table: its module imports, and each `name` in parentheses that names a
    module of it (a lower-case word) is one of its submodules."""
    import importlib
    import re

    readme = (Path(__file__).resolve().parents[1] / "README.md").read_text(encoding="utf-8")
    rows = [line for line in readme.splitlines() if re.match(r"^\|[^|]*\| `sarsp_edu[.\w]*` \|", line)]
    assert len(rows) > 20, len(rows)
    missing = []
    for row in rows:
        path = re.search(r"\| `(sarsp_edu[.\w]*)` \|", row).group(1)
        module = importlib.import_module(path)
        folder = Path(module.__file__).parent
        if not module.__file__.endswith("__init__.py"):
            continue
        exported = [getattr(module, name) for name in getattr(module, "__all__", ())]
        for name in re.findall(r"\(`([a-z_]+)`[,)]", row) + re.findall(r", `([a-z_]+)`[,)]", row):
            if any(hasattr(thing, name) for thing in exported):  # a method named, `score` say
                continue
            if not ((folder / f"{name}.py").exists() or (folder / name / "__init__.py").exists()):
                missing.append(f"{path}: ({name})")
    assert missing == [], missing
