"""Coding exercises of Tutorials 1 and 2: densities, tails, the kernel, the GP and TP posteriors.

Each reference is the package's own computation (or scipy's, which the
package's tests hold it to); each mistake is the function a student who made
it would write.
"""

from __future__ import annotations

import numpy as np
from scipy import linalg as sla, stats

# the answer keys of 2.2 and 2.3 are the agent's own parts (sarsp_edu.agent.parts): no copy to drift
from ...agent.parts import gp_posterior, tp_factor
from .grading import CodingExercise, Mistake

__all__ = ["MODEL_EXERCISES"]


# -- Tutorial 1: the Student-t density and its tail ------------------------------------------------
def _t_cases(rng):
    return [
        {"x": np.array([0.0]), "nu": 3.0},
        {"x": rng.normal(0, 2, 5), "nu": float(rng.uniform(2.5, 8))},
        {"x": np.concatenate([rng.normal(0, 30, 40), [-1e3, 1e3]]), "nu": 30.0},
        {"x": rng.uniform(-5, 5, 7), "nu": 1.0},
        {"x": rng.normal(0, 3, (3, 4)), "nu": float(rng.uniform(2.5, 8))},  # "x is an array": of any shape
    ]


def _t_logpdf(x, nu):
    return stats.t.logpdf(x, nu)


def _t_kernel_only(x, nu):
    return -(nu + 1) / 2 * np.log1p(x**2 / nu)


def _ratio_cases(rng):
    return [
        {"x": np.array([1.0, 10.0, 100.0]), "lam": 2.0, "nu": 3.0},
        {"x": rng.uniform(0.1, 50, 6), "lam": float(rng.uniform(1.5, 5)), "nu": float(rng.uniform(2.5, 10))},
        {"x": rng.uniform(1, 20, 4), "lam": 0.5, "nu": 1.0},
        {"x": rng.uniform(0.1, 30, (2, 3)), "lam": float(rng.uniform(1.5, 4)), "nu": 4.0},  # an array of any shape
        {"x": np.array([1e3, 1e12]), "lam": 2.0, "nu": 30.0},  # far out, where both densities underflow to 0
    ]


def _tail_ratio(x, lam, nu):
    return np.exp(stats.t.logpdf(lam * np.asarray(x), nu) - stats.t.logpdf(x, nu))


def _cost_cases(rng):
    return [
        {"residual": np.array([0.0, 1.0, 3.0, 10.0, 40.0]), "nu": 3.0},
        {"residual": rng.normal(0, 20, 6), "nu": float(rng.uniform(2.5, 30))},
        {"residual": rng.normal(0, 10, (2, 4)), "nu": 5.0},  # residuals of any shape
    ]


def _outlier_costs(residual, nu):
    return -stats.norm.logpdf(residual), -stats.t.logpdf(residual, nu)


#: said where a log density is off by the same amount at every x
_OFF_BY_A_CONSTANT = "Your values are off by the same amount at every x: a constant term is wrong."


def _outlier_costs_explained() -> str:
    """Exercise 1.3's reply: how many residuals of 1 one residual of 40 costs, computed."""
    one, forty = (float(_outlier_costs(r, 3.0)[0]) for r in (1.0, 40.0))
    return (f"The Gaussian's cost grows like r^2, the Student-t's like log r: one outlier cannot dominate a "
            f"Student-t fit. Under the Gaussian one residual of 40 costs {forty:.1f}, as much as about "
            f"{forty / one:.0f} residuals of 1 ({one:.2f} each), not 1,600: look at the two terms of your "
            f"Gaussian cost to say why.")


# -- Tutorial 2: the kernel, the GP posterior, the TP's factor and likelihood ----------------------
def _rbf(X, Y, amplitude, length_scale):
    from ...models.kernels import RBF

    return RBF(amplitude, length_scale)(X, Y)


def _squared_distances(X, Y):
    return ((np.asarray(X)[:, None, :] - np.asarray(Y)[None, :, :]) ** 2).sum(-1)


def _rbf_cases(rng):
    cases = []
    for n, m, d in ((1, 1, 1), (5, 3, 2), (7, 4, 5), (20, 6, 3)):
        cases.append({"X": rng.normal(0, 1.5, (n, d)), "Y": rng.normal(0, 1.5, (m, d)),
                      "amplitude": float(rng.uniform(0.4, 3)), "length_scale": float(rng.uniform(0.3, 2.5))})
    return cases


def _gp_problem(rng, n, m, d=1):
    """Training and test kernels of a smooth random problem: K (n, n), K_star (m, n), k_star_star (m,)."""
    X, Xs = rng.uniform(0, 5, (n, d)), rng.uniform(0, 5, (m, d))
    amplitude, length_scale = float(rng.uniform(0.5, 2)), float(rng.uniform(0.5, 1.5))
    K, K_star = _rbf(X, X, amplitude, length_scale), _rbf(Xs, X, amplitude, length_scale)
    y = np.sin(X[:, 0]) + 0.1 * rng.standard_normal(n)
    return {"K": K, "K_star": K_star, "k_star_star": np.full(m, amplitude**2), "y": y,
            "noise_variance": float(rng.uniform(0.05, 0.5))}


def _gp_cases(rng):
    varied = _gp_problem(rng, 6, 4)  # each test point's own prior variance (a kernel other than one RBF has them)
    varied["k_star_star"] = varied["k_star_star"] * np.array([1.0, 1.5, 2.0, 3.0])
    # a test point on a training input, with almost no noise: a posterior variance near 1e-8 (a floor on the
    # variance, 1e-4 say, shows there; one below the check's tolerance, kept for stability, does not matter)
    near = _gp_problem(rng, 4, 2)
    near["noise_variance"] = 1e-8
    X = np.array([[0.0], [1.0], [2.0], [3.5]])
    near["K"], near["K_star"] = _rbf(X, X, 1.0, 1.0), _rbf(np.array([[1.0], [2.7]]), X, 1.0, 1.0)
    near["k_star_star"] = np.ones(2)
    return [_gp_problem(rng, 1, 1), _gp_problem(rng, 6, 3), _gp_problem(rng, 25, 9, d=2), varied, near]


def _gp_timing(rng):
    return _gp_problem(rng, 500, 200, d=2)


def _beta(K, y, noise_variance):
    L = np.linalg.cholesky(K + noise_variance * np.eye(len(y)))
    return float(y @ sla.cho_solve((L, True), y))


def _tp_cases(rng):
    cases = []
    for n, nu in ((3, 3.0), (12, float(rng.uniform(2.5, 10))), (30, 50.0), (1, 4.0)):
        problem = _gp_problem(rng, n, 1)
        problem["y"] = problem["y"] * float(rng.uniform(0.5, 4))
        cases.append({"K": problem["K"], "y": problem["y"], "noise_variance": problem["noise_variance"], "nu": nu})
    return cases


def _tp_lml(K, y, noise_variance, nu):
    covariance = K + noise_variance * np.eye(len(y))
    return float(stats.multivariate_t(np.zeros(len(y)), (nu - 2) / nu * covariance, df=nu).logpdf(y))


def _pull_cases(rng):
    return [
        {"residual": np.array([0.0, 0.3, 1.0, 3.0, 30.0, -30.0]), "nu": 3.0, "scale": 0.5},
        {"residual": rng.normal(0, 5, 7), "nu": float(rng.uniform(2.5, 20)), "scale": float(rng.uniform(0.2, 2))},
        {"residual": rng.uniform(-100, 100, 5), "nu": 1.0, "scale": 1.0},
        {"residual": np.array([1e3, -1e4, 1e6, 3e8]), "nu": 3.0, "scale": 1.0},  # far outliers pull, however little
        {"residual": np.array([0.02, 0.05, -0.1, 0.3]), "nu": 3.0, "scale": 0.05},  # a small scale: pulls over 20
        {"residual": rng.normal(0, 4, (3, 2)), "nu": 4.0, "scale": 0.8},  # residuals of any shape
    ]


def _pull(residual, nu, scale):
    from ...models.processes import student_t_log_likelihood

    return student_t_log_likelihood(np.asarray(residual, dtype=float), nu, scale)[1]


MODEL_EXERCISES = {
    "1.1": CodingExercise(
        question="the log density of the standard Student-t distribution with nu degrees of freedom",
        signature="student_t_logpdf(x, nu) -> ndarray like x",
        reference=_t_logpdf,
        cases=_t_cases,
        mistakes=(
            Mistake(_t_kernel_only, "The shape is right but the normalising constant is missing: "
                    "log Gamma((nu + 1)/2) - log Gamma(nu/2) - log(nu pi)/2 belongs in every value."),
            Mistake(lambda x, nu: stats.t.pdf(x, nu), "These are densities; the exercise asks for their logarithm."),
            Mistake(lambda x, nu: _t_logpdf(x, nu) + (1 / 2) * np.log1p(x**2 / nu),
                    "Check the power of (1 + x^2/nu): it is -(nu + 1)/2, not -nu/2."),
            Mistake(lambda x, nu: stats.norm.logpdf(x), "This is the Gaussian's log density, whatever nu is."),
            Mistake(lambda x, nu: _t_logpdf(x, nu) + (nu + 1) / 2 * (np.log1p(x**2 / nu) - np.log1p(x**2)),
                    "Inside the logarithm x^2 is divided by nu."),
            Mistake(lambda x, nu: _t_logpdf(x, nu) + np.log(np.pi) / 2,
                    f"{_OFF_BY_A_CONSTANT} Look at the normalising constant's square root of nu pi."),
            Mistake(lambda x, nu: _t_logpdf(x, nu) - np.log(nu * np.pi) / 2,
                    f"{_OFF_BY_A_CONSTANT} Look at the normalising constant's square root of nu pi: its logarithm "
                    "is halved."),
        ),
        hint="Compare with the density printed at the top of section 1 (sympy's student_t_pdf), term by term.",
        explanation="It matches scipy.stats.t on fresh inputs, from x = 0 to |x| = 1000 and nu from 1 to 30.",
    ),
    "1.2": CodingExercise(
        question="the Student-t tail ratio f(lambda x) / f(x) at finite x",
        signature="tail_ratio(x, lam, nu) -> ndarray like x",
        examples={"lam": 5.0, "nu": (3.0, 6.0)},  # Figure 1's
        reference=_tail_ratio,
        cases=_ratio_cases,
        mistakes=(
            Mistake(lambda x, lam, nu: ((1 + lam * np.asarray(x, float) ** 2 / nu) / (1 + np.asarray(x, float) ** 2
                                                                                     / nu)) ** (-(nu + 1) / 2),
                    "That is eq. 8 as printed (section 2's printed_eq8_limit): lambda x^2 where (lambda x)^2 "
                    "belongs, the density at sqrt(lambda) x; the ratio takes it at lambda x."),
            Mistake(lambda x, lam, nu: np.exp(stats.t.logpdf(lam * np.asarray(x) ** 2, nu) - stats.t.logpdf(x, nu)),
                    "Your numerator is the density at lambda x^2; the ratio takes it at lambda x."),
            Mistake(lambda x, lam, nu: 1 / _tail_ratio(x, lam, nu), "It is upside down: f(lambda x) over f(x)."),
            Mistake(lambda x, lam, nu: np.full(np.shape(x), float(lam) ** (-nu - 1)),
                    "That is the limit as x grows (eq. 8), the same at every x; the exercise asks for the ratio "
                    "at each finite x."),
            Mistake(lambda x, lam, nu: np.log(_tail_ratio(x, lam, nu)), "That is the logarithm of the ratio."),
        ),
        hint="Compare your values with f(lambda x) / f(x) for exercise 1.1's density (its power is -(nu + 1)/2) at a "
             "few x. Far out both densities underflow to 0: there the log densities' difference, exponentiated, "
             "stays finite.",
        explanation="Its values approach lambda**(-nu - 1) as x grows: the regular variation of eq. 8.",
    ),
    "1.3": CodingExercise(
        question="the cost -log f(r) of a residual r under the standard Gaussian and under the Student-t",
        signature="outlier_costs(residual, nu) -> (gaussian_cost, student_t_cost)",
        reference=_outlier_costs,
        cases=_cost_cases,
        mistakes=(
            Mistake(lambda residual, nu: (residual**2 / 2, (nu + 1) / 2 * np.log1p(residual**2 / nu)),
                    "The constants are missing: a cost is all of -log f, constants included."),
            Mistake(lambda residual, nu: _outlier_costs(residual, nu)[::-1], "The two costs are swapped."),
            Mistake(lambda residual, nu: (stats.norm.pdf(residual), stats.t.pdf(residual, nu)),
                    "A cost is minus the log density, not the density."),
            Mistake(lambda residual, nu: (stats.norm.logpdf(residual), stats.t.logpdf(residual, nu)),
                    "Check the sign: a cost is minus the log density, so it grows with the residual."),
        ),
        hint="Check each cost on its own at r = 0 and r = 1, by hand from its density: a cost is all of "
             "-log f(r).",
        explanation=_outlier_costs_explained,
    ),
    "2.1": CodingExercise(
        question="the RBF kernel matrix k(x, x') = amplitude^2 exp(-|x - x'|^2 / (2 length_scale^2))",
        signature="rbf(X, Y, amplitude, length_scale) -> ndarray of shape (len(X), len(Y))",
        examples={"amplitude": 1.5, "length_scale": 0.5},  # section 2's kernel
        reference=_rbf,
        cases=_rbf_cases,
        mistakes=(
            Mistake(lambda X, Y, amplitude, length_scale: amplitude * np.exp(
                -_squared_distances(X, Y) / (2 * length_scale**2)), "The amplitude enters squared."),
            Mistake(lambda X, Y, amplitude, length_scale: amplitude**2 * np.exp(
                -_squared_distances(X, Y) / (2 * length_scale)),
                "Divide the squared distance by 2 l^2: the length scale is squared too."),
            Mistake(lambda X, Y, amplitude, length_scale: amplitude**2 * np.exp(
                -_squared_distances(X, Y) / length_scale**2), "The exponent has a 2 in its denominator."),
            Mistake(lambda X, Y, amplitude, length_scale: amplitude**2 * np.exp(
                -np.sqrt(_squared_distances(X, Y)) / (2 * length_scale**2)),
                "Use the squared distance |x - x'|^2, not the distance."),
            Mistake(lambda X, Y, amplitude, length_scale: amplitude**2 * np.exp(
                -((np.asarray(X)[:, None, :] - np.asarray(Y)[None, :, :]) ** 2)[..., 0] / (2 * length_scale**2)),
                "Sum the squared differences over every feature (column), not the first alone."),
        ),
        hint="Compute one entry by hand, k(X[0], Y[0]), and compare it with your matrix's [0, 0]; then one "
             "with several features.",
        explanation="It matches sarsp_edu.RBF on fresh inputs of 1 to 5 features.",
    ),
    "2.2": CodingExercise(
        question="the GP's posterior mean and latent variance at test points from a Cholesky factor (eqs. 4-5)",
        signature="gp_posterior(K, K_star, k_star_star, y, noise_variance) -> (mean, variance), each of shape (m,)",
        examples={"noise_variance": 0.5},
        reference=gp_posterior,
        cases=_gp_cases,
        mistakes=(
            Mistake(lambda K, K_star, k_star_star, y, noise_variance: (
                K_star @ np.linalg.solve(K, y),
                k_star_star - np.einsum("ij,ji->i", K_star, np.linalg.solve(K, K_star.T))),
                "The noise term is missing: the training covariance is K_y = K + sigma^2 I."),
            Mistake(lambda K, K_star, k_star_star, y, noise_variance: (
                gp_posterior(K, K_star, k_star_star, y, noise_variance)[0],
                gp_posterior(K, K_star, k_star_star, y, noise_variance)[1] + noise_variance),
                "That variance includes the noise: it is a new observation's; eq. 5 asks for the latent "
                "function's."),
            Mistake(lambda K, K_star, k_star_star, y, noise_variance: (
                gp_posterior(K, K_star, k_star_star, y, noise_variance)[0],
                np.sqrt(np.maximum(gp_posterior(K, K_star, k_star_star, y, noise_variance)[1], 0))),
                "The second result is a standard deviation; eq. 5 gives a variance."),
            Mistake(lambda K, K_star, k_star_star, y, noise_variance: (
                gp_posterior(K, K_star, k_star_star, y, noise_variance)[0],
                2 * k_star_star - gp_posterior(K, K_star, k_star_star, y, noise_variance)[1]),
                "Check the sign: the data explain part of the prior variance, so it is subtracted."),
            Mistake(lambda K, K_star, k_star_star, y, noise_variance: gp_posterior(
                K, K_star, k_star_star, y, np.sqrt(noise_variance)),
                "noise_variance is already a variance, sigma^2: add it to K as it is, not its square root."),
            Mistake(lambda K, K_star, k_star_star, y, noise_variance: (
                K_star @ np.linalg.solve(K, y), gp_posterior(K, K_star, k_star_star, y, noise_variance)[1]),
                "The variance is right; the mean needs the noise too: K_y^-1 y, K_y = K + sigma^2 I."),
            Mistake(lambda K, K_star, k_star_star, y, noise_variance: (
                K_star @ ((K + noise_variance * np.eye(len(y))) @ y),
                gp_posterior(K, K_star, k_star_star, y, noise_variance)[1]),
                "The mean multiplies y by the inverse of K_y = K + sigma^2 I (a solve with the Cholesky factor), "
                "not by the matrix itself."),
        ),
        hint="Check each result against its equation: the mean (eq. 4) needs K_y^-1 y, the variance (eq. 5) the "
             "quadratic form of K_star with K_y^-1; both from one Cholesky factor of K_y = K + sigma^2 I "
             "(Rasmussen and Williams, Algorithm 2.1).",
        on_linalg_error="K alone can be numerically singular; the targets' covariance, K_y = K + sigma^2 I, is not.",
        explanation="It matches the package's GaussianProcess on fresh problems (1 to 25 training points).",
        timing=_gp_timing,
    ),
    "2.3": CodingExercise(
        question="the TP's variance factor (nu + beta - 2) / (nu + n - 2), beta = y^T K_y^-1 y, K_y = K + sigma^2 I "
                 "(eq. 6, corrected)",
        signature="tp_variance_factor(K, y, noise_variance, nu) -> float",
        examples={"noise_variance": 0.5, "nu": 3.0},
        reference=tp_factor,
        cases=_tp_cases,
        mistakes=(
            Mistake(lambda K, y, noise_variance, nu: (nu + float(y @ np.linalg.solve(K, y)) - 2) / (nu + len(y) - 2),
                    "beta uses the training covariance with its noise, K_y = K + sigma^2 I."),
            Mistake(lambda K, y, noise_variance, nu: nu / (nu - 2),
                    "That is the prior's factor nu / (nu - 2), before any data; eq. 6 scales by what the data "
                    "say, through beta."),
            Mistake(lambda K, y, noise_variance, nu: (nu + float(y @ y) - 2) / (nu + len(y) - 2),
                    "beta is y^T K_y^-1 y, with the inverse covariance between the two y's."),
            Mistake(lambda K, y, noise_variance, nu: (nu + _beta(K, y, noise_variance) - 2) / (nu + len(y)),
                    "Your denominator is not the question's: compare them term by term."),
            Mistake(lambda K, y, noise_variance, nu: 1 / tp_factor(K, y, noise_variance, nu),
                    "The fraction is upside down."),
            Mistake(lambda K, y, noise_variance, nu: (nu + _beta(K, y, noise_variance)) / (nu + len(y)),
                    "Your numerator and your denominator each miss the same term of the question's: read them again."),
            Mistake(lambda K, y, noise_variance, nu: (nu + _beta(K, y, noise_variance) - 2) / (nu + len(y) - 3),
                    "n is the number of training targets, len(y), not len(y) - 1."),
            Mistake(lambda K, y, noise_variance, nu: (nu + np.sqrt(_beta(K, y, noise_variance)) - 2)
                    / (nu + len(y) - 2), "beta is the quadratic form itself, not its square root."),
            Mistake(lambda K, y, noise_variance, nu: (nu + float(y @ (K + noise_variance * np.eye(len(y))) @ y) - 2)
                    / (nu + len(y) - 2),
                    "beta uses the inverse of K_y = K + sigma^2 I (a solve), not the matrix itself."),
        ),
        hint="The factor is above 1 when beta > n: the data surprise the model and the TP widens its band.",
        on_linalg_error="K alone can be numerically singular; beta uses the targets' covariance, "
                        "K_y = K + sigma^2 I.",
        explanation="The factor depends on the training targets through beta: this is how the TP's variance "
                    "reacts to outliers and the GP's cannot.",
    ),
    "2.4": CodingExercise(
        question="the TP's log marginal likelihood: y ~ multivariate t, covariance K_y = K + sigma^2 I, "
                 "nu degrees of freedom",
        signature="tp_log_marginal_likelihood(K, y, noise_variance, nu) -> float",
        examples={"noise_variance": 0.5, "nu": 3.0},
        reference=_tp_lml,
        cases=_tp_cases,
        mistakes=(
            Mistake(lambda K, y, noise_variance, nu: float(stats.multivariate_t(
                np.zeros(len(y)), K + noise_variance * np.eye(len(y)), df=nu).logpdf(y)),
                "That takes K_y = K + sigma^2 I as the multivariate t's shape matrix; the exercise gives it as the "
                "covariance. How does a multivariate t's covariance follow from its shape and nu?"),
            Mistake(lambda K, y, noise_variance, nu: float(stats.multivariate_normal(
                np.zeros(len(y)), K + noise_variance * np.eye(len(y))).logpdf(y)),
                "That is the GP's (Gaussian) log marginal likelihood."),
            Mistake(lambda K, y, noise_variance, nu: -_tp_lml(K, y, noise_variance, nu),
                    "The sign: that is minus the log marginal likelihood, the loss a fit minimises; the exercise "
                    "asks for log p(y)."),
        ),
        hint="Check it where you can by hand: with one target (n = 1), log p(y) is a univariate Student-t's "
             "log density.",
        # leaving the noise out is said here: K alone is singular on most inputs, so that answer raises
        on_linalg_error="K alone can be numerically singular; the covariance is K_y = K + sigma^2 I.",
        explanation="It matches the package's StudentTProcess.log_marginal_likelihood, the quantity Adam climbs.",
    ),
    "2.7": CodingExercise(
        question="the pull of a point on the function under a Student-t likelihood: d log p(y | f) / d f",
        signature="student_t_pull(residual, nu, scale) -> ndarray like residual",
        reference=_pull,
        cases=_pull_cases,
        mistakes=(
            Mistake(lambda residual, nu, scale: np.asarray(residual) / scale**2,
                    "That is a Gaussian likelihood's pull, r / sigma_t^2: it grows without end, so an outlier "
                    "pulls hardest."),
            Mistake(lambda residual, nu, scale: -_pull(residual, nu, scale),
                    "The sign: a point above the function (r = y - f > 0) pulls it up."),
            Mistake(lambda residual, nu, scale: np.asarray(residual) / (nu * scale**2 + np.asarray(residual) ** 2),
                    "A factor from the exponent is missing."),
            Mistake(lambda residual, nu, scale: (nu + 1) * np.asarray(residual) / (nu + np.asarray(residual) ** 2),
                    "The scale sigma_t is missing: the residual is measured in units of sigma_t."),
            Mistake(lambda residual, nu, scale:
                    (nu + 1) * np.asarray(residual) / (nu * scale + np.asarray(residual) ** 2),
                    "The scale enters as the residual does: check its power."),
            Mistake(lambda residual, nu, scale: nu * np.asarray(residual) / (nu * scale**2 + np.asarray(residual) ** 2),
                    "The factor in front comes from the exponent: check it against the density."),
        ),
        hint="Differentiate -(nu + 1)/2 log(1 + r^2 / (nu sigma_t^2)) with r = y - f; d r / d f = -1.",
        explanation="It grows with the residual up to |r| = sqrt(nu) sigma_t, then falls towards 0: the farther a "
                    "point lies from the function, the less it pulls. That is how this model discounts outliers, which "
                    "the TP's posterior mean does not.",
    ),
}
