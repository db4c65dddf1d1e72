"""Coding exercises of Tutorial 5: what one run per configuration can show.

5.2 counts how often two runs of the same configurations name the same
better model (ours against the authors', or two of our seeds); 5.3 writes the
sign test over configurations.  Each reference is the package's own
(``sarsp_edu.paper.authors.agreement_share``, ``sarsp_edu.experiments.tables.sign_test``).
"""

from __future__ import annotations

import numpy as np
from scipy import stats

from .grading import CodingExercise, Mistake

__all__ = ["EVIDENCE_EXERCISES"]


def _agreement(tp_1, gp_1, tp_2, gp_2):
    from ...paper.authors import agreement_share

    return agreement_share(tp_1, gp_1, tp_2, gp_2)


def _agreement_cases(rng):
    cases = [
        {"tp_1": np.array([90.0, 80.0, 70.0]), "gp_1": np.array([85.0, 85.0, 70.0]),
         "tp_2": np.array([95.0, 70.0, 60.0]), "gp_2": np.array([80.0, 75.0, 65.0])},  # a tie in the first run
        {"tp_1": np.array([30.0, 40.0]), "gp_1": np.array([58.0, 57.0]),
         "tp_2": np.array([33.0, 36.0]), "gp_2": np.array([59.0, 60.0])},  # total cost: always the TP
        {"tp_1": np.array([1.0, 2.0]), "gp_1": np.array([1.0, 2.0]),
         "tp_2": np.array([1.0, 2.0]), "gp_2": np.array([1.0, 2.0])},  # ties everywhere: no better model
        {"tp_1": np.array([3.0]), "gp_1": np.array([2.0]), "tp_2": np.array([4.0]), "gp_2": np.array([1.0])},  # one
        # values a hair apart are not tied: a tie is equality (no tolerance)
        {"tp_1": np.array([1.0 + 1e-9, 2.0]), "gp_1": np.array([1.0, 1.0]),
         "tp_2": np.array([3.0, 2.0]), "gp_2": np.array([1.0, 1.0])},
        {"tp_1": np.array([1.0 + 1e-12, 2.0]), "gp_1": np.array([1.0, 1.0]),
         "tp_2": np.array([3.0, 2.0]), "gp_2": np.array([1.0, 1.0])},
    ]
    for n in (9, 45):
        tp_1, tp_2 = rng.normal(90, 5, n).round(1), rng.normal(90, 5, n).round(1)
        cases.append({"tp_1": tp_1, "gp_1": rng.normal(87, 5, n).round(1), "tp_2": tp_2,
                      "gp_2": np.where(rng.random(n) < 0.2, tp_2, rng.normal(87, 5, n).round(1))})
    return cases


def _sign_test(tp, gp):
    from ...experiments.tables import sign_test

    return sign_test(tp, gp)


def _sign_cases(rng):
    cases = [
        {"tp": np.array([3.0, 4.0, 5.0, 6.0, 7.0, 8.0]), "gp": np.ones(6)},  # 6 wins of 6
        {"tp": np.array([1.0, 2.0, 3.0, 4.0]), "gp": np.array([1.0, 1.0, 4.0, 4.0])},  # two ties
        {"tp": np.array([5.0, 5.0]), "gp": np.array([5.0, 5.0])},  # only ties: no evidence either way
        {"tp": np.array([2.0]), "gp": np.array([3.0])},  # one pair
        # values a hair apart are not tied: a tie is equality (no tolerance)
        {"tp": np.array([1.0 + 1e-9, 2.0 + 1e-9, 3.0 + 1e-9, 4.0]), "gp": np.array([1.0, 2.0, 3.0, 1.0])},
    ]
    for n in (12, 45):
        gp = rng.normal(58, 2, n).round()
        cases.append({"tp": np.where(rng.random(n) < 0.15, gp, rng.normal(56, 6, n).round()), "gp": gp})
    return cases


def _sign_with(count):
    """A sign test that counts wins and pairs by ``count(tp, gp) -> (k, n)``: for the mistakes.

    With only ties it gives 1.0, as the right answer does: the mistake shows on the other inputs.
    """
    def wrong(tp, gp):
        tp, gp = np.asarray(tp, float), np.asarray(gp, float)
        if not np.any(tp != gp):
            return 1.0
        k, n = count(tp, gp)
        return float(stats.binomtest(k, n, 0.5).pvalue)
    return wrong


def _one_sided(tp, gp):
    tp, gp = np.asarray(tp, float), np.asarray(gp, float)
    n = int((tp != gp).sum())
    return 1.0 if n == 0 else float(stats.binomtest(int((tp > gp).sum()), n, 0.5, alternative="greater").pvalue)


def _tails(tp, gp):
    """(w, u, the smaller tail's probability) of the sign test, or None when every pair ties."""
    tp, gp = np.asarray(tp, float), np.asarray(gp, float)
    u = int((tp != gp).sum())
    if u == 0:
        return None
    w = int((tp > gp).sum())
    return w, u, float(stats.binom.cdf(min(w, u - w), u, 0.5))


def _smaller_tail_undoubled(tp, gp):
    tails = _tails(tp, gp)
    return 1.0 if tails is None else tails[2]


def _doubled_without_cap(tp, gp):
    tails = _tails(tp, gp)
    return 1.0 if tails is None else 2 * tails[2]


def _normal_approximation(tp, gp):
    tp, gp = np.asarray(tp, float), np.asarray(gp, float)
    n = int((tp != gp).sum())
    if n == 0:
        return 1.0
    z = (int((tp > gp).sum()) - n / 2) / np.sqrt(n / 4)
    return float(2 * stats.norm.sf(abs(z)))


EVIDENCE_EXERCISES = {
    "5.2": CodingExercise(
        question="the share (%) of configurations in which two runs name the same model better",
        signature="agreement_share(tp_1, gp_1, tp_2, gp_2) -> float",
        reference=_agreement,
        cases=_agreement_cases,
        mistakes=(
            Mistake(lambda tp_1, gp_1, tp_2, gp_2: 100.0 * float(np.mean(
                np.sign(np.subtract(tp_1, gp_1)) == np.sign(np.subtract(tp_2, gp_2)))),
                "A tie names no better model: a configuration tied in either run is not an agreement."),
            Mistake(lambda tp_1, gp_1, tp_2, gp_2: _agreement(tp_1, gp_1, tp_2, gp_2) / 100,
                    "The share is asked in %, as the tables print it."),
            Mistake(lambda tp_1, gp_1, tp_2, gp_2: 100.0 * float(np.mean(
                np.sign(np.subtract(tp_1, tp_2)) == np.sign(np.subtract(gp_1, gp_2)))),
                "Compare TP with GP within each run first; then compare the two runs' answers."),
            Mistake(lambda tp_1, gp_1, tp_2, gp_2: _agreement(tp_1, gp_1, tp_2, gp_2) * len(tp_1) / 100,
                    "That is the count of agreeing configurations; the share divides it by all of them, in %."),
        ),
        hint="In each run the better model is the sign of TP - GP; a configuration agrees when both runs name "
             "the same one.",
        explanation="It matches the counts in the table above.",
    ),
    "5.3": CodingExercise(
        question="the two-sided p-value of the sign test of paired TP and GP values, ties dropped",
        signature="sign_test(tp, gp) -> float",
        reference=_sign_test,
        cases=_sign_cases,
        mistakes=(
            Mistake(_sign_with(lambda tp, gp: (int((tp > gp).sum()), len(tp))),
                    "A tie carries no sign: drop the tied pairs before counting."),
            Mistake(_one_sided, "The question is whether either model wins more often than chance: two-sided."),
            Mistake(_smaller_tail_undoubled, "That is one tail, the smaller; two-sided, both tails count: double it "
                                             "(at most 1)."),
            Mistake(_doubled_without_cap, "Doubling the smaller tail can pass 1 when the wins split evenly; a "
                                          "p-value is at most 1."),
            Mistake(_normal_approximation, "With a few dozen pairs use the exact binomial distribution, not its "
                                           "normal approximation."),
            Mistake(lambda tp, gp: float("nan") if not np.any(np.asarray(tp) != np.asarray(gp))
                    else _sign_test(tp, gp),
                    "With every pair tied there is no evidence either way: the p-value is 1."),
        ),
        hint="Count the pairs where TP > GP among those that differ; under 'no difference' that count is "
             "binomial with p = 1/2.",
        explanation="It uses only which model won each configuration, so it needs no assumption about the "
                    "sizes of the differences; the price is less power than the Wilcoxon test.",
    ),
}
