"""The commands' figures: a ``--figure`` path checked before the work, drawn without a display, written whole."""

from __future__ import annotations

from .arguments import check_file

__all__ = ["check_figure", "new_figure", "save_figure"]


def check_figure(parser, path, overwrite: bool) -> None:
    """Refuse a ``--figure`` file that cannot be written, exists (unless ``overwrite``), or whose suffix names no
    format matplotlib writes here.

    Parameters
    ----------
    parser : argparse.ArgumentParser
        Says the refusal (``parser.error``).
    path : str or None
        The ``--figure`` argument (None: nothing to check).
    overwrite : bool
        Whether an existing file may be replaced.
    """
    from pathlib import Path

    if path is not None:
        check_file(parser, "--figure", path, overwrite=overwrite)
        if Path(path).suffix.lower() not in (".png", ".svg", ".pdf"):
            parser.error(f"--figure {path}: name a .png, .svg or .pdf file")


def new_figure(rows: int, columns: int, size: tuple):
    """A new figure drawn without a display (the command may run where there is none).

    Parameters
    ----------
    rows, columns : int
        The grid of axes.
    size : tuple of float
        The figure's size in inches.

    Returns
    -------
    figure, axes
        As ``matplotlib.pyplot.subplots``.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt.subplots(rows, columns, figsize=size, layout="constrained")


def save_figure(figure, path, overwrite: bool = True) -> None:
    """Write ``figure`` to ``path`` (its suffix the format) through a temporary file, and close it; without
    ``overwrite`` a file another command made meanwhile is refused, not replaced.

    Parameters
    ----------
    figure : matplotlib.figure.Figure
    path : str or path-like
    overwrite : bool, default True
    """
    import io
    from pathlib import Path

    import matplotlib.pyplot as plt

    from .._internal.io import atomic_write_bytes

    buffer = io.BytesIO()
    figure.savefig(buffer, format=Path(path).suffix.lower()[1:], dpi=110)
    plt.close(figure)
    try:
        atomic_write_bytes(path, buffer.getvalue(), replace=overwrite)
    except FileExistsError:
        raise SystemExit(f"sarsp-edu tables: error: --figure {path} was written by another command meanwhile; "
                         "--overwrite replaces it") from None
    print(f"figure written to {path}")
