"""The Binder environment of ``test_binder.py``, built in a thread while other tests run.

Building it (a fresh virtual environment, repo2docker's base, ``binder/requirements.txt``,
``binder/postBuild``) installs some 800 MB of packages: about a minute and a half of one
core, most of it spent by pip unpacking wheels.  The root ``conftest.py`` starts the build
when nbval begins the tutorials (a kernel running one notebook leaves the second core
mostly idle, and no browser test runs then, whose timings a busy core would disturb) and
runs the test that uses it last.  The build only waits on subprocesses, so the thread
holds no lock the tests need.  Run alone, or under pytest-xdist (whose workers do not know
which of them will run the test, and would each build it), the test builds it itself.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import threading
from concurrent.futures import Future
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: what repo2docker's base environment provides before the repository's own files
REPO2DOCKER_BASE = ["jupyterlab>=4", "ipywidgets>=8", "ipykernel", "nbclient", "nbformat"]


@dataclass(frozen=True)
class BinderEnvironment:
    folder: Path  # holds the copied repository and the environment
    repo: Path
    python: str
    env: dict


def run(command, cwd, env) -> str:
    """Run a command; its stdout, or an AssertionError with the end of its output."""
    result = subprocess.run(command, cwd=cwd, env=env, capture_output=True, text=True)
    assert result.returncode == 0, (f"{' '.join(map(str, command))} failed:\n"
                                    f"{result.stdout[-3000:]}\n{result.stderr[-3000:]}")
    return result.stdout


def build(folder: Path) -> BinderEnvironment:
    """What repo2docker does with binder/, in ``folder``: the repository copied, then the environment."""
    repo = folder / "repo"
    shutil.copytree(ROOT, repo, ignore=shutil.ignore_patterns(
        ".git", "__pycache__", "*.egg-info", ".pytest_cache", ".hypothesis", "build", "dist", ".ipynb_checkpoints"))
    venv = folder / "venv"
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
    return BinderEnvironment(folder, repo, python, env)


_LOCK = threading.Lock()
_BUILD: dict = {}


def start() -> Future:
    """Start the build in a thread of its own (once); its future."""
    with _LOCK:
        if "future" not in _BUILD:
            future = Future()
            folder = Path(tempfile.mkdtemp(prefix="sarsp-edu-binder-"))
            _BUILD.update(future=future, folder=folder)

            def work():
                try:
                    future.set_result(build(folder))
                except BaseException as error:  # noqa: BLE001 - handed to the test that waits
                    future.set_exception(error)

            threading.Thread(target=work, name="binder-build", daemon=True).start()
        return _BUILD["future"]


def clean_up() -> None:
    """Wait for a build that was started to end, then remove its folder."""
    with _LOCK:
        future, folder = _BUILD.pop("future", None), _BUILD.pop("folder", None)
    if future is not None:
        try:
            future.exception(timeout=1800)
        finally:
            shutil.rmtree(folder, ignore_errors=True)
