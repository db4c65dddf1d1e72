from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy import stats

from sarsp_edu.models import tails


def test_densities_are_scipys():
    for nu in (1.5, 3.0, 10.0):
        f = sp.lambdify(tails.X, tails.student_t_pdf(tails.X, nu))
        for x in (0.1, 1.0, 7.0):
            assert f(x) == pytest.approx(stats.t.pdf(x, df=nu), rel=1e-12)
    g = sp.lambdify(tails.X, tails.gaussian_pdf())
    assert g(1.3) == pytest.approx(stats.norm.pdf(1.3), rel=1e-12)


def test_the_three_limits():
    assert sp.simplify(tails.student_t_tail_limit() - tails.LAMBDA ** (-1 - tails.NU)) == 0  # eq. 8
    assert tails.gaussian_tail_limit() == 0  # eq. 9, lambda > 1
    assert tails.gaussian_over_student_t_limit() == 0  # eq. 11
    assert tails.gaussian_over_student_t_limit(4) == 0


def test_the_papers_check_value_and_the_printed_form():
    assert tails.student_t_tail_limit(3, 5) == sp.Rational(1, 625)
    assert float(tails.student_t_tail_limit(3, 5)) == pytest.approx(tails.PAPER_CHECK_VALUE) == 0.0016
    assert tails.printed_eq8_limit(3, 5) == sp.Rational(1, 25)  # the misprint gives 0.04
    assert sp.simplify(tails.printed_eq8_limit() - tails.LAMBDA ** (-(tails.NU + 1) / 2)) == 0


def test_gaussian_limit_on_each_side_of_one():
    assert tails.gaussian_tail_limit(sp.Rational(1, 2)) == sp.oo
    assert tails.gaussian_tail_limit(1) == 1
    assert tails.gaussian_tail_limit(3) == 0


def test_derivation_steps_end_at_the_limits():
    assert sp.simplify(tails.derivation_steps("student_t")[-1][1] - tails.LAMBDA ** (-1 - tails.NU)) == 0
    assert tails.derivation_steps("gaussian")[-1][1] == 0
    assert tails.derivation_steps("ratio")[-1][1] == 0
    for kind in ("student_t", "gaussian", "ratio"):
        assert all(isinstance(text, str) and isinstance(expr, sp.Basic) for text, expr in tails.derivation_steps(kind))
    with pytest.raises(ValueError, match="density must be"):
        tails.derivation_steps("cauchy")


def test_numeric_ratios_tend_to_the_limits():
    data = tails.compute_tail_ratios((3.0, 6.0), 5.0, x_t=np.array([0.0, 1.0, 1e4]))
    for nu in (3.0, 6.0):
        assert data["student_t"][nu][0] == 1.0
        assert data["student_t"][nu][-1] == pytest.approx(5.0 ** (-1 - nu), rel=1e-6)
        # the closed form agrees with scipy's densities
        assert data["student_t"][nu][1] == pytest.approx(stats.t.pdf(5.0, nu) / stats.t.pdf(1.0, nu), rel=1e-12)
    assert data["gaussian"][-1] == pytest.approx(np.exp(-12.0))  # exp((1 - 25) x^2 / 2) at x = 1


def test_index_and_bad_arguments():
    assert tails.regular_variation_index(3) == -4.0
    with pytest.raises(ValueError, match="nu must be a positive finite number"):
        tails.regular_variation_index(-1)
    with pytest.raises(ValueError, match="lam"):
        tails.compute_tail_ratios(lam=0)
    with pytest.raises(ValueError, match="density must be"):
        tails.karamata_ratio("laplace")
