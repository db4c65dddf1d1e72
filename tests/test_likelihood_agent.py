"""The agent with a Student-t likelihood (model="t-likelihood"): its decisions are the Laplace approximation
on each strategic prior, computed independently here; with a very large nu they are the GP agent's; its
setting reads and stores as the others' do."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import optimize, special

from sarsp_edu import ExperimentConfig, GaussianProcess, SARSPAgent, StudentTLikelihoodGP
from sarsp_edu.experiments.experiment import Experiment
from sarsp_edu.models.kernels import RBF
from sarsp_edu.world.offline import cost_inputs, reward_inputs

from .worlds import SIX_BY_SIX

SMALL = ExperimentConfig(**SIX_BY_SIX, model="t-likelihood", episodes=2, n_switch_states=1)


def _dense_laplace_predictive(kernel, nu, scale, X, y, queries):
    """The Laplace predictive of a GP with Student-t noise, written from the definitions: the latent values of
    the distinct inputs, the mode of the exact log posterior by BFGS from the prior mean, the covariance
    (K^-1 + W)^-1 by explicit inverses, a new observation's variance with the noise's s^2 nu / (nu - 2)."""
    U, group = np.unique(X, axis=0, return_inverse=True)
    group = group.reshape(-1)
    K = kernel(U)
    K_inv = np.linalg.inv(K)

    def negative_log_posterior(f):
        r = y - f[group]
        c = nu * scale**2
        log_lik = (special.gammaln((nu + 1) / 2) - special.gammaln(nu / 2) - 0.5 * np.log(np.pi * c)
                   - 0.5 * (nu + 1) * np.log1p(r * r / c))
        gradient = np.bincount(group, (nu + 1) * r / (c + r * r), len(U))
        return -(log_lik.sum() - 0.5 * f @ K_inv @ f), -(gradient - K_inv @ f)

    found = optimize.minimize(negative_log_posterior, np.zeros(len(U)), jac=True, method="BFGS",
                              options={"gtol": 1e-10, "maxiter": 10_000})
    f = found.x
    r = y - f[group]
    c = nu * scale**2
    W = np.bincount(group, (nu + 1) * (c - r * r) / (c + r * r) ** 2, len(U))
    covariance = np.linalg.inv(K_inv + np.diag(W))
    k_star = kernel(queries, U)
    mean = k_star @ K_inv @ f
    var = (kernel.diag(queries) - np.einsum("ij,jk,ik->i", k_star, K_inv, k_star)
           + np.einsum("ij,jk,kl,il->i", k_star, K_inv, covariance @ K_inv, k_star))
    return mean, var + scale**2 * nu / (nu - 2)


@pytest.fixture
def experiment():
    return Experiment(SMALL)


@pytest.mark.parametrize("scale", [None, 0.01])
def test_a_decisions_predictions_are_the_laplace_predictive_of_each_prior_computed_independently(experiment, scale):
    """With the fitted hyperparameters, and with a noise scale of 0.01 (the paper-size fit's order, where most
    rows of a prior are outliers to the start and the search needs its EM steps)."""
    agent = experiment.agent
    assert isinstance(agent.cost_model, StudentTLikelihoodGP) and agent.cost_model.nu == SMALL.likelihood_nu
    if scale is not None:
        agent.cost_model = StudentTLikelihoodGP(RBF(0.9, 0.8), nu=3.0, scale=scale, optimizer=None).fit(
            agent.cost_data.X, agent.cost_data.y)
    observation, _ = experiment.env.reset(seed=3)
    agent.rng = np.random.default_rng(11)
    cost_priors = agent.strategic_prior(observation, "cost")
    reward_priors = agent.strategic_prior(observation, "reward")
    agent.rng = np.random.default_rng(11)  # the same draws again, inside the agent's own prediction
    mu_cost, var_cost, mu_reward, var_reward = agent.predict(observation)
    for model, buffer, priors, queries, (mu, var) in (
            (agent.cost_model, agent.cost_data, cost_priors, cost_inputs(observation), (mu_cost, var_cost)),
            (agent.reward_model, agent.reward_data, reward_priors, reward_inputs(observation),
             (mu_reward, var_reward))):
        for action, rows in enumerate(priors):
            mean, variance = _dense_laplace_predictive(model.kernel_, model.nu, model.scale_, buffer.X[rows],
                                                       buffer.y[rows], queries[action: action + 1])
            np.testing.assert_allclose([mu[action], var[action]], [mean[0], variance[0]], rtol=1e-6, atol=1e-9)


def test_with_a_very_large_nu_the_agent_decides_as_the_gp_agent():
    """Student-t noise with nu = 1e6 is Gaussian noise of variance s^2: with the GP's hyperparameters the two
    agents predict the same numbers (to O(1/nu)) and take the same actions, step after step."""
    from tests.test_sarsp import tiny_data

    data = tiny_data(0.2)
    kernel, noise = RBF(2.0, 1.0), 0.05
    gp = SARSPAgent(GaussianProcess(kernel, noise_variance=noise, optimizer=None),
                    GaussianProcess(kernel, noise_variance=noise, optimizer=None), data, k_prior=8, rng=4).fit()
    t = SARSPAgent(StudentTLikelihoodGP(kernel, nu=1e6, scale=noise**0.5, optimizer=None),
                   StudentTLikelihoodGP(kernel, nu=1e6, scale=noise**0.5, optimizer=None), data, k_prior=8,
                   rng=4).fit()
    for x in range(5):
        observation = np.array([x, 2, 4, 4, 0, 0, 0, 0], dtype=float)
        np.testing.assert_allclose(np.array(t.predict(observation)), np.array(gp.predict(observation)),
                                   rtol=1e-4, atol=1e-5)
        (action_t, decision_t), (action_gp, decision_gp) = t.act(observation), gp.act(observation)
        assert action_t == action_gp and decision_t.backup == decision_gp.backup


def test_its_nu_is_a_setting_of_its_own_checked_and_stored_only_for_it():
    assert SMALL.model_settings.likelihood_nu == 3.0
    with pytest.raises(ValueError, match=r"likelihood_nu must be a number above 2 .*got likelihood_nu=2"):
        ExperimentConfig(model="t-likelihood", likelihood_nu=2)
    with pytest.raises(ValueError, match="likelihood_nu"):
        ExperimentConfig(likelihood_nu=2e6)
    stored = SMALL.replace(likelihood_nu=5.0).to_dict()
    assert stored["likelihood_nu"] == 5.0 and ExperimentConfig.from_dict(stored) == SMALL.replace(likelihood_nu=5.0)
    tp = ExperimentConfig().to_dict()
    assert "likelihood_nu" not in tp and ExperimentConfig.from_dict(tp) == ExperimentConfig()
    assert set(ExperimentConfig(model="t-likelihood").ignored_settings()) >= {"nu", "noise_convention"}
    assert "likelihood_nu" in ExperimentConfig(model="gp").ignored_settings()


def test_the_models_offline_fit_runs_the_agents_adam_with_its_priors(experiment):
    model = experiment.agent.cost_model
    assert (model.optimizer, model.max_iter, model.prior) == ("adam", SMALL.optimizer_steps, "lognormal")
    assert model.n_iter_ == SMALL.optimizer_steps
    assert model.kernel_ != RBF(1.0, 1.0) and model.scale_ != 1.0  # the search moved them
