"""Which code computed a stored result: the package version, its source, its git commit, the numerics.

Every stored result records :func:`code_provenance`, so that a table built
from results computed at different times can say when they come from
different code (a speed-up that reorders arithmetic changes trajectories).
"""

from __future__ import annotations

import functools
import hashlib
import importlib.metadata
import platform
import subprocess
from pathlib import Path

from .._version import __version__

__all__ = ["code_label", "code_provenance", "code_versions"]

#: the sarsp_edu package's folder (this module lives in its experiments folder)
_PACKAGE = Path(__file__).resolve().parent.parent


def _source_files() -> list:
    """Every Python file of the package, sorted: what :func:`_source_sha256` hashes."""
    return sorted(_PACKAGE.rglob("*.py"))


def _source_sha256() -> str:
    """A hash of every Python file of the package (its path and bytes): the same code, the same hash."""
    digest = hashlib.sha256()
    for path in _source_files():
        digest.update(path.relative_to(_PACKAGE).as_posix().encode() + b"\0")
        digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()


def _git_commit() -> str | None:
    """The commit of the git checkout the package runs from (None outside one, or without git)."""
    try:
        result = subprocess.run(["git", "-C", str(_PACKAGE), "rev-parse", "HEAD"], capture_output=True,
                                text=True, timeout=5, check=False)
    except (OSError, subprocess.SubprocessError):
        return None
    commit = result.stdout.strip()
    return commit if result.returncode == 0 and commit else None


def _version(name: str) -> str | None:
    try:
        return importlib.metadata.version(name)
    except importlib.metadata.PackageNotFoundError:
        return None


@functools.lru_cache(maxsize=None)
def code_provenance() -> dict:
    """What computed a result made in this process.

    Returns
    -------
    dict
        ``sarsp_edu_version``; ``source_sha256``, a hash of the package's
        source files (exact, also outside a git checkout or with uncommitted
        changes); ``git_commit`` (None outside a git checkout); the versions of
        ``numpy``, ``scipy`` and ``python``.
    """
    return {
        "sarsp_edu_version": __version__,
        "source_sha256": _source_sha256(),
        "git_commit": _git_commit(),
        "numpy": _version("numpy"),
        "scipy": _version("scipy"),
        "python": platform.python_version(),
    }


def code_label(code: dict | None) -> str:
    """A short name for a recorded provenance: ``'0.2.2, source 1a2b3c4d, numpy 2.4.6, scipy 1.17.1'``.

    >>> code_label(None)
    'not recorded'
    """
    if not code:
        return "not recorded"
    return (f"{code.get('sarsp_edu_version')}, source {str(code.get('source_sha256'))[:8]}, "
            f"numpy {code.get('numpy')}, scipy {code.get('scipy')}")


def code_versions(results) -> dict:
    """How many of ``results`` each version of the code computed: ``{code_label: runs}``.

    More than one entry means the runs come from different code, whose numbers may differ.

    Parameters
    ----------
    results : iterable of ExperimentResult
    """
    counts: dict = {}
    for result in results:
        label = code_label(result.code)
        counts[label] = counts.get(label, 0) + 1
    return counts
