"""Every setting of an experiment, its defaults and its named presets: a light package.

The defaults of Algorithm 1 and of the world are defined once, in
:mod:`~sarsp_edu.config.defaults`; each setting's check once, in
:mod:`~sarsp_edu.config.settings`; each setting itself once, as a field of
:class:`ExperimentConfig` tagged with its group, in
:mod:`~sarsp_edu.config.experiment_config`, with the groups that the world,
the data, the models and the agent take (derived from those fields) and the
presets.
Importing it loads no numerical library, so the ``sarsp-edu`` command can
build its flags (and answer ``--help``) at once.
"""

from .defaults import *  # noqa: F401,F403
from .defaults import __all__ as _defaults
from .experiment_config import (
    PRESET_DOCS,
    PRESET_FIELDS,
    PRESETS,
    AgentSettings,
    DataSettings,
    ExperimentConfig,
    ModelSettings,
    WorldSettings,
    config_or_default,
    preset_of,
)
from .settings import CHECKS, GROUPS

__all__ = [
    *_defaults, "CHECKS", "GROUPS", "AgentSettings", "DataSettings", "ExperimentConfig", "ModelSettings", "PRESETS",
    "PRESET_DOCS", "PRESET_FIELDS", "WorldSettings", "config_or_default", "preset_of",
]
