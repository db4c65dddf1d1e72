"""The tutorials' exercise checks: right answers pass, wrong and missing ones do not."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sarsp_edu.exercises import EXERCISES, check, is_right
from sarsp_edu.sarsp import Decision

#: a right and a wrong answer to each exercise, worked out here by hand
ANSWERS = {
    "1.1": (1 / 32, 1 / 16),
    "1.2": ({"lambda < 1": math.inf, "lambda = 1": 1, "lambda > 1": 0},
            {"lambda < 1": 0, "lambda = 1": 1, "lambda > 1": math.inf}),
    "1.3": ((40**2 / 2 + 0.5 * math.log(2 * math.pi)) / (0.5 + 0.5 * math.log(2 * math.pi)), 1600),
    "2.2": ("below", "above"),
    "2.3": ("narrower", "wider"),
    "3.1": (50, 25),
    "3.2": ([1, 0, 0], [0, 1, 1]),
    "5.1": (69.8, 51.7),
}


def gp_like_decision():
    """Cost variances about 5.5, as a GP's with a large fitted noise: safe at 10 only where mu >= 1."""
    return Decision((4, 4), np.array([1.0, 2.0, 0.4, 1.4]), np.array([5.5, 5.6, 5.4, 11.0]),
                    np.array([-3.0, -2.0, -1.0, -2.5]), np.array([1.0] * 4), np.array([False] * 4),
                    np.array([False] * 4), 2, True)


@pytest.mark.parametrize("exercise", sorted(ANSWERS))
def test_right_wrong_and_missing_answers(exercise, capsys):
    right, wrong = ANSWERS[exercise]
    assert is_right(exercise, right) is True
    check(exercise, right)
    assert "right." in capsys.readouterr().out
    assert is_right(exercise, wrong) is False
    check(exercise, wrong)
    assert "not yet." in capsys.readouterr().out
    assert is_right(exercise, ...) is False
    check(exercise, ...)
    assert "not answered yet" in capsys.readouterr().out


def test_the_nu_that_doubles_the_variance():
    from sarsp_edu.demos import regression_data
    from sarsp_edu.kernels import RBF
    from sarsp_edu.processes import StudentTProcess

    X, y, _ = regression_data(n=40, magnitude=10.0, proportion=0.1, seed=0)
    beta = StudentTProcess(RBF(1.5, 0.5), nu=3.0, noise_variance=0.5, optimizer=None).fit(X, y).beta_
    assert is_right("2.1", beta - 2 * 40 + 2) is True
    assert is_right("2.1", beta - 40 + 2) is False
    assert is_right("2.1", 1.5) is False  # not a valid nu


def test_the_gps_safe_set_needs_its_decision():
    decision = gp_like_decision()
    assert is_right("4.1", [0, 1], decision=decision) is True  # variance <= 10 and distance >= 1
    assert is_right("4.1", [0, 1, 3], decision=decision) is False
    assert is_right("4.1", [], decision=decision) is False
    with pytest.raises(ValueError, match="decision="):
        check("4.1", [0, 1])


def test_every_exercise_is_tested_and_unknown_ones_are_refused():
    assert set(EXERCISES) == {*ANSWERS, "2.1", "4.1", "6.1"}
    with pytest.raises(ValueError, match="exercise must be one of"):
        check("9.9", 1)


def test_text_and_wrong_types_are_wrong_not_errors():
    assert is_right("1.1", "1/32") is False
    assert is_right("3.1", 50.0) is False  # a count is an integer
    assert is_right("3.2", "right right down") is False
    assert is_right("2.2", 0.5) is False



def test_the_trapped_share_is_read_from_the_ablation():
    from pathlib import Path

    from sarsp_edu.ablation import AblationResults

    results = AblationResults.load(Path(__file__).resolve().parents[1] / "results" / "ablation")
    # the stored per-step, 500-row GP runs: 309 of their 375 failures ended on at most 2 cells
    assert is_right("6.1", 82.4, results=results) is True
    assert is_right("6.1", 309 / 375, results=results) is False  # a fraction, not a percentage
    assert is_right("6.1", 70, results=results) is False
    with pytest.raises(ValueError, match="results="):
        check("6.1", 50)
