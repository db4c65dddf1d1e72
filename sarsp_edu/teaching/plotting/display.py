"""A figure shown in a notebook with a description of what it shows (alt text), for a screen reader.

Without one, a static copy of the notebook (nbconvert's HTML, the course's
pages) says "No description has been provided for this image".  The alt
text travels in the output's metadata, ``{"image/png": {"alt": ...}}``
(nbformat's per-type metadata, which nbconvert's templates read), the same
place as a dashboard's picture carries it (:mod:`sarsp_edu.teaching.dashboards.framework`).
"""

from __future__ import annotations

import base64

__all__ = ["alt_metadata", "figure_bundle", "show_figure"]


def alt_metadata(alt: str) -> dict:
    """The output metadata that carries ``alt`` as the PNG's description: ``{"image/png": {"alt": alt}}``."""
    if not isinstance(alt, str) or not alt.strip():
        raise ValueError(f"alt must say what the picture shows (a non-empty string), got alt={alt!r}")
    return {"image/png": {"alt": " ".join(alt.split())}}


def figure_bundle(figure, alt: str) -> tuple[dict, dict]:
    """A matplotlib figure as (data, metadata): the PNG that Jupyter's inline backend would show, and its alt text.

    The PNG is rendered as ``%matplotlib inline`` renders it (the figure's
    dpi, ``bbox_inches="tight"``), so a notebook cell that calls
    :func:`show_figure` instead of ``plt.show()`` stores the same picture.

    Parameters
    ----------
    figure : matplotlib.figure.Figure
    alt : str
        What the figure shows (see :func:`show_figure`); a blank one is a ``ValueError``.
    """
    from IPython.core.pylabtools import print_figure

    metadata = alt_metadata(alt)
    png = print_figure(figure, "png", bbox_inches="tight")
    data = {"image/png": base64.b64encode(png).decode("ascii"), "text/plain": repr(figure)}
    return data, metadata


def show_figure(figure, alt: str) -> None:
    """Show a figure in the notebook with its alt text, in place of ``plt.show()``; pyplot then forgets it.

    Parameters
    ----------
    figure : matplotlib.figure.Figure
    alt : str
        What the figure shows, for someone who cannot see it: its panels,
        axes and curves, and what to notice.  Numbers only where the
        picture or the cell's printed output shows them.

    Examples
    --------
    >>> fig, ax = plt.subplots()                                        # doctest: +SKIP
    >>> plot_densities(ax, tails.compute_densities(3.0))                # doctest: +SKIP
    >>> show_figure(fig, "The Gaussian and the Student-t densities against x.")  # doctest: +SKIP
    """
    from IPython.display import display

    data, metadata = figure_bundle(figure, alt)
    display(data, raw=True, metadata=metadata)
    # a pyplot figure: not shown a second time at the cell's end
    if getattr(figure.canvas, "manager", None) is not None:
        import matplotlib.pyplot as plt

        plt.close(figure)
