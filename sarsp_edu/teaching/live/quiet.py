"""A view of the live run that shows nothing: :class:`~sarsp_edu.teaching.live.controller.LiveRun` in a script or
a test, where no widget is drawn."""

from __future__ import annotations

__all__ = ["QuietView"]


class QuietView:
    """A view that shows nothing (a :class:`LiveRun` in a script or a test): the five methods of the module's
    docstring, each doing nothing."""

    def show_side(self, name) -> None:
        """Nothing: a side's run changed."""

    def show_metrics(self, throttle: bool = False) -> None:
        """Nothing: an episode may have ended."""

    def show_waiting(self, name, why: str) -> None:
        """Nothing: a side waits.

        Parameters
        ----------
        name : str
            The side.
        why : str
            What it waits for, in words.
        """

    def say(self, text: str) -> None:
        """Nothing: the status line."""

    def preview(self) -> None:
        """Nothing: the world the settings imply."""
