"""Binder, mimicked: what repo2docker does with binder/, in a fresh virtual environment.

1. copy the repository (repo2docker copies it into the image);
2. a fresh environment with repo2docker's base (JupyterLab, ipywidgets, a kernel);
3. ``pip install -r binder/requirements.txt`` from the repository's root;
4. ``binder/postBuild``, run from the repository's root;
5. import every module the tutorials import, with that environment's
   Python, and execute the tutorial the Binder badge opens (01) top to
   bottom with its kernel.

A broken binder/ folder, or a dependency a tutorial needs but pyproject.toml
does not install, fails this test.  Steps 1-4 are ``tests/binder_build.py``, run in a
thread while nbval runs the tutorials (the root conftest.py starts it and runs this
test last).  (Every tutorial is executed by nbval in
the test environment already; executing all of them again here doubled the
suite's time without finding anything nbval and the imports do not.)
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

from tests import binder_build
from tests.binder_build import run

ROOT = Path(__file__).resolve().parents[1]
BINDER = ROOT / "binder"
TUTORIALS = sorted((ROOT / "tutorials").glob("*.ipynb"))
#: the notebook the README's Binder badge opens
BADGE_NOTEBOOK = "01_tail_decay.ipynb"

EXECUTE = r"""
import sys, nbformat
from nbclient import NotebookClient
path = sys.argv[1]
notebook = nbformat.read(path, as_version=4)
NotebookClient(notebook, timeout=600, kernel_name="python3",
               resources={"metadata": {"path": str(__import__("pathlib").Path(path).parent)}}).execute()
errors = [o for c in notebook.cells for o in c.get("outputs", []) if o.get("output_type") == "error"]
print(f"{path}: {len(notebook.cells)} cells executed, {len(errors)} errors")
sys.exit(1 if errors else 0)
"""


def test_binder_folder_is_what_repo2docker_reads():
    assert (BINDER / "runtime.txt").read_text().strip() == f"python-{sys.version_info.major}.{sys.version_info.minor}"
    assert os.access(BINDER / "postBuild", os.X_OK), "postBuild must be executable"
    assert (BINDER / "postBuild").read_text().startswith("#!/bin/bash\n")
    assert "set -e" in (BINDER / "postBuild").read_text()
    # repo2docker ignores configuration at the top level when binder/ exists: keep none there
    for ignored in ("environment.yml", "requirements.txt", "postBuild", "runtime.txt", "apt.txt"):
        assert not (ROOT / ignored).exists(), f"{ignored} at the top level would be ignored by repo2docker"
    # and environment.yml would win over requirements.txt
    assert not (BINDER / "environment.yml").exists()


def test_binder_environment_imports_every_tutorial_and_runs_the_first(tmp_path):
    built = binder_build.start().result(timeout=1800)  # usually built while nbval ran the tutorials
    repo, python, env = built.repo, built.python, built.env
    # the package came from the copy, not from this checkout
    where = run([python, "-c", "import sarsp_edu; print(sarsp_edu.__file__)"], cwd=tmp_path, env=env)
    assert str(built.folder) in where and str(ROOT) not in where

    # Voila, which the lecturer's guide recommends for projecting, comes with the lab extra
    assert "voila" in run([python, "-m", "pip", "list"], cwd=repo, env=env).lower()
    modules = sorted(set().union(*(_imported_modules(notebook) for notebook in TUTORIALS)))
    assert {"sarsp_edu", "numpy", "matplotlib"} <= set(modules)
    run([python, "-c", "import importlib, sys; [importlib.import_module(m) for m in sys.argv[1:]]", *modules],
        cwd=tmp_path, env=env)
    script = tmp_path / "execute.py"
    script.write_text(EXECUTE)
    badge = repo / "tutorials" / BADGE_NOTEBOOK
    assert "0 errors" in run([python, str(script), str(badge)], cwd=badge.parent, env=env)


def _imported_modules(notebook: Path) -> set:
    """Top-level names of the modules a notebook's code cells import."""
    import ast

    import nbformat

    names = set()
    for cell in nbformat.read(notebook, as_version=4).cells:
        if cell.cell_type != "code":
            continue
        source = "\n".join(line for line in cell.source.splitlines() if not line.lstrip().startswith(("%", "!")))
        for node in ast.walk(ast.parse(source)):
            if isinstance(node, ast.Import):
                names.update(alias.name.split(".")[0] for alias in node.names)
            elif isinstance(node, ast.ImportFrom) and node.level == 0:
                names.add(node.module.split(".")[0])
    return names


def test_the_badge_opens_the_first_tutorial_in_jupyterlab():
    readme = (ROOT / "README.md").read_text()
    assert f"urlpath=lab/tree/tutorials/{BADGE_NOTEBOOK}" in readme
    assert (ROOT / "tutorials" / BADGE_NOTEBOOK).exists()


@pytest.mark.parametrize("notebook", TUTORIALS, ids=[p.stem for p in TUTORIALS])
def test_every_tutorial_is_listed_for_binder_users(notebook):
    assert notebook.name in (ROOT / "tutorials" / "README.md").read_text()
    assert f"tutorials/{notebook.name}" in (ROOT / "README.md").read_text()
