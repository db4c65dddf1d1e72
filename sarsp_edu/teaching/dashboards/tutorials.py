"""Widget dashboards for the tutorials: sliders wired to ``compute_*`` and ``plot_*``.

Each ``*_dashboard()`` returns an ipywidgets box.  The computation lives in
pure functions (:mod:`sarsp_edu.models.tails`, :mod:`sarsp_edu.teaching.demos`), the drawing
in :mod:`sarsp_edu.teaching.plotting`, the redraw framework in
:mod:`sarsp_edu.teaching.dashboards.framework`; this module only wires them, one function per
tutorial.  The live agents of tutorial 4 are in :mod:`sarsp_edu.teaching.live`.
"""

from __future__ import annotations

import html

import ipywidgets as widgets
import numpy as np

from ..._internal.validation import check_choice
from ...config import N_UNSAFE, NU
from ...models import tails
from .. import demos, plotting
from ..live import AgentDashboard, agent_dashboard
from .framework import Dashboard, Panel, control_row, slider
from .projector import projector

__all__ = [
    "AgentDashboard",
    "ablation_dashboard",
    "Dashboard",
    "Panel",
    "agent_dashboard",
    "gridworld_dashboard",
    "posterior_dashboard",
    "robust_dashboard",
    "projector",
    "tail_decay_dashboard",
]

# --------------------------------------------------------------------------
# tutorial 1: tail decay
# --------------------------------------------------------------------------
_T_LIMIT = None  # lambda**(-nu - 1), derived once by sympy


def _tex_number(value: float, digits: int = 4) -> str:
    r"""A number for TeX maths: 1.024e-07 as 1.024 \times 10^{-7} (maths would set the e-07 as a subtraction).

    >>> print(_tex_number(1.0241e-07), _tex_number(0.0016))
    1.024 \times 10^{-7} 0.0016
    """
    text = f"{value:.{digits}g}"
    if "e" not in text:
        return text
    mantissa, exponent = text.split("e")
    return f"{mantissa} \\times 10^{{{int(exponent)}}}"


def _student_t_limit_expr():
    global _T_LIMIT
    if _T_LIMIT is None:
        _T_LIMIT = tails.student_t_tail_limit()
    return _T_LIMIT


def tail_decay_dashboard(nu: float = NU, lam: float = 5.0) -> Dashboard:
    """Sliders for nu and lambda: the densities, their tails, and the Karamata ratio's limit.

    The limit shown is derived by sympy (``tails.student_t_tail_limit``)
    and evaluated at the slider values.

    Parameters
    ----------
    nu : float, default NU (3)
        The Student-t's degrees of freedom at the start, from 0.5 to 30 (the slider's range; outside is an error).
    lam : float, default 5
        lambda of the ratio ``f(lambda x)/f(x)`` at the start, from 1.5 to 10.
    """
    import sympy as sp

    controls = {
        "nu": slider("float", "nu", "ν (degrees of freedom)", nu, 0.5, 30.0, 0.5, expensive=False),
        "lam": slider("float", "lam", "λ", lam, 1.5, 10.0, 0.5, expensive=False),
    }

    def compute(nu, lam):
        densities = tails.compute_densities(nu)
        x = np.linspace(0.0, 20.0, 400)  # both ratios on one axis
        ratios = tails.compute_tail_ratios((nu,), lam, x_t=x, x_gauss=x)
        expr = _student_t_limit_expr()
        value = float(expr.subs({tails.LAMBDA: lam, tails.NU: nu}))
        info = (
            f"Student-t (sympy): $\\lim_{{x\\to\\infty}} f(\\lambda x)/f(x) = {sp.latex(expr)}"
            f" = {lam:g}^{{{-1 - nu:g}}} = {_tex_number(value)}$, regularly varying with index $-1-\\nu = {-1 - nu:g}$."
            f"<br>Gaussian: $f(\\lambda x)/f(x) = e^{{(1-\\lambda^2)x^2/2}} \\to 0$ for $\\lambda > 1$:"
            " no power of $\\lambda$, so not regularly varying; its tail is lighter than any Student-t's."
        )
        return {"densities": densities, "ratios": ratios}, info

    # 3.6, 3.6 and 4 inches: the three side by side in projector size on a 1280 px screen (Voila), so that the
    # lambda slider and the ratio it moves are on one 720 px screen; two and one in an 850 px notebook.
    panels = [
        Panel(lambda ax, result, **_: plotting.plot_densities(ax, result["densities"]), 3.6, inputs=("nu",),
              label_offsets=(24, 34), alt=lambda nu, **_: (
                  f"Linear scale: the density f(x) against x of the Gaussian N(0, 1) (dashed) and of the Student-t "
                  f"with nu = {nu:g} (solid). Both peak at x = 0; the Student-t is lower at the peak and higher in "
                  "the flanks.")),
        Panel(lambda ax, result, **_: plotting.plot_densities(ax, result["densities"], log=True), 3.6,
              inputs=("nu",), label_offsets=(24, 40), alt=lambda nu, **_: (
                  "Log scale: the same two densities on a logarithmic y axis, where the tails show. The Gaussian's "
                  f"falls away as a downward parabola; the Student-t's (nu = {nu:g}) falls slowly and stays orders "
                  "of magnitude above it far from 0.")),
        Panel(lambda ax, result, nu, **_: plotting.plot_tail_ratio_comparison(ax, result["ratios"], nu), 4.0,
              inputs=("nu", "lam"), label_offsets=(24, 40), alt=lambda nu, lam, **_: (
                  f"The Karamata ratio f(lambda x)/f(x) for lambda = {lam:g} against x, on a logarithmic y axis. "
                  f"The Student-t's ratio (nu = {nu:g}, solid) levels off at its limit lambda^(-1-nu), a thin "
                  "dashed line; the Gaussian's (dotted) falls steeply and leaves the bottom of the axis.")),
    ]
    return Dashboard(controls, compute, panels, height=3.8)


# --------------------------------------------------------------------------
# tutorial 2: GP and TP under outliers
# --------------------------------------------------------------------------
def posterior_dashboard(nu: float = NU, magnitude: float = 10.0, proportion: float = 0.1, seed: int = 0,
                        fit: bool = True) -> Dashboard:
    """GP and TP fitted side by side on 1-D data with outliers; sliders for nu, m, p and the seed.

    Shows the posterior mean and 2-sigma band, both variances on one axis
    (paper eq. 5 against eq. 6), marks the outliers, and prints
    the TP's variance factor (nu + beta - 2)/(nu + n - 2) (paper eq. 6 in
    its correct form) and both models' hyperparameters.

    Parameters
    ----------
    nu : float, default NU (3)
        The TP's degrees of freedom at the start, from 2.1 to 50 (the slider's range; outside is an error).
    magnitude : float, default 10
        Outlier magnitude m at the start (the outliers' targets are multiplied by it), from 1 to 100.
    proportion : float, default 0.1
        Outlier proportion p at the start: ``round(p * n)`` points are outliers, from 0 to 0.5.
    seed : int, default 0
        Seed of the data at the start, from 0 to 20.
    fit : bool, default True
        Whether the checkbox to fit the hyperparameters (50 Adam steps) starts ticked.
    """
    controls = {
        "nu": slider("float", "nu", "ν", nu, 2.1, 50.0, 0.1),
        "magnitude": slider("float", "magnitude", "outlier magnitude m", magnitude, 1.0, 100.0, 1.0),
        "proportion": slider("float", "proportion", "outlier proportion p", proportion, 0.0, 0.5, 0.05),
        "seed": slider("int", "seed", "seed", seed, 0, 20, 1),
        "fit": widgets.Checkbox(value=fit, description="fit hyperparameters (50 Adam steps)", indent=False),
        "scale_inputs": widgets.Checkbox(value=False, description="scale the outliers' inputs too (paper 5.3)",
                                         indent=False),
    }
    rows = [control_row([controls[k] for k in ("nu", "magnitude", "proportion", "seed")]),
            control_row([controls["fit"], controls["scale_inputs"]])]

    def compute(nu, magnitude, proportion, seed, fit, scale_inputs):
        data = demos.compute_posteriors(nu, magnitude, proportion, seed, fit=fit, scale_inputs=scale_inputs)
        rows = []
        for name in ("gp", "tp"):
            post = data[name]
            rows.append(f"{name.upper()}: amplitude {post['kernel'].amplitude:.3g}, length scale "
                        f"{post['kernel'].length_scale:.3g}, noise variance {post['noise_variance']:.3g}, "
                        f"log marginal likelihood {post['log_marginal_likelihood']:.2f}")
        factor = (f"TP variance factor $\\frac{{\\nu + \\beta - 2}}{{\\nu + n - 2}} = "
                  f"\\frac{{{data['nu']:g} + {_tex_number(data['beta'])} - 2}}{{{data['nu']:g} + {data['n']} - 2}} = "
                  f"{_tex_number(data['tp_scale'])}$, with $\\beta = y^T K_y^{{-1}} y$, $K_y = K + \\sigma^2 I$")
        return data, "<br>".join([factor, *rows])

    def draw_posterior(model):
        def draw(ax, data, **_):
            inlier_y = data["y"][~data["outliers"]]
            span = max(float(abs(inlier_y).max()), 1.0)
            plotting.plot_posterior(ax, data, model, ylim=(-3 * span, 3 * span))
        return draw

    def describe_posterior(model):
        def describe(nu, **_):
            name = "the Gaussian process" if model == "gp" else f"the Student-t process (nu = {nu:g})"
            return (f"The posterior of {name} against x: its mean ({'dashed' if model == 'gp' else 'solid'} line), "
                    "a darker band of the latent function's mean plus and minus 2 sd and a paler, wider band for a "
                    "new observation y* with the fitted noise; the data are black dots, the outliers red crosses "
                    "(triangles on the top or bottom edge where they lie beyond it).")
        return describe

    # The GP does not depend on nu: moving nu redraws the TP and the variances only.  The GP and TP
    # panels are 4 inches wide: side by side in projector size in an 850 px notebook.
    gp_inputs = ("magnitude", "proportion", "seed", "fit", "scale_inputs")
    panels = [
        Panel(draw_posterior("gp"), 4.0, inputs=gp_inputs, margins={"left": 0.55}, label_offsets=(24, 28),
              alt=describe_posterior("gp")),
        Panel(draw_posterior("tp"), 4.0, margins={"left": 0.55}, label_offsets=(24, 28), alt=describe_posterior("tp")),
        Panel(lambda ax, data, **_: plotting.plot_variances(ax, data), 5.0, label_offsets=(24, 38), alt=(
            "Both posterior variances against x on a logarithmic axis: the GP's (paper eq. 5, dashed) and the "
            "TP's (eq. 6, solid), thick for the latent function and thin for a new observation y* with the "
            "noise; thin red vertical lines mark the outliers' inputs.")),
    ]
    return Dashboard(controls, compute, panels, height=4.2, layout_rows=rows)


def robust_dashboard(nu: float = NU, magnitude: float = 10.0, proportion: float = 0.1, seed: int = 0) -> Dashboard:
    """The GP, the TP and the GP with a Student-t likelihood on the same outliers; sliders for nu, m, p, the seed.

    The same nu is the TP's degrees of freedom and the likelihood's.  Left:
    the three posterior means against the function without noise (each
    with its rmse on the grid); right: how much each point pulls the
    Student-t-likelihood GP's mean, against a Gaussian likelihood's pull.

    Parameters
    ----------
    nu : float, default NU (3)
        Degrees of freedom of the TP and of the likelihood at the start, from 2.1 to 50 (outside: an error).
    magnitude : float, default 10
        Outlier magnitude m at the start (the outliers' targets are multiplied by it), from 1 to 100.
    proportion : float, default 0.1
        Outlier proportion p at the start: ``round(p * n)`` points are outliers, from 0 to 0.5.
    seed : int, default 0
        Seed of the data at the start, from 0 to 20.
    """
    controls = {
        "nu": slider("float", "nu", "ν", nu, 2.1, 50.0, 0.1),
        "magnitude": slider("float", "magnitude", "outlier magnitude m", magnitude, 1.0, 100.0, 1.0),
        "proportion": slider("float", "proportion", "outlier proportion p", proportion, 0.0, 0.5, 0.05),
        "seed": slider("int", "seed", "seed", seed, 0, 20, 1),
    }

    def compute(nu, magnitude, proportion, seed):
        data = demos.compute_robust(nu, magnitude, proportion, seed)
        flagged = int((data["weights"] < 0.1).sum())
        text = (f"rmse against the function without noise: GP {data['rmse']['gp']:.2f}, TP {data['rmse']['tp']:.2f}, "
                f"Student-t likelihood {data['rmse']['robust']:.2f}; fitted noise scale s = {data['scale']:.2g}; "
                f"{flagged} of {len(data['y'])} points pull with less than a tenth of a Gaussian's weight "
                f"({int(data['outliers'].sum())} are outliers)")
        return data, text

    def draw_means(ax, data, **_):
        inlier_y = data["y"][~data["outliers"]]
        span = max(float(abs(inlier_y).max()), 1.0)
        plotting.plot_robust(ax, data, ylim=(-2.5 * span, 2.5 * span))

    panels = [
        Panel(draw_means, 6.5, margins={"left": 0.6}, label_offsets=(24, 30), alt=(
            "The posterior means against x of the GP (dashed), the TP (solid) and the GP with a Student-t "
            "likelihood (dash-dotted, its latent 2-sd band shaded), with the function without noise (dotted "
            "grey), the data (black dots) and the outliers (red crosses, triangles on the edge where off scale); "
            "the legend gives each mean's rmse.")),
        Panel(lambda ax, data, **_: plotting.plot_outlier_weights(ax, data), 4.5, label_offsets=(24, 30), alt=(
            "How much each point pulls the Student-t-likelihood GP's mean, against x: a black bar per data "
            "point, a red bar with a cross per outlier, and a dashed grey line at 1, a Gaussian likelihood's "
            "pull.")),
    ]
    return Dashboard(controls, compute, panels, height=4.2)


# --------------------------------------------------------------------------
# tutorial 3: the world and its shift
# --------------------------------------------------------------------------
def gridworld_dashboard(seed: int = 0, n_switch_states: int = 6, magnitude: float = 40.0,
                        proportion: float = 0.2) -> Dashboard:
    """The world before and after the covariate shift, the offline coverage and the outliers.

    Sliders for nss, the seed, m and p.  The world and its 100 offline
    episodes are cached per seed, so the nss, m and p sliders are quick.

    Parameters
    ----------
    seed : int, default 0
        Seed of the world and its offline data at the start, from 0 to 50 (the slider's range; outside is an error).
    n_switch_states : int, default 6
        nss, the unsafe states the shift moves, at the start: from 0 to ``N_UNSAFE``.
    magnitude : float, default 40
        Outlier magnitude m at the start: outlier rows' inputs and targets are multiplied by it, from 1 to 100.
    proportion : float, default 0.2
        Outlier proportion p at the start: the share of offline rows made outliers, from 0 to 0.5.
    """
    controls = {
        "seed": slider("int", "seed", "seed", seed, 0, 50, 1),
        "n_switch_states": slider("int", "n_switch_states", "nss (switch states)", n_switch_states, 0, N_UNSAFE, 1),
        "magnitude": slider("float", "magnitude", "outlier magnitude m", magnitude, 1.0, 100.0, 1.0),
        "proportion": slider("float", "proportion", "outlier proportion p", proportion, 0.0, 0.5, 0.05),
    }

    def compute(seed, n_switch_states, magnitude, proportion):
        world = demos.compute_world(seed, n_switch_states, magnitude, proportion)
        info = (f"{world['transitions']} random-policy transitions kept as {world['cost_rows']} cost-model "
                f"rows (at most 12 copies of an input) and {world['reward_rows']} reward-model rows (1 copy); "
                f"{len(world['outlier_rows'])} rows (p = {proportion:g}) had inputs and targets multiplied "
                f"by m = {magnitude:g}. States moved by the shift: {len(world['moved'])}.")
        return world, info

    # The two worlds are 7.8 inches wide together: side by side in projector size in an 850 px notebook.
    panels = [
        Panel(lambda ax, world, **_: plotting.plot_gridworld(
            ax, world["before"], visits=world["visits"], legend=False, title="offline world and its coverage"),
            3.2, inputs=("seed",), margins={"left": 0.45, "right": 0.2}, label_offsets=(16, 16), alt=(
                "The offline world, a grid of cells 0 to 9 in x (across) and in y (down): red squares are the "
                "unsafe states, a blue ring the start, a green star the goal; grey shading shows how often the "
                "offline episodes visited each cell, darker for more visits.")),
        Panel(lambda ax, world, n_switch_states, **_: plotting.plot_gridworld(
            ax, world["after"], title=f"after the shift, nss = {n_switch_states}"),
            4.6, inputs=("seed", "n_switch_states"), margins={"left": 0.45, "right": 1.7}, label_offsets=(16, 16),
            alt=lambda n_switch_states, **_: (
                f"The same world after the covariate shift with nss = {n_switch_states}: the unsafe states that "
                "moved are outlined in black at their new cells, their old cells are dashed red outlines, and a "
                "curved arrow runs from each old cell to its new one; a legend beside the grid names each mark.")),
        Panel(lambda ax, world, **_: plotting.plot_outlier_scatter(
            ax, world, title="cost-model data, outliers as red triangles"),
            5.0, inputs=("seed", "magnitude", "proportion"), margins={"left": 0.7}, label_offsets=(24, 30), alt=(
                "The cost model's data on logarithmic axes: the size of each row's input (1 + its norm) across, "
                "its target (1 + the distance to danger) up; clean rows are black dots and outlier rows red "
                "triangles, each marker's area growing with the rows at that point.")),
    ]
    return Dashboard(controls, compute, panels, height=3.6)


# --------------------------------------------------------------------------
# tutorial 6: the printed algorithm and the code
# --------------------------------------------------------------------------
def ablation_dashboard(results, prior: str = "per step", fits: str = "500 rows") -> Dashboard:
    """Stored ablation runs, one setting at a time: how the prior is drawn x how the models are fitted.

    Parameters
    ----------
    results : AblationResults
        ``AblationResults.load(folder)``; the four settings of
        ``ablation.PRIOR_AND_FITS`` are shown where they have runs.
    prior : {"per step", "per action"}
    fits : {"500 rows", "default fits"}
    """
    from ...experiments.ablation import PRIOR_AND_FITS

    check_choice("prior", prior, ("per step", "per action"))
    check_choice("fits", fits, ("500 rows", "default fits"))
    runs = results.runs()
    controls = {
        "prior": widgets.ToggleButtons(options=["per step", "per action"], value=prior,
                                       description="strategic prior", style={"description_width": "initial"}),
        "fits": widgets.ToggleButtons(options=["500 rows", "default fits"], value=fits,
                                      description="hyperparameters fitted on", style={"description_width": "initial"}),
    }
    shown = runs[runs["setting"].isin(PRIOR_AND_FITS.values())]
    limits = {"task_success_rate": (0, 100), "trapped_share": (0, 100),
              "total_cost": (0, 1.1 * max(float(shown["total_cost"].max()) if len(shown) else 1.0, 1.0))}

    def compute(prior, fits):
        name = PRIOR_AND_FITS[(prior, fits)]
        part = runs[runs["setting"] == name]
        if not len(part):
            raise ValueError(f"the ablation holds no finished run of {name!r} yet; run: "
                             f"sarsp-edu ablation --settings '{name}' --out <its folder>")
        count = part.groupby("model").size().to_dict()
        info = (f"<b>{html.escape(name)}</b>: {count.get('TP', 0)} TP and {count.get('GP', 0)} GP runs "
                f"(configurations x seeds, {int(part.episodes.max())} episodes each); "
                f"trapped failures TP {int(part[part.model == 'TP'].trapped_failures.sum())} of "
                f"{int(part[part.model == 'TP'].failures.sum())}, "
                f"GP {int(part[part.model == 'GP'].trapped_failures.sum())} "
                f"of {int(part[part.model == 'GP'].failures.sum())}.")
        return part, info

    def describe(what):
        return lambda prior, fits, **_: (
            f"{what} in the setting where the prior is drawn {prior} and the models are fitted "
            f"{'on 500 rows' if fits == '500 rows' else 'as by default'}: a bar at "
            "the mean of the TP's runs and one at the GP's, with a dot per run (the TP's circles, the GP's squares).")

    panels = [
        Panel(lambda ax, part, **_: plotting.plot_ablation_runs(
            ax, part, "task_success_rate", title="reaching the goal", ylim=limits["task_success_rate"]), 3.6,
            alt=describe("The task success rate (%)")),
        Panel(lambda ax, part, **_: plotting.plot_ablation_runs(
            ax, part, "total_cost", title="violations", ylim=limits["total_cost"]), 3.6,
            alt=describe("The total cost (violations)")),
        Panel(lambda ax, part, **_: plotting.plot_ablation_runs(
            ax, part, "trapped_share", title="trapped", ylim=limits["trapped_share"]), 3.6,
            alt=describe("The share of failures that ended trapped (%)")),
    ]
    return Dashboard(controls, compute, panels, height=3.4)

