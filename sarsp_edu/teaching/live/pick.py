"""Each side of the live dashboard picks its model: the Student-t process, the GP, or the GP with Student-t noise.

A pick changes that side's model at once, as a slider move changes the
world: the run on show stops, the preview is drawn, and both sides are
fitted for the next *Run*, each in a process of its own (loaded from the fit
cache where it was fitted before: ``sarsp-edu prefit --models tp gp
t-likelihood`` fits all three before class).
"""

from __future__ import annotations

import ipywidgets as widgets

from ..._internal.validation import check_choice
from ...config import MODEL_TITLES

__all__ = ["MODEL_TITLES", "TP_AND_GP", "model_pickers", "model_sides", "picked_side"]



def model_sides(models) -> dict:
    """A side per model, named by it: name -> (title, the settings that side changes).

    Parameters
    ----------
    models : iterable of str
        Each one of :data:`MODEL_TITLES`.
    """
    models = list(models)
    for model in models:
        check_choice("model", model, tuple(MODEL_TITLES))
    return {model: (MODEL_TITLES[model], {"model": model}) for model in models}


#: tutorial 4's two sides: name -> (title, the settings that side changes)
TP_AND_GP = model_sides(("tp", "gp"))


def model_pickers(dashboard) -> dict:
    """A dropdown per side that changes its model alone (a side that changes other settings keeps them).

    Parameters
    ----------
    dashboard : AgentDashboard
        Its ``sides`` and its ``pick_model``.

    Returns
    -------
    dict
        Side name -> ``ipywidgets.Dropdown``.
    """
    pickers = {}
    for place, (name, (_, changes)) in zip(("left", "right"), dashboard.sides.items()):
        if set(changes) != {"model"} or changes["model"] not in MODEL_TITLES:
            continue
        picker = widgets.Dropdown(options=[(title, model) for model, title in MODEL_TITLES.items()],
                                  value=changes["model"], description=place, layout=widgets.Layout(width="auto"))
        picker.observe(lambda change, name=name: dashboard.pick_model(name, change["new"]), names="value")
        pickers[name] = picker
    return pickers


def picked_side(sides: dict, name, model: str) -> dict:
    """``sides`` with side ``name`` running ``model`` under its title (the same dict, changed in place: the run
    and its fit queue hold it).

    Parameters
    ----------
    sides : dict
        Name -> (title, changed settings).
    name : str
        The side.
    model : str
        One of :data:`MODEL_TITLES`.
    """
    check_choice("model", model, tuple(MODEL_TITLES))
    if name not in sides:
        raise ValueError(f"name must be a side of the dashboard ({sorted(sides)}), got name={name!r}")
    sides[name] = (MODEL_TITLES[model], {"model": model})
    return sides
