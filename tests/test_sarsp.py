from __future__ import annotations

import numpy as np
import pytest

from sarsp_edu import RBF, GaussianProcess, ObservationBuffer, SARSPAgent, StudentTProcess
from sarsp_edu.agent.sarsp import choose_action
from sarsp_edu.world.offline import OfflineData, cost_inputs

INF = np.inf


# --------------------------------------------------------------------------
# the decision rule on hand-built predictions
# --------------------------------------------------------------------------
def test_safe_action_with_the_highest_reward():
    action, safe, backup = choose_action(
        mu_cost=np.array([2.0, 0.5, 3.0, 2.0]),   # action 1 predicted in danger (< d)
        var_cost=np.array([0.1, 0.1, 0.9, 0.5]),  # action 2 too uncertain (> 0.8)
        mu_reward=np.array([-5.0, -1.0, -2.0, -3.0]),
        known_unsafe=np.zeros(4, bool), d=1.0, variance_threshold=0.8,
    )
    np.testing.assert_array_equal(safe, [True, False, False, True])
    assert action == 3 and not backup  # -3 beats -5 among the safe ones


def test_thresholds_are_inclusive():
    action, safe, backup = choose_action(
        np.array([1.0, 0.999, 5.0, 5.0]), np.array([0.8, 0.1, 0.8000001, 0.1]),
        np.array([0.0, 10.0, 10.0, -1.0]), np.zeros(4, bool), d=1.0, variance_threshold=0.8,
    )
    np.testing.assert_array_equal(safe, [True, False, False, True])  # cost >= d and var <= sigma^2
    assert action == 0


def test_known_unsafe_pairs_are_overridden():
    known = np.array([False, False, False, True])
    action, safe, backup = choose_action(
        np.array([2.0, 2.0, 2.0, 9.0]), np.array([0.1, 0.1, 0.1, 0.0]),
        np.array([-3.0, -2.0, -4.0, 0.0]), known, d=1.0, variance_threshold=0.8,
    )
    assert not safe[3] and action == 1  # action 3 had the best everything, but is in S_u


def test_backup_takes_the_highest_reward_when_nothing_is_safe():
    known = np.array([True, False, False, False])
    action, safe, backup = choose_action(
        np.array([0.0, 0.0, 5.0, 5.0]), np.array([0.1, 0.1, 2.0, 3.0]),
        np.array([10.0, -2.0, -1.0, -3.0]), known, d=1.0, variance_threshold=0.8,
    )
    assert backup and not safe.any()
    assert action == 2  # action 0's reward is overridden to -inf


def test_ties_go_to_the_lowest_action():
    action, _, backup = choose_action(
        np.full(4, 2.0), np.full(4, 0.1), np.array([-1.0, -2.0, -1.0, -1.0]),
        np.zeros(4, bool), d=1.0, variance_threshold=0.8,
    )
    assert action == 0 and not backup
    action, _, backup = choose_action(
        np.zeros(4), np.full(4, 0.1), np.array([-3.0, -1.0, -1.0, -2.0]),
        np.zeros(4, bool), d=1.0, variance_threshold=0.8,
    )
    assert action == 1 and backup


def test_all_actions_known_unsafe():
    action, safe, backup = choose_action(np.ones(4) * 5, np.zeros(4), np.zeros(4), np.ones(4, bool), 1.0, 0.8)
    assert action == 0 and backup and not safe.any()


# --------------------------------------------------------------------------
# the update rule on a tiny buffer
# --------------------------------------------------------------------------
OBS = np.array([2, 2, 5, 5, 6, 3, 2, 1.0])  # agent (2, 2), goal (5, 5), nearest unsafe (3, 2)


def tiny_data(cost_target_of_right: float) -> OfflineData:
    """Data that say moving RIGHT from (2, 2) leads `cost_target_of_right` from danger."""
    cost = ObservationBuffer(5, max_duplicates=12)
    reward = ObservationBuffer(5, max_duplicates=1)
    for a in range(4):
        target = cost_target_of_right if a == 0 else 3.0
        for _ in range(3):
            cost.add([a, 2, 2, 3, 2], target)
        reward.add([a, 2, 2, 5, 5], -4.0)
    for x in range(5):
        cost.add([1, x, 4, 3, 2], 2.0)
        reward.add([1, x, 4, 5, 5], -3.0)
    return OfflineData(cost=cost, reward=reward, episodes=1, transitions=len(cost), visits=np.zeros((10, 10)))


def tiny_agent(cost_target_of_right: float, model_cls=GaussianProcess, data=None, **kwargs):
    """An agent on `tiny_data` with fixed hyperparameters (so fits are instant)."""
    data = tiny_data(cost_target_of_right) if data is None else data

    def model():
        return model_cls(RBF(2.0, 1.0), noise_variance=0.01, optimizer=None)

    params = dict(k_prior=100, rng=0)  # the prior is the whole (tiny) buffer
    params.update(kwargs)
    return SARSPAgent(model(), model(), data, **params).fit()


def test_no_violation_changes_nothing():
    agent = tiny_agent(5.0)
    before = agent.cost_data.y.copy()
    outcome = agent.learn(OBS, 0, {"cost": 0, "distance_to_unsafe": 1.0}, None)
    assert not outcome.violation and not agent.unsafe_pairs
    np.testing.assert_array_equal(agent.cost_data.y, before)


def test_violation_where_the_model_said_safe_overwrites_and_retrains():
    agent = tiny_agent(5.0)  # the data say RIGHT is 5 from danger: the model predicts >= d
    mu_cost, _, _, _ = agent.predict(OBS)
    assert mu_cost[0] >= 1.0
    action, decision = agent.act(OBS)
    outcome = agent.learn(OBS, 0, {"cost": 1, "distance_to_unsafe": 0.0}, decision)
    assert outcome.violation and outcome.added_to_unsafe and outcome.corrected
    assert outcome.buffer_update == "overwritten"
    np.testing.assert_array_equal(agent.cost_data.y[agent.cost_data.rows_of([0, 2, 2, 3, 2])], [0.0, 0.0, 0.0])
    assert agent.corrective_updates == 1
    assert ((2, 2), 0) in agent.unsafe_pairs
    assert agent.cost_model.predict(np.array([[0, 2, 2, 3, 2.0]]))[0] < 1.0  # retrained on the correction
    # the pair is now overridden in the next decision from that cell
    _, decision = agent.act(OBS)
    assert decision.known_unsafe[0] and not decision.safe[0]


def test_violation_of_an_unseen_input_adds_it():
    agent = tiny_agent(5.0)
    observation = np.array([7, 7, 5, 5, 4, 3, 2, 4.0])  # far from every row: predicted cost ~ 0 < d
    mu_cost, var_cost, _, _ = agent.predict(observation)
    action = int(np.argmin(var_cost))
    assert mu_cost[action] < 1.0  # so only the lowest-variance clause can fire
    rows = len(agent.cost_data)
    outcome = agent.learn(observation, action, {"cost": 1, "distance_to_unsafe": 0.0}, None)
    assert outcome.corrected and outcome.buffer_update == "added"
    assert len(agent.cost_data) == rows + 1
    assert agent.cost_data.count([action, 7, 7, 3, 2]) == 1


def test_violation_where_the_model_said_unsafe_is_not_corrected():
    agent = tiny_agent(0.0)  # the data already say RIGHT leads into danger
    rows, y = len(agent.cost_data), agent.cost_data.y.copy()
    _, decision = agent.act(OBS)
    decision.backup = True  # the lowest-variance clause does not apply to a backup action
    outcome = agent.learn(OBS, 0, {"cost": 1, "distance_to_unsafe": 0.0}, decision)
    assert outcome.violation and outcome.added_to_unsafe and not outcome.corrected
    assert agent.corrective_updates == 0 and len(agent.cost_data) == rows
    np.testing.assert_array_equal(agent.cost_data.y, y)


def test_the_agent_works_on_a_copy_of_the_data():
    data = tiny_data(5.0)
    before = data.cost.y.copy()
    agent = tiny_agent(5.0, data=data)
    agent.learn(OBS, 0, {"cost": 1, "distance_to_unsafe": 0.0}, None)
    assert agent.corrective_updates == 1  # the agent's copy changed ...
    np.testing.assert_array_equal(data.cost.y, before)  # ... the caller's did not


def test_per_step_prior_holds_random_rows_and_every_actions_matches():
    agent = tiny_agent(5.0, k_prior=2, prior_draw="per_step")
    priors = agent.strategic_prior(OBS, "cost")
    assert len(priors) == 4 and all(p is priors[0] for p in priors)  # one set, shared
    matches = [set(agent.cost_data.rows_of(query)) for query in cost_inputs(OBS)]
    assert all(len(m) == 3 for m in matches)
    for m in matches:
        assert m <= set(priors[0])
    assert len(priors[0]) <= 2 + 4 * 3
    agent = tiny_agent(5.0, k_prior=2, n_matching=2, prior_draw="per_step")
    rows = set(agent.strategic_prior(OBS, "cost")[0])
    assert all(len(m & rows) >= 2 for m in matches)


def test_per_action_prior_holds_its_own_matches_only():
    agent = tiny_agent(5.0, k_prior=1, n_matching=10)
    priors = agent.strategic_prior(OBS, "cost")
    for rows, query in zip(priors, cost_inputs(OBS)):
        assert set(agent.cost_data.rows_of(query)) <= set(rows)
        assert len(rows) <= 1 + 3  # one random row plus the three matches


def large_buffer_agent(prior_draw, n=1000, k=100):
    cost = ObservationBuffer(5, max_duplicates=12)
    reward = ObservationBuffer(5, max_duplicates=1)
    for i in range(n):
        cost.add([i % 4, i, 0, 0, 0], 1.0)
        reward.add([i % 4, i, 0, 0, 0], -1.0)
    data = OfflineData(cost=cost, reward=reward, episodes=1, transitions=n, visits=np.zeros((10, 10)))
    def model():
        return GaussianProcess(RBF(1.0, 1.0), noise_variance=0.1, optimizer=None)

    return SARSPAgent(model(), model(), data, k_prior=k, n_matching=0, prior_draw=prior_draw,
                      cost_fit_points=50, reward_fit_points=50, rng=0).fit()


def test_per_action_priors_draw_independent_rows_per_action():
    """Four actions' random rows overlap as independent draws do (k^2 / n), not wholly."""
    n, k = 1000, 100
    agent = large_buffer_agent("per_action", n, k)
    overlaps = []
    for _ in range(100):
        priors = agent.strategic_prior(OBS, "cost")
        assert [len(p) for p in priors] == [k] * 4 and len({id(p) for p in priors}) == 4
        overlaps += [len(np.intersect1d(priors[i], priors[j])) for i in range(4) for j in range(i + 1, 4)]
    # hypergeometric: mean k^2 / n = 10, sd ~ 2.85, so the mean of 600 pairs is 10 +- 0.12
    assert np.mean(overlaps) == pytest.approx(k * k / n, abs=0.6)
    # the reward model draws its own priors too
    assert not np.array_equal(agent.strategic_prior(OBS, "reward")[0], agent.strategic_prior(OBS, "cost")[0])


def test_per_step_prior_is_one_set_for_the_four_actions():
    agent = large_buffer_agent("per_step")
    priors = agent.strategic_prior(OBS, "cost")
    assert all(p is priors[0] for p in priors) and len(priors[0]) == 100
    _, decision = agent.act(OBS)
    assert decision.prior_size[0].tolist() == [100] * 4


def test_per_action_predictions_equal_conditioning_each_prior_on_its_own():
    """The batched prediction is the model conditioned on each action's prior."""
    agent = tiny_agent(5.0, StudentTProcess, k_prior=5)
    state = agent.rng.bit_generator.state
    mu, var, _, _ = agent.predict(OBS)  # the cost model's priors are drawn first
    agent.rng.bit_generator.state = state  # the same priors again
    priors = agent.strategic_prior(OBS, "cost")
    for a, rows in enumerate(priors):
        model = agent.cost_model.condition(agent.cost_data.X[rows], agent.cost_data.y[rows])
        m, v = model.predict(cost_inputs(OBS)[a : a + 1], return_var=True, include_noise=True)
        assert mu[a] == pytest.approx(m[0], rel=1e-9) and var[a] == pytest.approx(v[0], rel=1e-8)


@pytest.mark.parametrize("model_cls", [GaussianProcess, StudentTProcess])
def test_sampled_predictions_estimate_the_closed_form(model_cls):
    exact = tiny_agent(5.0, model_cls)
    sampled = tiny_agent(5.0, model_cls, predictive="sample", n_samples=10_000)  # LIMITS' largest
    mu_e, var_e, mr_e, _ = exact.predict(OBS)
    mu_s, var_s, mr_s, _ = sampled.predict(OBS)
    np.testing.assert_allclose(mu_s, mu_e, atol=5 * np.sqrt(var_e.max() / 10_000) + 1e-9)
    np.testing.assert_allclose(var_s, var_e, rtol=0.1)


def test_decision_record():
    agent = tiny_agent(5.0)
    action, decision = agent.act(OBS)
    assert decision.position == (2, 2) and decision.action == action
    for name in ("mu_cost", "var_cost", "mu_reward", "var_reward", "known_unsafe", "safe"):
        assert getattr(decision, name).shape == (4,)
    assert decision.prior_size[0].tolist() == [len(agent.cost_data)] * 4  # k = 100 exceeds the tiny data
    assert set(decision.scores) == {"mu_cost", "var_cost", "mu_reward"}


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(d=0), "d must be a positive finite number"),
        (dict(variance_threshold=-1), "variance_threshold"),
        (dict(k_prior=0), r"k_prior must be an integer from 1 to 5000 \(.*\), got k_prior=0"),
        (dict(k_prior=10_000), "k_prior must be an integer from 1 to 5000"),
        (dict(n_matching=-1), "n_matching"),
        (dict(predictive="mc"), "predictive must be one of"),
        (dict(n_samples=1), "n_samples"),
        (dict(reward_fit_points=1), "reward_fit_points"),
        (dict(prior_draw="per_episode"), "prior_draw"),
        (dict(retrain=True), "retrain"),
    ],
)
def test_bad_agent_arguments(kwargs, match):
    from sarsp_edu.config import AgentSettings

    with pytest.raises(ValueError, match=match):
        tiny_agent(5.0, **kwargs)
    with pytest.raises(ValueError, match=match):  # the same check, where the settings are made
        AgentSettings(**kwargs)


def test_an_agent_takes_its_settings_as_a_group_or_by_name():
    from sarsp_edu import ExperimentConfig
    from sarsp_edu.config import AgentSettings

    config = ExperimentConfig.from_preset("reference")
    model = GaussianProcess(RBF(2.0, 1.0), noise_variance=0.01, optimizer=None)
    grouped = SARSPAgent(model, model, tiny_data(5.0), config.agent_settings)
    assert grouped.settings == config.agent_settings and grouped.k_prior == 400 and grouped.predictive == "sample"
    changed = SARSPAgent(model, model, tiny_data(5.0), config.agent_settings, k_prior=50)
    assert changed.k_prior == 50 and changed.predictive == "sample"
    assert SARSPAgent(model, model, tiny_data(5.0)).settings == AgentSettings()
    with pytest.raises(ValueError, match=r"AgentSettings has no settings \['nu'\]"):
        SARSPAgent(model, model, tiny_data(5.0), nu=4.0)


def test_an_agents_settings_have_one_source():
    """``agent.k_prior`` is ``agent.settings.k_prior``: a change through either is seen through both, checked."""
    model = GaussianProcess(RBF(2.0, 1.0), noise_variance=0.01, optimizer=None)
    agent = SARSPAgent(model, model, tiny_data(5.0))
    agent.k_prior = 7
    assert agent.settings.k_prior == 7 and "k_prior" not in vars(agent)
    agent.settings = agent.settings.replace(prior_draw="per_step")
    assert agent.prior_draw == "per_step"
    with pytest.raises(ValueError, match="k_prior"):
        agent.k_prior = -1
    assert agent.k_prior == 7
    with pytest.raises(AttributeError, match="no attribute 'k_priors'"):
        agent.k_priors


def test_public_strategic_prior():
    agent = tiny_agent(5.0, k_prior=2)
    priors = agent.strategic_prior(OBS, "cost")
    for a in range(4):
        assert set(agent.cost_data.rows_of([a, 2, 2, 3, 2])) <= set(priors[a])
    assert set(agent.reward_data.rows_of([0, 2, 2, 5, 5])) <= set(agent.strategic_prior(OBS, "reward")[0])
    with pytest.raises(ValueError, match="model must be one of 'cost', 'reward'"):
        agent.strategic_prior(OBS, "value")


# --------------------------------------------------------------------------
# when the corrective update retrains
# --------------------------------------------------------------------------
def violate_right(agent):
    """A violation after RIGHT from (2, 2), observed 0.5 from danger."""
    _, decision = agent.act(OBS)
    return agent.learn(OBS, 0, {"cost": 1, "distance_to_unsafe": 0.5}, decision)


def test_retrain_if_changed_skips_an_update_that_changes_nothing():
    # d = 0.1: a prediction of 0.5 still "says safe", so the update fires twice
    agent = tiny_agent(5.0, d=0.1)  # default retrain="if_changed"
    first = violate_right(agent)
    assert first.corrected and first.buffer_update == "overwritten" and first.retrained
    second = violate_right(agent)  # the stored targets already hold 0.5
    assert second.corrected and second.buffer_update == "unchanged" and not second.retrained
    assert agent.corrective_updates == 2 and agent.retrains == 1


@pytest.mark.parametrize("rule, retrains", [("always", 2), ("never", 0)])
def test_retrain_always_and_never(rule, retrains):
    agent = tiny_agent(5.0, d=0.1, retrain=rule)
    violate_right(agent)
    outcome = violate_right(agent)
    assert outcome.buffer_update == "unchanged" and outcome.retrained == (rule == "always")
    assert agent.corrective_updates == 2 and agent.retrains == retrains


# without, and with a row that makes the buffer's bound too loose for a table
@pytest.mark.parametrize("far", [0, 3000])
def test_the_agents_whole_number_bound_changes_no_prediction(far):
    """Predictions with the per-buffer distance bound are the bits of those that check every distance."""
    agent = large_buffer_agent("per_action")
    if far:
        agent.cost_data.add([0, far, 0, 0, 0], 1.0)
        agent.reward_data.add([0, far, 0, 0, 0], -1.0)
    observation = np.array([3.0, 4.0, 9.0, 9.0, 1.0, 2.0, 0.0, 0.0])
    predictor = agent.prior_predictor
    bound = predictor.whole_bound(agent.cost_data, cost_inputs(observation))
    assert bound is not None and (bound >= 2**20) == bool(far)
    runs = []
    for hinted in (True, False):
        if not hinted:
            predictor.whole_bound = lambda buffer, queries: None
        agent.rng = np.random.default_rng(5)
        runs.append([agent.predict(observation) for _ in range(3)])
    for with_bound, without in zip(*runs):
        for a, b in zip(with_bound, without):
            assert np.array_equal(a, b)
    agent.cost_data.add([1, 1, 1, 1, 1], 0.5)  # a new input: the kept bound is recomputed
    del predictor.whole_bound
    kept = predictor.kept_length(agent.cost_data)
    agent.predict(observation)
    assert predictor.kept_length(agent.cost_data) == kept + 1


@pytest.mark.parametrize("prior_draw", ["per_action", "per_step"])
def test_kernels_gathered_from_the_buffers_table_change_no_prediction(prior_draw):
    """Priors' kernel matrices gathered from a buffer's table are the bits of those built from
    distances, also after the buffer gains an input and after the kernel changes (each rebuilds it)."""
    observation = np.array([3.0, 4.0, 9.0, 9.0, 1.0, 2.0, 0.0, 0.0])
    runs, tabled = [], []
    for table in (True, False):  # with the tables, then without any
        agent = large_buffer_agent(prior_draw)
        agent.prior_predictor.kernel_table = table
        predictions = [agent.predict(observation)]
        agent.cost_data.add([2, 7, 7, 7, 7], 0.25)
        predictions.append(agent.predict(observation))
        agent.cost_model.kernel_ = RBF(1.5, 2.0)
        predictions.append(agent.predict(observation))
        runs.append(predictions)
        kept = agent.prior_predictor.table(agent.cost_model, agent.cost_data, 2.0**20)
        tabled.append(kept is not None and kept.kernel == RBF(1.5, 2.0))
    assert tabled == [True, False]
    for with_table, without in zip(*runs):
        for a, b in zip(with_table, without):
            assert np.array_equal(a, b)


def test_learn_asks_whether_the_action_was_the_backup():
    """The corrective test depends on it, so it is never assumed silently."""
    with pytest.raises(TypeError, match="decision"):
        tiny_agent(5.0).learn(OBS, 0, {"cost": 1, "distance_to_unsafe": 0.0})
