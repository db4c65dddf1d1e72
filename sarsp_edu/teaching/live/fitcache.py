"""Fitted experiments kept on disk, so that a live dashboard starts at once for settings fitted before.

Fitting an agent's offline models takes a few seconds (Adam on the whole
cost buffer and on a thousand reward rows; minutes for a GP with Student-t
noise, whose every step searches a Laplace mode); the live dashboard
(:class:`~sarsp_edu.teaching.live.AgentDashboard`) would make a lecturer wait for it
after every Run All.  It therefore keeps what each fit computed (the fitted
hyperparameters, the optimiser's trace, the rows it used and the Cholesky
factor of the training covariance; for a GP with Student-t noise, where its
mode's search began, the mode being searched again), and rebuilds the experiment from it the
next time the same settings are asked for, in this kernel or a later one: the
world and its data are prepared afresh (a fraction of a second) and the
factor is checked against them.

An entry holds arrays and JSON only (a ``.npz`` file read with
``allow_pickle=False``), so a shared cache folder cannot make a kernel run
anyone's code.  An entry is used only if its digest matches its contents and
the log marginal likelihood recomputed from its factor and the freshly
prepared data is, bit for bit, the one it stored: an edited entry (its
factor or hyperparameters changed) or data that changed since are refused,
removed and fitted afresh.

A fit is reused only where it is the same bits a new fit would be: the
key is the whole :class:`~sarsp_edu.config.ExperimentConfig` together with
a fingerprint of what computed it (the package's source files, the versions
of Python, numpy and scipy, the BLAS library and the processor).  A changed
package, another numpy or another machine never reuses an old fit; it fits
afresh.  Runs of :func:`~sarsp_edu.experiments.experiment.compare`, the sweeps and the
tests never read the cache: they fit every time.  A warning a fit gave
(a hyperparameter at its bound, say) is not given again when the fit is
loaded; the dashboard's key numbers say which fits were loaded.

Where: ``$SARSP_EDU_CACHE`` if set (``off`` turns the cache off), else
``$XDG_CACHE_HOME/sarsp_edu/fits`` (``~/.cache/sarsp_edu/fits``).  At most
:data:`CACHE_BYTES` are kept: the entries used least recently go first.
Entries are written through a temporary file and an atomic rename, so an
interrupted write never leaves half a fit behind; an entry that cannot be
read is removed (where it can be) and fitted again, and a cache that cannot be
used at all (a folder in an entry's place, a read-only folder) is skipped with
one warning.
"""

from __future__ import annotations

import functools
import hashlib
import io
import json
import os
import platform
import warnings
from pathlib import Path

import numpy as np

from ..._internal.io import atomic_write_bytes

__all__ = ["CACHE_BYTES", "CACHE_VARIABLE", "cache_directory", "clear", "entries", "fingerprint", "load", "store"]

#: the environment variable naming the cache folder (``off``: no cache)
CACHE_VARIABLE = "SARSP_EDU_CACHE"
#: the most the cache keeps on disk (an entry, one agent's fitted models, is about 13 MB at the paper's settings)
CACHE_BYTES = 256 * 2**20
_SUFFIX = ".fit.npz"
#: the entries' layout (an entry of another layout is fitted afresh)
_FORMAT = 2
#: what each fitted GP or TP keeps as arrays
_ARRAYS = ("theta_", "objective_trace_", "fit_indices_", "L_")
#: what a fitted GP with Student-t noise keeps as arrays: its hyperparameters (amplitude, length scale, the
#: noise's scale and nu), where its mode's search began, each start's objective; the mode is searched again
_LIKELIHOOD_ARRAYS = ("hyper_", "mode_start_", "start_objectives_")
_OFF = {"off", "0", "false", "no", ""}


def cache_directory() -> Path | None:
    """The cache's folder, or None when ``SARSP_EDU_CACHE`` turns it off (a ValueError where it names the home
    folder of an unknown user)."""
    chosen = os.environ.get(CACHE_VARIABLE)
    if chosen is not None:
        if chosen.strip().lower() in _OFF:
            return None
        try:
            return Path(chosen).expanduser()
        except RuntimeError:  # '~user/...' of a user this machine does not know
            raise ValueError(f"{CACHE_VARIABLE}={chosen!r} names the home folder of a user this machine does not "
                             f"know; give a folder path, or {CACHE_VARIABLE}=off to turn the cache off") from None
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
    import scipy.linalg  # noqa: F401  (loads the BLAS and LAPACK a fit uses, whatever was imported before)
    from threadpoolctl import threadpool_info

    from ...experiments.provenance import code_provenance

    code = {k: v for k, v in code_provenance().items() if k != "git_commit"}  # the source hash says it all
    blas = sorted(f"{i.get('internal_api')} {i.get('version')} {i.get('architecture')}" for i in threadpool_info()
                  if i.get("user_api") == "blas")  # not the OpenMP runtimes, which come and go with imports
    parts = [*(f"{k}={v}" for k, v in sorted(code.items())), *blas, platform.machine(), _processor()]
    return hashlib.sha256("\n".join(parts).encode()).hexdigest()


def _steps_taken(experiment) -> int:
    return len(experiment.act_seconds)


#: the models whose fits the cache keeps
CACHED_MODELS = ("tp", "gp", "t-likelihood")


def cached(config) -> bool:
    """Whether the cache keeps the fits of ``config``: every model of its agent (the cost and the reward model's
    kinds) of :data:`CACHED_MODELS`."""
    return all(kind in CACHED_MODELS for kind in config.model_kinds)


def _path(config, directory=None) -> Path | None:
    directory = cache_directory() if directory is None else Path(directory)
    if directory is None or not cached(config):
        return None
    key = hashlib.sha256(f"{fingerprint()}\n{config!r}".encode()).hexdigest()[:32]
    return directory / f"{config.model}-{key}{_SUFFIX}"


_warned = set()


def _warn_once(problem: str) -> None:
    """One warning per kind of problem and process: the cache is skipped, the fit is computed afresh."""
    if problem not in _warned:
        _warned.add(problem)
        warnings.warn(f"the cache of fits is skipped: {problem}; the live dashboard fits afresh (remove what is "
                      f"named, or set {CACHE_VARIABLE}=off to turn the cache off)", stacklevel=3)


def _digest(arrays: dict, meta: dict) -> str:
    digest = hashlib.sha256(json.dumps(meta, sort_keys=True).encode())
    for name in sorted(arrays):
        array = np.ascontiguousarray(arrays[name])
        digest.update(f"{name} {array.dtype.str} {array.shape}".encode())
        digest.update(array.tobytes())
    return digest.hexdigest()


def _models(agent) -> dict:
    return {"cost": agent.cost_model, "reward": agent.reward_model}


def _contents(experiment) -> tuple[dict, dict]:
    """The arrays and the JSON that an entry keeps of a just-fitted experiment."""
    arrays, models = {}, {}
    for name, model in _models(experiment.agent).items():
        models[name] = {"n_features_in_": int(model.n_features_in_), "n_iter_": int(model.n_iter_),
                        "log_marginal_likelihood_value_": float(model.log_marginal_likelihood_value_)}
        if _has_student_t_noise(model):
            start = model.mode_start_
            arrays.update({f"{name}.hyper_": np.array([model.kernel_.amplitude, model.kernel_.length_scale,
                                                        model.scale_, model.nu_], dtype=float),
                           f"{name}.mode_start_": np.zeros(0) if start is None else start,
                           f"{name}.start_objectives_": np.asarray(model.start_objectives_, dtype=float)})
            models[name].update(kind="t-likelihood", mode_start=start is not None, n_newton_=int(model.n_newton_),
                                gradient_norm_=float(model.gradient_norm_))
            continue
        arrays.update({f"{name}.{attribute}": getattr(model, attribute) for attribute in _ARRAYS})
        models[name]["jitter_"] = float(model.jitter_)
    meta = {"format": _FORMAT, "fingerprint": fingerprint(), "config": experiment.config.to_dict(), "models": models}
    return arrays, meta


def _restore(agent, arrays: dict, meta: dict) -> None:
    """Give ``agent`` the fitted models an entry kept, on the data it holds now; ValueError where they differ.

    The agent draws each fit's rows as in a fit (:meth:`SARSPAgent.fit`, whose
    random stream moves on the same); each model takes the stored
    hyperparameters and factor and recomputes the rest from the rows, which
    must give the stored log marginal likelihood bit for bit.
    """
    names = {id(model): name for name, model in _models(agent).items()}
    agent.fit(fit_model=lambda model, X, y: _restore_model(names[id(model)], model, X, y, arrays, meta))


def _has_student_t_noise(model) -> bool:
    from ...models.processes.likelihood import StudentTLikelihoodGP

    return isinstance(model, StudentTLikelihoodGP)


def _restore_likelihood_model(name: str, model, X, y, arrays: dict, stored: dict) -> None:
    """A GP with Student-t noise restored on the rows ``X, y``: its mode searched again at the stored
    hyperparameters, from where the fit's search began, which gives the fit's bits."""
    from ...models.kernels import RBF

    if (stored.get("kind") != "t-likelihood" or type(stored.get("mode_start")) is not bool
            or type(stored.get("n_newton_")) is not int or type(stored.get("gradient_norm_")) is not float):
        raise ValueError(f"the {name} model's stored numbers are not those of a GP with Student-t noise")
    hyper, start, objectives = (arrays[f"{name}.{attribute}"] for attribute in _LIKELIHOOD_ARRAYS)
    n_distinct = len(np.unique(X, axis=0))
    for label, array, shape in (("hyper_", hyper, (4,)), ("start_objectives_", objectives, objectives.shape[:1]),
                                ("mode_start_", start, (n_distinct,) if stored["mode_start"] else (0,))):
        if array.shape != shape or array.dtype.kind != "f" or not np.all(np.isfinite(array)):
            raise ValueError(f"the {name} model's {label} is {array.dtype}{array.shape}, not {shape}")
    if not np.all(hyper > 0):
        raise ValueError(f"the {name} model's hyperparameters are not positive: {hyper.tolist()}")
    amplitude, length_scale, scale, nu = (float(v) for v in hyper)
    model.n_features_in_ = stored["n_features_in_"]
    model._settle(np.asarray(X, dtype=float), np.asarray(y, dtype=float), RBF(amplitude, length_scale), scale, nu,
                  start if stored["mode_start"] else None, stored["gradient_norm_"], objectives, stored["n_iter_"])
    if (model.log_marginal_likelihood_value_ != stored["log_marginal_likelihood_value_"]
            or model.n_newton_ != stored["n_newton_"]):
        raise ValueError(f"the {name} model's hyperparameters do not give the stored mode on these data: the entry "
                         "was edited, or the data changed")


def _restore_model(name: str, model, X, y, arrays: dict, meta: dict) -> None:
    """One model of an entry, restored on the rows ``X, y`` drawn for it."""
    from ...models.linalg import group_rows

    if _has_student_t_noise(model):
        stored = _checked_model_meta(meta["models"][name], X.shape[1], jitter=False)
        return _restore_likelihood_model(name, model, X, y, arrays, stored)
    stored = _checked_model_meta(meta["models"][name], X.shape[1])
    data = group_rows(X, y)
    G = len(data.counts)
    shapes = {"theta_": (len(model._theta_bounds()),), "objective_trace_": (stored["n_iter_"] + 1,),
              "fit_indices_": (len(X),), "L_": (G, G)}
    for attribute, shape in shapes.items():
        array = arrays[f"{name}.{attribute}"]
        kind = "i" if attribute == "fit_indices_" else "f"
        if array.shape != shape or array.dtype.kind != kind or not np.all(np.isfinite(array)):
            raise ValueError(f"the {name} model's {attribute} is {array.dtype}{array.shape}, not {shape}")
    if not np.array_equal(np.sort(arrays[f"{name}.fit_indices_"]), np.arange(len(X))):
        raise ValueError(f"the {name} model's fit rows are not the rows it was fitted on")
    model.n_features_in_, model.n_iter_ = stored["n_features_in_"], stored["n_iter_"]
    for attribute in ("theta_", "objective_trace_", "fit_indices_"):
        setattr(model, attribute, arrays[f"{name}.{attribute}"])
    model.kernel_, model.noise_variance_, extra = model._unpack(model.theta_)
    model._set_extra(extra)
    L = arrays[f"{name}.L_"]
    _check_factor(name, model, data, L, stored["jitter_"])
    model._adopt_factor(X, y, data, L, stored["jitter_"])
    if model.log_marginal_likelihood_value_ != stored["log_marginal_likelihood_value_"]:
        raise ValueError(f"the {name} model's factor and hyperparameters do not give the stored likelihood on "
                         "these data: the entry was edited, or the data changed")


def _checked_model_meta(stored, features: int, jitter: bool = True) -> dict:
    """A model's stored numbers, of the types and in the ranges a fit gives; ValueError otherwise."""
    ok = (isinstance(stored, dict) and type(stored.get("n_features_in_")) is int
          and stored["n_features_in_"] == features and type(stored.get("n_iter_")) is int and stored["n_iter_"] >= 0
          and (not jitter or (type(stored.get("jitter_")) is float and 0 <= stored["jitter_"] < np.inf))
          and type(stored.get("log_marginal_likelihood_value_")) is float)
    if not ok:
        raise ValueError(f"a model's stored numbers are not a fit's: {stored!r}")
    return stored


def _check_factor(name: str, model, data, L, jitter: float) -> None:
    """Refuse a factor that is not the Cholesky factor of the covariance the hyperparameters give on ``data``.

    Checked on two random directions, K v against L (L^T v): a few matrix-vector products where refactorising
    would cost the fit's last Cholesky again.
    """
    G = len(data.counts)
    K = model._training_covariance(data)
    K.flat[:: G + 1] += jitter
    v = np.random.default_rng(0).standard_normal((G, 2))
    if np.any(np.triu(L, 1)) or not np.allclose(L @ (L.T @ v), K @ v, rtol=1e-9,
                                                  atol=1e-9 * np.abs(K).max() * np.abs(v).sum(axis=0).max()):
        raise ValueError(f"the {name} model's factor is not that of its covariance on these data")


def load(config, prepared, directory=None):
    """The :class:`~sarsp_edu.experiments.experiment.Experiment` of ``config`` rebuilt from a stored fit, or None.

    An entry that cannot be read, was edited, or is not the fit of these settings on this machine and package
    is removed, and None returned: the caller fits again.

    Parameters
    ----------
    config : ExperimentConfig
        The settings whose fit is looked up.
    prepared : Prepared
        The world and data of ``config`` (:func:`~sarsp_edu.world.preparation.prepare`).
    directory : str or Path, optional
        A folder in the cache's place (the live dashboard's fits in other processes hand their fits over through
        one where the cache is off).  None: the cache's folder (:func:`cache_directory`); None when it is off.

    Returns
    -------
    Experiment or None
        With ``loaded_from_cache`` True.
    """
    from ...experiments.experiment import Experiment

    path = _path(config, directory)
    if path is None or not os.path.lexists(path):
        return None
    if path.is_symlink() or not path.is_file():
        _warn_once(f"{path} is not a regular file (a folder or a link in an entry's place)")
        return None
    try:
        with np.load(path, allow_pickle=False) as stored:
            arrays = {name: stored[name] for name in stored.files if name != "meta"}
            meta = json.loads(str(stored["meta"]))
        digest = meta.pop("digest", None)
        if digest != _digest(arrays, meta) or meta.get("format") != _FORMAT:
            raise ValueError("its digest does not match its contents")
        if meta["fingerprint"] != fingerprint() or meta["config"] != config.to_dict():
            raise ValueError("not the fit of these settings")
        experiment = Experiment(config, prepared=prepared, fit=lambda agent: _restore(agent, arrays, meta))
    except Exception as exc:  # unreadable, edited or not ours: fitted again and stored anew, and said
        reason = str(exc).strip().splitlines()[0][:200] if str(exc).strip() else type(exc).__name__
        warnings.warn(f"the stored fit {path} was refused ({reason}): it is fitted again and stored anew",
                      UserWarning, stacklevel=2)
        try:
            path.unlink(missing_ok=True)
        except OSError as exc:
            _warn_once(f"{path} cannot be used nor removed ({exc.strerror or exc})")
        return None
    try:
        os.utime(path)  # most recently used
    except OSError:
        pass
    experiment.loaded_from_cache = True
    return experiment


def store(experiment, directory=None) -> Path | None:
    """Keep a just-fitted ``experiment`` (before its first step) for its settings; the entry's path
    (None if it could not be written).

    The folder keeps at most ``CACHE_BYTES``: the least recently used entries beyond that are removed.

    Parameters
    ----------
    experiment : Experiment
        Fitted, and not stepped yet.
    directory : str or Path, optional
        A folder in the cache's place, as for :func:`load`.  None: the cache's folder.

    Returns
    -------
    Path or None
        None if the cache is off or the entry could not be written (warned once).

    Raises
    ------
    ValueError
        If ``experiment`` has taken a step.
    """
    if _steps_taken(experiment):
        raise ValueError(f"only a just-fitted experiment is stored, this one has taken {_steps_taken(experiment)} "
                         "steps")
    path = _path(experiment.config, directory)
    if path is None:
        return None
    arrays, meta = _contents(experiment)
    meta["digest"] = _digest(arrays, meta)
    buffer = io.BytesIO()
    np.savez(buffer, meta=np.array(json.dumps(meta)), **arrays)
    first = directory is None and not path.parent.exists()  # the user's cache folder, made now
    try:
        atomic_write_bytes(path, buffer.getvalue())
    except OSError as exc:  # a full or read-only disk, a folder in the way: a later fit, nothing else
        _warn_once(f"{path} cannot be written ({exc.strerror or exc})")
        return None
    if first:
        warnings.warn(f"sarsp_edu keeps fitted runs in {path.parent} ({len(buffer.getvalue()) / 2**20:.0f} MB this "
                      f"one, at most {CACHE_BYTES / 2**20:.0f} MB in all) so that the live dashboards and the "
                      f"capstone's check start at once next time; 'sarsp-edu cache --clear' removes them, "
                      f"{CACHE_VARIABLE}=off keeps none", UserWarning, stacklevel=2)
    _prune(path.parent)
    return path


def entries(directory=None) -> list:
    """The stored fits, most recently used first: ``(path, bytes)`` (regular files only); ``directory``:
    another folder than the cache's."""
    directory = cache_directory() if directory is None else Path(directory)
    if directory is None or not directory.is_dir():
        return []
    found = []
    for path in directory.glob(f"*{_SUFFIX}"):
        try:
            if path.is_symlink() or not path.is_file():
                continue
            stat = path.stat()
        except OSError:  # removed meanwhile by another kernel, or a link that loops
            continue
        found.append((stat.st_mtime, path, stat.st_size))
    return [(path, size) for _, path, size in sorted(found, reverse=True)]


def _prune(directory) -> None:
    total = 0
    for path, size in entries(directory):
        total += size
        if total > CACHE_BYTES:
            try:
                path.unlink(missing_ok=True)
            except OSError:
                pass


def clear() -> int:
    """Remove every stored fit; how many were removed."""
    found = entries()
    for path, _ in found:
        path.unlink(missing_ok=True)
    return len(found)
