"""The paper itself, for comparison only: its published numbers (``published``, re-exported here) and the
authors' own per-episode records of its 90 runs with ours beside them (``authors``)."""

from .published import (
    EPISODE_80,
    FIGURES,
    TABLE1,
    TABLE2,
    TABLE2_CV,
    TABLE2_PERCENT,
    TABLE3,
    TABLE3_PERCENT,
    TABLE4,
    TABLE4_PERCENT,
)

__all__ = ["EPISODE_80", "FIGURES", "TABLE1", "TABLE2", "TABLE2_CV", "TABLE2_PERCENT", "TABLE3", "TABLE3_PERCENT",
           "TABLE4", "TABLE4_PERCENT"]
