"""Exercise 7.2: a safety rule of the student's own, run paired against the package's TP agent.

Exercise 7.1 checks that the student's functions are Algorithm 1's decision;
here the student designs one.  The rule takes the safe set's place:
``rule(mu_cost, var_cost, known_unsafe, d, variance_threshold)`` returns four
booleans, which actions are safe (exercise 4.1's signature), and the agent
takes the safe action with the highest predicted reward, or the backup (the
highest predicted reward of all) when the rule admits none.  For example, a
lower bound on the distance, ``mu_cost - 1.645 * sqrt(var_cost) >= d``; the
latent instead of the noisy variance is not among the rule's inputs.

:func:`run_rule` runs a TP agent deciding with the rule beside the package's
TP agent, on the same worlds with the same seeds, at three configurations of
the paper's grid (:data:`CONFIGURATIONS`, the ablation's), and
:class:`RuleRun` reads the runs: each agent's total cost, success rate and
backup share with 95% intervals over the runs, the paired differences, and
Definition 4's verdict per configuration.  The check (``check("7.2", rule,
run=...)``) judges only what can be judged: that the rule is a valid part (four
booleans, no action of S_u called safe, its inputs left as they were, the same
answer twice) and that the run was made with it.  Which agent to deploy is the
student's to argue, in writing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from scipy import stats

from ...agent.decision import override_known_unsafe, pick
from ...config import ExperimentConfig
from ...experiments.metrics import backup_share, prefers
from .capstone import _experiments, _Progress
from .grading import raised
from .running import TimedOut, call_copies
from .wording import describe

__all__ = ["CONFIGURATIONS", "EPISODES", "SEEDS", "OwnRule", "RuleRun", "rule_problem", "run_rule"]

#: (m, p, nss): the ablation's three configurations, one each of the outliers' magnitudes and shares
CONFIGURATIONS = ((40.0, 0.2, 2), (60.0, 0.3, 6), (80.0, 0.4, 10))
#: the seeds each configuration runs with
SEEDS = (0, 1)
#: episodes a run: enough for the agents to part, few enough to run in minutes
EPISODES = 30
#: the measures compared, as the records' last row holds them, and the backup share (%)
MEASURES = ("total_cost", "task_success_rate", "mean_steps", "backup_share")
#: what Definition 4 reads of each agent
_DEFINITION_4 = ("mean_reward", "cost_rate", "task_success_rate")


def _cases() -> list:
    """Exercise 4.1's inputs: fresh random decisions and the edge cases (a variance at sigma*^2, S_u ...)."""
    from .coding import CODING

    rng = np.random.default_rng(7)
    return [case for _ in range(4) for case in CODING["4.1"].cases(rng)]


def rule_problem(rule) -> str | None:
    """Why ``rule`` is not a valid safe-set part (None when it is): it must return four booleans for four actions,
    never call an action of S_u safe, leave its inputs as they were and give the same answer twice."""
    if not callable(rule):
        return ("Hand in your rule, a function rule(mu_cost, var_cost, known_unsafe, d, variance_threshold): got "
                f"{rule!r}.")
    for case in _cases():
        try:
            first, arguments = call_copies(rule, case, limited=True)
            second = call_copies(rule, case, limited=True)[0]
        except NotImplementedError:
            return "Not written yet; replace the line raise NotImplementedError(...) with your rule."
        except TimedOut as exc:
            return f"Your rule {exc} on {describe(case)}: is there a loop that never ends?"
        except (Exception, SystemExit) as exc:  # the student's code may raise anything: said with its input
            return f"Your rule raised {raised(exc)} on {describe(case)}."
        changed = [name for name, before, after in zip(case, case.values(), arguments)
                   if isinstance(before, np.ndarray) and not np.array_equal(before, after)]
        if changed:
            return (f"Your rule changed its input {changed[0]} in place on {describe(case)}: leave its inputs as "
                    "they are.")
        flags = np.asarray(first)
        n = len(case["mu_cost"])
        if flags.shape != (n,) or not (flags.dtype == bool or np.isin(flags, (0, 1)).all()):
            return f"Your rule returned {first!r} on {describe(case)}: return {n} booleans, one per action."
        if not np.array_equal(flags.astype(bool), np.asarray(second).astype(bool)):
            return f"Your rule answered {describe(case)} twice differently: a rule gives one answer to one input."
        unsafe = flags.astype(bool) & np.asarray(case["known_unsafe"], bool)
        if unsafe.any():
            return (f"Your rule calls action {int(np.flatnonzero(unsafe)[0])} safe although it is known unsafe (in "
                    f"S_u) on {describe(case)}: a move seen to violate is never safe.")
    return None


def _fingerprint(rule) -> tuple:
    """The rule's answers to exercise 4.1's inputs: two rules that agree on all of them count as one."""
    return tuple(tuple(bool(flag) for flag in np.asarray(call_copies(rule, case, limited=True)[0]))
                 for case in _cases())


def _choose_with(rule):
    """The agent's choice from the rule's safe set: its safe action of highest predicted reward, or the backup."""
    def choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold):
        safe = np.asarray(rule(mu_cost, var_cost, known_unsafe, d, variance_threshold)).astype(bool)
        return pick(safe, override_known_unsafe(mu_cost, var_cost, mu_reward, known_unsafe)[2])
    return choose


@dataclass
class RuleRun:
    """The paired runs of :func:`run_rule`: one row per configuration, seed and agent ("yours", "package")."""

    rows: list = field(default_factory=list)
    fingerprint: tuple = ()
    episodes: int = EPISODES

    def frame(self) -> pd.DataFrame:
        """One row per run: m, p, nss, seed, agent, :data:`MEASURES`, the mean reward and the cost rate."""
        columns = dict.fromkeys(["m", "p", "nss", "seed", "agent", *MEASURES, *_DEFINITION_4])
        return pd.DataFrame(self.rows, columns=list(columns))

    def summary(self) -> pd.DataFrame:
        """Per measure: each agent's mean over the runs and the paired difference (yours - package), each with a
        95% t-interval, and in how many runs yours is the lower."""
        wide = self.frame().pivot_table(index=["m", "p", "nss", "seed"], columns="agent", values=list(MEASURES))
        out = []
        for measure in MEASURES:
            yours, package = wide[(measure, "yours")].to_numpy(), wide[(measure, "package")].to_numpy()
            row = {"measure": measure}
            for name, values in (("yours", yours), ("package", package), ("yours - package", yours - package)):
                mean, (low, high) = _interval(values)
                row[name], row[f"{name} 95% CI"] = mean, f"[{low:.3g}, {high:.3g}]"
            row["yours lower in"] = f"{int(np.sum(yours < package))} of {len(yours)}"
            out.append(row)
        return pd.DataFrame(out).set_index("measure")

    def definition4(self) -> pd.DataFrame:
        """Definition 4 at each configuration, on the mean over its seeds: which agent it prefers."""
        frame = self.frame()
        rows = []
        for (m, p, nss), group in frame.groupby(["m", "p", "nss"]):
            yours, package = (group[group["agent"] == agent][list(_DEFINITION_4)].mean().to_dict()
                              for agent in ("yours", "package"))
            first, second = prefers(yours, package), prefers(package, yours)
            verdict = ("cannot decide (a cost rate undefined)" if first is None or second is None else
                       "yours" if first else "the package's" if second else "neither")
            rows.append({"m": m, "p": p, "nss": nss, "seeds": len(group) // 2, "preferred": verdict})
        return pd.DataFrame(rows)


def _interval(values) -> tuple[float, tuple[float, float]]:
    """The mean and its 95% t-interval (NaN ends from one value; the mean itself where all are equal)."""
    values = np.asarray(values, float)
    mean = float(values.mean())
    if len(values) < 2:
        return mean, (math.nan, math.nan)
    half = float(stats.t.ppf(0.975, len(values) - 1) * values.std(ddof=1) / math.sqrt(len(values)))
    return mean, (mean - half, mean + half)


def run_rule(rule, configurations=CONFIGURATIONS, seeds=SEEDS, episodes: int = EPISODES,
             progress: bool = True) -> RuleRun:
    """Run a TP agent deciding with ``rule`` beside the package's TP agent, paired, at each configuration and seed.

    Parameters
    ----------
    rule : callable
        ``rule(mu_cost, var_cost, known_unsafe, d, variance_threshold) -> four booleans``
        (:func:`rule_problem` says why one is refused).
    configurations : sequence of (m, p, nss), default :data:`CONFIGURATIONS`
    seeds : sequence of int, default :data:`SEEDS`
    episodes : int, default :data:`EPISODES`
    progress : bool, default True
        One line that says which run is going (emptied at the end).

    Returns
    -------
    RuleRun

    Raises
    ------
    ValueError
        If ``rule`` is not a valid part, or no configuration or seed is given.
    """
    from ...agent.parts import DecisionParts

    problem = rule_problem(rule)
    if problem is not None:
        raise ValueError(problem)
    configurations, seeds = [tuple(c) for c in configurations], list(seeds)
    if not configurations or not seeds:
        raise ValueError(f"run_rule needs at least one configuration and one seed, got configurations="
                         f"{configurations!r}, seeds={seeds!r}")
    parts = DecisionParts(safe_set=rule, choose=_choose_with(rule))
    result = RuleRun(fingerprint=_fingerprint(rule), episodes=episodes)
    shown = _Progress(progress, len(configurations) * len(seeds) * episodes * 2, label="Exercise 7.2")
    done = 0
    try:
        for m, p, nss in configurations:
            for seed in seeds:
                config = ExperimentConfig(outlier_magnitude=m, outlier_proportion=p, n_switch_states=nss,
                                          seed=seed, episodes=episodes)
                package, yours = _experiments(config, parts)
                for agent, run in (("package", package), ("yours", yours)):
                    while not run.finished:
                        shown.say(f"m = {m:g}, p = {p:g}, nss = {nss}, seed {seed}: {agent}, episode "
                                  f"{len(run.episodes) + 1} of {episodes}", done)
                        run.run_episode()
                        done += 1
                    records = run.records()
                    last = records.iloc[-1]
                    result.rows.append({"m": m, "p": p, "nss": nss, "seed": seed, "agent": agent,
                                        **{key: float(last[key]) for key in MEASURES[:3]},
                                        "backup_share": 100.0 * backup_share(records),
                                        "mean_reward": float(last["mean_reward"]),
                                        "cost_rate": float(last["cost_rate"])})
    finally:
        shown.close()
    return result


@dataclass(frozen=True)
class OwnRule:
    """Exercise 7.2: the rule is a valid part and its run was made with it (the choice of agent is not checked)."""

    question: str
    hint: str

    def verdict(self, answer, reuse: bool = False, run=None, **_) -> tuple[bool, str]:
        """``(right, why)``: the rule is a valid part and ``run`` was made with it.

        Parameters
        ----------
        answer : callable
            The student's rule.
        reuse : bool, default False
            Unused: the check is fast (as :class:`~.capstone.Capstone`'s, it is passed by ``is_right``).
        run : RuleRun, optional
            What :func:`run_rule` returned for the rule.
        """
        problem = rule_problem(answer)
        if problem is not None:
            return False, problem
        if not isinstance(run, RuleRun):
            return False, ("Your rule is a valid part; now run it: run = run_rule(your_rule), then check it with "
                           "run=run.")
        if run.fingerprint != _fingerprint(answer):
            return False, "This run was made with another rule (or an earlier version of it): run run_rule again."
        expected = len(CONFIGURATIONS) * len(SEEDS) * 2
        if len(run.rows) < expected or run.episodes < EPISODES:
            return False, (f"This run is shorter than the exercise's ({len(run.rows)} of {expected} runs, "
                           f"{run.episodes} of {EPISODES} episodes): run run_rule(your_rule) with its defaults.")
        made = {(row["m"], row["p"], row["nss"], row["seed"], row["agent"]) for row in run.rows}
        lacking = [(m, p, nss, seed) for m, p, nss in CONFIGURATIONS for seed in SEEDS
                   if not {(m, p, nss, seed, "yours"), (m, p, nss, seed, "package")} <= made]
        if lacking:  # as many runs, but not the exercise's worlds: run_rule(rule, configurations=[...] * 3)
            m, p, nss, seed = lacking[0]
            return False, (f"This run is not the exercise's: it has no paired run at (m, p, nss) = ({m:g}, {p:g}, "
                           f"{nss}), seed {seed} ({len(lacking)} of {len(CONFIGURATIONS) * len(SEEDS)} missing): "
                           "run run_rule(your_rule) with its defaults.")
        return True, (f"Your rule is a valid part and its {expected} runs are made. Which agent you would deploy, "
                      "and why, is yours to argue in the cell below: the check does not judge it.")


OWN_RULE = {
    "7.2": OwnRule(
        question="your own safety rule, run paired against the package's TP agent, and which you would deploy",
        hint="A rule returns four booleans; an action in S_u is never safe.",
    ),
}
