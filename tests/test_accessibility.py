"""Pictures for everyone in a lecture hall of 200: the GP and the TP told apart without colour, colours that
stay apart in greyscale and for red-green colour vision deficiency, alt text on every picture, a visible
keyboard focus, and no character a standard font lacks.

Colour vision deficiency is simulated with the matrices of Machado, Oliveira and Fernandes (2009, "A
physiologically-based model for simulation of color vision deficiency", IEEE TVCG 15(6)), severity 1.0
(dichromacy), applied to linear sRGB; colour differences are CIE76 Delta E*ab in CIELAB (D65 white).
"""

from __future__ import annotations

import re

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pandas as pd
import pytest
from matplotlib.collections import PathCollection
from matplotlib.colors import to_rgb
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from sarsp_edu.models import tails
from sarsp_edu.teaching import demos, plotting
from sarsp_edu.teaching.plotting import COLOURS

#: Machado et al. (2009), Table 1, severity 1.0: linear RGB -> linear RGB as a dichromat sees it
MACHADO_2009 = {
    "protanopia": np.array([[0.152286, 1.052583, -0.204868],
                            [0.114503, 0.786281, 0.099216],
                            [-0.003882, -0.048116, 1.051998]]),
    "deuteranopia": np.array([[0.367322, 0.860646, -0.227968],
                              [0.280085, 0.672501, 0.047413],
                              [-0.011820, 0.042940, 0.968881]]),
}
#: sRGB (linear) to CIE XYZ, D65 (IEC 61966-2-1)
SRGB_TO_XYZ = np.array([[0.4124564, 0.3575761, 0.1804375],
                        [0.2126729, 0.7151522, 0.0721750],
                        [0.0193339, 0.1191920, 0.9503041]])
D65 = np.array([0.95047, 1.0, 1.08883])

#: the least lightness difference (CIELAB L*, 0-100) of two colours a figure contrasts: greyscale print
GREY_MIN_DL = 15.0
#: the least CIE76 Delta E*ab between them as a protanope or a deuteranope sees them (2.3 is just noticeable;
#: 20 is told apart at a glance, even in a thin line)
CVD_MIN_DE = 20.0
#: the pairs of colours that the figures contrast, by their names in COLOURS
CONTRASTED = [("gp", "tp"), ("gp", "robust"), ("tp", "robust"), ("data", "unsafe")]


def linear_rgb(colour) -> np.ndarray:
    """sRGB (any matplotlib colour) to linear RGB (IEC 61966-2-1's transfer function undone)."""
    c = np.asarray(to_rgb(colour), dtype=float)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def lab(rgb_linear) -> np.ndarray:
    """Linear RGB to CIELAB (D65)."""
    t = SRGB_TO_XYZ @ np.clip(rgb_linear, 0.0, 1.0) / D65
    f = np.where(t > (6 / 29) ** 3, np.cbrt(t), t / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


def seen(colour, vision: str | None = None) -> np.ndarray:
    """The colour in CIELAB as someone with ``vision`` ("protanopia", "deuteranopia", None: typical) sees it."""
    rgb = linear_rgb(colour)
    return lab(rgb if vision is None else MACHADO_2009[vision] @ rgb)


def delta_e(a, b, vision: str | None = None) -> float:
    return float(np.linalg.norm(seen(a, vision) - seen(b, vision)))


def lightness_gap(a, b) -> float:
    return float(abs(seen(a)[0] - seen(b)[0]))


def test_the_simulation_keeps_greys_and_the_colour_science_is_right():
    assert np.allclose(seen("white"), [100, 0, 0], atol=0.01) and np.allclose(seen("black"), 0, atol=0.01)
    for matrix in MACHADO_2009.values():  # a dichromat sees greys as everyone does: each row sums to 1
        assert np.allclose(matrix.sum(axis=1), 1.0, atol=1e-5)
    assert delta_e("#777777", "#777777", "deuteranopia") < 0.01
    assert lightness_gap("#000000", "#ffffff") == pytest.approx(100.0, abs=0.01)


@pytest.mark.parametrize("pair", CONTRASTED, ids="-".join)
def test_contrasted_colours_stay_apart_in_greyscale_and_for_red_green_colour_blindness(pair):
    a, b = (COLOURS[name] for name in pair)
    assert lightness_gap(a, b) >= GREY_MIN_DL, f"{pair}: L* {lightness_gap(a, b):.1f} apart in greyscale"
    for vision in MACHADO_2009:
        assert delta_e(a, b, vision) >= CVD_MIN_DE, f"{pair}: Delta E {delta_e(a, b, vision):.1f} for {vision}"


def test_the_checks_fail_for_colours_known_to_collapse():
    # red and green: alike to a deuteranope (why the goal is a star and the unsafe states squares)
    assert delta_e(COLOURS["unsafe"], COLOURS["goal"], "deuteranopia") < CVD_MIN_DE
    assert delta_e("#ff0000", "#00a000", "deuteranopia") < CVD_MIN_DE
    # the Student-t likelihood's old mid green beside the GP's orange: alike to a protanope
    assert delta_e("#2ca02c", COLOURS["gp"], "protanopia") < CVD_MIN_DE
    # the old clean rows' blue beside the outliers' red: one grey in print
    assert lightness_gap(COLOURS["tp"], COLOURS["unsafe"]) < GREY_MIN_DL


# --------------------------------------------------------------------------
# the GP and the TP differ in line style or marker, not only in colour
# --------------------------------------------------------------------------
def _signature(artist) -> tuple:
    """How an artist looks, colour aside: its line style and marker."""
    if isinstance(artist, Line2D):
        marker = artist.get_marker()
        return ("line", artist.get_linestyle(), None if marker in ("None", "", None) else str(marker))
    path = artist.get_paths()[0]
    return ("points", tuple(np.round(path.vertices, 3).ravel()))


def _by_label(ax, gp: str, tp: str) -> tuple[list, list]:
    artists = [*ax.get_lines(), *ax.collections]
    return ([a for a in artists if a.get_label().startswith(gp)], [a for a in artists if a.get_label().startswith(tp)])


def _by_colour(ax) -> tuple[list, list]:
    def colour_of(artist):
        colour = artist.get_color() if isinstance(artist, Line2D) else artist.get_facecolor()[0]
        return tuple(np.round(to_rgb(colour), 3))

    artists = [a for a in [*ax.get_lines(), *ax.collections] if isinstance(a, (Line2D, PathCollection))]
    return tuple([a for a in artists if colour_of(a) == tuple(np.round(to_rgb(COLOURS[m]), 3))] for m in ("gp", "tp"))


def _records(n: int, shift: float = 0.0) -> pd.DataFrame:
    episodes = np.arange(1, n + 1)
    return pd.DataFrame({"episode": episodes, "total_cost": episodes + shift, "mean_reward": -episodes + shift})


def _learning_curves() -> pd.DataFrame:
    base = np.linspace(90.0, 85.0, 50)
    curves = pd.DataFrame({"authors TP": base + 1.0, "authors GP": base - 1.0}, index=np.arange(1, 51))
    for model, shift in (("TP", 0.5), ("GP", -0.5)):
        curves[f"ours {model}"] = base + shift
        curves[f"ours {model} low"], curves[f"ours {model} high"] = base + shift - 2, base + shift + 2
    return curves


def _figures():
    """(name, Axes, GP artists, TP artists) for every picture that draws both models."""
    densities = tails.compute_densities(3.0)
    for log in (False, True):
        ax = Figure().subplots()
        plotting.plot_densities(ax, densities, log=log)
        yield (f"densities log={log}", ax, *_by_label(ax, "Gaussian", "Student-t"))
    ax = Figure().subplots()
    x = np.linspace(0.0, 20.0, 100)
    plotting.plot_tail_ratio_comparison(ax, tails.compute_tail_ratios((3.0,), 5.0, x_t=x, x_gauss=x), 3.0)
    yield ("Karamata ratio", ax, *_by_label(ax, "Gaussian", "Student-t"))
    posteriors = demos.compute_posteriors(3.0, 10.0, 0.1, 0, fit=False)
    ax = Figure().subplots()
    plotting.plot_variances(ax, posteriors)
    yield ("variances", ax, *_by_label(ax, "GP", "TP"))
    axes = Figure().subplots(1, 2)
    for one, model in zip(axes, ("gp", "tp")):
        plotting.plot_posterior(one, posteriors, model)
    yield ("posteriors", axes[0], [axes[0].get_lines()[0]], [axes[1].get_lines()[0]])
    ax = Figure().subplots()
    plotting.plot_robust(ax, demos.compute_robust())
    yield ("robust", ax, *_by_label(ax, "GP (", "TP ("))
    for n in (5, 40):  # with markers (a short run) and without
        axes = Figure().subplots(1, 2)
        plotting.plot_live_metrics(axes, {"tp": _records(n), "gp": _records(n, 1.0)}, ["total_cost", "mean_reward"])
        yield (f"live metrics, {n} episodes", axes[0], *_by_label(axes[0], "GP", "TP"))
        axes = Figure().subplots(1, 2)
        plotting.plot_live_metrics(axes, {"per step": _records(n), "per action": _records(n, 1.0)},
                                   ["total_cost", "mean_reward"], labels={"per step": "GP", "per action": "TP"})
        yield (f"live metrics of two settings, {n} episodes", axes[0], *_by_label(axes[0], "GP", "TP"))
    ax = Figure().subplots()
    plotting.plot_macro(ax, pd.DataFrame({"TP": [17.0, 45.0], "GP": [57.0, 56.0]}, index=[2, 10]), metric="total_cost")
    yield ("macro", ax, *_by_label(ax, "GP", "TP"))
    ax = Figure().subplots()
    table = pd.DataFrame({"ours TP": [1.0, 2.0], "authors TP": [1.5, 2.5], "ours GP": [3.0, 1.0],
                          "authors GP": [2.0, 1.5]})
    plotting.plot_beside_authors(ax, table, metric="total_cost")
    yield ("beside the authors", ax, *_by_label(ax, "GP", "TP"))
    ax = Figure().subplots()
    plotting.plot_learning_curves_beside_authors(ax, _learning_curves(), metric="task_success_rate")
    gp, tp = _by_label(ax, "GP", "TP")
    yield ("learning curves", ax, [a for a in gp if isinstance(a, Line2D)], [a for a in tp if isinstance(a, Line2D)])
    ax = Figure().subplots()
    runs = pd.DataFrame({"model": ["TP", "TP", "GP", "GP"], "total_cost": [3.0, 4.0, 5.0, 6.0]})
    plotting.plot_ablation_runs(ax, runs, "total_cost")
    yield ("ablation runs", ax, *_by_colour(ax))


@pytest.mark.parametrize("name, ax, gp, tp", list(_figures()), ids=lambda v: v if isinstance(v, str) else "")
def test_the_gp_and_the_tp_differ_in_line_style_or_marker(name, ax, gp, tp):
    assert gp and tp, f"{name}: no GP or no TP artist found"
    overlap = {_signature(a) for a in gp} & {_signature(a) for a in tp}
    assert not overlap, f"{name}: the GP and the TP share {overlap}: only their colours tell them apart"


def test_the_style_check_fails_for_two_models_drawn_alike():
    ax = Figure().subplots()
    ax.plot([0, 1], color=COLOURS["gp"], label="GP")
    ax.plot([0, 1], color=COLOURS["tp"], label="TP")
    gp, tp = _by_label(ax, "GP", "TP")
    assert {_signature(a) for a in gp} & {_signature(a) for a in tp}


# --------------------------------------------------------------------------
# alt text: every picture says what it shows, with no number the picture does not show
# --------------------------------------------------------------------------
def _numbers(text: str) -> set:
    return set(re.findall(r"(?<![\w^(.-])\d+(?:\.\d+)?", text))


@pytest.mark.parametrize("factory", ["tail_decay_dashboard", "posterior_dashboard", "robust_dashboard",
                                     "gridworld_dashboard"])
def test_a_dashboards_picture_carries_alt_text_that_names_only_numbers_it_shows(factory):
    from matplotlib.text import Text

    from sarsp_edu.teaching.dashboards import tutorials

    dashboard = getattr(tutorials, factory)()
    bundle, metadata = dashboard._repr_mimebundle_()
    alt = metadata["image/png"]["alt"]
    assert "image/png" in bundle and len(alt) > 100 * len(dashboard.panels)
    assert alt.startswith(f"{len(dashboard.panels)} pictures side by side")
    shown = set()
    for figure in dashboard.figures:
        figure.canvas.draw()  # the tick labels
        shown |= set().union(*(_numbers(t.get_text()) for t in figure.findobj(Text)))
    assert _numbers(alt) <= shown, f"alt text numbers {_numbers(alt) - shown} that no picture shows"
    first = list(dashboard.controls)[0]
    control = dashboard.controls[first]
    control.value = control.max  # the alt text follows the sliders where a picture names their values
    assert dashboard._repr_mimebundle_()[1]["image/png"]["alt"] == dashboard.alt_text()


def test_a_figure_is_shown_with_its_alt_text_and_a_missing_one_is_refused(monkeypatch):
    import base64

    import IPython.display
    import matplotlib.pyplot as plt

    shown = []
    monkeypatch.setattr(IPython.display, "display", lambda *objs, **kwargs: shown.append((objs, kwargs)))
    figure, ax = plt.subplots(figsize=(3, 2))
    ax.plot([0, 1])
    plotting.show_figure(figure, "A rising line.")
    (data,), kwargs = shown[0]
    assert kwargs == {"raw": True, "metadata": {"image/png": {"alt": "A rising line."}}}
    assert base64.b64decode(data["image/png"]).startswith(b"\x89PNG") and data["text/plain"].startswith("<Figure")
    assert not plt.fignum_exists(figure.number)  # not shown a second time at the cell's end
    with pytest.raises(ValueError, match="alt must say what the picture shows"):
        plotting.show_figure(Figure(), "  ")


def test_the_live_grid_says_what_it_draws_and_uses_no_glyph_for_the_goal():
    from sarsp_edu import SafeGridWorld
    from sarsp_edu.teaching.live import markup

    svg = markup.gridworld_svg(SafeGridWorld(seed=0).layout(), trajectory=[(0, 0), (1, 0)],
                               unsafe_pairs=[((1, 0), 1)], title="episode 1 of 3")
    label = re.search(r'aria-label="([^"]+)"', svg).group(1)
    assert 'role="img"' in svg and label.startswith("episode 1 of 3: a 10 by 10 grid world")
    assert "its path" in label and "(S_u)" in label
    assert "<polygon" in svg and all(ord(c) < 128 for c in svg)


# --------------------------------------------------------------------------
# a visible focus, a size button on every dashboard, and no character a standard font lacks
# --------------------------------------------------------------------------
def test_every_dashboard_outlines_the_focused_control_and_has_a_size_button():
    from sarsp_edu.teaching.dashboards.projector import FOCUS_OUTLINE
    from sarsp_edu.teaching.dashboards.tutorials import gridworld_dashboard, tail_decay_dashboard

    for on in (False, True):  # the outline whatever the size
        board = tail_decay_dashboard() if on else gridworld_dashboard()
        board.set_projector(on)
        css = [c.value for c in board.children if "<style>" in getattr(c, "value", "")]
        assert len(css) == 1 and "sarsp-dashboard" in board._dom_classes
        for selector in (".noUi-handle", "button", ".widget-readout"):
            assert f".sarsp-dashboard {selector}:focus-visible" in css[0]
        assert f"outline: {FOCUS_OUTLINE} !important" in css[0]
        assert board.size_toggle in board.children[0].children  # in the controls, where a lecturer looks


def test_the_size_button_switches_its_dashboard_alone():
    from sarsp_edu.teaching.dashboards.tutorials import posterior_dashboard, tail_decay_dashboard

    one, other = tail_decay_dashboard(), posterior_dashboard()
    for board in (one, other):
        board.set_projector(True)
    assert one.size_toggle.description == "Large text: on" and one.images[0].layout.flex
    one.size_toggle.value = False  # a click
    assert not one.projector and "sarsp-projector" not in one._dom_classes
    assert one.size_toggle.description == "Large text: off" and one.images[0].layout.width.endswith("%")
    assert other.projector and other.size_toggle.value
    one.set_projector(True)  # from code: the button follows
    assert one.size_toggle.value and one.size_toggle.description == "Large text: on"


def test_no_character_of_the_package_is_missing_from_debians_default_font():
    """Every non-ASCII character in the package's source (the dashboards' labels, tables, titles) is in DejaVu
    Sans, the font Debian's Chromium and matplotlib fall back to: a missing one shows as an empty box."""
    from pathlib import Path

    from matplotlib import font_manager
    from matplotlib.ft2font import FT2Font

    font = FT2Font(font_manager.findfont("DejaVu Sans"))
    missing = {}
    for path in sorted(Path(plotting.__file__).resolve().parents[1].rglob("*.py")):
        for char in set(path.read_text(encoding="utf-8")):
            if ord(char) > 127 and font.get_char_index(ord(char)) == 0:
                missing.setdefault(f"U+{ord(char):04X} {char}", []).append(path.name)
    assert not missing, f"characters DejaVu Sans lacks: {missing}"
    assert font.get_char_index(0x23F3) == 0  # the check can fail: an hourglass is not in it
