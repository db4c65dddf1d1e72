"""Every setting of an experiment, its defaults and its named presets: a light package.

The defaults of Algorithm 1 and of the world are defined once, in
:mod:`~sarsp_edu.config.defaults`; the settings groups that the world, the
data, the models and the agent take, with each setting's check, in
:mod:`~sarsp_edu.config.settings`; :class:`ExperimentConfig`, one run's
settings, and the presets in :mod:`~sarsp_edu.config.experiment_config`.
Importing it loads no numerical library, so the ``sarsp-edu`` command can
build its flags (and answer ``--help``) at once.
"""

from .defaults import *  # noqa: F401,F403
from .defaults import __all__ as _defaults
from .experiment_config import PRESET_DOCS, PRESET_FIELDS, PRESETS, ExperimentConfig, config_or_default, preset_of
from .settings import CHECKS, AgentSettings, DataSettings, ModelSettings, WorldSettings

__all__ = [
    *_defaults, "CHECKS", "AgentSettings", "DataSettings", "ExperimentConfig", "ModelSettings", "PRESETS",
    "PRESET_DOCS", "PRESET_FIELDS", "WorldSettings", "config_or_default", "preset_of",
]
