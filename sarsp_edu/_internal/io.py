"""Atomic file writes: a reader never sees a half-written result."""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path


def one_line_warning(message, category, *args, **kwargs) -> str:
    """``warnings.formatwarning`` for a terminal: ``warning: message``, without a file name and a source line."""
    return f"warning: {message}\n"


def lock_folder(folder, name: str, what: str):
    """Hold ``folder``'s lock file ``name`` for this process, or say that another ``what`` holds it.

    Returns the open lock file (closing it releases the lock); None where the
    platform has no ``fcntl`` (Windows), which then runs without one.
    """
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not on Linux or macOS
        return None
    folder = Path(folder)
    handle = open(folder / name, "a+")
    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        handle.seek(0)
        holder = handle.read().strip()
        handle.close()
        raise ValueError(f"another {what} is running in {folder}{f' (process {holder})' if holder else ''}; "
                         "wait for it to finish, or use another folder") from None
    handle.seek(0)
    handle.truncate()
    handle.write(f"{os.getpid()}\n")
    handle.flush()
    return handle


class StoredResultError(ValueError):
    """A stored result that cannot be used: the message names the file and what is wrong with it."""


def check_regular_file(path: Path) -> None:
    """Refuse a folder, a device (``/dev/zero``) or a pipe in a stored file's place: never read, it can fill the
    memory or wait for ever."""
    if not path.is_file():
        raise StoredResultError(f"{path} is not a regular file (a folder, a device or a pipe in a stored file's "
                                "place); restore the file")


def read_json(path, keys=()) -> dict:
    """A JSON object from ``path`` that holds ``keys``, or :class:`StoredResultError` naming the file."""
    path = Path(path)
    if path.exists():
        check_regular_file(path)
    try:
        payload = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise StoredResultError(f"{path} cannot be read ({exc}); it was probably cut short") from None
    except RecursionError:
        raise StoredResultError(f"{path} cannot be read: it nests lists or objects thousands deep, as no stored "
                                "result does; restore it") from None
    except ValueError as exc:  # an integer of more digits than Python converts (sys.get_int_max_str_digits)
        raise StoredResultError(f"{path} cannot be read ({exc}); no stored result holds such a number") from None
    missing = [key for key in keys if not isinstance(payload, dict) or key not in payload]
    if missing:
        raise StoredResultError(f"{path} lacks {', '.join(repr(k) for k in missing)}")
    return payload


def _permissions(directory: bool = False) -> int:
    """The mode ``open``/``mkdir`` would give a new file or folder under the current umask.

    ``tempfile`` creates its files 0600 and folders 0700 whatever the umask,
    which would keep a lecturer's results from the students on a shared
    server; a renamed temporary must end up as an ordinary file would.
    """
    mask = os.umask(0)
    os.umask(mask)
    return (0o777 if directory else 0o666) & ~mask


def staging_directory(parent, name: str) -> Path:
    """A new, empty hidden folder in ``parent`` to build ``name`` in before renaming it into place."""
    staging = Path(tempfile.mkdtemp(prefix=f".{name}.", dir=parent))
    os.chmod(staging, _permissions(directory=True))
    return staging


def publish_folder(final, write, marker: str) -> Path:
    """Build the folder ``final`` with ``write(staging)`` in a hidden staging folder beside it, then rename it into
    place: a reader sees the whole folder or none of it.

    Where another process published ``final`` first (its ``marker`` file is there), ours is removed and theirs
    kept; on any error the staging folder is removed and the error raised.
    """
    final = Path(final)
    final.parent.mkdir(parents=True, exist_ok=True)
    staging = staging_directory(final.parent, final.name)
    try:
        write(staging)
        try:
            os.rename(staging, final)
        except OSError:
            if not (final / marker).exists():
                raise
            shutil.rmtree(staging)  # another worker finished the same folder first
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    return final


def atomic_write_text(path, text: str, replace: bool = True) -> Path:
    """Write ``text`` to ``path`` through a temporary file and an atomic rename (see :func:`atomic_write_bytes`)."""
    return atomic_write_bytes(path, text.encode("utf-8"), replace=replace)


def atomic_write_bytes(path, data: bytes, replace: bool = True) -> Path:
    """Write ``data`` to ``path`` through a temporary file and an atomic rename.

    The temporary file lives in the same folder (a rename is atomic only
    within one file system) and is removed if anything fails.  With
    ``replace=False`` the file is linked into place only if ``path`` does not
    exist, atomically: ``FileExistsError`` if another writer made it first
    (two commands writing one new file: neither is lost silently).
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        os.fchmod(fd, _permissions())
        with os.fdopen(fd, "wb") as handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        if replace:
            os.replace(tmp, path)
        else:
            os.link(tmp, path)  # fails if path exists, whoever made it
            os.unlink(tmp)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
    return path
