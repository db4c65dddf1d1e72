"""A drawn path shows which way it runs (arrowheads or first steps along it, and where it ends); an ablation
panel names the setting it shows."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import pytest
from matplotlib.figure import Figure
from matplotlib.patches import FancyArrowPatch

from sarsp_edu import SafeGridWorld
from sarsp_edu.teaching import plotting

#: up two cells, right one and back, right again, then pushed against a wall for three more steps
PATH = [(4, 5), (4, 4), (4, 3), (5, 3), (4, 3), (5, 3), (6, 3), (6, 3), (6, 3), (6, 3)]


def _drawn(direction):
    ax = Figure().subplots()
    plotting.plot_gridworld(ax, SafeGridWorld(seed=0), trajectory=PATH, direction=direction, show_moved=False)
    arrows = [patch for patch in ax.patches if isinstance(patch, FancyArrowPatch)]
    arrows += [artist for artist in ax.artists if isinstance(artist, FancyArrowPatch)]
    return ax, arrows


def _texts(ax):
    return [text.get_text() for text in ax.texts]


def test_without_a_direction_the_path_is_drawn_as_before():
    ax, arrows = _drawn(None)
    assert not arrows and not _texts(ax)
    assert [t.get_text() for t in ax.get_legend().get_texts()].count("end") == 0


def _ends(arrow):
    """An arrow's tail and head, rounded: ((x0, y0), (x1, y1))."""
    return tuple(tuple(round(float(v), 2) for v in point) for point in arrow._posA_posB)


def test_arrows_point_along_each_move_once_and_both_ways_beside_each_other():
    _, arrows = _drawn("arrows")
    # distinct moves: up twice, right, back left, right (again: not drawn twice), right once more
    assert len(arrows) == 5
    heads = sorted((round(x1 - x0, 2), round(y1 - y0, 2)) for (x0, y0), (x1, y1) in map(_ends, arrows))
    assert heads == [(-0.4, 0.0), (0.0, -0.4), (0.0, -0.4), (0.4, 0.0), (0.4, 0.0)]  # up is -y: row 0 on top
    between_4_and_5 = sorted(_ends(a) for a in arrows if {a_x for (a_x, _) in _ends(a)} == {4.3, 4.7})
    assert between_4_and_5 == [((4.3, 3.13), (4.7, 3.13)), ((4.7, 2.87), (4.3, 2.87))], (
        "a move made both ways is drawn twice, each on its right of the path")


def test_the_end_is_marked_with_the_steps_spent_there():
    ax, _ = _drawn("arrows")
    assert "end" in [t.get_text() for t in ax.get_legend().get_texts()]
    assert "3 steps here" in _texts(ax)  # (6, 3) reached at step 6, then three steps that left it there


def test_steps_write_the_first_step_at_each_cell():
    ax, arrows = _drawn("steps")
    assert not arrows
    texts = _texts(ax)
    assert sorted(t for t in texts if t.isdigit()) == sorted(["0", "1", "2", "3", "6"])
    assert "3 steps here" in texts


def test_a_path_that_ends_moving_gets_no_count_and_a_wrong_direction_is_refused():
    ax = Figure().subplots()
    plotting.plot_gridworld(ax, SafeGridWorld(seed=0), trajectory=PATH[:4], direction="arrows")
    assert not [t for t in _texts(ax) if "steps here" in t]
    with pytest.raises(ValueError, match="direction must be one of"):
        plotting.plot_gridworld(Figure().subplots(), SafeGridWorld(seed=0), trajectory=PATH, direction="numbers")


def test_an_ablation_panel_names_the_setting_its_runs_come_from():
    import pandas as pd

    from sarsp_edu.experiments.ablation import PRIOR_AND_FITS

    runs = pd.DataFrame({"setting": PRIOR_AND_FITS[("per step", "500 rows")], "model": ["TP", "GP"],
                         "total_cost": [35.0, 31.0]})
    ax = Figure().subplots()
    plotting.plot_ablation_runs(ax, runs, "total_cost", title="violations")
    assert ax.get_title() == "violations: per step, 500 rows"
    ax = Figure().subplots()
    plotting.plot_ablation_runs(ax, pd.concat([runs, runs.assign(setting="another")]), "total_cost", title="violations")
    assert ax.get_title() == "violations", "runs of several settings: the title alone"
