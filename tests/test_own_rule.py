"""Exercise 7.2: a student's own safety rule, checked as a part and run paired against the package's agent."""

from __future__ import annotations

import numpy as np
import pytest

from sarsp_edu.agent.decision import choose_action, safe_actions
from sarsp_edu.teaching.exercises import check, is_right
from sarsp_edu.teaching.exercises.own_rule import (
    CONFIGURATIONS,
    EPISODES,
    SEEDS,
    RuleRun,
    _choose_with,
    _fingerprint,
    rule_problem,
    run_rule,
)


def lower_bound(mu_cost, var_cost, known_unsafe, d, variance_threshold):
    return (mu_cost - 1.645 * np.sqrt(var_cost) >= d) & ~np.asarray(known_unsafe, bool)


def test_a_valid_rule_passes_and_each_kind_of_invalid_one_is_named():
    assert rule_problem(lower_bound) is None
    assert rule_problem(safe_actions) is None  # the package's own safe set is a rule too

    def unwritten(*args):
        raise NotImplementedError()

    def three(mu_cost, *args):
        return [True] * 3

    def ignores_su(mu_cost, var_cost, known_unsafe, d, variance_threshold):
        return mu_cost >= d

    def mutates(mu_cost, var_cost, known_unsafe, d, variance_threshold):
        var_cost *= 0
        return (mu_cost >= d) & ~known_unsafe

    rng = np.random.default_rng(0)

    def dice(mu_cost, var_cost, known_unsafe, d, variance_threshold):
        return (rng.random(len(mu_cost)) < 0.5) & ~known_unsafe

    def raises(*args):
        return 1 / 0

    for rule, said in ((42, "Hand in your rule"), (unwritten, "Not written yet"), (three, "return 4 booleans"),
                       (ignores_su, "known unsafe (in S_u)"), (mutates, "changed its input var_cost in place"),
                       (dice, "twice differently"), (raises, "raised ZeroDivisionError")):
        problem = rule_problem(rule)
        assert problem is not None and said in problem, (rule, problem)


def test_the_agents_choice_takes_the_rules_safe_action_of_highest_reward_or_the_backup():
    choose = _choose_with(safe_actions)
    rng = np.random.default_rng(3)
    for _ in range(200):
        mu_cost, var_cost = rng.normal(1, 1, 4), rng.uniform(0, 2, 4)
        mu_reward, known_unsafe = rng.normal(0, 1, 4), rng.random(4) < 0.3
        action, _, backup = choose_action(mu_cost, var_cost, mu_reward, known_unsafe, 1.0, 0.8)
        assert choose(mu_cost, var_cost, mu_reward, known_unsafe, 1.0, 0.8) == (action, backup)


def test_the_package_rule_run_as_a_students_takes_the_packages_decisions():
    """A rule equal to the package's safe set: the two agents' runs are the same, step for step."""
    run = run_rule(safe_actions, configurations=((40.0, 0.2, 2),), seeds=(0,), episodes=2, progress=False)
    frame = run.frame()
    assert frame["agent"].tolist() == ["package", "yours"]
    mine, package = (frame[frame["agent"] == name].drop(columns="agent").iloc[0] for name in ("yours", "package"))
    assert mine.equals(package)
    summary = run.summary()
    assert summary.loc["total_cost", "yours - package"] == 0 and summary.loc["total_cost", "yours lower in"] == "0 of 1"
    assert run.definition4()["preferred"].tolist() == ["neither"]


def _run_of(rule, rows: int = len(CONFIGURATIONS) * len(SEEDS) * 2, episodes: int = EPISODES,
            configurations=CONFIGURATIONS) -> RuleRun:
    """A run as run_rule stores it, with made-up measures: the check reads whose it is, its size and its worlds."""
    made = RuleRun(fingerprint=_fingerprint(rule), episodes=episodes)
    worlds = [(m, p, nss, seed) for m, p, nss in configurations for seed in SEEDS]
    for i in range(rows):
        m, p, nss, seed = worlds[(i // 2) % len(worlds)]
        made.rows.append({"m": m, "p": p, "nss": nss, "seed": seed, "agent": ("package", "yours")[i % 2],
                          "total_cost": 10.0 + i, "task_success_rate": 50.0, "mean_steps": 40.0,
                          "backup_share": 20.0, "mean_reward": -100.0, "cost_rate": 0.01})
    return made


def test_the_check_wants_a_valid_rule_and_its_own_full_run_and_never_judges_the_choice(capsys):
    check("7.2", lower_bound)
    assert "now run it" in capsys.readouterr().out
    assert not is_right("7.2", lower_bound, run=_run_of(safe_actions))  # another rule's run
    check("7.2", lower_bound, run=_run_of(lower_bound, rows=2))
    assert "shorter than the exercise's (2 of 12 runs" in capsys.readouterr().out
    check("7.2", lower_bound, run=_run_of(lower_bound, episodes=5))
    assert "5 of 30 episodes" in capsys.readouterr().out
    assert is_right("7.2", lower_bound, run=_run_of(lower_bound))
    check("7.2", lower_bound, run=_run_of(lower_bound, configurations=[CONFIGURATIONS[0]] * 3))  # one world, 3 times
    assert "not the exercise's: it has no paired run at (m, p, nss) = (60, 0.3, 6), seed 0" in capsys.readouterr().out
    check("7.2", lambda mu_cost, var_cost, known_unsafe, d, variance_threshold: mu_cost >= d,
          run=_run_of(lower_bound))
    assert "known unsafe" in capsys.readouterr().out


def test_run_rule_refuses_an_invalid_rule_and_an_empty_design_before_any_run():
    with pytest.raises(ValueError, match="known unsafe"):
        run_rule(lambda mu_cost, var_cost, known_unsafe, d, variance_threshold: mu_cost >= d, progress=False)
    with pytest.raises(ValueError, match="at least one configuration and one seed"):
        run_rule(lower_bound, seeds=(), progress=False)
