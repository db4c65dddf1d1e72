"""The gridworld's renderings: a text grid (``"ansi"``) or an RGB image (``"rgb_array"``)."""

from __future__ import annotations

import gymnasium as gym
import numpy as np


class Rendering:
    """``render`` for :class:`~sarsp_edu.world.gridworld.SafeGridWorld` (a mixin)."""

    def render(self):
        """A text grid (``"ansi"``) or an RGB image (``"rgb_array"``)."""
        if self.render_mode is None:
            gym.logger.warn("render() called without render_mode; pass render_mode='ansi' or 'rgb_array'")
            return None
        if self.render_mode == "ansi":
            return self._render_text()
        return self._render_rgb()

    def _render_text(self) -> str:
        rows = [["." for _ in range(self.size)] for _ in range(self.size)]
        for x, y in self._unsafe:
            rows[y][x] = "X"
        gx, gy = self._goal
        rows[gy][gx] = "G"
        ax, ay = self._agent
        rows[ay][ax] = "!" if rows[ay][ax] == "X" else ("*" if (ax, ay) == self._goal else "A")
        legend = "A agent  G goal  X unsafe  ! agent in an unsafe state  * agent at the goal"
        return "\n".join(" ".join(row) for row in rows) + "\n" + legend + "\n"

    def _render_rgb(self, cell: int = 24) -> np.ndarray:
        colours = {
            "empty": (245, 245, 245),
            "unsafe": (214, 39, 40),
            "goal": (44, 160, 44),
            "agent": (31, 119, 180),
            "line": (200, 200, 200),
        }
        image = np.empty((self.size * cell, self.size * cell, 3), dtype=np.uint8)
        image[:] = colours["empty"]

        def paint(x, y, colour, margin=0):
            image[y * cell + margin : (y + 1) * cell - margin, x * cell + margin : (x + 1) * cell - margin] = colour

        for x, y in self._unsafe:
            paint(x, y, colours["unsafe"])
        paint(*self._goal, colours["goal"])
        paint(*self._agent, colours["agent"], margin=cell // 5)
        image[::cell, :] = colours["line"]
        image[:, ::cell] = colours["line"]
        return image
