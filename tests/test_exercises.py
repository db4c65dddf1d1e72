"""The exercise checks: for every coding exercise a right function (written here by hand, apart from the
package) passes, and two usual wrong ones get their diagnosis, never the answer; short answers are taken
in any numeric type."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import linalg as sla, special, stats

from sarsp_edu import StudentTProcess
from sarsp_edu.agent.sarsp import Decision
from sarsp_edu.teaching.demos import regression_data
from sarsp_edu.teaching.exercises import CODING, EXERCISES, check, grade, is_right, same


# -- right answers, written from the equations ------------------------------------------------------
def student_t_logpdf(x, nu):
    x = np.asarray(x, dtype=float)
    const = special.gammaln((nu + 1) / 2) - special.gammaln(nu / 2) - 0.5 * np.log(nu * np.pi)
    return const - (nu + 1) / 2 * np.log1p(x**2 / nu)


def tail_ratio(x, lam, nu):
    return np.exp(student_t_logpdf(lam * np.asarray(x), nu) - student_t_logpdf(x, nu))


def outlier_costs(residual, nu):
    r = np.asarray(residual, dtype=float)
    return r**2 / 2 + 0.5 * np.log(2 * np.pi), -student_t_logpdf(r, nu)


def rbf(X, Y, amplitude, length_scale):
    d2 = ((X[:, None, :] - Y[None, :, :]) ** 2).sum(-1)
    return amplitude**2 * np.exp(-d2 / (2 * length_scale**2))


def gp_posterior(K, K_star, k_star_star, y, noise_variance):
    L = np.linalg.cholesky(K + noise_variance * np.eye(len(y)))
    alpha = sla.cho_solve((L, True), y)
    V = sla.solve_triangular(L, K_star.T, lower=True)
    return K_star @ alpha, k_star_star - (V**2).sum(0)


def tp_variance_factor(K, y, noise_variance, nu):
    beta = y @ np.linalg.solve(K + noise_variance * np.eye(len(y)), y)
    return (nu + beta - 2) / (nu + len(y) - 2)


def tp_log_marginal_likelihood(K, y, noise_variance, nu):
    n = len(y)
    L = np.linalg.cholesky(K + noise_variance * np.eye(n))
    beta = y @ sla.cho_solve((L, True), y)
    return float(special.gammaln((nu + n) / 2) - special.gammaln(nu / 2) - n / 2 * np.log((nu - 2) * np.pi)
                 - np.log(np.diag(L)).sum() - (nu + n) / 2 * np.log1p(beta / (nu - 2)))


def cap_duplicates(X, y, cap):
    seen, keep = {}, []
    for i, x in enumerate(X):
        key = tuple(x)
        seen[key] = seen.get(key, 0) + 1
        if seen[key] <= cap:
            keep.append(i)
    return X[keep], y[keep]


def student_t_pull(residual, nu, scale):
    residual = np.asarray(residual, dtype=float)
    return (nu + 1) * residual / (nu * scale**2 + residual**2)


def distance_to_unsafe(position, unsafe):
    return min(math.dist(position, cell) for cell in unsafe)


def move(position, action, size):
    dx, dy = {0: (1, 0), 1: (0, 1), 2: (-1, 0), 3: (0, -1)}[action]
    return (min(max(position[0] + dx, 0), size - 1), min(max(position[1] + dy, 0), size - 1))


def safe_actions(mu_cost, var_cost, known_unsafe, d, variance_threshold):
    return [bool(not k and v <= variance_threshold and m >= d) for m, v, k in zip(mu_cost, var_cost, known_unsafe)]


def choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold):
    safe = safe_actions(mu_cost, var_cost, known_unsafe, d, variance_threshold)
    rewards = [(-math.inf if k else r) for r, k in zip(mu_reward, known_unsafe)]
    candidates = [a for a in range(4) if safe[a]] or list(range(4))
    best = candidates[0]
    for a in candidates:
        if rewards[a] > rewards[best]:
            best = a
    return best, not any(safe)


def corrects(mu_cost, var_cost, action, d, was_backup):
    return mu_cost[action] >= d or (var_cost[action] == min(var_cost) and not was_backup)


def symmetric_percent_difference(a, b):
    """The exercise's rule: the mean of the sizes |a| and |b| (Table 1's totals are never negative)."""
    return 0.0 if a == b else abs(a - b) / ((abs(a) + abs(b)) / 2) * 100


def agreement_share(tp_1, gp_1, tp_2, gp_2):
    same = [(t1 > g1 and t2 > g2) or (t1 < g1 and t2 < g2) for t1, g1, t2, g2 in zip(tp_1, gp_1, tp_2, gp_2)]
    return 100.0 * sum(same) / len(same)


def sign_test(tp, gp):
    """By hand: twice the smaller binomial tail of the win count, at most 1."""
    wins = sum(t > g for t, g in zip(tp, gp))
    n = sum(t != g for t, g in zip(tp, gp))
    if n == 0:
        return 1.0
    tail = sum(math.comb(n, i) for i in range(0, min(wins, n - wins) + 1)) / 2 ** n
    return min(1.0, 2 * tail)


def tsr_and_cost_rate(episode_cost, episode_steps, task_completed):
    clean = sum(s for c, s, done in zip(episode_cost, episode_steps, task_completed) if done and c == 0)
    total = sum(episode_cost)
    return 100 * np.mean(task_completed), (total / clean if total and clean else 0.0)


def prefers(summary_1, summary_2, a):
    return summary_1["cost_rate"] < summary_2["cost_rate"] and (
        summary_1["mean_reward"] >= summary_2["mean_reward"]
        or summary_1["task_success_rate"] >= summary_2["task_success_rate"]
        or summary_1["task_success_rate"] >= a)


def backup_shares(mu_cost, var_cost, d, thresholds):
    """By hand, a decision at a time: the backup decides where no action passes both tests."""
    shares = []
    for threshold in thresholds:
        backups = sum(not any(v <= threshold and m >= d for m, v in zip(mus, variances))
                      for mus, variances in zip(mu_cost, var_cost))
        shares.append(100.0 * backups / len(mu_cost))
    return np.array(shares)


RIGHT = {"1.1": student_t_logpdf, "1.2": tail_ratio, "1.3": outlier_costs, "2.1": rbf, "2.2": gp_posterior,
         "2.3": tp_variance_factor, "2.4": tp_log_marginal_likelihood, "2.7": student_t_pull, "3.1": cap_duplicates,
         "3.2": distance_to_unsafe, "3.3": move, "4.1": safe_actions, "4.2": choose, "4.3": corrects,
         "5.1": symmetric_percent_difference, "5.2": agreement_share, "5.3": sign_test,
         "6.1": tsr_and_cost_rate, "6.2": prefers, "6.3": backup_shares}


# -- two usual wrong answers of each, with the diagnosis they must get -------------------------------
WRONG = {
    "1.1": [(lambda x, nu: -(nu + 1) / 2 * np.log1p(np.asarray(x) ** 2 / nu), "normalising constant is missing"),
            (lambda x, nu: np.exp(student_t_logpdf(x, nu)), "These are densities")],
    "1.2": [(lambda x, lam, nu: np.exp(student_t_logpdf(lam * np.asarray(x) ** 2, nu) - student_t_logpdf(x, nu)),
             "the density at lambda x^2"),
            (lambda x, lam, nu: ((1 + lam * np.asarray(x, float) ** 2 / nu) / (1 + np.asarray(x, float) ** 2 / nu))
             ** (-(nu + 1) / 2), "eq. 8 as printed"),
            (lambda x, lam, nu: 1 / tail_ratio(x, lam, nu), "upside down")],
    "1.3": [(lambda residual, nu: (np.asarray(residual) ** 2 / 2,
                                    (nu + 1) / 2 * np.log1p(np.asarray(residual) ** 2 / nu)),
             "The constants are missing"),
            (lambda residual, nu: outlier_costs(residual, nu)[::-1], "swapped")],
    "2.7": [(lambda residual, nu, scale: np.asarray(residual) / scale**2, "Gaussian likelihood's pull"),
            (lambda residual, nu, scale: (nu + 1) * np.asarray(residual) / (nu + np.asarray(residual) ** 2),
             "scale sigma_t is missing")],
    "2.1": [(lambda X, Y, amplitude, length_scale: rbf(X, Y, amplitude, length_scale) / amplitude,
             "amplitude enters squared"),
            (lambda X, Y, amplitude, length_scale: rbf(X, Y, amplitude, np.sqrt(length_scale)),
             "the length scale is squared too")],
    "2.2": [(lambda K, K_star, k_star_star, y, noise_variance: gp_posterior(K, K_star, k_star_star, y, 0.0),
             "noise term is missing"),
            (lambda K, K_star, k_star_star, y, noise_variance: (
                gp_posterior(K, K_star, k_star_star, y, noise_variance)[0],
                np.sqrt(gp_posterior(K, K_star, k_star_star, y, noise_variance)[1])), "standard deviation")],
    "2.3": [(lambda K, y, noise_variance, nu: tp_variance_factor(K, y, 0.0, nu), "K_y = K + sigma^2 I"),
            (lambda K, y, noise_variance, nu: nu / (nu - 2), "prior's factor")],
    "2.4": [(lambda K, y, noise_variance, nu: float(stats.multivariate_normal(
                np.zeros(len(y)), K + noise_variance * np.eye(len(y))).logpdf(y)), "GP's"),
            (lambda K, y, noise_variance, nu: tp_log_marginal_likelihood(K * nu / (nu - 2), y,
                                                                         noise_variance * nu / (nu - 2), nu),
             "as the multivariate t's shape matrix")],
    "3.1": [(lambda X, y, cap: (lambda rows: (rows[:, :-1], rows[:, -1]))(
                cap_duplicates(np.column_stack([X, y]), y, cap)[0]), "Count copies of the input x alone"),
            (lambda X, y, cap: tuple(part[::-1] for part in cap_duplicates(X[::-1], y[::-1], cap)),
             "Keep the first copies")],
    "3.2": [(lambda position, unsafe: min(abs(position[0] - u[0]) + abs(position[1] - u[1]) for u in unsafe),
             "Manhattan"),
            (lambda position, unsafe: min(math.dist(position, u) for u in unsafe) ** 2, "squared distance")],
    "3.3": [(lambda position, action, size: move(position, {0: 0, 1: 3, 2: 2, 3: 1}[action], size),
             "y grows downwards"),
            (lambda position, action, size: (position[0] + (1, 0, -1, 0)[action], position[1] + (0, 1, 0, -1)[action]),
             "clip to 0 .. size - 1")],
    "4.1": [(lambda mu_cost, var_cost, known_unsafe, d, variance_threshold:
             safe_actions(mu_cost, var_cost, [False] * 4, d, variance_threshold), "never safe"),
            (lambda mu_cost, var_cost, known_unsafe, d, variance_threshold:
             safe_actions(mu_cost, np.sqrt(var_cost), known_unsafe, d, variance_threshold),
             "the variance itself")],
    "4.2": [(lambda mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold:
             (int(np.argmax(np.where(known_unsafe, -np.inf, mu_reward))), False), "only among the safe actions"),
            (lambda mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold: (
                choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold)[0]
                if any(safe_actions(mu_cost, var_cost, known_unsafe, d, variance_threshold))
                else int(np.argmax(np.where(known_unsafe, -np.inf, -np.asarray(var_cost)))),
                not any(safe_actions(mu_cost, var_cost, known_unsafe, d, variance_threshold))),
             "not the most certain one")],
    "4.3": [(lambda mu_cost, var_cost, action, d, was_backup: bool(mu_cost[action] >= d), "second reason"),
            (lambda mu_cost, var_cost, action, d, was_backup:
             bool(mu_cost[action] >= d or var_cost[action] == min(var_cost)),
             "taken as the backup")],
    "5.1": [(lambda a, b: (a - b) / abs(b) * 100, "Table 2's convention"),
            (lambda a, b: abs(a - b) / max(a, b) * 100, "the larger of the two")],
    "5.2": [(lambda t1, g1, t2, g2: 100.0 * np.mean(np.sign(t1 - g1) == np.sign(t2 - g2)), "A tie names no better"),
            (lambda t1, g1, t2, g2: agreement_share(t1, g1, t2, g2) / 100, "in %")],
    "5.3": [(lambda tp, gp: 1.0 if not np.any(tp != gp) else stats.binomtest(int(np.sum(tp > gp)), len(tp)).pvalue,
             "drop the tied pairs"),
            (lambda tp, gp: 1.0 if not np.any(tp != gp) else stats.binomtest(
                int(np.sum(tp > gp)), int(np.sum(tp != gp)), alternative="greater").pvalue, "two-sided")],
    "6.1": [(lambda c, s, done: (np.mean(done), tsr_and_cost_rate(c, s, done)[1]), "in %"),
            (lambda c, s, done: (tsr_and_cost_rate(c, s, done)[0], sum(c) / sum(s) if sum(c) else 0.0),
             "not of all episodes")],
    "6.2": [(lambda s1, s2, a: s1["cost_rate"] < s2["cost_rate"] and s1["mean_reward"] >= s2["mean_reward"]
             and s1["task_success_rate"] >= s2["task_success_rate"], "or, not and"),
            (lambda s1, s2, a: s1["cost_rate"] < s2["cost_rate"] and (
                s1["mean_reward"] >= s2["mean_reward"] or s1["task_success_rate"] >= s2["task_success_rate"]),
             "third branch missing")],
    "6.3": [(lambda mu, var, d, thresholds: np.array([100 * np.mean(~((var <= t) & (mu >= d)).any(axis=1))
                                                      for t in thresholds]) / 100, "in %"),
            (lambda mu, var, d, thresholds: np.array([100 * np.mean(~((var <= t) & (mu >= d)))
                                                      for t in thresholds]), "not actions")],
}

# -- the slips a student's attempt at every exercise made, each with the reply that names it -----------
SLIPS = {
    "1.1": [(lambda x, nu: student_t_logpdf(x, nu) + np.log(np.pi) / 2, "off by the same amount at every x")],
    "2.2": [(lambda K, K_star, k_star_star, y, noise_variance: gp_posterior(K, K_star, k_star_star, y,
                                                                            np.sqrt(noise_variance)),
             "not its square root")],
    "2.3": [(lambda K, y, noise_variance, nu: (nu + y @ np.linalg.solve(K + noise_variance * np.eye(len(y)), y))
             / (nu + len(y)), "miss the same term")],
    "2.7": [(lambda residual, nu, scale: (nu + 1) * np.asarray(residual) / (nu * scale + np.asarray(residual) ** 2),
             "check its power")],
    "3.1": [(lambda X, y, cap: cap_duplicates(X, y, cap + 1), "one copy too many")],
    "3.3": [(lambda position, action, size: move(position, action, size + 1), "clip to size - 1")],
    "4.2": [(lambda mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold: (
                choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold)
                if any(safe_actions(mu_cost, var_cost, known_unsafe, d, variance_threshold))
                else (int(np.argmax(mu_reward)), True)), "passes over the actions known unsafe"),
            (lambda mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold: (
                3 - choose(mu_cost[::-1], var_cost[::-1], mu_reward[::-1], known_unsafe[::-1], d,
                           variance_threshold)[0],
                choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold)[1]), "lowest action number"),
            (lambda mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold: (
                choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold)[0],
                not choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold)[1]), "upside down")],
    "4.3": [(lambda mu_cost, var_cost, action, d, was_backup: bool(mu_cost[action] > d or (
                var_cost[action] <= min(var_cost) and not was_backup)), "exactly d"),
            (lambda mu_cost, var_cost, action, d, was_backup: bool(mu_cost[action] >= d or (
                action == int(np.argmin(var_cost)) and not was_backup)), "tie for the lowest variance")],
    "5.1": [(lambda a, b: abs(a - b) / (a + b) * 100, "the two added up"),
            (lambda a, b: abs(a - b) / ((a + b) / 2), "those of a fraction")],
    "5.2": [(lambda t1, g1, t2, g2: agreement_share(t1, g1, t2, g2) * len(t1) / 100, "the count")],
    "5.3": [(lambda tp, gp: float("nan") if not np.any(np.asarray(tp) != np.asarray(gp)) else sign_test(tp, gp),
             "the p-value is 1"),
            (lambda tp, gp: 1.0 if not np.any(tp != gp) else stats.binom.cdf(
                min(np.sum(tp > gp), np.sum(tp < gp)), np.sum(tp != gp), 0.5), "double it"),
            (lambda tp, gp: 1.0 if not np.any(tp != gp) else 2 * stats.binom.cdf(
                min(np.sum(tp > gp), np.sum(tp < gp)), np.sum(tp != gp), 0.5), "at most 1")],
    "6.1": [(lambda c, s, done: (float(np.sum(done)), tsr_and_cost_rate(c, s, done)[1]), "not their count")],
    "6.2": [(lambda s1, s2, a: s1["cost_rate"] < s2["cost_rate"] and (
                s1["mean_reward"] > s2["mean_reward"] or s1["task_success_rate"] > s2["task_success_rate"]
                or s1["task_success_rate"] >= a), "equal to agent 2's is enough")],
    "6.3": [(lambda mu, var, d, thresholds: np.array([100 * np.mean(~((var < t) & (mu >= d)).any(axis=1))
                                                      for t in thresholds]), "at most, not below"),
            (lambda mu, var, d, thresholds: np.array([100 * np.mean(~(var <= t).any(axis=1))
                                                      for t in thresholds]), "distance of at least d")],
}


@pytest.mark.parametrize("name", sorted(SLIPS))
def test_a_students_slips_are_caught_and_named(name):
    for slip, diagnosis in SLIPS[name]:
        right, message = grade(name, CODING[name], slip)
        assert not right and diagnosis in message, message


def test_a_missing_return_a_failing_factorisation_and_one_wrong_result_of_two_are_said():
    right, message = grade("4.1", CODING["4.1"], lambda mu_cost, var_cost, known_unsafe, d, variance_threshold: None)
    assert not right and "returned None" in message
    no_noise = lambda K, y, noise_variance, nu: float(y @ np.linalg.cholesky(K)[:, 0])  # noqa: E731
    right, message = grade("2.3", CODING["2.3"], no_noise)
    assert not right and "LinAlgError" in message and "K_y = K + sigma^2 I" in message
    right, message = grade("6.1", CODING["6.1"], lambda c, s, done: (tsr_and_cost_rate(c, s, done)[0], -1.0))
    assert not right and "its result number 2 (of 2) differs from the package's; the other is right" in message
    right, message = grade("6.1", CODING["6.1"], lambda c, s, done: (-1.0, -1.0))
    assert not right and "both of its results differ" in message and "right" not in message
    assert "(yours: (-1, -1))" in message  # a small result is said, so the case can be redone by hand


def test_small_inputs_are_said_in_full_large_ones_by_their_shape():
    right, message = grade("5.1", CODING["5.1"], lambda a, b: 3.0)
    assert not right and message.startswith("On a = 28, b = 58, it gives other values than the package (yours: 3).")
    right, message = grade("6.2", CODING["6.2"], lambda s1, s2, a: not prefers(s1, s2, a))
    assert "summary_1 = {mean_reward: " in message and "task_success_rate: " in message
    right, message = grade("2.1", CODING["2.1"], lambda X, Y, amplitude, length_scale: np.ones((len(X), len(Y))))
    assert not right and "X of shape (" in message and "raised" not in message


def test_there_are_at_least_twelve_coding_exercises_two_or_more_in_each_tutorial():
    assert len(CODING) >= 12 and set(RIGHT) == set(CODING) == set(WRONG)
    for tutorial in "123456":
        assert sum(name.startswith(tutorial + ".") for name in CODING) >= 2


@pytest.mark.parametrize("name", sorted(CODING))
def test_a_right_function_passes_on_fresh_inputs(name, capsys):
    for seed in (None, 1, 2):  # the notebook's inputs and two other draws
        right, message = grade(name, CODING[name], RIGHT[name], rng=seed)
        assert right, message
    check(name, RIGHT[name])
    out = capsys.readouterr().out
    assert out.startswith(f"Exercise {name}: right.") and "<function" not in out  # a computed reply, said as text


@pytest.mark.parametrize("name", sorted(CODING))
def test_usual_mistakes_get_their_diagnosis_not_the_answer(name, capsys):
    for wrong, diagnosis in WRONG[name]:
        right, message = grade(name, CODING[name], wrong)
        assert not right and diagnosis in message, message
        check(name, wrong)
        out = capsys.readouterr().out
        assert out.startswith(f"Exercise {name}: not yet.") and diagnosis in out
        assert "def " not in out and "return" not in out  # no code given away


def test_a_placeholder_an_exception_and_a_wrong_shape_are_said_plainly(capsys):
    def placeholder(X, Y, amplitude, length_scale):
        raise NotImplementedError("write your answer here")

    check("2.1", placeholder)
    assert capsys.readouterr().out == ("Exercise 2.1: not yet. Not written yet; replace the line raise "
                                       "NotImplementedError(...) with your code.\n")
    check("2.1", lambda X, Y, amplitude, length_scale: np.linalg.cholesky(-np.eye(2)))
    assert "Your function raised LinAlgError: Matrix is not positive definite" in capsys.readouterr().out
    check("2.1", lambda X, Y, amplitude, length_scale: rbf(X, Y, amplitude, length_scale).T)
    assert "has shape" in capsys.readouterr().out
    check("2.2", lambda K, K_star, k_star_star, y, noise_variance: gp_posterior(K, K_star, k_star_star, y,
                                                                                noise_variance)[0])
    assert "should return 2 things" in capsys.readouterr().out
    check("2.1", 3.0)
    assert "asks for a function" in capsys.readouterr().out


def test_a_right_answer_that_refactorises_per_query_is_called_slow():
    def per_query(K, K_star, k_star_star, y, noise_variance):
        means, variances = [], []
        for i in range(len(K_star)):
            A = K + noise_variance * np.eye(len(y))
            means.append(K_star[i] @ np.linalg.solve(A, y))
            variances.append(k_star_star[i] - K_star[i] @ np.linalg.inv(A) @ K_star[i])
        return np.array(means), np.array(variances)

    right, message = grade("2.2", CODING["2.2"], per_query)
    assert right and "It is right but slow" in message
    assert "factorise once and solve for every query together" in message


@pytest.mark.parametrize("answer", [50, 50.0, np.int64(50), np.float32(50), np.array(50)])
def test_short_answers_are_taken_in_any_numeric_type(answer):
    assert is_right("3.4", answer) is True
    assert is_right("3.4", 25) is False and is_right("3.4", True) is False and is_right("3.4", "50") is True


def test_short_answers_right_wrong_and_missing(capsys):
    assert is_right("1.4", {"lambda < 1": math.inf, "lambda = 1": 1, "lambda > 1": 0})
    assert not is_right("1.4", {"lambda < 1": 0, "lambda = 1": 1, "lambda > 1": math.inf})
    assert is_right("2.5", "below") and not is_right("2.5", "above")
    assert is_right("2.6", "narrower") and not is_right("2.6", "wider")
    check("3.4", ...)
    assert capsys.readouterr().out == "Exercise 3.4: not answered yet; replace ... with your answer.\n"
    check("3.4", 25)
    out = capsys.readouterr().out
    assert out.startswith("Exercise 3.4: not yet.") and "50" not in out


def test_the_replies_that_hold_numbers_compute_them(capsys):
    check("1.3", RIGHT["1.3"])
    out = capsys.readouterr().out
    residuals_of_one = stats.norm.logpdf(40.0) / stats.norm.logpdf(1.0)  # costs are minus these
    assert f"as much as about {residuals_of_one:.0f} residuals of 1" in out and "not 1,600" in out
    X, y, _ = regression_data(n=40, magnitude=10.0, proportion=0.0, seed=0)
    clean = StudentTProcess(nu=3.0).fit(X, y)
    assert clean.variance_scale_ < 1 and is_right("2.5", "below")
    check("2.5", "below")
    out = capsys.readouterr().out  # the numbers the student is to print are not given away
    assert "beta / n = 0.33 at nu = 3" in out and f"{clean.variance_scale_:.2f}" not in out


def test_exercise_4_4_reads_the_notebooks_decision():
    decision = Decision((4, 4), np.array([1.0, 2.0, 0.4, 1.4]), np.array([5.5, 5.6, 5.4, 11.0]),
                        np.array([-3.0, -2.0, -1.0, -2.5]), np.array([1.0] * 4), np.array([False] * 4),
                        np.array([False] * 4), 2, True)
    assert is_right("4.4", [0, 1], decision=decision) and not is_right("4.4", [0, 1, 3], decision=decision)
    with pytest.raises(ValueError, match="decision=gp_decision"):
        is_right("4.4", [0])


def test_an_unknown_exercise_names_the_known_ones():
    with pytest.raises(ValueError, match=r"exercise must be one of \['1.1', '1.2'"):
        check("9.9", 1)
    assert list(EXERCISES)[:4] == ["1.1", "1.2", "1.3", "1.4"]


@pytest.mark.parametrize("got, expected, equal", [
    (1.0 + 1e-9, 1.0, True), (1.01, 1.0, False), (np.array([1e6, 1.0]), np.array([1e6, 1.0 + 1e-3]), True),
    (np.array([np.inf, 1.0]), np.array([np.inf, 1.0]), True), (np.array([-np.inf]), np.array([np.inf]), False),
    ([True, False], np.array([True, False]), True), (np.int64(3), 3, True), (3.0, 3, True), (2.5, 3, False),
    (np.nan, np.nan, True), (np.array([np.nan, 2.0]), np.array([np.nan, 2.0]), True), (np.nan, 1.0, False),
    (1.0, np.nan, False),
])
def test_same_uses_the_quantitys_own_scale(got, expected, equal):
    assert same(got, expected) is equal


def test_a_prediction_may_be_a_function_and_its_placeholder_is_not_answered(capsys):
    def my_prediction():
        raise NotImplementedError()

    check("2.5", my_prediction)
    assert "Not written yet" in capsys.readouterr().out
    assert is_right("2.5", lambda: "below")


# -- "Labs without holes", section 1: the grader's holes, one test each ----------------------------------
#: the values of number arguments that the notebooks use in their examples (besides each first case's)
NOTEBOOK_VALUES = {"3.1": {"cap": (1, 12)}, "3.3": {"size": 10}, "4.1": {"d": 1.0, "variance_threshold": 0.8},
                   "4.2": {"d": 1.0, "variance_threshold": 0.8}, "4.3": {"d": 1.0}, "6.2": {"a": 100.0},
                   "6.3": {"d": 1.0}}


def _written_in(name, position, value):
    """The right answer of ``name`` with its argument number ``position`` replaced by a fixed ``value``."""
    def answer(*args):
        args = list(args)
        args[position] = value
        return RIGHT[name](*args)
    return answer


def _number_arguments():
    for name in sorted(CODING):
        first = CODING[name].cases(np.random.default_rng(0))[0]
        for position, (argument, value) in enumerate(first.items()):
            if isinstance(value, (bool, int, float, np.number)):
                for fixed in dict.fromkeys([value, *np.atleast_1d(NOTEBOOK_VALUES.get(name, {}).get(argument, ()))]):
                    yield name, position, argument, fixed


@pytest.mark.parametrize("name, position, argument, fixed", list(_number_arguments()))
def test_an_answer_with_a_number_argument_written_in_is_judged_wrong(name, position, argument, fixed):
    """Hole 1: every number argument takes several values, so writing one in (d = 1, cap = 12) is caught."""
    right, message = grade(name, CODING[name], _written_in(name, position, fixed))
    assert not right, f"{name}: {argument} = {fixed} written in passes"


def test_exercise_4_3_varies_d_and_tells_the_distance_alone_from_the_whole_safe_test():
    """Hole 1: 4.3 used d = 1 in every case, and no case told 'called it safe' from Algorithm 1's safe test."""
    cases = CODING["4.3"].cases(np.random.default_rng(0))
    assert len({case["d"] for case in cases}) >= 3
    assert any(case["mu_cost"][case["action"]] >= case["d"] and case["var_cost"][case["action"]] > 0.8
               and (case["was_backup"] or case["var_cost"][case["action"]] > case["var_cost"].min())
               for case in cases)
    d_is_one = lambda mu_cost, var_cost, action, d, was_backup: corrects(mu_cost, var_cost, action, 1.0,  # noqa: E731
                                                                          was_backup)
    right, message = grade("4.3", CODING["4.3"], d_is_one)
    assert not right and "d = 1 gives, whatever d is" in message
    whole_test = lambda mu_cost, var_cost, action, d, was_backup: bool(  # noqa: E731
        (mu_cost[action] >= d and var_cost[action] <= 0.8) or (var_cost[action] <= min(var_cost) and not was_backup))
    right, message = grade("4.3", CODING["4.3"], whole_test)
    assert not right and "the predicted distance alone" in message
    assert "whatever the variance" in CODING["4.3"].question


@pytest.mark.parametrize("name", ["1.1", "1.2", "1.3", "2.7"])
def test_array_arguments_are_given_in_more_than_one_dimension(name):
    """Hole 2: 'x is an array' allows any shape; an answer that flattens it is caught."""
    assert any(np.ndim(next(iter(case.values()))) == 2 for case in CODING[name].cases(np.random.default_rng(0)))

    def flattening(x, *rest):
        result = RIGHT[name](np.ravel(x), *rest)
        return tuple(np.ravel(r) for r in result) if isinstance(result, tuple) else np.ravel(result)

    right, message = grade(name, CODING[name], flattening)
    assert not right and "has shape" in message


def test_the_buffer_cap_is_given_inputs_of_one_and_three_features():
    """Hole 2: X of shape (n, d) for any d; an answer that keys on the first two columns is caught."""
    assert {case["X"].shape[1] for case in CODING["3.1"].cases(np.random.default_rng(0))} >= {1, 2, 3}
    two_columns = lambda X, y, cap: cap_duplicates(X[:, :2], y, cap) if X.shape[1] == 2 else (X, y)  # noqa: E731
    assert not grade("3.1", CODING["3.1"], two_columns)[0]


@pytest.mark.parametrize("name, change, argument", [
    ("2.1", lambda args: args[0].fill(0.0), "X"),
    ("3.1", lambda args: args[1].sort(), "y"),
    ("6.2", lambda args: args[0].update(cost_rate=0.0), "summary_1"),
    ("5.3", lambda args: args[1].sort(), "gp"),
])
def test_an_answer_that_changes_its_inputs_in_place_is_judged_wrong(name, change, argument):
    """Hole 3: the student's function gets copies; the copies are compared with the originals afterwards."""
    def changing(*args):
        result = RIGHT[name](*[np.array(a) if isinstance(a, np.ndarray) else dict(a) if isinstance(a, dict) else a
                               for a in args])
        change(args)
        return result

    right, message = grade(name, CODING[name], changing)
    assert not right and f"changed its input {argument} in place" in message and "work on a copy" in message


def test_an_answer_that_runs_too_long_is_stopped_after_ten_seconds(capsys):
    """Hole 4: the check returns within the limit, and says so in one line."""
    import time

    start = time.perf_counter()
    check("2.1", lambda X, Y, amplitude, length_scale: time.sleep(15))
    out = capsys.readouterr().out
    assert time.perf_counter() - start < 20
    assert out.startswith("Exercise 2.1: not yet. Your function did not return within 10 s") and out.count("\n") == 1


def test_an_endless_loop_is_stopped_and_a_prediction_too(monkeypatch, capsys):
    import threading
    import time

    from sarsp_edu.teaching.exercises import running

    monkeypatch.setattr(running, "TIME_LIMIT", 0.5)

    def endless(x, nu):
        while True:
            pass

    before = set(threading.enumerate())
    right, message = grade("1.1", CODING["1.1"], endless)
    assert not right and "did not return within 0.5 s" in message
    stopped = [t for t in threading.enumerate() if t not in before and t.name == "sarsp_edu-exercise"]
    for thread in stopped:
        thread.join(5)  # an endless loop of Python code is asked to stop, and does
    assert not any(thread.is_alive() for thread in stopped)
    check("3.4", lambda: time.sleep(15))
    assert "Exercise 3.4: not yet. Your function did not return within 0.5 s" in capsys.readouterr().out


@pytest.mark.parametrize("exercise, answer, said", [
    ("3.4", lambda: 1 / 0, "Your answer raised ZeroDivisionError: division by zero."),
    ("2.5", lambda: {}["x"], "Your answer raised KeyError: 'x'."),
    ("3.4", 10**400, "Could not read an int of 401 digits as a whole number."),
    ("3.4", "a few", "Could not read 'a few' as a whole number."),  # 'fifty' is read: 50
    ("3.4", 49.5, "Could not read 49.5 as a whole number."),
    ("3.4", None, "Your answer is None."),
    ("3.4", lambda: None, "Your answer is None (is your function's return statement missing?)."),
    ("1.4", "inf", "Could not read 'inf' as a dict of three limits."),
    ("1.4", {"lambda < 1": "lots", "lambda = 1": 1, "lambda > 1": 0}, "Could not read 'lots' as the limit"),
    ("4.4", [0, 7], "7 is not an action: they are numbered 0 to 3."),
])
def test_a_prediction_that_raises_or_cannot_be_read_gets_one_line(exercise, answer, said, capsys):
    """Hole 4: never a traceback; what could not be read is said, with the accepted forms."""
    decision = Decision((4, 4), np.array([1.0, 2.0, 0.4, 1.4]), np.array([5.5, 5.6, 5.4, 11.0]),
                        np.array([-3.0, -2.0, -1.0, -2.5]), np.array([1.0] * 4), np.array([False] * 4),
                        np.array([False] * 4), 2, True)
    check(exercise, answer, **({"decision": decision} if exercise == "4.4" else {}))
    out = capsys.readouterr().out
    assert out.startswith(f"Exercise {exercise}: not yet. ") and said in out and out.count("\n") == 1
    assert "raised" in said or "Accepted: " in out


@pytest.mark.parametrize("answer", [lambda a, b: 10**400, lambda a, b: "69.8", lambda a, b: [[1], [2, 3]]])
def test_a_result_that_cannot_be_read_is_said_not_raised(answer):
    right, message = grade("5.1", CODING["5.1"], answer)
    assert not right and "cannot be read as a number" in message


@pytest.mark.parametrize("exercise, answers", [
    ("2.5", ["below", "Below.", "BELOW", " below 1 ", "<", "< 1", "smaller", "less than 1", np.str_("below")]),
    ("2.6", ["narrower", "Narrower.", "smaller", "<", "tighter"]),
    ("3.4", [50, "50", " 50 ", "50.0", np.int64(50), np.float32(50), np.array(50), lambda: np.int32(50)]),
    ("1.4", [{"lambda<1": "infinity", "lambda=1": "1", "lambda>1": 0},
             {"λ < 1": math.inf, "λ = 1": np.float64(1.0), "λ > 1": np.int64(0)},
             {"lambda < 1": "∞", "lambda == 1": 1.0, "lambda > 1": "0"},
             {"λ<1": float("inf"), "λ=1": np.array(1), "λ>1": 0.0}]),
])
def test_predictions_take_the_spellings_a_student_would_use(exercise, answers):
    """Hole 5: words with a capital and a full stop, symbols, numbers as text, numpy scalars, 'λ < 1'."""
    for answer in answers:
        assert is_right(exercise, answer), answer
    assert not is_right(exercise, {"2.5": "above", "2.6": "wider", "3.4": 49}.get(exercise, {
        "lambda < 1": 0, "lambda = 1": 1, "lambda > 1": math.inf}))


def test_exercise_4_4_takes_a_list_a_set_an_array_a_mask_or_text():
    decision = Decision((4, 4), np.array([1.0, 2.0, 0.4, 1.4]), np.array([5.5, 5.6, 5.4, 11.0]),
                        np.array([-3.0, -2.0, -1.0, -2.5]), np.array([1.0] * 4), np.array([False] * 4),
                        np.array([False] * 4), 2, True)
    for answer in ([0, 1], (1, 0), {0, 1}, np.array([0, 1]), [np.int64(0), 1.0], "0, 1", "[0, 1]",
                   np.array([True, True, False, False]), ["RIGHT", "down"]):
        assert is_right("4.4", answer, decision=decision), answer


@pytest.mark.parametrize("exercise, answer", [("2.5", "maybe"), ("2.5", 1.0), ("2.6", "same"), ("3.4", "a few"),
                                              ("3.4", True), ("1.4", [math.inf, 1])])
def test_an_answer_that_cannot_be_read_lists_the_forms_and_gets_no_hint(exercise, answer, capsys):
    """Hole 5: the hint is for a wrong idea; an unreadable answer is told the accepted forms instead."""
    check(exercise, answer)
    out = capsys.readouterr().out
    assert "Could not read" in out and "Accepted: " in out and EXERCISES[exercise].hint not in out


def test_replies_do_not_give_the_answer_away(capsys):
    """Hole 6: no formula, algorithm or function to call in a reply; the module's examples show no answer."""
    import sarsp_edu.teaching.exercises as exercises

    assert "50, one colour" not in exercises.__doc__ and 'check("3.4", np.int64(50))' not in exercises.__doc__
    right, message = grade("1.3", CODING["1.3"], lambda residual, nu: (np.asarray(residual) ** 2,
                                                                          outlier_costs(residual, nu)[1]))
    assert not right and "log(2 pi)" not in message and "r^2/2" not in message
    right, message = grade("3.1", CODING["3.1"], lambda X, y, cap: (X[:1], y[:1]))
    assert not right and "dict" not in message and "tuple(x)" not in message
    replies = [m.diagnosis for exercise in CODING.values() for m in exercise.mistakes]
    replies += [exercise.hint for exercise in EXERCISES.values()]
    for reply in replies:
        assert "binomtest" not in reply and "chessboard" not in reply and "X[:, None" not in reply, reply
        assert "ACTION_MOVES" not in reply and " & " not in reply and "keyed by" not in reply, reply
    check("3.4", 49)
    out = capsys.readouterr().out
    assert "not a string" not in out and "chessboard" not in out and "50" not in out


@pytest.mark.parametrize("name, answer, diagnosis", [
    ("6.2", lambda s1, s2, a: prefers(s1, s2, 100.0), "a fixed at 100"),
    ("6.2", lambda s1, s2, a: s1["cost_rate"] < s2["cost_rate"] and (
        s1["mean_reward"] >= s2["mean_reward"] or s1["task_success_rate"] >= s2["task_success_rate"]
        or s1["task_success_rate"] / 100 >= a), "compared as a fraction"),
    ("6.2", lambda s1, s2, a: prefers(s1, s2, a / 100), "both in %"),
    ("2.4", lambda K, y, noise_variance, nu: -tp_log_marginal_likelihood(K, y, noise_variance, nu), "The sign"),
    ("5.1", lambda a, b: round(symmetric_percent_difference(a, b), 1), "rounded (to 1 decimal)"),
    ("2.2", lambda K, K_star, k_star_star, y, noise_variance: tuple(
        np.round(r, 3) for r in gp_posterior(K, K_star, k_star_star, y, noise_variance)), "rounded (to 3 decimals)"),
    ("1.2", lambda x, lam, nu: np.exp(student_t_logpdf(lam * np.asarray(x) ** 2, nu) - student_t_logpdf(x, nu)),
     "the density at lambda x^2"),
    ("1.2", lambda x, lam, nu: np.exp(stats.t.logpdf(lam * np.asarray(x) ** 2, nu) - stats.t.logpdf(x, nu)),
     "the density at lambda x^2"),
])
def test_the_misdiagnoses_seen_get_the_right_diagnosis(name, answer, diagnosis):
    """Hole 6: 6.2 with a = 100 or TSR / 100, 2.4's sign slip, 5.1 rounded, and 1.2's misprint (the tutorial's
    teaching point) each get their own reply."""
    right, message = grade(name, CODING[name], answer)
    assert not right and diagnosis in message, message
    if name == "5.1":
        assert "yours: 69.8" not in message
    if name == "2.4":
        assert "shape matrix" not in message


def test_exercise_5_1_has_one_rule_for_negative_values():
    """Hole 7: rewards are negative; the question says the rule, the key follows it, Table 1's totals unchanged."""
    from sarsp_edu.experiments.metrics import symmetric_percent_difference as package
    from sarsp_edu.teaching.exercises.records import _symmetric

    assert "(|a| + |b|) / 2" in CODING["5.1"].question
    cases = CODING["5.1"].cases(np.random.default_rng(0))
    assert any(case["a"] < 0 and case["b"] < 0 for case in cases) and any(case["a"] * case["b"] < 0 for case in cases)
    assert _symmetric(-28.0, -58.0) == pytest.approx(69.77, abs=0.01) and _symmetric(-3.0, 5.0) == pytest.approx(200)
    for a, b in ((28.0, 58.0), (0.0, 4.0), (5.0, 5.0), (0.0, 0.0)):
        assert _symmetric(a, b) == package(a, b)
    table_1_only = lambda a, b: 0.0 if a == b else abs(a - b) / ((a + b) / 2) * 100  # noqa: E731
    right, message = grade("5.1", CODING["5.1"], table_1_only)
    assert not right and "negative values" in message


def test_exercise_6_1_has_one_rule_where_eq_12_divides_by_zero():
    """Hole 7: 0 where either is 0, as running_metrics keeps it; said once, in the question."""
    from sarsp_edu.experiments.metrics import running_metrics

    assert "0 where either of the two is 0" in CODING["6.1"].question
    assert "either" not in CODING["6.1"].hint
    cases = CODING["6.1"].cases(np.random.default_rng(0))
    undefined = [case for case in cases if case["episode_cost"].sum() > 0
                 and not (case["task_completed"] & (case["episode_cost"] == 0)).any()]
    assert undefined
    for case in undefined:
        rows = running_metrics(np.zeros(len(case["episode_cost"])), *case.values())
        assert rows["cost_rate"].iloc[-1] == 0.0 == CODING["6.1"].reference(**case)[1]

    def as_nan(c, s, done):
        tsr, rate = tsr_and_cost_rate(c, s, done)
        clean = sum(si for ci, si, di in zip(c, s, done) if di and ci == 0)
        return tsr, (math.nan if clean == 0 else rate)

    right, message = grade("6.1", CODING["6.1"], as_nan)
    assert not right and "the question asks for 0" in message


def test_in_a_voila_page_check_prints_nothing(monkeypatch, capsys):
    """A dashboard served by Voila shows no 'Exercise 2.1: not yet' line: check stays silent in its kernel."""
    def rbf(X, Y, amplitude, length_scale):
        raise NotImplementedError

    monkeypatch.setenv("VOILA_KERNEL_ID", "a-kernel-id")
    for exercise, answer in (("2.1", rbf), ("3.4", 49), ("7.1", {}), ("4.1", ...)):
        check(exercise, answer)
    assert capsys.readouterr().out == ""
    monkeypatch.setenv("VOILA_KERNEL_ID", "")  # an empty value is no Voila kernel
    check("2.1", rbf)
    assert capsys.readouterr().out.startswith("Exercise 2.1: not yet. Not written yet")


# -- an independent probe of the grader: answers in styles the exercises did not anticipate -----------------
def test_numbers_held_as_objects_are_numbers_and_an_object_that_raises_is_said():
    """sympy's Floats in an array (dtype object) are right; an object whose conversion raises gets one line."""
    import sympy as sp

    def with_sympy(x, nu):
        return np.array([sp.Float(v) for v in np.ravel(student_t_logpdf(x, nu))], dtype=object).reshape(np.shape(x))

    class Unconvertible:
        def __array__(self, *args, **kwargs):
            raise RuntimeError("no array")

    assert grade("1.1", CODING["1.1"], with_sympy)[0]
    right, message = grade("1.1", CODING["1.1"], lambda x, nu: Unconvertible())
    assert not right and "cannot be read as numbers" in message


def test_two_results_stacked_into_one_array_are_told_to_return_a_tuple():
    right, message = grade("1.3", CODING["1.3"], lambda residual, nu: np.array(outlier_costs(residual, nu)))
    assert not right and "returns one array of shape (2, 5): return them as a tuple" in message


@pytest.mark.parametrize("exercise, wrong, said", [
    ("3.3", lambda position, action, size: move(position, action, 10), "size = 10 gives"),
    ("1.2", lambda x, lam, nu: tail_ratio(x, 5.0, nu), "lam = 5 gives"),
    ("2.2", lambda K, K_star, k_star_star, y, noise_variance: gp_posterior(K, K_star, k_star_star, y, 0.5),
     "noise_variance = 0.5 gives"),
])
def test_a_notebook_value_written_in_is_named(exercise, wrong, said):
    """The notebook's size 10, Figure 1's lambda = 5 and section 2's noise 0.5, written into the code."""
    right, message = grade(exercise, CODING[exercise], wrong)
    assert not right and said in message, message


def test_a_preference_that_is_never_true_is_not_told_to_use_or():
    """An answer false on every case (total cost for the cost rate, equal here) matches no 'and for or'."""
    def by_total_cost(summary_1, summary_2, a):
        return summary_1["total_cost"] < summary_2["total_cost"]

    right, message = grade("6.2", CODING["6.2"], by_total_cost)
    assert not right and "or, not and" not in message


@pytest.mark.parametrize("exercise, answers", [
    ("2.5", ["less than one", "smaller than one", "lower than 1", "below 1.0", "It is below 1.",
             "the factor is below 1"]),
    ("2.6", ["gets narrower", "more narrow", "It gets narrower.", "less wide"]),
    ("1.4", [{"lambda < 1.0": math.inf, "lambda = 1.0": 1, "lambda > 1.0": 0}]),
])
def test_predictions_take_more_spellings(exercise, answers):
    for answer in answers:
        assert is_right(exercise, answer), answer
    assert not is_right(exercise, {"2.5": "not below", "2.6": "gets wider"}.get(exercise, {
        "lambda < 1.0": 0, "lambda = 1.0": 1, "lambda > 1.0": math.inf}))


def test_exercise_4_4_takes_actions_joined_by_and():
    decision = Decision((4, 4), np.array([1.0, 2.0, 0.4, 1.4]), np.array([5.5, 5.6, 5.4, 11.0]),
                        np.array([-3.0, -2.0, -1.0, -2.5]), np.array([1.0] * 4), np.array([False] * 4),
                        np.array([False] * 4), 2, True)
    assert is_right("4.4", "0 and 1", decision=decision) and is_right("4.4", "RIGHT and DOWN", decision=decision)


def test_the_answer_keys_of_the_agent_exercises_are_the_core_itself():
    """4.3 grades against the agent's own corrective condition, 2.2 and 2.3 against its own parts, 3.2 and 3.3
    against the world's own step and cost signal: a change to the agent or the world changes what is graded."""
    from sarsp_edu import SafeGridWorld
    from sarsp_edu.agent.decision import corrects
    from sarsp_edu.agent.parts import gp_posterior, tp_factor

    assert CODING["4.3"].reference is corrects
    assert CODING["2.2"].reference is gp_posterior and CODING["2.3"].reference is tp_factor
    env = SafeGridWorld(seed=3)
    rng = np.random.default_rng(0)
    for _ in range(20):
        env.reset(seed=int(rng.integers(1000)))
        position, action = env.layout().agent, int(rng.integers(4))
        _, distance = env.nearest_unsafe(position)
        assert CODING["3.2"].reference(np.array(position), env.layout().unsafe_states) == distance
        env.step(action)
        assert tuple(CODING["3.3"].reference(np.array(position), action, env.size)) == env.layout().agent


# -- the answer keys themselves: cases that fit the signature, mistakes that are mistakes -------------------------
def _signature_arguments(signature: str) -> list:
    return [name.strip() for name in signature[signature.index("(") + 1: signature.index(")")].split(",")]


@pytest.mark.parametrize("name", sorted(CODING))
def test_every_case_gives_the_signatures_arguments_in_its_order(name):
    """Grading passes a case's values by position (a student may rename the arguments): each case must list the
    signature's arguments in its order, and the key must take them in that order."""
    import inspect

    exercise = CODING[name]
    arguments = _signature_arguments(exercise.signature)
    assert list(inspect.signature(exercise.reference).parameters)[:len(arguments)] == arguments
    for seed in (0, 1, 2):
        for case in exercise.cases(np.random.default_rng(seed)):
            assert list(case) == arguments, (name, list(case))


@pytest.mark.parametrize("name", sorted(CODING))
def test_every_listed_mistake_applies_to_the_exercises_inputs_and_differs_from_the_key(name):
    """A mistake that raises on the inputs, or gives the key's answer on every one, could never be diagnosed.

    One exception: a mistake that solves with K alone (no noise) may meet a K that is singular to the last digit.
    Whether LAPACK's pivot is then exactly zero depends on the processor's BLAS kernels (the seed-2 problem of 30
    points in 2.3 raises with OpenBLAS's Haswell kernels, not with its SkylakeX ones). A student's code that raises
    so gets the exercise's ``on_linalg_error`` advice, and the grader skips a mistake on an input it raises on; so
    such a mistake may raise LinAlgError on some inputs, where the exercise has that advice, and must apply to at
    least one input of every draw."""
    from sarsp_edu.teaching.exercises.grading import same
    from sarsp_edu.teaching.exercises.running import call_copies

    exercise = CODING[name]
    draws = [exercise.cases(np.random.default_rng(seed)) for seed in (0, 1, 2)]
    keys = [[call_copies(exercise.reference, case)[0] for case in cases] for cases in draws]
    for mistake in exercise.mistakes:
        differs = False
        for cases, draw_keys in zip(draws, keys):
            applied = 0
            for case, key in zip(cases, draw_keys):
                try:
                    answer = call_copies(mistake.wrong, case)[0]
                except np.linalg.LinAlgError:
                    if not exercise.on_linalg_error:
                        raise
                    continue
                except ZeroDivisionError:  # a slip written as a student writes it, at a = b = 0 where the key
                    if name != "5.1":      # gives 0: the grader skips a mistake on an input it raises on
                        raise
                    continue
                applied += 1
                differs = differs or not same(answer, key)
            assert applied, f"{name}: the mistake {mistake.diagnosis[:60]!r}... applies to no input of a draw"
        assert differs, f"{name}: the mistake {mistake.diagnosis[:60]!r}... gives the key's answers"
