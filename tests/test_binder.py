"""Binder, mimicked: what repo2docker does with binder/, in a fresh virtual environment.

1. copy the repository (repo2docker copies it into the image);
2. a fresh environment with repo2docker's base (JupyterLab, ipywidgets, a kernel);
3. ``pip install -r binder/requirements.txt`` from the repository's root;
4. ``binder/postBuild``, run from the repository's root;
5. execute every tutorial top to bottom with that environment's kernel.

A broken binder/ folder, a dependency missing from pyproject.toml, or a
tutorial that only works on a developer's machine fails this test.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BINDER = ROOT / "binder"
TUTORIALS = sorted((ROOT / "tutorials").glob("*.ipynb"))
#: what repo2docker's base environment provides before the repository's own files
REPO2DOCKER_BASE = ["jupyterlab>=4", "ipywidgets>=8", "ipykernel", "nbclient", "nbformat"]

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


def run(command, cwd, env):
    result = subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True)
    assert result.returncode == 0, f"{' '.join(map(str, command))} failed:\n{result.stdout[-3000:]}\n{result.stderr[-3000:]}"
    return result.stdout


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


def test_binder_environment_runs_every_tutorial(tmp_path):
    repo = tmp_path / "repo"
    shutil.copytree(ROOT, repo, ignore=shutil.ignore_patterns(
        ".git", "__pycache__", "*.egg-info", ".pytest_cache", ".hypothesis", "build", "dist", ".ipynb_checkpoints"))
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    bin_dir = venv / "bin"
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["PATH"] = f"{bin_dir}{os.pathsep}{env.get('PATH', '')}"
    env["VIRTUAL_ENV"] = str(venv)
    env["MPLBACKEND"] = "Agg"
    python = str(bin_dir / "python")

    run([python, "-m", "pip", "install", "--quiet", *REPO2DOCKER_BASE], cwd=repo, env=env)
    run([python, "-m", "pip", "install", "--quiet", "-r", "binder/requirements.txt"], cwd=repo, env=env)
    run(["./binder/postBuild"], cwd=repo, env=env)
    run([python, "-m", "ipykernel", "install", "--sys-prefix", "--name", "python3"], cwd=repo, env=env)
    # the package came from the copy, not from this checkout
    where = run([python, "-c", "import sarsp_edu; print(sarsp_edu.__file__)"], cwd=tmp_path, env=env)
    assert str(venv) in where

    script = tmp_path / "execute.py"
    script.write_text(EXECUTE)
    for notebook in sorted((repo / "tutorials").glob("*.ipynb")):
        output = run([python, str(script), str(notebook)], cwd=notebook.parent, env=env)
        assert "0 errors" in output


@pytest.mark.parametrize("notebook", TUTORIALS, ids=[p.stem for p in TUTORIALS])
def test_tutorial_opens_in_jupyterlab_by_the_badge(notebook):
    readme = (ROOT / "README.md").read_text()
    assert "urlpath=lab/tree/tutorials/01_tail_decay.ipynb" in readme
    assert notebook.name in (ROOT / "tutorials" / "README.md").read_text()
