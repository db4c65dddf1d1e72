"""Where a course's notebooks are: the sources in ``tutorials/source/``, each student notebook beside that folder.

The one place both :mod:`~sarsp_edu.teaching.course` (which writes the student
notebooks) and :mod:`~sarsp_edu.teaching.pages` (which renders them) find them.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["sources", "student_notebooks", "student_path"]


def sources(tutorials: Path, only=None) -> list[Path]:
    """The source notebooks of a tutorials folder, in order (``only``: those whose number NN is listed).

    Parameters
    ----------
    tutorials : path-like
        The tutorials folder; the sources are ``source/NN_name.ipynb`` in it.
    only : iterable of int or str, optional
        Tutorial numbers to keep; a number with no source is a ``ValueError``.  None or empty: all.
    """
    found = sorted((Path(tutorials) / "source").glob("[0-9][0-9]_*.ipynb"))
    if not found:
        raise FileNotFoundError(f"{tutorials}/source holds no source notebook (NN_name.ipynb)")
    if only:
        wanted = {f"{int(number):02d}" for number in only}
        numbers = {path.name[:2] for path in found}
        if wanted - numbers:
            raise ValueError(f"only must name tutorials among {sorted(numbers)}, got {sorted(wanted - numbers)}")
        found = [path for path in found if path.name[:2] in wanted]
    return found


def student_path(source: Path) -> Path:
    """Where a source's student notebook lives: ``tutorials/NN_name.ipynb`` beside ``tutorials/source/``."""
    return source.parent.parent / source.name


def student_notebooks(tutorials: Path) -> list[Path]:
    """The student notebooks of a tutorials folder, one per source; an error if one was never made."""
    notebooks = [student_path(path) for path in sources(tutorials)]
    missing = [str(p) for p in notebooks if not p.exists()]
    if missing:
        raise FileNotFoundError(f"no student notebook {missing}: run 'sarsp-edu course student' first")
    return notebooks
