"""Every public function and method has a docstring, and those of two or more arguments a numpydoc Parameters
section (the house style of scikit-learn's and numpy's reference pages)."""

from __future__ import annotations

import ast
from pathlib import Path

import sarsp_edu

PACKAGE = Path(sarsp_edu.__file__).parent


def _public_definitions(tree):
    """(qualified name, node) of the module's public functions and the public methods of its public classes."""
    def visit(body, prefix):
        for node in body:
            if isinstance(node, ast.ClassDef) and not node.name.startswith("_"):
                yield from visit(node.body, f"{prefix}{node.name}.")
            elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and not node.name.startswith("_"):
                decorators = {getattr(d, "id", getattr(d, "attr", None)) for d in node.decorator_list}
                if not decorators & {"property", "setter", "cached_property"}:
                    yield prefix + node.name, node
    yield from visit(tree.body, "")


def test_public_functions_say_what_each_argument_is():
    missing = []
    for path in sorted(PACKAGE.rglob("*.py")):
        relative = path.relative_to(PACKAGE.parent)
        if any(part.startswith("_") and part != "__init__.py" for part in relative.parts[1:]):
            continue  # private modules: no public API
        for name, node in _public_definitions(ast.parse(path.read_text())):
            arguments = [a.arg for a in node.args.posonlyargs + node.args.args + node.args.kwonlyargs
                         if a.arg not in ("self", "cls")] + [a.arg for a in (node.args.vararg, node.args.kwarg) if a]
            doc = ast.get_docstring(node)
            if not doc:
                missing.append(f"{relative}:{node.lineno} {name}: no docstring")
            elif len(arguments) >= 2 and "Parameters\n----------" not in doc:
                missing.append(f"{relative}:{node.lineno} {name}({', '.join(arguments)}): no Parameters section")
    assert not missing, "\n".join(missing)
