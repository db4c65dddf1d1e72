"""Tail decay of the Student-t and Gaussian densities, worked in sympy (paper section 3.3).

Karamata's definition (paper eq. 7): ``f`` is *regularly varying* with index
``p`` if, for every ``lambda > 0``, ``f(lambda x) / f(x) -> lambda**p`` as
``x -> oo``.

- Student-t density (appendix C): the ratio tends to ``lambda**(-1 - nu)``
  (paper eq. 8): regularly varying with index ``-1 - nu``, a power-law tail.
- Gaussian density (appendix D): the ratio is ``exp((1 - lambda**2) x**2 / 2)``,
  which tends to 0 for ``lambda > 1`` (paper eq. 9) and to infinity for
  ``lambda < 1``: no power of ``lambda``, so not regularly varying.
- Gaussian over Student-t (paper eq. 11): tends to 0, so the Student-t has
  heavier tails (Definition 3).

A note on the paper's printed eq. 8 and 9: their numerators write
``lambda x**2`` where ``f(lambda x)`` needs ``(lambda x)**2 = lambda**2 x**2``.
Taken literally, the printed eq. 8 tends to ``lambda**(-(nu + 1) / 2)``, not
``lambda**(-1 - nu)``.  The paper's stated result, its check value
``5**(-4) = 0.0016`` and its Figure 1 all match the correct ratio, which is
what this module computes; :func:`printed_eq8_limit` shows the literal one.

Import cost: this module imports sympy; ``import sarsp_edu`` does not.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from .._internal.validation import check_positive

__all__ = [
    "X",
    "LAMBDA",
    "NU",
    "student_t_pdf",
    "gaussian_pdf",
    "karamata_ratio",
    "student_t_tail_limit",
    "gaussian_tail_limit",
    "gaussian_over_student_t_limit",
    "printed_eq8_limit",
    "derivation_steps",
    "regular_variation_index",
    "compute_tail_ratios",
    "compute_densities",
    "PAPER_CHECK_VALUE",
]

#: the symbols: x > 0, lambda > 0, nu > 0
X = sp.Symbol("x", positive=True)
LAMBDA = sp.Symbol("lambda", positive=True)
NU = sp.Symbol("nu", positive=True)
_C = sp.Symbol("c", positive=True)  # (lambda**2 - 1) / 2 when lambda > 1

#: the paper's check value for nu = 3, lambda = 5: 5**(-1 - 3) = 0.0016
PAPER_CHECK_VALUE = 5.0 ** (-1 - 3)


def student_t_pdf(x=X, nu=NU) -> sp.Expr:
    """Student-t density with ``nu`` degrees of freedom (paper appendix C, eq. C.1).

    Parameters
    ----------
    x, nu : sympy expressions or numbers, default the symbols ``X`` and ``NU``
    """
    return sp.gamma((nu + 1) / 2) / (sp.sqrt(nu * sp.pi) * sp.gamma(nu / 2)) * (1 + x**2 / nu) ** (-(nu + 1) / 2)


def gaussian_pdf(x=X) -> sp.Expr:
    """Standard Gaussian density (paper appendix D, eq. D.1)."""
    return sp.exp(-(x**2) / 2) / sp.sqrt(2 * sp.pi)


def karamata_ratio(density: str, lam=LAMBDA, nu=NU) -> sp.Expr:
    """The ratio ``f(lambda x) / f(x)`` of paper eq. 7, simplified.

    Parameters
    ----------
    density : {"student_t", "gaussian"}
    lam, nu : sympy expressions or numbers

    Examples
    --------
    >>> karamata_ratio("gaussian")
    exp(x**2*(1 - lambda**2)/2)
    """
    if density == "student_t":
        return sp.simplify(student_t_pdf(lam * X, nu) / student_t_pdf(X, nu))
    if density == "gaussian":
        return sp.simplify(gaussian_pdf(lam * X) / gaussian_pdf(X))
    raise ValueError(f"density must be 'student_t' or 'gaussian', got density={density!r}")


def student_t_tail_limit(nu=NU, lam=LAMBDA) -> sp.Expr:
    """``lim_{x -> oo} f(lambda x) / f(x)`` for the Student-t density (paper eq. 8).

    Parameters
    ----------
    nu, lam : sympy expressions or numbers, default the symbols ``NU`` and ``LAMBDA``

    Examples
    --------
    >>> student_t_tail_limit()
    lambda**(-nu - 1)
    >>> student_t_tail_limit(3, 5)
    1/625
    """
    return sp.limit(karamata_ratio("student_t", lam, nu), X, sp.oo)


def gaussian_tail_limit(lam=LAMBDA) -> sp.Expr:
    """``lim_{x -> oo} f(lambda x) / f(x)`` for the Gaussian density (paper eq. 9).

    With a symbolic ``lambda`` the paper's case ``lambda > 1`` is taken, by
    writing ``lambda**2 = 1 + 2c`` with ``c > 0`` (sympy cannot decide the
    sign of ``1 - lambda**2`` on its own).  With a number, the exact limit:
    0 for ``lambda > 1``, 1 for ``lambda = 1``, oo for ``lambda < 1``.

    Examples
    --------
    >>> gaussian_tail_limit(), gaussian_tail_limit(5), gaussian_tail_limit(sp.Rational(1, 2))
    (0, 0, oo)
    """
    ratio = karamata_ratio("gaussian", lam)
    if isinstance(lam, sp.Symbol):
        ratio = ratio.subs(lam**2, 1 + 2 * _C)
    return sp.limit(ratio, X, sp.oo)


def gaussian_over_student_t_limit(nu=NU) -> sp.Expr:
    """``lim_{x -> oo}`` Gaussian density / Student-t density (paper eq. 11): 0, heavier t tails.

    Examples
    --------
    >>> gaussian_over_student_t_limit(), gaussian_over_student_t_limit(30)
    (0, 0)
    """
    return sp.limit(gaussian_pdf(X) / student_t_pdf(X, nu), X, sp.oo)


def printed_eq8_limit(nu=NU, lam=LAMBDA) -> sp.Expr:
    """The limit of paper eq. 8 *as printed*, with ``lambda x**2`` in the numerator.

    Parameters
    ----------
    nu, lam : sympy expressions or numbers, default the symbols ``NU`` and ``LAMBDA``

    Examples
    --------
    >>> printed_eq8_limit()
    lambda**(-nu/2 - 1/2)
    >>> printed_eq8_limit(3, 5)  # not the paper's 0.0016
    1/25
    """
    ratio = sp.simplify(((1 + lam * X**2 / nu) / (1 + X**2 / nu)) ** (-(nu + 1) / 2))
    return sp.limit(ratio, X, sp.oo)


def regular_variation_index(nu) -> float:
    """The index ``p = -1 - nu`` of the Student-t density (paper, after eq. 8)."""
    return -1.0 - check_positive("nu", nu)


def derivation_steps(density: str = "student_t") -> list[tuple[str, sp.Expr]]:
    """The limit of eq. 8 (``"student_t"``), 9 (``"gaussian"``) or 11 (``"ratio"``) worked step by step.

    Returns
    -------
    list of (explanation, sympy expression)
        Each step is computed, not typed: a notebook can show them with
        ``sympy.latex``.
    """
    if density == "student_t":
        ratio = sp.simplify(student_t_pdf(LAMBDA * X) / student_t_pdf(X))
        base = sp.simplify((NU + X**2) / (NU + LAMBDA**2 * X**2))
        base_limit = sp.limit(base, X, sp.oo)
        return [
            ("the Karamata ratio f(lambda x) / f(x)", student_t_pdf(LAMBDA * X) / student_t_pdf(X)),
            ("the normalising constants cancel", ratio),
            ("the base of the power, as x -> oo", base_limit),
            ("the power is continuous, so the limit is", sp.powsimp(base_limit ** ((NU + 1) / 2), force=True)),
            ("which sympy's limit confirms: regularly varying, index -1 - nu", student_t_tail_limit()),
        ]
    if density == "gaussian":
        ratio = karamata_ratio("gaussian")
        return [
            ("the Karamata ratio f(lambda x) / f(x)", gaussian_pdf(LAMBDA * X) / gaussian_pdf(X)),
            ("simplified", ratio),
            ("for lambda > 1 write lambda squared as 1 + 2c, with c > 0", ratio.subs(LAMBDA**2, 1 + 2 * _C)),
            ("so the limit is 0 (and oo for lambda < 1): not a power of lambda", gaussian_tail_limit()),
        ]
    if density == "ratio":
        quotient = sp.simplify(gaussian_pdf(X) / student_t_pdf(X))
        return [
            ("Gaussian density over Student-t density", gaussian_pdf(X) / student_t_pdf(X)),
            ("simplified: a polynomial times exp(-x squared / 2)", quotient),
            ("the exponential wins: the limit is 0, so the Student-t tails are heavier",
             gaussian_over_student_t_limit()),
        ]
    raise ValueError(f"density must be 'student_t', 'gaussian' or 'ratio', got density={density!r}")


# --------------------------------------------------------------------------
# numbers for the figures
# --------------------------------------------------------------------------
def _student_t_ratio(x, nu, lam):
    # ((nu + x^2) / (nu + lam^2 x^2))^((nu + 1) / 2), computed in log space
    return np.exp(0.5 * (nu + 1) * (np.log(nu + x**2) - np.log(nu + lam**2 * x**2)))


def compute_tail_ratios(nus=(3.0, 6.0), lam: float = 5.0, x_t=None, x_gauss=None) -> dict:
    """The curves of the paper's Figure 1: Karamata ratios against x.

    Parameters
    ----------
    nus : sequence of float, default (3, 6)
    lam : float, default 5
    x_t : ndarray, optional
        Where to evaluate the Student-t ratios; default 400 points on [0, 20].
    x_gauss : ndarray, optional
        Where to evaluate the Gaussian ratio; default 400 points on [0, 1].

    Returns
    -------
    dict
        ``"x_t"``, ``"student_t"`` (``{nu: ratio}``), ``"limits"``
        (``{nu: lam**(-1 - nu)}``), ``"x_gauss"``, ``"gaussian"``, ``"lam"``.
    """
    lam = check_positive("lam", lam)
    nus = [check_positive("nu", nu) for nu in nus]
    x_t = np.linspace(0.0, 20.0, 400) if x_t is None else np.asarray(x_t, dtype=float)
    x_gauss = np.linspace(0.0, 1.0, 400) if x_gauss is None else np.asarray(x_gauss, dtype=float)
    return {
        "lam": lam,
        "x_t": x_t,
        "student_t": {nu: _student_t_ratio(x_t, nu, lam) for nu in nus},
        "limits": {nu: lam ** (-1.0 - nu) for nu in nus},
        "x_gauss": x_gauss,
        "gaussian": np.exp(0.5 * (1.0 - lam**2) * x_gauss**2),
    }


def compute_densities(nu: float, x=None) -> dict:
    """Student-t and standard Gaussian densities on a grid (for linear and log plots).

    Parameters
    ----------
    nu : float
        The Student-t's degrees of freedom (> 0).
    x : array-like, optional
        Where to evaluate them; default 801 points on [-8, 8].

    Returns
    -------
    dict with ``"x"``, ``"student_t"``, ``"gaussian"`` and ``"nu"``.
    """
    from scipy import stats

    nu = check_positive("nu", nu)
    x = np.linspace(-8.0, 8.0, 801) if x is None else np.asarray(x, dtype=float)
    return {"x": x, "nu": nu, "student_t": stats.t.pdf(x, df=nu), "gaussian": stats.norm.pdf(x)}
