"""The course: one source notebook per tutorial, the student notebooks made from it, the hand-outs.

Each tutorial has one **source** notebook in ``tutorials/source/``, with the
answers in it between nbgrader's ``### BEGIN SOLUTION`` / ``### END SOLUTION``
markers and nbgrader's cell metadata on the graded cells, so that an
instructor can drop the sources into an nbgrader course unchanged.  The
**student** notebooks in ``tutorials/`` are made from them by
:func:`student_notebook`, which does what ``nbgrader generate_assignment``
does to a cell: a solution region becomes nbgrader's stub (``# YOUR CODE
HERE`` / ``raise NotImplementedError()``, indented as the marker was; ``YOUR
ANSWER HERE`` in a written answer), hidden tests are removed, outputs
cleared.  ``sarsp-edu course student`` writes and executes them;
``sarsp-edu course handout`` copies what students get (the student notebooks,
the glossary and the stored results they read, never the sources) into a
folder or a zip.
"""

from __future__ import annotations

import copy
import os
import re
import shutil
import tempfile
import zipfile
from pathlib import Path

from .execution import NotebookFailed, execute, executed  # running a notebook: execution.py
from .layout import sources, student_notebooks, student_path  # where a course's notebooks are: layout.py
from .pages import write_pages  # the static pages are built in pages.py

__all__ = [
    "BEGIN_SOLUTION",
    "END_SOLUTION",
    "CODE_STUB",
    "TEXT_STUB",
    "clear_solutions",
    "student_notebook",
    "check_source",
    "execute",
    "execute_sources",
    "write_student_notebooks",
    "NotebookFailed",
    "typed_answers",
    "clear_reveals",
    "write_pages",
    "write_handout",
]

BEGIN_SOLUTION, END_SOLUTION = "### BEGIN SOLUTION", "### END SOLUTION"
BEGIN_HIDDEN, END_HIDDEN = "### BEGIN HIDDEN TESTS", "### END HIDDEN TESTS"
#: nbgrader's default stubs (ClearSolutions.code_stub["python"] and .text_stub)
CODE_STUB = "# YOUR CODE HERE\nraise NotImplementedError()"
TEXT_STUB = "YOUR ANSWER HERE"
#: the nbgrader cell-metadata schema this package writes
SCHEMA_VERSION = 3
#: what a student copy holds beside the notebooks (paths relative to the repository)
#: (repository path, path in the hand-out): the students' README is one of its own, which links only to what
#: the hand-out holds (the repository's tutorials/README.md links to the lecturer's guide and the sources); not
#: REPRODUCTION.md, which reports every run and so answers Tutorial 6's predictions (the notebooks name it, unlinked)
HANDOUT_FILES = (("tutorials/GLOSSARY.md", "tutorials/GLOSSARY.md"), ("tutorials/HANDOUT.md", "tutorials/README.md"),
                 ("tutorials/nbval_sanitize.cfg", "tutorials/nbval_sanitize.cfg"))
#: the stored results the tutorials read (``../results/...`` from ``tutorials/``); a test checks that every
#: results folder a student notebook names is here
HANDOUT_RESULTS = ("results/sweep-default", "results/sweep-latent", "results/sweep-reduced", "results/sweep-reference",
                   "results/ablation", "results/ablation-t-likelihood")


def _regions(lines: list[str], begin: str, end: str):
    """(start, stop) line indices of each ``begin`` ... ``end`` region; an unpaired marker is an error."""
    regions, start = [], None
    for i, line in enumerate(lines):
        if begin in line:
            if start is not None:
                raise ValueError(f"'{begin}' at line {i + 1} before the '{end}' of line {start + 1}")
            start = i
        elif end in line:
            if start is None:
                raise ValueError(f"'{end}' at line {i + 1} without a '{begin}'")
            regions.append((start, i))
            start = None
    if start is not None:
        raise ValueError(f"'{begin}' at line {start + 1} has no '{end}'")
    return regions


def clear_solutions(source: str, stub: str = CODE_STUB) -> str:
    """``source`` with every solution region replaced by ``stub``, indented as its BEGIN marker.

    Parameters
    ----------
    source : str
        A cell's source; an unpaired marker is a ``ValueError``.
    stub : str, default :data:`CODE_STUB`
        The text that replaces each region, its two marker lines included.

    Examples
    --------
    >>> print(clear_solutions("def f(x):\\n    ### BEGIN SOLUTION\\n    return x\\n    ### END SOLUTION"))
    def f(x):
        # YOUR CODE HERE
        raise NotImplementedError()
    """
    return _replace_regions(source, BEGIN_SOLUTION, END_SOLUTION, stub)


def _replace_regions(source: str, begin: str, end: str, stub: str | None) -> str:
    """Each ``begin`` ... ``end`` region replaced by ``stub`` indented as ``begin`` (removed when None)."""
    lines = source.split("\n")
    for start, stop in reversed(_regions(lines, begin, end)):
        indent = re.match(r"\s*", lines[start]).group(0)
        lines[start:stop + 1] = [] if stub is None else [indent + line for line in stub.split("\n")]
    return "\n".join(lines)


def _grading(cell) -> dict:
    return cell.get("metadata", {}).get("nbgrader", {})


def student_notebook(source):
    """The student version of a source notebook (an ``nbformat`` notebook; the source is not changed).

    A code cell's solution regions become :data:`CODE_STUB`; a written
    answer (a Markdown cell marked ``solution`` in its nbgrader metadata)
    becomes :data:`TEXT_STUB`, whole or region by region; hidden tests are
    removed; outputs and execution counts are cleared; a Markdown link out of
    ``source/`` is pointed from the student's folder instead (:func:`relinked`).
    """
    notebook = copy.deepcopy(source)
    for cell in notebook.cells:
        text = cell.source
        if cell.cell_type == "code":
            text = _replace_regions(clear_solutions(text, CODE_STUB), BEGIN_HIDDEN, END_HIDDEN, None).rstrip("\n")
            cell.outputs, cell.execution_count = [], None
        elif _grading(cell).get("solution"):
            lines = text.split("\n")
            text = (clear_solutions(text, TEXT_STUB) if _regions(lines, BEGIN_SOLUTION, END_SOLUTION)
                    else TEXT_STUB)
        else:
            text = relinked(text)
        cell.source = text
    return notebook


def check_source(source) -> list[str]:
    """What in a source notebook breaks nbgrader's format ([] when nothing does).

    Every cell with a solution region is an nbgrader solution cell; every
    graded cell has a unique ``grade_id`` and ``points``; every nbgrader
    metadata block has the keys and the schema version nbgrader writes.
    """
    problems, ids = [], set()
    keys = {"grade", "grade_id", "locked", "schema_version", "solution", "task"}
    for index, cell in enumerate(source.cells):
        where = f"cell {index}"
        meta = _grading(cell)
        try:
            marked = bool(_regions(cell.source.split("\n"), BEGIN_SOLUTION, END_SOLUTION))
            _regions(cell.source.split("\n"), BEGIN_HIDDEN, END_HIDDEN)
        except ValueError as exc:
            problems.append(f"{where}: {exc}")
            continue
        if marked and not meta.get("solution"):
            problems.append(f"{where}: has a solution region but no nbgrader metadata with solution: true")
        if not meta:
            continue
        missing = keys - set(meta)
        if missing:
            problems.append(f"{where}: nbgrader metadata lacks {sorted(missing)}")
        if meta.get("schema_version") != SCHEMA_VERSION:
            problems.append(f"{where}: nbgrader schema_version {meta.get('schema_version')!r}, not {SCHEMA_VERSION}")
        if meta.get("grade_id") in ids:
            problems.append(f"{where}: grade_id {meta.get('grade_id')!r} is used twice")
        ids.add(meta.get("grade_id"))
        if meta.get("grade") and not isinstance(meta.get("points"), (int, float)):
            problems.append(f"{where}: a graded cell needs points")
        if meta.get("grade") and not meta.get("solution") and not meta.get("locked"):
            problems.append(f"{where}: a test cell (grade, no solution) must be locked")
    return problems


def clear_reveals(notebook):
    """Clear the outputs of the cells that reveal a prediction's answer (tagged ``reveal``), in place.

    A student sees the answer when running the cell, after the prediction's
    check, never in the stored notebook before predicting.
    """
    from .prose import REVEAL_TAG

    for cell in notebook.cells:
        if cell.cell_type == "code" and REVEAL_TAG in cell.metadata.get("tags", []):
            cell.outputs, cell.execution_count = [], None
    return notebook


def execute_sources(tutorials="tutorials", timeout: int = 900, only=None) -> list[Path]:
    """Execute the source notebooks in place (their stored outputs are nbval's reference).

    ``only`` lists the tutorials' numbers to run (all by default).

    Parameters
    ----------
    tutorials : path-like, default "tutorials"
        The tutorials folder.
    timeout : int, default 900
        Seconds each cell may run (nbclient's ``timeout``).
    only : iterable of int or str, optional
        As in :func:`sources`.

    Returns
    -------
    list of Path
        The notebooks written.
    """
    import nbformat

    from .._internal.io import atomic_write_text

    written = []
    for path in sources(Path(tutorials), only):
        notebook = executed(nbformat.read(path, as_version=4), path.parent, timeout, path)
        atomic_write_text(path, nbformat.writes(notebook) + "\n")
        written.append(path)
    return written


def _answers(notebook) -> dict:
    """The sources of a notebook's answer cells (nbgrader's ``solution`` cells), by their grade id."""
    return {_grading(cell).get("grade_id", index): cell.source for index, cell in enumerate(notebook.cells)
            if _grading(cell).get("solution")}


def _free_backup(path: Path) -> Path:
    """Where to keep the old ``path``: ``NAME.bak``, or ``NAME.bak2``, ``NAME.bak3`` ... where those exist (a backup
    never replaces an older one)."""
    number = 1
    while True:
        backup = path.with_name(f"{path.name}.bak{'' if number == 1 else number}")
        if not backup.exists():
            return backup
        number += 1


def typed_answers(path: Path, generated) -> list:
    """The answer cells of the student notebook at ``path`` whose text differs from ``generated``'s (a student
    typed in them); empty where the file does not exist or holds the generated stubs.

    Parameters
    ----------
    path : Path
        A student notebook that may exist.
    generated : nbformat.NotebookNode
        The student notebook made afresh from its source (:func:`student_notebook`).

    Returns
    -------
    list of str
        The grade ids of the answer cells that differ, sorted.
    """
    import nbformat

    if not path.exists():
        return []
    held, fresh = _answers(nbformat.read(path, as_version=4)), _answers(generated)
    return sorted(str(key) for key, text in held.items() if fresh.get(key) != text)


def write_student_notebooks(tutorials="tutorials", run: bool = True, timeout: int = 900, only=None,
                            overwrite: bool = False, report=None) -> list[Path]:
    """Write (and run, so that their stored outputs are what a student first sees) the student notebooks.

    Each is written atomically beside its ``source/`` folder; a source that
    breaks nbgrader's format is refused before anything is written.  The
    cells that reveal a prediction's answer keep no output (:func:`clear_reveals`).
    ``only`` lists the tutorials' numbers to write (all by default).

    Parameters
    ----------
    tutorials : path-like, default "tutorials"
        The tutorials folder.
    run : bool, default True
        Execute each student notebook before writing it (in ``tutorials``).
    timeout : int, default 900
        Seconds each cell may run (nbclient's ``timeout``).
    only : iterable of int or str, optional
        As in :func:`sources`.
    overwrite : bool, default False
        Replace a student notebook whose answer cells hold a student's text (:func:`typed_answers`), keeping
        the old file beside it as ``NAME.ipynb.bak``; without it such a notebook is refused, before anything
        is written.
    report : callable, optional
        Called with a line for each old notebook kept as ``.bak``.

    Returns
    -------
    list of Path
        The notebooks written.

    Raises
    ------
    ValueError
        A source not in nbgrader's format, or a student notebook with typed answers and no ``overwrite``.
    NotebookFailed
        A cell raised while a notebook ran; the notebooks before it are written, it and those after are not.
    """
    import nbformat

    from .._internal.io import atomic_write_bytes, atomic_write_text

    tutorials = Path(tutorials)
    notebooks = []
    for path in sources(tutorials, only):
        source = nbformat.read(path, as_version=4)
        problems = check_source(source)
        if problems:
            raise ValueError(f"{path} is not in nbgrader's format: " + "; ".join(problems))
        notebooks.append((path, student_notebook(source)))
    typed = {student_path(path): typed_answers(student_path(path), notebook) for path, notebook in notebooks}
    typed = {target: cells for target, cells in typed.items() if cells}
    if typed and not overwrite:
        said = "; ".join(f"{target} ({len(cells)} answer cell{'s' if len(cells) > 1 else ''}: {', '.join(cells)})"
                         for target, cells in typed.items())
        raise ValueError(f"a student typed answers in {said}; add --overwrite to replace them (each old file is kept "
                         "beside it as .bak), or copy the notebooks elsewhere first")
    written = []
    for path, notebook in notebooks:
        if run:
            clear_reveals(executed(notebook, tutorials, timeout, path))
        target = student_path(path)
        if target in typed:
            backup = _free_backup(target)
            atomic_write_bytes(backup, target.read_bytes())
            if report is not None:
                report(f"kept the student's answers of {target} in {backup}")
        atomic_write_text(target, nbformat.writes(notebook) + "\n")
        written.append(target)
    return written


def write_handout(root=".", out=None, zip_path=None) -> Path:
    """A student copy of the course: student notebooks, glossary and stored results, no sources.

    Parameters
    ----------
    root : path
        The repository (holding ``tutorials/`` and ``results/``).
    out : path, optional
        A new or empty folder to write the copy into.
    zip_path : path, optional
        A zip file to write instead (written atomically).

    Returns the folder or the zip file.  The copy keeps the repository's
    layout (``tutorials/``, ``results/``), so the notebooks' ``../results``
    paths work in it.
    """
    root = Path(root)
    if (out is None) == (zip_path is None):
        raise ValueError("give exactly one of out (a folder) or zip_path (a zip file)")
    notebooks = student_notebooks(root / "tutorials")
    files = [(p, Path("tutorials") / p.name) for p in notebooks]
    files += [(root / name, Path(inside)) for name, inside in HANDOUT_FILES if (root / name).exists()]
    for folder in HANDOUT_RESULTS:
        for path in sorted((root / folder).rglob("*")):
            if path.is_file() and not path.name.startswith("."):
                files.append((path, path.relative_to(root)))
    inside = {name.as_posix() for _, name in files}
    texts = {name: _unlinked(path.read_text(encoding="utf-8"), name, inside) for path, name in files
             if name.suffix == ".md"}
    if zip_path is not None:
        zip_path = Path(zip_path)
        handle, temporary = tempfile.mkstemp(prefix=f".{zip_path.name}.", dir=zip_path.parent or ".")
        try:
            with open(handle, "wb") as stream, zipfile.ZipFile(stream, "w", zipfile.ZIP_DEFLATED) as archive:
                for path, name in files:
                    if name in texts:
                        archive.writestr(str(Path("sarsp-edu-course") / name), texts[name])
                    else:
                        archive.write(path, Path("sarsp-edu-course") / name)
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(temporary, 0o666 & ~umask)  # as any new file, not mkstemp's 0600
            Path(temporary).replace(zip_path)
        except BaseException:
            Path(temporary).unlink(missing_ok=True)
            raise
        return zip_path
    out = Path(out)
    if out.exists() and any(out.iterdir()):
        raise ValueError(f"out must be a new or empty folder, got out={str(out)!r}, which holds files")
    for path, name in files:
        (out / name).parent.mkdir(parents=True, exist_ok=True)
        if name in texts:
            (out / name).write_text(texts[name], encoding="utf-8")
        else:
            shutil.copy2(path, out / name)
    return out


_LINK = re.compile(r"(!?)\[([^\]]*)\]\(([^)#\s]+)((?:#[^)]*)?)\)")


def _local(target: str) -> bool:
    return "://" not in target and not target.startswith("mailto:")


def relinked(text: str, source: str = "source") -> str:
    """Markdown ``text`` of a notebook in ``source/`` with each relative link that leaves that folder
    ('../GLOSSARY.md') pointed from the folder above it ('GLOSSARY.md'), where the student notebook lies.

    A link inside ``source/`` (a sibling notebook) is kept: the student copy's sibling has the same name.

    Parameters
    ----------
    text : str
        A Markdown cell's text.
    source : str, default "source"
        The sources' folder, relative to the student notebooks' folder.

    >>> relinked("[glossary](../GLOSSARY.md#nu) and [T4](04_sarsp_live.ipynb)")
    '[glossary](GLOSSARY.md#nu) and [T4](04_sarsp_live.ipynb)'
    """
    def moved(match):
        target = match.group(3)
        if not _local(target) or not os.path.normpath(target).startswith(".."):
            return match.group(0)
        new = os.path.relpath(os.path.normpath(os.path.join(source, target)), ".").replace(os.sep, "/")
        return f"{match.group(1)}[{match.group(2)}]({new}{match.group(4)})"
    return _LINK.sub(moved, text)


def _unlinked(text: str, name: Path, inside: set) -> str:
    """A Markdown page of the hand-out with each relative link to a file the hand-out lacks said as text ('the
    figure (`results/x.png` in the sarsp_edu repository)'), so that no link of the copy leads nowhere."""
    def said(match):
        label, target = match.group(2), match.group(3)
        resolved = os.path.normpath((name.parent / target).as_posix())
        if not _local(target) or resolved in inside:
            return match.group(0)
        return f"{label} (`{target}` in the sarsp_edu repository)" if label else f"`{target}` (sarsp_edu repository)"
    return _LINK.sub(said, text)
