"""The exercises in which the student writes a function, by "tutorial.number": one table, which the checker,
the capstone and its diagnosis (:mod:`~sarsp_edu.teaching.exercises.parting`) read."""

from __future__ import annotations

from .agent import AGENT_EXERCISES
from .evidence import EVIDENCE_EXERCISES
from .grading import CodingExercise
from .models import MODEL_EXERCISES
from .records import RECORD_EXERCISES

__all__ = ["CODING"]

#: the exercises in which the student writes a function, by "tutorial.number"
CODING: dict[str, CodingExercise] = {**MODEL_EXERCISES, **AGENT_EXERCISES, **EVIDENCE_EXERCISES,
                                     **RECORD_EXERCISES}
