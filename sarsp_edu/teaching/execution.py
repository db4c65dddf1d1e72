"""Running a tutorial notebook as the course command does: what is kept of it, and a failing cell in one line."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["NotebookFailed", "execute", "executed"]


def execute(notebook, folder, timeout: int = 900):
    """Run ``notebook`` in ``folder`` and keep what every reader can see.

    The live widgets' state is not stored: a notebook viewed without a
    kernel (GitHub, nbviewer, an HTML export offline) then shows each
    dashboard's picture, the PNG its output carries beside the widget, where
    a stored state would make an export load the widgets from the network.
    Run times are not stored either: they change at every run.

    Parameters
    ----------
    notebook : nbformat.NotebookNode
        Executed and changed in place, and returned.
    folder : path-like
        The kernel's working folder.
    timeout : int, default 900
        Seconds each cell may run (nbclient's ``timeout``).
    """
    from nbclient import NotebookClient

    from .live import AUTOPLAY_VARIABLE, SNAPSHOT_VARIABLE

    # the kernel inherits them: nobody watches a batch run, and a live dashboard's stored picture shows its
    # agents after 10 episodes rather than the world before Run
    settings = {AUTOPLAY_VARIABLE: "0", SNAPSHOT_VARIABLE: "10"}
    before = {name: os.environ.get(name) for name in settings}
    os.environ.update(settings)
    try:
        NotebookClient(notebook, timeout=timeout, kernel_name="python3", store_widget_state=False,
                       resources={"metadata": {"path": str(folder)}}).execute()
    finally:
        for name, value in before.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value
    notebook.metadata.pop("widgets", None)
    for cell in notebook.cells:
        cell.metadata.pop("execution", None)
    return notebook


class NotebookFailed(RuntimeError):
    """A notebook's cell raised as the course command ran it; the message names the notebook, the cell and the
    error in one line.  Nothing of that notebook was written."""


def executed(notebook, folder, timeout: int, path: Path):
    """:func:`execute`, a cell that raises said in one line (:class:`NotebookFailed`) rather than nbclient's
    traceback of the whole cell.

    Parameters
    ----------
    notebook : nbformat.NotebookNode
        Executed in place, as :func:`execute` does.
    folder : path-like
        The kernel's working folder.
    timeout : int
        Seconds each cell may run.
    path : Path
        The notebook's file, named in the message.
    """
    from nbclient.exceptions import CellExecutionError

    try:
        return execute(notebook, folder, timeout)
    except CellExecutionError as exc:
        for index, cell in enumerate(notebook.cells):
            errors = [out for out in cell.get("outputs", []) if out.get("output_type") == "error"]
            if errors:
                first = (cell.source.strip().split("\n") or [""])[0][:60]
                raise NotebookFailed(f"{path}: cell {index + 1} ({first!r}) raised {errors[0].get('ename')}: "
                                     f"{errors[0].get('evalue')}; no file was written for it") from None
        raise NotebookFailed(f"{path}: a cell raised ({str(exc).strip().splitlines()[-1]}); no file was written "
                             "for it") from None
