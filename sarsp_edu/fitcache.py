"""Fitted experiments kept on disk, so that a live dashboard starts at once for settings fitted before.

Fitting an agent's offline models takes a few seconds (Adam on the whole
cost buffer and on a thousand reward rows); the live dashboard
(:class:`~sarsp_edu.live.AgentDashboard`) would make a lecturer wait for it
after every Run All.  It therefore keeps each experiment it fits, pickled
before the experiment's first step, and loads it the next time the same
settings are asked for, in this kernel or a later one.

A fit is reused only where it is the same bits a new fit would be: the
key is the whole :class:`~sarsp_edu.config.ExperimentConfig` together with
a fingerprint of what computed it (the package's source files, the versions
of Python, numpy and scipy, the BLAS library and the processor).  A changed
package, another numpy or another machine never reuses an old fit; it fits
afresh.  Runs of :func:`~sarsp_edu.experiment.compare`, the sweeps and the
tests never read the cache: they fit every time.  A warning a fit gave
(a hyperparameter at its bound, say) is not given again when the fit is
loaded; the dashboard's key numbers say which fits were loaded.

Where: ``$SARSP_EDU_CACHE`` if set (``off`` turns the cache off), else
``$XDG_CACHE_HOME/sarsp_edu/fits`` (``~/.cache/sarsp_edu/fits``).  At most
:data:`CACHE_BYTES` are kept: the entries used least recently go first.
Entries are written through a temporary file and an atomic rename, so an
interrupted write never leaves half a fit behind; an entry that cannot be
read is removed and fitted again.
"""

from __future__ import annotations

import functools
import hashlib
import os
import pickle
import platform
from pathlib import Path

from ._io import atomic_write_bytes

__all__ = ["CACHE_BYTES", "CACHE_VARIABLE", "cache_directory", "clear", "entries", "fingerprint", "load", "store"]

#: the environment variable naming the cache folder (``off``: no cache)
CACHE_VARIABLE = "SARSP_EDU_CACHE"
#: the most the cache keeps on disk (an entry, one agent's fitted experiment, is about 30 MB)
CACHE_BYTES = 256 * 2**20
_SUFFIX = ".fit.pickle"
_OFF = {"off", "0", "false", "no", ""}


def cache_directory() -> Path | None:
    """The cache's folder, or None when ``SARSP_EDU_CACHE`` turns it off."""
    chosen = os.environ.get(CACHE_VARIABLE)
    if chosen is not None:
        return None if chosen.strip().lower() in _OFF else Path(chosen).expanduser()
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "sarsp_edu" / "fits"


def _processor() -> str:
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as handle:
            for line in handle:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor()


@functools.lru_cache(maxsize=1)
def fingerprint() -> str:
    """A digest of what a fit's bits depend on besides its settings: this code, its libraries, the machine."""
    from threadpoolctl import threadpool_info

    from .provenance import code_provenance

    code = {k: v for k, v in code_provenance().items() if k != "git_commit"}  # the source hash says it all
    blas = sorted(f"{i.get('internal_api')} {i.get('version')} {i.get('architecture')}" for i in threadpool_info())
    parts = [*(f"{k}={v}" for k, v in sorted(code.items())), *blas, platform.machine(), _processor()]
    return hashlib.sha256("\n".join(parts).encode()).hexdigest()


def _steps_taken(experiment) -> int:
    return len(experiment.act_seconds)


def _path(config) -> Path | None:
    directory = cache_directory()
    if directory is None:
        return None
    key = hashlib.sha256(f"{fingerprint()}\n{config!r}".encode()).hexdigest()[:32]
    return directory / f"{config.model}-{key}{_SUFFIX}"


def load(config):
    """The fitted :class:`~sarsp_edu.experiment.Experiment` of ``config`` stored earlier, or None."""
    path = _path(config)
    if path is None or not path.exists():
        return None
    try:
        with open(path, "rb") as handle:
            experiment = pickle.load(handle)
        if repr(experiment.config) != repr(config) or _steps_taken(experiment):
            raise ValueError("not the fit of these settings")
    except Exception:  # unreadable or not ours: fitted again and stored anew
        path.unlink(missing_ok=True)
        return None
    os.utime(path)  # most recently used
    experiment.loaded_from_cache = True
    return experiment


def store(experiment) -> Path | None:
    """Keep a just-fitted ``experiment`` (before its first step) for its settings; the entry's path."""
    if _steps_taken(experiment):
        raise ValueError(f"only a just-fitted experiment is stored, this one has taken {_steps_taken(experiment)} steps")
    path = _path(experiment.config)
    if path is None:
        return None
    try:
        atomic_write_bytes(path, pickle.dumps(experiment, protocol=pickle.HIGHEST_PROTOCOL))
    except OSError:  # a full or read-only disk costs a later fit, nothing else
        return None
    _prune()
    return path


def entries() -> list:
    """The stored fits, most recently used first: ``(path, bytes)``."""
    directory = cache_directory()
    if directory is None or not directory.is_dir():
        return []
    found = []
    for path in directory.glob(f"*{_SUFFIX}"):
        try:
            stat = path.stat()
        except FileNotFoundError:  # removed meanwhile by another kernel
            continue
        found.append((stat.st_mtime, path, stat.st_size))
    return [(path, size) for _, path, size in sorted(found, reverse=True)]


def _prune() -> None:
    total = 0
    for path, size in entries():
        total += size
        if total > CACHE_BYTES:
            path.unlink(missing_ok=True)


def clear() -> int:
    """Remove every stored fit; how many were removed."""
    found = entries()
    for path, _ in found:
        path.unlink(missing_ok=True)
    return len(found)
