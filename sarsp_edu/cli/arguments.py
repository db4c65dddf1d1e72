"""The command's settings flags, built from ``ExperimentConfig``'s fields, and the checks on its paths.

Every check runs before any work starts: a folder that cannot be written,
results of other settings in the way, a missing file, each ends the command
with one line naming the flag, the value and what to do.
"""

from __future__ import annotations

import argparse
import dataclasses
import errno
import os
import sys


def _none_or(convert):
    def parse(text: str):
        return None if text.lower() == "none" else convert(text)

    parse.__name__ = convert.__name__
    return parse


def _float_or_word(text: str):
    """A number, or a word that a setting takes besides numbers (``likelihood_nu``'s "fitted")."""
    try:
        return float(text)
    except ValueError:
        return text


_float_or_word.__name__ = "float"

_TYPES = {
    "float": float,
    "float | str": _float_or_word,
    "int": int,
    "str": str,
    "int | None": _none_or(int),
    "str | None": _none_or(str),
}


def add_config_arguments(parser: argparse.ArgumentParser, skip=()) -> None:
    """One flag per ``ExperimentConfig`` field, with the field's own help text.

    Defaults are left to the dataclass (one source of truth): a flag not
    given is not passed on.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        The (sub)command's parser; the flags go in one argument group, after ``--preset``.
    skip : iterable of str, default ()
        Field names given no flag (those the command sets itself, such as ``model`` for ``compare``).
    """
    from ..config import LIMITS, PRESET_DOCS, PRESET_FIELDS, ExperimentConfig

    preset_fields = set(PRESET_FIELDS)

    group = parser.add_argument_group(
        "experiment settings (defaults: the 'default' preset; a flag given overrides the preset)")
    group.add_argument(
        "--preset", choices=list(PRESET_DOCS), default=None,
        help="a named set of SARSP settings: " + "; ".join(f"'{k}': {v}" for k, v in PRESET_DOCS.items())
        + " [default: default]")
    for f in dataclasses.fields(ExperimentConfig):
        if f.name in skip:
            continue
        names = [f"--{f.name.replace('_', '-')}"]
        if "flag" in f.metadata:
            names.insert(0, f"--{f.metadata['flag']}")
        bound = f"; at most {LIMITS[f.name][0]:,}" if f.name in LIMITS else ""
        help_text = f"{f.metadata['help']} [default: {f.metadata.get('shown_default', f.default)}{bound}]"
        if f.name in preset_fields:
            help_text = help_text[:-1] + ", or the preset's]"
        kwargs = dict(dest=f.name, default=argparse.SUPPRESS, help=help_text)
        if f.type == "bool":
            kwargs["action"] = argparse.BooleanOptionalAction
        else:
            kwargs["type"] = _TYPES[f.type]
            kwargs["metavar"] = f.name.upper() if "flag" not in f.metadata else f.metadata["flag"].upper()
            if "choices" in f.metadata:
                kwargs["choices"] = list(f.metadata["choices"])
                kwargs["metavar"] = "{" + ",".join(str(c) for c in f.metadata["choices"]) + "}"
        group.add_argument(*names, **kwargs)


def config_flags(args: argparse.Namespace) -> dict:
    """The ``ExperimentConfig`` fields given as flags (a flag not given is absent)."""
    from ..config import ExperimentConfig

    names = {f.name for f in dataclasses.fields(ExperimentConfig)}
    return {k: v for k, v in vars(args).items() if k in names}


def config_from_args(parser: argparse.ArgumentParser, args: argparse.Namespace, base=None):
    """Build the config (the preset, or ``base``, then the flags given), turning a bad value into a usage error.

    A flag that the other settings leave unused (``--n-samples`` with exact
    predictions, say) is reported on standard error.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        Reports a value the config refuses (``parser.error``: the usage line and exit status 2).
    args : argparse.Namespace
        The parsed command line: ``--preset``, the settings flags and ``command``.
    base : ExperimentConfig, optional
        The settings the flags change (a resumed sweep's stored ones); None: the preset's.

    Returns
    -------
    ExperimentConfig
    """
    from ..config import ExperimentConfig

    values = config_flags(args)
    try:
        if base is not None:
            config = base.replace(**values)
        else:
            config = ExperimentConfig.from_preset(getattr(args, "preset", None) or "default", **values)
    except ValueError as exc:
        parser.error(str(exc))
    ignored = config.ignored_settings()
    if args.command == "compare":  # both models run: the TP's settings count
        ignored = {k: v for k, v in ignored.items() if k not in ("nu", "noise_convention")}
    for name in sorted(set(values) & set(ignored)):
        print(f"warning: --{name.replace('_', '-')} is ignored: {ignored[name]}", file=sys.stderr)
    farthest = 2 * (config.grid_size - 1)  # the Manhattan distance across the grid, corner to corner
    if config.d > farthest:
        print(f"warning: --d {config.d:g} is beyond every distance on a {config.grid_size}x{config.grid_size} grid "
              f"(at most {farthest}): no action is ever predicted safe, every decision is the backup",
              file=sys.stderr)
    return config


#: what marks a folder as holding each command's results
_MARKERS = {"sweep": "sweep.json", "ablation": "ablation.json", "run": "result.json", "compare": "tp/result.json"}


def results_of(kind: str) -> str:
    """"a sweep's results", "an ablation's results": what a folder holding ``kind``'s marker holds."""
    return f"{'an' if kind[0] in 'aeiou' else 'a'} {kind}'s results"


def check_writable(parser: argparse.ArgumentParser, flag: str, name, path) -> None:
    """Refuse a folder ``path`` (to make, or to write in) that cannot be written, before any work starts.

    The folder is made and a file written and removed in it, then whatever
    this made is removed again: a permission, a read-only or pseudo file
    system (``/proc``), a file in the way, a name too long: each is found now,
    not after the run, and nothing is left behind.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        Reports a refusal (``parser.error``: the usage line and exit status 2).
    flag : str
        The flag named in the message, such as ``"--out"``.
    name : str or path-like
        The value as the user gave it, named in the message.
    path : pathlib.Path
        The folder to check.
    """
    import tempfile

    made = []
    ancestor = path
    while not ancestor.exists():
        if ancestor.is_symlink():  # a link to nothing: exists() is False, yet no folder can be made there
            try:
                ancestor.resolve(strict=True)
                loops = False
            except (RuntimeError, OSError) as exc:  # Python 3.13 says a loop with OSError(ELOOP)
                loops = isinstance(exc, RuntimeError) or exc.errno == errno.ELOOP
            if loops:
                parser.error(f"{flag} {name} cannot be made: {ancestor} is a symbolic link that loops")
            parser.error(f"{flag} {name} cannot be made: {ancestor} is a symbolic link to {os.readlink(ancestor)}, "
                         "which does not exist; make that folder or remove the link")
        made.append(ancestor)
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        parser.error(f"{flag} {name} cannot be made: {ancestor} is a file")
    try:
        for folder in reversed(made):
            folder.mkdir()
        handle, probe = tempfile.mkstemp(prefix=".sarsp-edu-probe-", dir=path)
        os.close(handle)
        os.unlink(probe)
    except OSError as exc:
        parser.error(f"{flag} {name} cannot be written: {exc.strerror or exc}")
    finally:
        for folder in made:  # the deepest first
            try:
                folder.rmdir()
            except OSError:
                pass


def check_out(parser: argparse.ArgumentParser, out, command: str, config=None, overwrite: bool = False) -> None:
    """Refuse an ``--out`` folder the command could not or should not write to, before any work starts.

    A command writes into a new folder, an empty one, or one holding its own
    kind of results: a sweep or an ablation resumes there; a run or a
    comparison replaces a result of the same settings there, and one of other
    settings only with ``--overwrite``.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        Reports a refusal (``parser.error``: the usage line and exit status 2).
    out : str or path-like or None
        The ``--out`` value; None (not given): nothing is checked.
    command : str
        ``"run"``, ``"compare"``, ``"sweep"`` or ``"ablation"``: whose results the folder may hold.
    config : ExperimentConfig, optional
        The settings of a run or comparison, compared with those stored in the folder; None: not compared.
    overwrite : bool, default False
        ``--overwrite``: replace a run or comparison of other settings.
    """
    if out is None:
        return
    from pathlib import Path

    if not str(out).strip():
        parser.error("--out was given an empty folder name; give a folder (new, empty, or holding a "
                     f"{command}'s results)")
    path = Path(out)
    if path.exists() and not path.is_dir():
        parser.error(f"--out {out} is a file; give a folder (new, empty, or holding a {command}'s results)")
    check_writable(parser, "--out", out, path)
    if not (path.is_dir() and any(not entry.name.startswith(".") for entry in path.iterdir())):
        return
    kind = next((k for k, marker in _MARKERS.items() if (path / marker).exists()), None)
    if kind != command:
        holds = results_of(kind) if kind else "other files"
        parser.error(f"--out {out} holds {holds}; '{command}' writes into a new folder, an empty one "
                     f"or one holding a {command}'s results")
    if command in ("run", "compare") and config is not None and not overwrite:
        differing = stored_settings_differ(path / _MARKERS[command], config, same_model=command == "run")
        if differing:
            parser.error(f"--out {out} holds a {command} of other settings ({differing}); to keep both, give "
                         "another folder; to replace it, add --overwrite")


def stored_settings_differ(result_json, config, same_model: bool = True) -> str:
    """The settings in which a stored run differs from ``config``, in a line ('' when none).

    With ``same_model=False`` (a comparison, whose ``tp/`` is read) the model is not compared.

    Parameters
    ----------
    result_json : path-like
        The stored run's ``result.json``; one that cannot be read is reported in the line.
    config : ExperimentConfig
        The settings now asked for.
    same_model : bool, default True
        Compare the ``model`` field too.
    """
    from .._internal.io import StoredResultError, read_json
    from ..config import ExperimentConfig

    try:
        stored = read_json(result_json, keys=("config",))["config"]
    except StoredResultError:
        return f"{result_json} cannot be read"
    ours = (config if same_model else config.replace(model=stored.get("model", config.model))).to_dict()
    known = {f.name for f in dataclasses.fields(ExperimentConfig)}
    missing = object()  # a setting one side leaves out (another model's alone: to_dict drops it)
    fields_ = sorted(k for k in known if stored.get(k, missing) != ours.get(k, missing))
    return ", ".join(f"{k}: stored {stored.get(k, 'nothing')!r}, now {ours.get(k, 'nothing')!r}" for k in fields_)


def check_file(parser: argparse.ArgumentParser, flag: str, name, overwrite: bool | None = None) -> None:
    """Refuse an output file that could not or should not be written, before any work starts.

    Only a regular file is replaced (a symbolic link, a device or a pipe
    would be swapped for a file), and with ``overwrite=False`` not even that.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        Reports a refusal (``parser.error``: the usage line and exit status 2).
    flag : str
        The flag named in the message, such as ``"--zip"``.
    name : str or path-like
        The file to write; its folder is checked with :func:`check_writable`.
    overwrite : bool or None, default None
        False: refuse a file that exists; True or None: an existing regular file may be replaced.
    """
    from pathlib import Path

    if not str(name).strip():
        parser.error(f"{flag} was given an empty file name; give a file to write")
    path = Path(name)
    if path.is_symlink():
        parser.error(f"{flag} {name} is a symbolic link; give the file itself or a new name (writing would replace "
                     "the link by a file)")
    if path.is_dir():
        parser.error(f"{flag} {name} is a folder; give a file name")
    if path.exists() and not path.is_file():
        parser.error(f"{flag} {name} is not a regular file (a device, a pipe or a socket); give a new file name")
    if path.exists() and overwrite is False:
        parser.error(f"{flag} {name} exists; add --overwrite to replace it, or give a new name")
    check_writable(parser, flag, name, path.parent)
