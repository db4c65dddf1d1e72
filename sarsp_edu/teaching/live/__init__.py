"""The live dashboards: two agents stepping side by side on one world.

Tutorial 4 runs the TP agent beside the GP agent, tutorial 6 one agent as the
printed algorithm and as the reference code run it.  The runs of
:func:`sarsp_edu.experiments.experiment.experiments_on_one_world` are fitted ahead: a
side fitted before is loaded from :mod:`sarsp_edu.teaching.live.fitcache`, the others are
fitted at once, each in a process of its own (:mod:`.fitting`), and a slider
move stops the fits nobody waits for; :func:`prefit` fills the cache before
class.  :class:`LiveRun` (:mod:`.controller`) runs the agents with no widgets,
in one thread of its own that alone steps and draws them (the buttons, the
sliders and the notebook's cells send it commands), so the notebook stays
responsive;
:class:`AgentDashboard` (:mod:`.view`) is its view, whose pictures come from :mod:`sarsp_edu.teaching.plotting`
(``plot_live_metrics``) and :mod:`sarsp_edu.teaching.live.markup` (``gridworld_svg``,
``decision_table_html``).
"""

from .background import changed_settings, prefit, slider_config
from .controller import LiveRun
from .snapshot import AUTOPLAY_VARIABLE, SNAPSHOT_VARIABLE
from .view import TP_AND_GP, AgentDashboard, agent_dashboard

__all__ = ["AUTOPLAY_VARIABLE", "SNAPSHOT_VARIABLE", "TP_AND_GP", "AgentDashboard", "LiveRun",
           "agent_dashboard", "changed_settings", "prefit", "slider_config"]
