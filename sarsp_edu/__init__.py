"""sarsp_edu: a teaching package for safe reinforcement learning with Gaussian
and Student-t processes, after "Hybrid Safe Reinforcement Learning: Tackling
Distribution Shift and Outliers with the Student-t's Process".
"""

from __future__ import annotations

from .kernels import RBF
from .processes import GaussianProcess, NotFittedError, StudentTProcess

__version__ = "0.1.0"

__all__ = [
    "RBF",
    "GaussianProcess",
    "StudentTProcess",
    "NotFittedError",
    "__version__",
]
