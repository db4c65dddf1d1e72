"""The models' pictures: densities and tail ratios (tutorial 1), GP and TP posteriors (tutorial 2)."""

from __future__ import annotations

import numpy as np
from matplotlib.transforms import Bbox, TransformedBbox

from .style import COLOURS, SMALL, finish_axes, log_scale, model_style

__all__ = [
    "plot_densities",
    "plot_gaussian_ratio",
    "plot_outlier_weights",
    "plot_posterior",
    "plot_robust",
    "plot_tail_ratio_comparison",
    "plot_tail_ratios",
    "plot_variances",
]


def plot_densities(ax, data, *, log: bool = False):
    """Student-t and Gaussian densities (``tails.compute_densities``), linear or log scale.

    The Gaussian is dashed (drawn on top, so that both show where they meet), the Student-t solid.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    data : dict
        :func:`~sarsp_edu.models.tails.compute_densities`'s output.
    log : bool, default False
        A log y axis (down to 1e-16), to show the tails.
    """
    ax.plot(data["x"], data["gaussian"], lw=2, zorder=2.5, label="Gaussian N(0, 1)", **model_style("gp"))
    ax.plot(data["x"], data["student_t"], lw=2, label=f"Student-t, nu = {data['nu']:g}", **model_style("tp"))
    if log:
        log_scale(ax)
        ax.set_ylim(1e-16, 1.0)
        ax.set_title("log scale: the tails")
    else:
        ax.set_title("linear scale")
        # headroom: the legend in a strip above the peak, not across the curves' flanks
        ax.set_ylim(top=1.4 * max(np.max(data["gaussian"]), np.max(data["student_t"])))
    ax.set_xlabel("x")
    ax.set_ylabel("density f(x)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=SMALL, frameon=False, loc="best" if log else "upper right")
    return ax


def plot_tail_ratios(ax, data, *, show_limits: bool = True, title: str | None = None):
    """Paper Figure 1(a): the Student-t ratio f(lambda x)/f(x) against x, with its limit lambda^(-1-nu).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    data : dict
        :func:`~sarsp_edu.models.tails.compute_tail_ratios`'s output: one curve per nu.
    show_limits : bool, default True
        Draw each limit as a dashed line and give it in the legend.
    title : str, optional
        The panel's title; default one naming lambda.
    """
    from matplotlib import colormaps

    cmap = colormaps["Blues"]
    nus = list(data["student_t"])
    for i, nu in enumerate(nus):
        colour = cmap(0.5 + 0.5 * i / max(len(nus) - 1, 1))
        limit = data["limits"][nu]
        label = f"Student-t, nu = {nu:g}"
        if show_limits:
            ax.axhline(limit, color=colour, ls="--", lw=1)
            label += f" (limit λ^(-1-ν) = {limit:.3g})"
        ax.plot(data["x_t"], data["student_t"][nu], color=colour, lw=2, label=label)
    finish_axes(ax, "x", f"f({data['lam']:g} x) / f(x)", title or f"Student-t ratio, lambda = {data['lam']:g}")
    return ax


def plot_tail_ratio_comparison(ax, data, nu: float):
    """The Student-t ratio for one nu beside the Gaussian's, on a log scale (tutorial 1's dashboard).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    data : dict
        :func:`~sarsp_edu.models.tails.compute_tail_ratios`'s output (its every nu is drawn).
    nu : float
        A key of ``data["limits"]``: its limit sets the bottom of the y axis.
    """
    plot_tail_ratios(ax, data, title="Karamata ratio f(λx)/f(x)")
    ax.plot(data["x_gauss"], data["gaussian"], color=COLOURS["gp"], lw=2, ls=":", label="Gaussian")
    log_scale(ax)
    low, high = max(data["limits"][nu] / 100, 1e-30), 1.5
    # headroom: the legend in a strip above the ratios (all at most 1), not over the falling Gaussian curve
    ax.set_ylim(low, high * (high / low) ** 0.4)
    for minor in (False, True):  # no ticks in the strip: a ratio above 1 is never drawn
        locator = ax.yaxis.get_minor_locator() if minor else ax.yaxis.get_major_locator()
        ax.set_yticks([tick for tick in locator.tick_values(low, 1.0) if low <= tick <= 1.0], minor=minor)
    # short labels: the long "(limit λ^(-1-ν) = ...)" of plot_tail_ratios runs past the panel's edge
    handles, labels = ax.get_legend_handles_labels()
    labels = [label.replace("limit λ^(-1-ν) = ", "limit ") for label in labels]
    ax.legend(handles, labels, fontsize=SMALL, frameon=False, loc="upper left")
    return ax


def plot_gaussian_ratio(ax, data, *, title: str | None = None):
    """Paper Figure 1(b): the Gaussian ratio f(lambda x)/f(x) = exp((1 - lambda^2) x^2 / 2) on [0, 1].

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    data : dict
        :func:`~sarsp_edu.models.tails.compute_tail_ratios`'s output.
    title : str, optional
        The panel's title; default one naming lambda.
    """
    ax.plot(data["x_gauss"], data["gaussian"], color=COLOURS["gp"], lw=2, label="Gaussian")
    finish_axes(ax, "x", f"f({data['lam']:g} x) / f(x)", title or f"Gaussian ratio, lambda = {data['lam']:g}")
    return ax


def _clip_at_top(ax, low: float, high: float) -> None:
    """Clip the axes' curves and bands to y in [low, high] within the axes' x-limits.

    The legend then sits in a strip above ``high`` with nothing under it.  The
    box spans exactly the axes' x-limits: a wider one would count in the axes'
    extent, and a constrained layout would shrink the axes to make room for it.
    """
    x_low, x_high = ax.get_xlim()
    clip = TransformedBbox(Bbox.from_extents(x_low, low, x_high, high), ax.transData)
    for artist in [*ax.collections, *ax.lines]:
        if artist.get_clip_on():
            artist.set_clip_box(clip)


def plot_posterior(ax, data, model: str, *, title: str | None = None, ylim=None):
    """Posterior mean, latent 2-sd band and the wider band of a new observation, outliers marked.

    ``data`` is ``demos.compute_posteriors``'s output.  The outer band (``var_noisy``)
    shows the fitted noise, where the GP and the TP differ most visibly.

    Outliers outside ``ylim`` are drawn as triangles on the edge they lie beyond.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    data : dict
        :func:`~sarsp_edu.teaching.demos.compute_posteriors`'s output.
    model : {"gp", "tp"}
        Which posterior to draw.
    title : str, optional
        The panel's title; default the model's name.
    ylim : (float, float), optional
        The y range of the data; default matplotlib's.
    """
    post = data[model]
    colour = COLOURS[model]
    x = data["x_grid"]
    if "var_noisy" in post:  # the band of a new observation y*: the fitted noise made visible
        sd_y = np.sqrt(post["var_noisy"])
        ax.fill_between(x, post["mean"] - 2 * sd_y, post["mean"] + 2 * sd_y, color=colour, alpha=0.08,
                        label=f"± 2 sd of y* (noise {post['noise_variance']:.2g})")
    sd = np.sqrt(post["var"])
    ax.fill_between(x, post["mean"] - 2 * sd, post["mean"] + 2 * sd, color=colour, alpha=0.25,
                    label="mean ± 2 sd (latent f)")
    ax.plot(x, post["mean"], lw=2, label="posterior mean", **model_style(model))  # the GP's dashed, the TP's solid
    inliers = ~data["outliers"]
    ax.scatter(data["X"][inliers], data["y"][inliers], s=14, color=COLOURS["data"], zorder=3, label="data")
    if ylim is not None:
        ax.set_ylim(*ylim)
    low, high = ax.get_ylim()
    in_view = data["outliers"] & (data["X"] <= x[-1])
    ys = data["y"]
    inside = in_view & (ys >= low) & (ys <= high)
    if inside.any():
        # not clipped: an outlier just inside the range (at y = -4.05 of -4.1, say) is drawn whole, over the spine
        ax.scatter(data["X"][inside], ys[inside], s=40, marker="x", color=COLOURS["unsafe"], zorder=4,
                   label="outliers", clip_on=False)
    label = "off scale"  # under "outliers" in the legend's column; short, for a 4-inch panel
    for mask, edge, marker in ((in_view & (ys > high), high, "^"), (in_view & (ys < low), low, "v")):
        if mask.any():
            ax.scatter(data["X"][mask], np.full(mask.sum(), edge), s=60, marker=marker, color=COLOURS["unsafe"],
                       zorder=5, clip_on=False, label=label)
            label = None
    hidden = int((data["outliers"] & (data["X"] > x[-1])).sum())
    if hidden:
        ax.text(0.99, 0.02, f"{hidden} outliers beyond x = {x[-1]:g}", transform=ax.transAxes, ha="right",
                fontsize=SMALL, color=COLOURS["unsafe"])
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.grid(alpha=0.3)
    # headroom: the legend above the plotted range (whose top edge holds the off-scale outliers), not over the data
    _clip_at_top(ax, low, high)
    ticks = [t for t in ax.get_yticks() if low <= t <= high]  # no tick where nothing is drawn
    ax.set_ylim(low, high + 0.55 * (high - low))
    ax.set_yticks(ticks)
    ax.axhline(high, color="grey", lw=0.6, ls=":")
    # tight spacing: the two columns fit a 4-inch panel (the dashboard's, side by side on a projector)
    ax.legend(fontsize=SMALL, frameon=False, loc="upper left", ncols=2, handlelength=1.0, handletextpad=0.4,
              columnspacing=0.6, borderaxespad=0.3)
    ax.set_title(title or {"gp": "Gaussian process", "tp": f"Student-t process, nu = {data['nu']:g}"}[model])
    return ax


def plot_variances(ax, data, *, title: str | None = None):
    """The two posterior variances on one log axis: paper eq. 5 (GP) against eq. 6 (TP).

    The GP's curves are dashed and drawn on top, the TP's solid; the latent
    variances thick, those of a new observation y* (with the noise) thin.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    data : dict
        :func:`~sarsp_edu.teaching.demos.compute_posteriors`'s output.
    title : str, optional
        The panel's title; default one naming both equations.
    """
    x = data["x_grid"]
    ax.plot(x, data["gp"]["var"], lw=2, zorder=2.5, label="GP, eq. 5", **model_style("gp"))
    ax.plot(x, data["tp"]["var"], lw=2, label="TP, eq. 6 (corrected)", **model_style("tp"))
    for model in ("gp", "tp"):
        if "var_noisy" in data[model]:
            ax.plot(x, data[model]["var_noisy"], lw=1.1, zorder=2.5 if model == "gp" else 2,
                    label=f"{model.upper()}, of y* (with noise)", **model_style(model))
    ax.vlines(data["X"][data["outliers"] & (data["X"] <= x[-1])], 0, 1, transform=ax.get_xaxis_transform(),
              color=COLOURS["unsafe"], lw=0.8, alpha=0.5, label="outlier inputs")
    log_scale(ax)
    ax.set_xlabel("x")
    ax.set_ylabel("posterior variance")
    ax.grid(alpha=0.3)
    low, high = ax.get_ylim()
    ax.set_ylim(low, high * (high / low) ** 0.7)  # headroom for the legend, above the curves
    ax.legend(fontsize=SMALL, frameon=False, loc="upper right", ncols=2, handlelength=1.5, columnspacing=1.0)
    ax.set_title(title or "posterior variance: eq. 5 (GP) and eq. 6 (TP)")
    return ax


def plot_robust(ax, data, *, ylim=None):
    """The posterior means of the GP, the TP and the Student-t-likelihood GP on one data set, the truth dotted.

    ``data`` is ``demos.compute_robust``'s output; the Student-t-likelihood
    GP's latent 2-sd band is shaded.  The GP's mean is dashed and drawn over
    the TP's solid one (the two often coincide), the Student-t likelihood's
    dash-dotted.  Outliers beyond ``ylim`` are drawn as triangles on its edge.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    data : dict
        :func:`~sarsp_edu.teaching.demos.compute_robust`'s output.
    ylim : (float, float), optional
        The y range of the data; default matplotlib's.
    """
    x = data["x_grid"]
    ax.plot(x, data["truth"], color="grey", lw=1.5, ls=":", label="the function without noise")
    mean, sd = data["mean"]["robust"], data["robust_sd"]
    ax.fill_between(x, mean - 2 * sd, mean + 2 * sd, color=COLOURS["robust"], alpha=0.15)
    names = {"gp": "GP", "tp": "TP", "robust": "Student-t likelihood"}
    for name in ("gp", "tp", "robust"):
        ax.plot(x, data["mean"][name], lw=2.2 if name == "robust" else 1.6, zorder=2.5 if name == "gp" else 2,
                label=f"{names[name]} (rmse {data['rmse'][name]:.2f})", **model_style(name))
    inliers = ~data["outliers"]
    ax.scatter(data["X"][inliers], data["y"][inliers], s=12, color=COLOURS["data"], zorder=3, label="data")
    if ylim is not None:
        ax.set_ylim(*ylim)
    low, high = ax.get_ylim()
    ys, xs = data["y"], data["X"]
    inside = data["outliers"] & (ys >= low) & (ys <= high)
    if inside.any():
        ax.scatter(xs[inside], ys[inside], s=40, marker="x", color=COLOURS["unsafe"], zorder=4, label="outliers")
    label = "outliers off scale"
    for mask, edge, marker in ((data["outliers"] & (ys > high), high, "^"), (data["outliers"] & (ys < low), low, "v")):
        if mask.any():
            ax.scatter(xs[mask], np.full(mask.sum(), edge), s=60, marker=marker, color=COLOURS["unsafe"], zorder=5,
                       clip_on=False, label=label)
            label = None
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.grid(alpha=0.3)
    # the legend in a strip above the plotted range (whose top edge holds the off-scale outliers), as in
    # plot_posterior: the curves are clipped at that edge, so nothing runs under the legend
    _clip_at_top(ax, low, high)
    ticks = [t for t in ax.get_yticks() if low <= t <= high]
    ax.set_ylim(low, high + 0.45 * (high - low))
    ax.set_yticks(ticks)
    ax.axhline(high, color="grey", lw=0.6, ls=":")
    ax.legend(fontsize=SMALL, frameon=False, loc="upper left", ncols=2, handlelength=1.2, columnspacing=0.8)


def plot_outlier_weights(ax, data):
    """How much each point pulls the Student-t-likelihood GP's mean, against a Gaussian likelihood's pull (1).

    ``data["weights"]`` are ``(nu + 1) s^2 / (nu s^2 + r^2)`` at the
    posterior mode: an outlier's falls towards 0.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    data : dict
        :func:`~sarsp_edu.teaching.demos.compute_robust`'s output.
    """
    xs, weights, outliers = data["X"], data["weights"], data["outliers"]
    ax.vlines(xs[~outliers], 0, weights[~outliers], color=COLOURS["data"], lw=1.2, label="data")
    ax.vlines(xs[outliers], 0, weights[outliers], color=COLOURS["unsafe"], lw=2.5, label="outliers")
    ax.scatter(xs[outliers], weights[outliers], s=30, marker="x", color=COLOURS["unsafe"], zorder=3)
    ax.axhline(1.0, color="grey", lw=0.8, ls="--", label="Gaussian (1)")
    top = max(1.6, float(weights.max()) * 1.15)
    ax.set_ylim(0, top)
    ax.set_xlabel("x")
    ax.set_ylabel("pull on the mean")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=SMALL, frameon=False, loc="upper left", ncols=3, handlelength=1.2, columnspacing=0.8)

