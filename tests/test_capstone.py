"""The agent's plug-in point (``DecisionParts``) and the capstone, exercise 7.1: a student's agent run beside the
package's."""

from __future__ import annotations

import time

import numpy as np
import pytest
from scipy import linalg

from sarsp_edu import (
    RBF,
    ExperimentConfig,
    GaussianProcess,
    SARSPAgent,
    StudentTProcess,
)
from sarsp_edu.agent.decision import choose_action, choose_with_backup, corrects, safe_actions
from sarsp_edu.agent.parts import (
    DecisionParts,
    corrective_applies,
    decide,
    gp_posterior,
    predict_from_parts,
    rbf,
    tp_factor,
)
from sarsp_edu.experiments.experiment import Experiment, experiments_on_one_world
from sarsp_edu.teaching.exercises import CODING, capstone, check, is_right
from sarsp_edu.teaching.live import fitcache
from sarsp_edu.world.offline import ObservationBuffer, OfflineData

#: a run of two episodes on little data (fits of a second): 127 decisions, 12 violations, 6 of them corrected
SMALL = ExperimentConfig(seed=7, episodes=2, offline_episodes=10, optimizer_steps=10)


@pytest.fixture(autouse=True)
def no_fit_cache(monkeypatch):
    monkeypatch.setenv("SARSP_EDU_CACHE", "off")


# the answers of Tutorials 2 and 4, as a student writes them
def student_rbf(X, Y, amplitude, length_scale):
    squared = ((X[:, None, :] - Y[None, :, :]) ** 2).sum(-1)
    return amplitude**2 * np.exp(-squared / (2 * length_scale**2))


def student_posterior(K, K_star, k_star_star, y, noise_variance):
    L = np.linalg.cholesky(K + noise_variance * np.eye(len(y)))
    V = linalg.solve_triangular(L, K_star.T, lower=True)
    return K_star @ linalg.cho_solve((L, True), y), k_star_star - (V**2).sum(axis=0)


def student_factor(K, y, noise_variance, nu):
    beta = y @ np.linalg.solve(K + noise_variance * np.eye(len(y)), y)
    return (nu + beta - 2) / (nu + len(y) - 2)


def student_safe(mu_cost, var_cost, known_unsafe, d, variance_threshold):
    return ~np.asarray(known_unsafe) & (np.asarray(var_cost) <= variance_threshold) & (np.asarray(mu_cost) >= d)


def student_choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold):
    safe = student_safe(mu_cost, var_cost, known_unsafe, d, variance_threshold)
    reward = np.where(known_unsafe, -np.inf, mu_reward)
    if safe.any():
        return int(np.argmax(np.where(safe, reward, -np.inf))), False
    return int(np.argmax(reward)), True


def student_corrects(mu_cost, var_cost, action, d, was_backup):
    return bool(mu_cost[action] >= d or (var_cost[action] <= np.min(var_cost) and not was_backup))


STUDENT = {"kernel": student_rbf, "posterior": student_posterior, "tp_factor": student_factor,
           "safe_set": student_safe, "choose": student_choose, "corrective": student_corrects}


def wrapped_package_parts() -> DecisionParts:
    """The package's own functions behind new function objects: the agent takes its assembled path."""
    def wrap(function):
        return lambda *args: function(*args)
    return DecisionParts(**{name: wrap(getattr(DecisionParts, name)) for name in DecisionParts.names()})


# -- the plug-in point ---------------------------------------------------------------------------------
def test_the_default_parts_are_the_packages_and_keep_the_fast_path():
    parts = DecisionParts()
    assert parts.replaced() == [] and parts.package_models
    assert DecisionParts.of(None) == parts and DecisionParts.of({}) == parts
    assert DecisionParts.of({"choose": student_choose}).replaced() == ["choose"]
    assert DecisionParts.of({"choose": student_choose}).package_models
    assert not DecisionParts.of({"tp_factor": student_factor}).package_models
    assert (parts.kernel, parts.safe_set, parts.choose, parts.corrective) == (rbf, safe_actions,
                                                                             choose_with_backup, corrects)


@pytest.mark.parametrize("parts, error, named", [
    ({"kernal": student_rbf}, ValueError, "kernal"),
    ({"kernel": 3.0}, TypeError, "DecisionParts.kernel must be a function"),
    ([student_rbf], TypeError, "must be a DecisionParts"),
])
def test_parts_that_cannot_be_read_are_refused_by_name(parts, error, named):
    with pytest.raises(error, match=named):
        DecisionParts.of(parts)


@pytest.mark.parametrize("function, reference", [(student_rbf, rbf), (student_posterior, gp_posterior),
                                                 (student_factor, tp_factor)])
def test_the_packages_parts_answer_their_exercises(function, reference):
    name = {rbf: "2.1", gp_posterior: "2.2", tp_factor: "2.3"}[reference]
    assert is_right(name, reference) and is_right(name, function)


def _fitted(model_class, seed, **kwargs):
    rng = np.random.default_rng(seed)
    X = rng.integers(0, 6, (60, 5)).astype(float)
    X[40:] = X[:20]  # repeated inputs, as a strategic prior's matching rows
    y = X[:, 1] - X[:, 3] + 0.1 * rng.standard_normal(60)
    return model_class(RBF(1.3, 1.7), noise_variance=0.2, optimizer=None, **kwargs).fit(X, y), X, y


@pytest.mark.parametrize("model_class, kwargs", [(GaussianProcess, {}), (StudentTProcess, {"noise_convention": "shah"}),
                                                 (StudentTProcess, {"noise_convention": "tfp", "nu": 4.0})])
@pytest.mark.parametrize("queries_per_set", [1, 4])
def test_predictions_assembled_from_parts_are_predict_batchs(model_class, kwargs, queries_per_set):
    model, X, y = _fitted(model_class, 0, **kwargs)
    rng = np.random.default_rng(1)
    sets = [np.sort(rng.choice(len(y), size=size, replace=False)) for size in (12, 30, 45)]
    queries = rng.integers(0, 6, (len(sets), queries_per_set, 5)).astype(float)
    expected = model.predict_batch([X[r] for r in sets], [y[r] for r in sets], queries, include_noise=True)
    for parts in (wrapped_package_parts(), DecisionParts(**STUDENT)):
        got = predict_from_parts(parts, model, [X[r] for r in sets], [y[r] for r in sets], queries,
                                 include_noise=True)
        for g, e in zip(got, expected):
            np.testing.assert_allclose(g, e, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("kernel, said", [
    (lambda X, Y, a, l: np.ones(len(X)), "the kernel part returned a matrix of shape"),
    (lambda X, Y, a, l: "matrix", "the kernel part returned a matrix that is not numbers"),
])
def test_a_part_whose_result_the_agent_cannot_use_is_named(kernel, said):
    model, X, y = _fitted(GaussianProcess, 0)
    with pytest.raises(ValueError, match=said):
        predict_from_parts(DecisionParts(kernel=kernel), model, [X[:10]], [y[:10]], X[None, :1])


def test_the_rule_assembled_from_parts_is_choose_action():
    for case in CODING["4.2"].cases(np.random.default_rng(0)):
        args = list(case.values())
        expected = choose_action(*args)
        for parts in (DecisionParts(), wrapped_package_parts(), DecisionParts(**STUDENT)):
            action, safe, backup = decide(parts, *args)
            assert action == expected[0] and backup == expected[2]
            np.testing.assert_array_equal(safe, expected[1])
    for case in CODING["4.3"].cases(np.random.default_rng(0)):
        assert corrective_applies(DecisionParts(**STUDENT), *case.values()) == corrects(*case.values())
    with pytest.raises(ValueError, match="the choose part must return an action number"):
        decide(DecisionParts(choose=lambda *args: (7, False)), *args)
    with pytest.raises(ValueError, match="the safe_set part must return 4 booleans"):
        decide(DecisionParts(safe_set=lambda *args: [0.5, 1, 1, 1]), *args)


def _agent(parts, seed=3):
    """A TP agent on 300 random rows, its hyperparameters fixed (instant fits), per-step priors of 40 rows."""
    cost, reward = ObservationBuffer(5, max_duplicates=12), ObservationBuffer(5, max_duplicates=1)
    rng = np.random.default_rng(seed)
    for _ in range(300):
        cell, other, action = rng.integers(0, 6, 2), rng.integers(0, 6, 2), int(rng.integers(0, 4))
        cost.add(np.r_[action, cell, other], float(np.hypot(*(cell - other))))
        reward.add(np.r_[action, cell, other], -float(np.hypot(*(cell - other))))
    data = OfflineData(cost=cost, reward=reward, episodes=1, transitions=300, visits=np.zeros((10, 10)))
    models = [StudentTProcess(RBF(2.0, 1.5), noise_variance=0.3, optimizer=None, noise_convention="tfp")
              for _ in range(2)]
    return SARSPAgent(*models, data, parts=parts, rng=seed, k_prior=40, prior_draw="per_step").fit()


def test_an_agent_with_right_parts_takes_the_packages_decisions_and_corrections():
    package, student = _agent(None), _agent(STUDENT)
    assert student.parts.replaced() == list(STUDENT)
    rng = np.random.default_rng(0)
    for _ in range(10):
        observation = np.r_[rng.integers(0, 6, 4), 0, rng.integers(0, 6, 2), 0.0].astype(float)  # cells of the data
        (ours, our_decision), (yours, your_decision) = package.act(observation), student.act(observation)
        assert ours == yours and our_decision.backup == your_decision.backup
        for name in ("mu_cost", "var_cost", "mu_reward", "var_reward"):
            np.testing.assert_allclose(getattr(your_decision, name), getattr(our_decision, name), rtol=1e-7)
        info = {"cost": 1, "distance_to_unsafe": 0.0}
        learned = [agent.learn(observation, ours, info, decision)
                   for agent, decision in ((package, our_decision), (student, your_decision))]
        assert [(o.corrected, o.buffer_update, o.retrained) for o in learned] == [
            (learned[0].corrected, learned[0].buffer_update, learned[0].retrained)] * 2
    assert package.corrective_updates == student.corrective_updates > 0


def test_each_side_of_one_world_takes_its_own_parts(tmp_path, monkeypatch):
    monkeypatch.setenv("SARSP_EDU_CACHE", str(tmp_path))
    with pytest.raises(ValueError, match=r"parts names sides \['third'\]"):
        experiments_on_one_world(SMALL, {"yours": {}}, parts={"third": STUDENT})
    for cached in (False, True, True):  # fitted, stored; then loaded from the cache
        runs = experiments_on_one_world(SMALL, {"yours": {}, "package": {}}, cache=fitcache if cached else None,
                                        parts={"yours": STUDENT})
        assert runs["yours"].agent.parts == DecisionParts(**STUDENT)
        assert runs["package"].agent.parts == DecisionParts()
    assert runs["yours"].loaded_from_cache
    assert Experiment(SMALL, parts=STUDENT).agent.parts.replaced() == list(STUDENT)


# -- the capstone's check --------------------------------------------------------------------------------
def verdict(answer, **context):
    return capstone.run_check(answer, config=SMALL, progress=False, **context)


def test_right_functions_get_the_decisions_they_agreed_on():
    right, message = verdict(STUDENT)
    assert right, message
    assert "took the same 127 decisions in 2 episodes (seed 7, the TP agent)" in message
    assert "after each of the 12 violations (6 corrected)" in message


def test_a_wrong_kernel_is_named_at_the_first_step_with_its_usual_mistake():
    def rbf_l_not_squared(X, Y, amplitude, length_scale):
        return amplitude**2 * np.exp(-((X[:, None, :] - Y[None, :, :]) ** 2).sum(-1) / (2 * length_scale))

    right, message = verdict({**STUDENT, "kernel": rbf_l_not_squared})
    assert not right
    assert message.startswith("Episode 1, step 1 (decision 1 of the run), the agent at ")
    assert "the predicted distances to danger of the four actions differ: yours [" in message
    assert "Your rbf (exercise 2.1) gives other values than the package's on the inputs this step gave it" in message
    assert "the length scale is squared too" in message and "X of shape (" in message


def test_a_corrective_test_with_and_for_or_is_named_after_the_violation_it_decides():
    def corrects_and(mu_cost, var_cost, action, d, was_backup):
        return bool(mu_cost[action] >= d and var_cost[action] <= np.min(var_cost) and not was_backup)

    right, message = verdict({**STUDENT, "corrective": corrects_and})
    assert not right
    assert "after the violation, your agent did not correct the cost model's data, the package's did" in message
    assert "Your corrects (exercise 4.3)" in message and "Either reason is enough: or, not and." in message


def test_a_backup_that_forgets_the_known_unsafe_moves_is_named():
    def choose_forgetting(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold):
        safe = student_safe(mu_cost, var_cost, known_unsafe, d, variance_threshold)
        if safe.any():
            return int(np.argmax(np.where(safe, mu_reward, -np.inf))), False
        return int(np.argmax(mu_reward)), True

    right, message = verdict({**STUDENT, "choose": choose_forgetting})
    assert not right and "(the backup; safe: none)" in message
    assert "Your choose (exercise 4.2)" in message and "known_unsafe = [" in message
    assert "The backup, too, passes over the actions known unsafe" in message


def test_a_function_that_raises_inside_the_agent_is_named_with_its_input():
    def factor_without_noise(K, y, noise_variance, nu):
        return (nu + float(y @ np.linalg.solve(K, y)) - 2) / (nu + len(y) - 2)

    right, message = verdict({**STUDENT, "tp_factor": factor_without_noise})
    assert not right and message.startswith("Episode 1, step 1 ")
    assert "your tp_variance_factor (exercise 2.3) raised LinAlgError" in message
    assert "K of shape (" in message and CODING["2.3"].on_linalg_error in message


def test_a_result_of_the_wrong_shape_stops_the_agent_and_names_the_function():
    right, message = verdict({**STUDENT, "kernel": lambda X, Y, a, l: student_rbf(X, Y, a, l)[:, :1]})
    assert not right and "your agent stopped: ValueError: the kernel part returned a matrix of shape" in message
    assert "Your rbf (exercise 2.1)" in message and "has shape (" in message


def not_written(*args):
    raise NotImplementedError()


@pytest.mark.parametrize("answer, said", [
    ({**STUDENT, "posterior": not_written},
     "Not written yet: your gp_posterior (exercise 2.2) raises NotImplementedError"),
    ({**STUDENT, "safe_set": lambda mu_cost, var_cost, known_unsafe, d, threshold: 1 / 0},
     "Your safe_actions (exercise 4.1) raised ZeroDivisionError: division by zero on mu_cost = ["),
    ({name: STUDENT[name] for name in ("kernel", "posterior", "tp_factor", "safe_set", "choose")},
     "These parts are still the package's own: corrective (exercise 4.3)"),
    (DecisionParts(), "These parts are still the package's own: kernel (exercise 2.1), posterior"),
    ("rbf", "Hand in DecisionParts(kernel=rbf, "),
])
def test_an_answer_that_cannot_run_is_said_before_any_fit(answer, said, monkeypatch):
    monkeypatch.setattr(capstone, "_experiments", lambda *args: pytest.fail("the run started"))
    right, message = verdict(answer)
    assert not right and message.startswith(said), message


def test_a_function_that_never_returns_is_stopped_by_the_time_limit(monkeypatch):
    from sarsp_edu.teaching.exercises import running

    monkeypatch.setattr(running, "TIME_LIMIT", 0.2)

    def endless(mu_cost, var_cost, action, d, was_backup):
        while True:
            time.sleep(0.01)

    right, message = verdict({**STUDENT, "corrective": endless})
    assert not right and "your corrects (exercise 4.3) did not return within 0.2 s" in message.lower()
    assert "is there a loop that never ends?" in message


def test_check_prints_the_verdict_and_is_right_reuses_it(monkeypatch, capsys):
    runs = []

    def counted(answer, config=None, progress=True):
        runs.append(answer)
        return True, "agreed."

    monkeypatch.setattr(capstone, "run_check", counted)
    parts = DecisionParts(**STUDENT)
    check("7.1", parts)
    assert capsys.readouterr().out == "Exercise 7.1: right. agreed.\n"
    assert is_right("7.1", parts) and len(runs) == 1, "is_right reuses the check of the same functions just before"
    check("7.1", parts)
    assert len(runs) == 2, "check always runs"
    assert is_right("7.1", {**STUDENT, "kernel": lambda *args: student_rbf(*args)}) and len(runs) == 3


def test_the_check_shows_its_progress_on_stderr_only(capsys):
    check("7.1", STUDENT, config=SMALL)
    captured = capsys.readouterr()
    assert captured.out.startswith("Exercise 7.1: right. ") and captured.out.count("\n") == 1
    assert "Exercise 7.1" in captured.err and "episode" in captured.err


def test_the_capstones_run_is_the_tp_agent_at_the_package_defaults():
    assert capstone.CONFIG == ExperimentConfig(seed=capstone.CONFIG.seed, episodes=capstone.CONFIG.episodes)
    assert capstone.CONFIG.model == "tp" and capstone.CONFIG.episodes <= 5


def test_a_function_wrong_only_where_the_run_never_goes_is_found_by_its_own_check():
    """A safe set that forgets S_u takes the package's decisions in the run; its exercise's check finds it."""
    def safe_forgetting(mu_cost, var_cost, known_unsafe, d, variance_threshold):
        return (np.asarray(var_cost) <= variance_threshold) & (np.asarray(mu_cost) >= d)

    right, message = verdict({**STUDENT, "safe_set": safe_forgetting})
    assert not right and message.startswith("Your agent took the package's decisions in this run, but")
    assert "your safe_actions (exercise 4.1)" in message and "A pair in S_u (known unsafe) is never safe" in message
    assert 'check("4.1", safe_actions)' in message


def test_a_single_precision_kernel_is_named_where_it_changes_a_decision():
    def rbf_float32(X, Y, amplitude, length_scale):
        return student_rbf(np.float32(X), np.float32(Y), amplitude, length_scale).astype(np.float32)

    right, message = verdict({**STUDENT, "kernel": rbf_float32})
    assert not right and "Your rbf (exercise 2.1) returns single-precision numbers (float32)" in message


def test_a_textbook_posterior_with_an_explicit_inverse_is_right_here_as_in_its_own_exercise():
    """Exercise 2.2 accepts the textbook form with inv(K + s2 I); the capstone, which judges what a decision uses,
    to the rounding an ill-conditioned prior allows, agrees (it may not call right values 'rounded')."""
    from sarsp_edu.teaching.exercises import CODING
    from sarsp_edu.teaching.exercises.grading import grade

    def posterior_by_inverse(K, K_star, k_star_star, y, noise_variance):
        inverse = np.linalg.inv(K + noise_variance * np.eye(len(y)))
        return K_star @ inverse @ y, k_star_star - np.einsum("ij,jk,ik->i", K_star, inverse, K_star)

    assert grade("2.2", CODING["2.2"], posterior_by_inverse)[0]
    right, message = verdict({**STUDENT, "posterior": posterior_by_inverse})
    assert right, message
    assert "Your values are rounded" not in message


def test_a_claim_of_rounding_needs_values_that_are_rounded():
    from sarsp_edu.teaching.exercises import CODING
    from sarsp_edu.teaching.exercises.grading import grade

    reference = CODING["5.1"].reference

    def a_little_off(a, b):  # wrong in the seventh digit, not rounded
        return reference(a, b) * (1 + 3e-7) + 1e-9

    def rounded(a, b):
        return round(reference(a, b), 2)

    assert "Your values are rounded" not in grade("5.1", CODING["5.1"], a_little_off)[1]
    assert "rounded (to 2 decimals)" in grade("5.1", CODING["5.1"], rounded)[1]
