"""The grader without false verdicts: every branch of Definition 4 tested, natural wordings read, slips named."""

from __future__ import annotations

import itertools
from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest

from sarsp_edu.teaching.exercises import EXERCISES
from sarsp_edu.teaching.exercises.action_lists import read_actions
from sarsp_edu.teaching.exercises.counts import read_count
from sarsp_edu.teaching.exercises.grading import grade
from sarsp_edu.teaching.exercises.limits import read_limits
from sarsp_edu.teaching.exercises.parsing import (
    NARROWER,
    WIDER,
    Unreadable,
    read_word,
)
from sarsp_edu.teaching.exercises.sides import read_band, read_side


def definition_4(reward, own_rate, against_a, cost=lambda c1, c2: c1 < c2):
    """Definition 4 with each branch given: the key when every argument is the default's."""
    def prefers(s1, s2, a):
        return bool(cost(s1["cost_rate"], s2["cost_rate"]) and (
            reward(s1, s2) or own_rate(s1, s2) or against_a(s1, s2, a)))
    return prefers


KEY = dict(reward=lambda s1, s2: s1["mean_reward"] >= s2["mean_reward"],
           own_rate=lambda s1, s2: s1["task_success_rate"] >= s2["task_success_rate"],
           against_a=lambda s1, s2, a: s1["task_success_rate"] >= a)
#: for each branch, the ways a student gets it wrong: left out, agent 2's value for agent 1's, strict, reversed,
#: another quantity
SLIPS = {
    "reward": [lambda s1, s2: False, lambda s1, s2: s2["mean_reward"] >= s1["mean_reward"],
               lambda s1, s2: s1["mean_reward"] > s2["mean_reward"],
               lambda s1, s2: s1["total_cost"] <= s2["total_cost"],
               lambda s1, s2: s1["total_cost"] >= s2["total_cost"]],
    "own_rate": [lambda s1, s2: False, lambda s1, s2: s2["task_success_rate"] >= s1["task_success_rate"],
                 lambda s1, s2: s1["task_success_rate"] > s2["task_success_rate"]],
    "against_a": [lambda s1, s2, a: False, lambda s1, s2, a: s2["task_success_rate"] >= a,
                  lambda s1, s2, a: max(s1["task_success_rate"], s2["task_success_rate"]) >= a,
                  lambda s1, s2, a: s1["task_success_rate"] > a, lambda s1, s2, a: s1["task_success_rate"] >= a / 100,
                  lambda s1, s2, a: s1["task_success_rate"] >= 100],
    "cost": [lambda c1, c2: c1 <= c2, lambda c1, c2: c1 > c2, lambda c1, c2: True],
}


@pytest.mark.parametrize("branch, index", [(branch, i) for branch, slips in SLIPS.items() for i in range(len(slips))])
def test_every_slip_in_every_branch_of_definition_4_is_caught(branch, index):
    mutant = definition_4(**{**KEY, branch: SLIPS[branch][index]}) if branch != "cost" else \
        definition_4(**KEY, cost=SLIPS["cost"][index])
    right, reply = grade("6.2", EXERCISES["6.2"], mutant)
    assert not right, f"the slip {branch} #{index} was accepted"
    assert grade("6.2", EXERCISES["6.2"], definition_4(**KEY))[0]


def test_the_slips_are_named_for_what_they_are():
    third = definition_4(**{**KEY, "against_a": SLIPS["against_a"][1]})
    assert grade("6.2", EXERCISES["6.2"], third)[1] == (
        "The third branch asks agent 1's own success rate to reach a: agent 2's rate does not make agent 1 "
        "preferred.")
    total = definition_4(**{**KEY, "reward": SLIPS["reward"][3]})
    assert grade("6.2", EXERCISES["6.2"], total)[1] == ("The first branch compares the mean rewards (mean_reward), "
                                                         "not the total costs.")


def test_the_issues_counter_example_is_among_the_cases():
    import numpy as np

    cases = EXERCISES["6.2"].cases(np.random.default_rng(0))
    example = [case for case in cases if case["summary_1"]["task_success_rate"] == 70
               and case["summary_2"]["task_success_rate"] == 90 and case["a"] == 80]
    assert example and not definition_4(**KEY)(example[0]["summary_1"], example[0]["summary_2"], 80.0)


@pytest.mark.parametrize("answer, side", [("decreases", "narrower"), ("goes down", "narrower"),
                                          ("less than before", "narrower"), ("It shrinks.", "narrower"),
                                          ("increases", "wider"), ("it grows", "wider")])
def test_a_direction_said_as_a_change_is_read(answer, side):
    assert read_word(answer, {"wider": WIDER, "narrower": NARROWER}) == side


@pytest.mark.parametrize("answer, side", [("it goes down", "below"), (0.37, "below"), ("0.37", "below"),
                                          ("goes up", "above"), (1.8, "above"), ("Above.", "above")])
def test_a_side_of_1_is_read_from_words_or_a_number(answer, side):
    assert read_side(answer) == side


@pytest.mark.parametrize("answer", ["not wider", "not narrower", "maybe"])
def test_a_negation_or_a_guess_stays_unread(answer):
    with pytest.raises(Unreadable):
        read_word(answer, {"wider": WIDER, "narrower": NARROWER})


def test_numbers_in_words_and_1_itself():
    assert [read_count(word) for word in ("zero", "one", "twelve", "fifty", "Forty-two", "ninety nine")] == \
        [0, 1, 12, 50, 42, 99]
    assert read_limits({"lambda < 1": "infinity", "lambda = 1": "one", "lambda > 1": "zero"}) == \
        {"<1": float("inf"), "=1": 1.0, ">1": 0.0}
    with pytest.raises(Unreadable, match="it is on neither side of 1"):
        read_side(1.0)


def test_a_duplicated_action_is_refused():
    with pytest.raises(Unreadable, match="Your list names action 0 twice"):
        read_actions([0, 0, 1, 2])
    assert read_actions([2, 0]) == [0, 2]


def test_no_two_slips_of_one_branch_share_a_reply_by_accident():
    # each reply of 6.2 names one mistake: two different replies never come from one student's function
    replies = {}
    for branch, slips in SLIPS.items():
        for slip in slips:
            mutant = definition_4(**{**KEY, branch: slip}) if branch != "cost" else definition_4(**KEY, cost=slip)
            replies.setdefault(grade("6.2", EXERCISES["6.2"], mutant)[1], []).append(branch)
    assert all(len(set(branches)) == 1 for reply, branches in replies.items() if "Redo" not in reply), replies
    assert list(itertools.chain(*replies.values()))


def test_a_percent_difference_that_divides_by_zero_at_0_0_is_refused():
    def first_attempt(a, b):
        return abs(a - b) / ((abs(a) + abs(b)) / 2) * 100  # right everywhere but a = b = 0, where the guide gives 0

    right, reply = grade("5.1", EXERCISES["5.1"], first_attempt)
    assert not right and reply == "Your function raised ZeroDivisionError: float division by zero (on a = 0, b = 0)."


@pytest.mark.parametrize("name", ["2.3", "4.1", "5.1"])
def test_no_reply_states_the_formula_it_asks_for(name):
    said = " ".join(mistake.diagnosis for mistake in EXERCISES[name].mistakes)
    for giveaway in ("(nu + beta - 2) / (nu + n - 2)", "nu + n - 2.", "variance <= sigma*^2 and distance >= d",
                     "Divide by the mean", "take the absolute difference", "times 100"):
        assert giveaway not in said, giveaway


# -- a cold pass's findings, each a test -----------------------------------------------------------------
def test_a_move_guarded_one_cell_short_of_a_wall_is_refused():
    from sarsp_edu.world.gridworld.layout import moved

    def one_short(position, action, size):
        x, y = int(position[0]), int(position[1])
        if action == 1 and y >= size - 2:  # DOWN stops a cell early
            return np.array([x, y])
        return np.array(moved(position, action, size))

    assert not grade("3.3", EXERCISES["3.3"], one_short)[0]


def capped_by_rounded_keys(decimals: int):
    """A duplicate cap (exercise 3.1) that keys each input by its rounding to ``decimals``: a slip."""
    def cap_duplicates(X, y, cap):
        kept, counts = [], {}
        for i, x in enumerate(np.asarray(X)):
            key = tuple(np.round(x, decimals))
            if counts.get(key, 0) < cap:
                counts[key] = counts.get(key, 0) + 1
                kept.append(i)
        return np.asarray(X)[kept], np.asarray(y)[kept]
    return cap_duplicates


def test_rows_keyed_by_their_rounded_inputs_are_refused():
    from sarsp_edu.teaching.exercises import CODING

    assert not grade("3.1", CODING["3.1"], capped_by_rounded_keys(0))[0]


def test_a_corrective_test_that_never_corrects_or_rounds_the_variances_is_refused():
    from sarsp_edu.teaching.exercises import CODING

    assert grade("4.3", CODING["4.3"], lambda mu_cost, var_cost, action, d, was_backup: False)[1] == (
        "Your test never corrects the data: after a violation, the question gives two reasons that do.")

    def rounded(mu_cost, var_cost, action, d, was_backup):
        return bool(mu_cost[action] >= d or (round(var_cost[action], 1) <= round(min(var_cost), 1) and not was_backup))

    assert not grade("4.3", CODING["4.3"], rounded)[0]


def test_a_limit_near_but_not_at_its_value_is_wrong():
    from sarsp_edu.teaching.exercises import is_right

    assert is_right("1.4", {"lambda < 1": "infinite", "lambda = 1": "one", "lambda > 1": 0})
    for near in ({"lambda < 1": "inf", "lambda = 1": 1.01, "lambda > 1": 0},
                 {"lambda < 1": "inf", "lambda = 1": 1, "lambda > 1": 1e-300}):
        assert not is_right("1.4", near)


@pytest.mark.parametrize("answer, side", [("lower", "narrower"), ("reduced", "narrower"), ("smaller band", "narrower"),
                                          ("narrower than at nu = 3", "narrower"), ("wider than before", "wider")])
def test_more_wordings_of_a_band_are_read(answer, side):
    assert read_word(answer, {"wider": WIDER, "narrower": NARROWER}) == side


@pytest.mark.parametrize("answer", ['1 > factor', '1/3', 'beta < n'])
def test_more_wordings_of_below_are_read(answer):
    assert read_side(answer) == "below"


def test_a_count_with_its_unit_is_read():
    assert [read_count(a) for a in ("50 cells", "fifty cells", "12 unsafe states")] == [50, 50, 12]


def test_a_cost_rate_alone_is_named_as_such():
    reply = grade("6.2", EXERCISES["6.2"], lambda s1, s2, a: s1["cost_rate"] < s2["cost_rate"])[1]
    assert reply.startswith("A lower cost rate is not enough on its own")


def test_the_pulls_replies_never_spell_the_denominator():
    said = " ".join(mistake.diagnosis for mistake in EXERCISES["2.7"].mistakes)
    assert "nu sigma_t^2 + r^2" not in said and "nu + 1, not nu" not in said


def test_a_second_cold_pass_s_findings():
    from sarsp_edu.teaching.exercises import CODING

    assert read_side("beneath one") == "below"
    assert read_word("not as wide", {"wider": WIDER, "narrower": NARROWER}) == "narrower"
    assert read_word("slimmer", {"wider": WIDER, "narrower": NARROWER}) == "narrower"
    with pytest.raises(Unreadable):
        read_count("5 0")  # two numbers, not 50

    assert not grade("3.1", CODING["3.1"], capped_by_rounded_keys(1))[0]


def test_a_third_cold_pass_s_findings():
    from sarsp_edu.teaching.exercises import is_right

    for answer in ([float("inf"), 1, 0], (float("inf"), 1, 0), "inf, 1, 0",
                   {"lambda < 1": "diverges", "lambda = 1": 1, "lambda > 1": 0}):
        assert is_right("1.4", answer), answer
    assert not is_right("1.4", [0, 1, float("inf")])  # in the question's order: the other way round is wrong
    with pytest.raises(Unreadable):
        read_limits([1, 0])


# -- the fourth cold pass: a tolerance taken for a tie, a formula's 0/0 hiding its mistake, eq. 8 as printed -------
@pytest.mark.parametrize("rtol", [1e-3, 1e-2])
def test_a_tie_within_a_tolerance_is_not_the_most_certain_action(rtol):
    def tolerant(mu_cost, var_cost, action, d, was_backup):
        return bool(mu_cost[action] >= d or (np.isclose(var_cost[action], var_cost.min(), rtol=rtol)
                                             and not was_backup))

    right, reply = grade("4.3", EXERCISES["4.3"], tolerant)
    assert not right and "a tie is equality" in reply


def test_a_tie_within_numpys_default_closeness_is_no_tie_either():
    def with_isclose(mu_cost, var_cost, action, d, was_backup):
        return bool(mu_cost[action] >= d or (np.isclose(var_cost[action], var_cost.min()) and not was_backup))

    assert not grade("4.3", EXERCISES["4.3"], with_isclose)[0]


@pytest.mark.parametrize("name", ["5.2", "5.3"])
def test_a_tie_found_with_a_tolerance_is_refused(name):
    from scipy import stats

    def agreement(tp_1, gp_1, tp_2, gp_2):
        first = np.where(np.isclose(tp_1, gp_1), 0, np.sign(np.subtract(tp_1, gp_1)))
        second = np.where(np.isclose(tp_2, gp_2), 0, np.sign(np.subtract(tp_2, gp_2)))
        return 100.0 * float(np.mean((first == second) & (first != 0)))

    def sign_test(tp, gp):
        differ = ~np.isclose(tp, gp)
        n = int(differ.sum())
        return 1.0 if n == 0 else float(stats.binomtest(int((np.asarray(tp) > gp)[differ].sum()), n).pvalue)

    assert not grade(name, EXERCISES[name], agreement if name == "5.2" else sign_test)[0]


def test_a_backup_over_the_raw_rewards_when_every_action_is_known_unsafe_is_refused():
    def raw(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold):
        from sarsp_edu.agent.parts import DecisionParts

        if known_unsafe.all():
            return int(np.argmax(mu_reward)), True
        return DecisionParts().choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold)

    assert not grade("4.2", EXERCISES["4.2"], raw)[0]


def test_a_wrong_percent_difference_is_named_before_its_division_by_zero_at_0_0():
    right, reply = grade("5.1", EXERCISES["5.1"], lambda a, b: abs(a - b) / abs(b) * 100)
    assert not right and reply.startswith("On a = 28, b = 58, it gives other values than the package (yours: 51.7241).")
    assert reply.endswith("Your function raised ZeroDivisionError: float division by zero (on a = 0, b = 0).")
    right, reply = grade("5.1", EXERCISES["5.1"], lambda a, b: 200 * abs(a - b) / abs(a + b))
    assert not right and reply.startswith("Right while a and b share a sign")


def test_eq_8_as_printed_is_named_as_printed():
    def printed(x, lam, nu):
        x = np.asarray(x, dtype=float)
        return ((1 + lam * x**2 / nu) / (1 + x**2 / nu)) ** (-(nu + 1) / 2)

    right, reply = grade("1.2", EXERCISES["1.2"], printed)
    assert not right and reply.startswith("That is eq. 8 as printed")


def test_capstone_values_that_differ_are_shown_to_the_digits_where_they_differ():
    from sarsp_edu.teaching.exercises.parting import _apart

    yours, ours = _apart([0.16412345, 0.0654], [0.16412349, 0.0654])
    assert yours != ours and yours == "[0.16412345, 0.0654]"
    assert _apart([1.0, 2.0], [1.5, 2.0]) == ("[1, 2]", "[1.5, 2]")


# -- the fifth cold pass: a tolerance at the knife edges, wordings with an aside, the capstone's one input ------
TOLERANT = {
    "4.1": lambda m, v, k, d, t: ((v <= t) | np.isclose(v, t)) & ((m >= d) | np.isclose(m, d)) & ~k,
    "6.3": lambda m, v, d, thresholds: np.array([100.0 * np.mean(~(((v <= t) | np.isclose(v, t))
                                                                    & (m >= d - 1e-3)).any(axis=1))
                                                 for t in thresholds]),
}


@pytest.mark.parametrize("name", sorted(TOLERANT))
def test_a_safe_set_with_a_tolerance_at_its_thresholds_is_refused(name):
    right, reply = grade(name, EXERCISES[name], TOLERANT[name])
    assert not right, reply


def test_rounding_to_three_decimals_or_a_slack_below_d_is_refused_where_the_rule_is_exact():
    def rounded(mu_cost, var_cost, known_unsafe, d, variance_threshold):
        return (np.round(var_cost, 3) <= variance_threshold) & (np.round(mu_cost, 3) >= d) & ~known_unsafe

    def slack(mu_cost, var_cost, action, d, was_backup):
        return bool(mu_cost[action] >= d - 1e-6 or (var_cost[action] == var_cost.min() and not was_backup))

    right, reply = grade("4.1", EXERCISES["4.1"], rounded)
    assert not right and "0.9999999" in reply  # a hair below d, shown as it is (not rounded to 1)
    assert not grade("4.3", EXERCISES["4.3"], slack)[0]


@pytest.mark.parametrize("answer, side", [('falls below 1', 'below'), ('stays under one', 'below')])
def test_a_side_said_with_a_verb_or_an_aside_is_read(answer, side):
    assert read_side(answer) == side


@pytest.mark.parametrize("answer, word", [('the band shrinks as nu grows', NARROWER),
                                          ('less wide than at nu = 3', NARROWER)])
def test_a_direction_said_with_an_aside_or_a_comparison_is_read(answer, word):
    assert read_word(answer, {"wider": WIDER, "narrower": NARROWER}) == (
        "narrower" if word is NARROWER else "wider")


@pytest.mark.parametrize("answer", ["narrower, but wider at first", "not wider", "narrower (not narrower)"])
def test_an_aside_that_negates_or_disagrees_is_still_refused_not_flipped(answer):
    with pytest.raises(Unreadable):
        read_word(answer, {"wider": WIDER, "narrower": NARROWER})


def test_the_capstone_names_a_parts_mistake_from_its_exercises_check_not_from_one_input():
    from sarsp_edu.agent.parts import DecisionParts
    from sarsp_edu.teaching.exercises.parting import _culprit

    def upside_down(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold):
        action, backup = DecisionParts().choose(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold)
        return action, not backup

    case = dict(mu_cost=np.array([0.2, 0.5, 0.9, 0.1]), var_cost=np.array([0.1, 0.2, 0.3, 0.05]),
                mu_reward=np.array([-2.0, -2.0, -4.0, -1.0]), known_unsafe=np.array([False, True, False, False]),
                d=1.0, variance_threshold=0.8)
    said = _culprit([("choose", case, upside_down(*case.values()))], DecisionParts(choose=upside_down))
    assert "the second value is upside down" in said and "The reward decides only among" not in said


# -- the sixth cold pass: an aside in brackets that disagrees, a count said in a sentence ------------------------
@pytest.mark.parametrize("answer", ["narrower (no, wider)", "narrower (the band widens)", "narrower (or wider)"])
def test_an_aside_in_brackets_that_negates_or_disagrees_is_refused(answer):
    with pytest.raises(Unreadable):
        read_word(answer, {"wider": WIDER, "narrower": NARROWER})


@pytest.mark.parametrize("answer", ["below (not below)", "below (it goes up)"])
def test_a_side_with_a_disagreeing_aside_is_refused(answer):
    with pytest.raises(Unreadable):
        read_side(answer)


@pytest.mark.parametrize("answer", ["narrower at nu = 30", "the band is narrower at nu = 30",
                                    "it decreases toward the GP band"])
def test_a_direction_at_the_questions_own_nu_is_read(answer):
    assert read_word(answer, {"wider": WIDER, "narrower": NARROWER}) == "narrower"


@pytest.mark.parametrize("answer", ['It is 50', 'the answer is 50', '50 unsafe cells'])
def test_a_count_said_in_a_sentence_is_read(answer):
    assert read_count(answer) == 50


@pytest.mark.parametrize("answer", ["50 (or 25)", "50 (not 50)", "50 (half? no, a quarter: 25)"])
def test_a_count_with_a_doubting_aside_is_refused(answer):
    with pytest.raises(Unreadable):
        read_count(answer)


# -- the seventh cold pass: a number beside the word on the other side, a count in a longer sentence -------------
@pytest.mark.parametrize("answer", ["below 1 (about 3.3)", "below, about 3.3", "above 1 (about 0.37)"])
def test_a_side_whose_number_says_the_other_side_is_refused(answer):
    with pytest.raises(Unreadable):
        read_side(answer)


@pytest.mark.parametrize("answer", ['The grid can hold 50 unsafe cells.', 'at most 50', '50 unsafe cells at most',
                                    '50 of the 100 cells'])
def test_a_count_in_a_longer_sentence_is_read(answer):
    assert read_count(answer) == 50


@pytest.mark.parametrize("answer", ["50 or 51", "not 49", "0.5 of 100"])
def test_a_sentence_with_a_doubt_or_no_whole_count_is_refused(answer):
    with pytest.raises(Unreadable):
        read_count(answer)


# -- the eighth cold pass: rewards a hair apart, a side said with 'will be' or a reason -------------------------
def test_rewards_rounded_or_compared_with_a_tolerance_are_refused():
    from sarsp_edu.agent.parts import DecisionParts

    choose = DecisionParts().choose
    for slip in (lambda m, v, r, k, d, t: choose(m, v, np.round(r, 6), k, d, t),
                 lambda m, v, r, k, d, t: choose(m, v, np.where(np.isclose(r, np.max(r)), np.max(r), r), k, d, t)):
        assert not grade("4.2", EXERCISES["4.2"], slip)[0]


@pytest.mark.parametrize("answer", ['it comes out below 1', 'it will be below 1', 'it is going to be below 1'])
def test_a_side_said_in_the_future_or_with_its_reason_is_read(answer):
    assert read_side(answer) == "below"


def test_an_as_inside_a_comparison_is_no_clause_break():
    options = {"wider": WIDER, "narrower": NARROWER}
    assert read_word("not as wide", options) == "narrower" and read_word("it will be narrower", options) == "narrower"


# -- the ninth cold pass: tolerances as tight as math.isclose's, numbers that contradict, number words in a sentence
def test_a_tolerance_as_tight_as_math_isclose_is_refused_where_the_rule_is_exact():
    import math

    def close(a, b):
        return math.isclose(a, b)

    safe = lambda m, v, k, d, t: np.array([(vv <= t or close(vv, t)) and (mm >= d or close(mm, d)) and not kk  # noqa: E731
                                           for mm, vv, kk in zip(m, v, k)])
    tie = lambda m, v, a, d, b: bool(m[a] >= d or (np.isclose(v[a], v.min(), rtol=1e-6, atol=0) and not b))  # noqa: E731
    assert not grade("4.1", EXERCISES["4.1"], safe)[0]
    assert not grade("4.3", EXERCISES["4.3"], tie)[0]


def test_a_ratio_of_densities_that_underflows_far_out_is_refused():
    from scipy import stats

    right, reply = grade("1.2", EXERCISES["1.2"], lambda x, lam, nu: stats.t.pdf(lam * np.asarray(x), nu)
                         / stats.t.pdf(x, nu))
    assert not right


@pytest.mark.parametrize("answer", ["It can hold fifty", "it holds fifty"])
def test_a_number_word_in_a_sentence_is_read(answer):
    assert read_count(answer) == 50


@pytest.mark.parametrize("answer", ["50, 25", "50 (or 25)", "50%"])
def test_a_count_beside_another_count_or_as_a_share_is_refused(answer):
    with pytest.raises(Unreadable):
        read_count(answer)


# -- the tenth cold pass: near-duplicates, actions said in a sentence, a doubt said as 'maybe' --------------------
def _capped(decimals):
    """Exercise 3.1 written with a loop; its inputs compared as they are, or rounded to ``decimals``."""
    def cap_duplicates(X, y, cap):
        X = np.asarray(X, dtype=float)
        kept_X, kept_y, counts = [], [], {}
        for row, key, target in zip(X, X if decimals is None else np.round(X, decimals), y):
            if counts.get(tuple(key), 0) < cap:
                counts[tuple(key)] = counts.get(tuple(key), 0) + 1
                kept_X.append(row)
                kept_y.append(target)
        return np.array(kept_X).reshape(-1, X.shape[1]), np.array(kept_y)
    return cap_duplicates


def test_duplicates_found_by_rounding_the_inputs_are_refused():
    assert grade("3.1", EXERCISES["3.1"], _capped(None))[0]  # the same loop, comparing exactly, is right
    assert not grade("3.1", EXERCISES["3.1"], _capped(6))[0]


@pytest.mark.parametrize("answer", ['actions 0, 1 and 2', 'RIGHT, DOWN, LEFT are safe', 'RIGHT (0), DOWN (1), LEFT (2)',
                                    'the safe actions are 0, 1 and 2'])
def test_actions_said_in_a_sentence_are_read(answer):
    assert read_actions(answer) == [0, 1, 2]


@pytest.mark.parametrize("answer", ["0, 1, 2 or 3", "0, 1, 2 (or 3)", "0, 1, 2?"])
def test_actions_with_a_doubt_are_refused(answer):
    with pytest.raises(Unreadable):
        read_actions(answer)


def test_maybe_is_a_doubt():
    with pytest.raises(Unreadable):
        read_count("maybe 50")
    with pytest.raises(Unreadable, match="a count is exact"):  # since the twenty-fourth pass: a hedge
        read_count("about 50")


# -- the eleventh cold pass: a contradicting reason said with another verb, a count of actions in brackets --------
# (since the fourteenth: a reason is not graded, only a restated side is refused; the verdict says so)


def test_a_direction_whose_reason_climbs_is_refused():
    with pytest.raises(Unreadable):
        read_word("narrower, because the factor climbs", {"wider": WIDER, "narrower": NARROWER})


def test_a_count_of_the_actions_in_brackets_is_not_an_action():
    assert read_actions("0, 1 and 2 (three actions)") == [0, 1, 2]


# -- the twelfth cold pass: each test point's own prior variance, beta against n as a reason, a hedged limit -------
def test_a_posterior_that_takes_one_prior_variance_for_every_test_point_is_refused():
    from sarsp_edu.agent.parts import gp_posterior

    def first_only(K, K_star, k_star_star, y, noise_variance):
        mean, variance = gp_posterior(K, K_star, k_star_star, y, noise_variance)
        return mean, variance - np.asarray(k_star_star) + np.asarray(k_star_star)[0]

    assert grade("2.2", EXERCISES["2.2"], gp_posterior)[0]
    assert not grade("2.2", EXERCISES["2.2"], first_only)[0]


def test_a_hedged_limit_is_refused_since_the_nineteenth_pass():  # the limits are exact numbers
    with pytest.raises(Unreadable, match="a limit is exact"):
        read_limits({"lambda < 1": "inf", "lambda = 1": "about 1", "lambda > 1": 0})


# -- the thirteenth cold pass: a count's bound or estimate, the smallest posterior variance, one float past an
# edge, rewards of either sign; reasons that name the premise, a working, names beside numbers -----------------
@pytest.mark.parametrize("answer", ["less than 50", "more than 50", "over 50", "under 50", "fewer than 50",
                                    "below 50", "above 50", "just under 50", "slightly less than 50",
                                    "a bit more than 50", "more than fifty", "nearly 50", "almost 50",
                                    "50 is too many", "50 percent", "fifty percent", "50 per cent", "at least 50",
                                    "50+", "50 = 10*10/4"])
def test_a_bound_an_estimate_or_a_share_is_not_the_count(answer):
    right, reply = is_right_3_4(answer)
    assert not right, reply


@pytest.mark.parametrize("answer", ['50 = 10*10/2', '10 * 10 / 2 = 50', 'at most 50'])
def test_a_count_with_its_working_or_the_grids_size_is_read(answer):
    assert read_count(answer) == 50


def is_right_3_4(answer):
    from sarsp_edu.teaching.exercises import _verdict

    return _verdict("3.4", answer)


@pytest.mark.parametrize("answer, actions", [('only 0', [0]), ('0 (RIGHT)', [0]), ('just RIGHT', [0]),
                                             ('all but 3', [0, 1, 2]), ('everything except UP', [0, 1, 2]),
                                             ('0 (RIGHT), 1 (DOWN), 2 (LEFT)', [0, 1, 2]),
                                             ('1 (DOWN), 0, 2', [0, 1, 2])])
def test_actions_said_with_their_names_or_as_all_but_some_are_read(answer, actions):
    assert read_actions(answer) == actions


@pytest.mark.parametrize("answer, said", [('0 (DOWN)', 'names action 0 as DOWN')])
def test_actions_whose_names_or_clauses_disagree_are_refused_naming_why(answer, said):
    with pytest.raises(Unreadable, match=said):
        read_actions(answer)


def test_a_floor_on_the_posterior_variance_is_refused():
    from sarsp_edu.agent.parts import gp_posterior

    def floored(K, K_star, k_star_star, y, noise_variance):
        mean, variance = gp_posterior(K, K_star, k_star_star, y, noise_variance)
        return mean, np.maximum(variance, 0.01)

    assert not grade("2.2", EXERCISES["2.2"], floored)[0]


@pytest.mark.parametrize("exercise", ["4.1", "4.2"])
def test_a_tolerance_of_1e_13_at_the_knife_edges_is_refused(exercise):
    from sarsp_edu.agent.sarsp import choose_action

    def slack(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold):
        return choose_action(mu_cost, var_cost, mu_reward, known_unsafe, d - 1e-13, variance_threshold + 1e-13)

    if exercise == "4.1":
        def answer(mu_cost, var_cost, known_unsafe, d, variance_threshold):
            return ~known_unsafe & (mu_cost >= d - 1e-13) & (var_cost <= variance_threshold + 1e-13)
    else:
        answer = slack
    assert not grade(exercise, EXERCISES[exercise], answer)[0]


def test_definition_4_with_the_rewards_sizes_in_place_of_the_rewards_is_refused():
    def sizes(s1, s2, a):
        return bool(s1["cost_rate"] < s2["cost_rate"] and (
            abs(s1["mean_reward"]) <= abs(s2["mean_reward"]) or s1["task_success_rate"] >= s2["task_success_rate"]
            or s1["task_success_rate"] >= a))

    assert not grade("6.2", EXERCISES["6.2"], sizes)[0]


# -- the fourteenth cold pass: the prediction graded, not its reason; counts with their working; all or none -------


@pytest.mark.parametrize("answer", ['A narrower band.', 'the band will shrink'])
def test_more_wordings_of_narrower_are_read(answer):
    assert read_word(answer, {"wider": WIDER, "narrower": NARROWER}) == "narrower"


@pytest.mark.parametrize("answer", ['up to 50', 'no more than 50', 'a maximum of 50', '5 x 10', '10*10/2'])
def test_a_count_with_its_working_a_bound_of_the_question_or_what_it_is_not_is_read(answer):
    assert read_count(answer) == 50


def test_a_count_refused_is_quoted_as_the_student_wrote_it():
    with pytest.raises(Unreadable, match="Could not read '5 x 10 cells, roughly' as a whole number"):
        read_count("5 x 10 cells, roughly")


@pytest.mark.parametrize("answer, actions", [('all', [0, 1, 2, 3]), ('all four', [0, 1, 2, 3]),
                                             ('every action', [0, 1, 2, 3]), ('none of them', []),
                                             ('Actions 0 (RIGHT) and 2 (LEFT) are safe.', [0, 2]),
                                             ('0-3', [0, 1, 2, 3])])
def test_all_none_and_lists_with_what_is_not_safe_are_read(answer, actions):
    assert read_actions(answer) == actions


def test_a_floor_of_1e_4_on_the_posterior_variance_is_refused_and_one_of_1e_9_is_not():
    from sarsp_edu.agent.parts import gp_posterior

    def floored(floor):
        def posterior(K, K_star, k_star_star, y, noise_variance):
            mean, variance = gp_posterior(K, K_star, k_star_star, y, noise_variance)
            return mean, np.maximum(variance, floor)
        return posterior

    assert not grade("2.2", EXERCISES["2.2"], floored(1e-4))[0]
    assert grade("2.2", EXERCISES["2.2"], floored(1e-9))[0]  # below the check's tolerance: kept for stability


# -- the fifteenth cold pass: a prediction is read alone --------------------------------------------------------
#: answers that earlier passes read with their reasons, asides or workings: each reading of a reason accepted
#: some wrong predictions and refused some right ones, so a prediction is now read alone, and these are refused
#: with a reply that asks for the prediction alone
SAID_MORE = [('read_count', '50 (half of 100, a checkerboard)'),
             ('read_count', 'half of 100, so 50'), ('read_count', '50 — one colour of a 10 x 10 chessboard'),
             ('read_count', '50, i.e. half of a 10x10 grid'), ('read_count', '50 (5 in each of the 10 rows)'),
             ('read_count', '50: 5 per row, 10 rows'),
             ('read_count', 'half of 100, so 50'),
             ('read_side', "below 1 because the clean targets sit within the priors' scale"),
             ('read_side', 'below, because beta exceeds n'), ('read_side', 'below; beta climbs past n'),
             ('read_side', 'below 1 (about 0.37)'), ('read_side', 'above 1, as beta > n'),
             ('read_side', 'Narrower: the factor falls towards 1'), ('read_side', 'narrower - the factor shrinks'),
             ('read_side', 'Below - clean data do not surprise the model, so beta < n'),
             ('read_side', 'below, because without outliers beta does not exceed n'),
             ('read_side', 'Below: the data are not surprising'),
             ('read_side', 'below 1 since beta grows more slowly than n'),
             ('read_side', 'below, as the fitted noise absorbs the spread and beta rises less than n'),
             ('read_side', 'Below. Without outliers beta is less than n.'),
             ('read_side', 'below, as in section 3 without outliers'),
             ('read_side', 'below, beta/n = 0.33 after 50 Adam steps'), ('read_side', 'below: beta/n is about 1/3'),
             ('read_side', 'Below 1: the factor is about 0.35, not 3.3'),
             ('read_side', 'below. With outliers it is above 1.'), ('read_side', 'below (with outliers, above)'),
             ('read_side', 'below 1 (beta / n = 3.3 at nu = 3)'), ('read_side', 'below 1 (3.3)'),
             ('read_side', 'below, about 3.3'), ('read_side', '0.4 (above 1)'),
             ('read_actions', '[0, 1, 2] — UP is not safe'),
             ('read_actions', '0 and 2: 1 is too close and 3 is in S_u'), ('read_actions', '0 and 2 (both)'),
             ('read_word', 'Narrower, as nu grows the TP approaches the GP'),
             ('read_word', 'Narrower: as nu increases the factor decreases towards 1'),
             ('read_word', 'narrower, because the factor drops as nu goes up'),
             ('read_word', 'Narrower - the heavier tails at nu = 3 widen the band more'),
             ('read_word', 'narrower; with more degrees of freedom the TP is closer to the GP, which is not widened'),
             ('read_word', 'narrower (the band at nu = 3 is wider)'),
             ('read_word', 'Narrower since larger nu means lighter tails'),
             ('read_word', "narrower, but still wider than the GP's"),
             ('read_word', 'narrower, because beta exceeds n'),
             ('read_word', 'narrower, the factor goes from 5.10 to 6'),
             ('read_word', 'narrower, the factor falls from 6 to 5.1'), ('read_word', 'narrower, since beta > n'),
             ('read_word', 'narrower, since beta < n')]


@pytest.mark.parametrize("reader, answer", SAID_MORE)
def test_a_prediction_with_more_after_it_is_refused_asking_for_it_alone(reader, answer):
    read = {"read_count": read_count, "read_side": read_side, "read_actions": read_actions,
            "read_word": lambda text: read_word(text, {"wider": WIDER, "narrower": NARROWER})}[reader]
    with pytest.raises(Unreadable, match="alone|doubts its own answer"):  # '(not 1 or 3)' holds an 'or'
        read(answer)


@pytest.mark.parametrize("reader, answer", [("read_count", "probably 50"), ("read_count", "I guess 50"),
                                            ("read_count", "50 (not sure)"), ("read_word", "narrower, probably"),
                                            ("read_word", "narrower (don't know)"), ("read_side", "likely below"),
                                            ("read_actions", "0 and 2 (not sure)"), ("read_actions", "all, maybe")])
def test_a_prediction_that_doubts_itself_is_refused(reader, answer):
    read = {"read_count": read_count, "read_side": read_side, "read_actions": read_actions,
            "read_word": lambda text: read_word(text, {"wider": WIDER, "narrower": NARROWER})}[reader]
    with pytest.raises(Unreadable, match="doubts its own answer"):
        read(answer)


@pytest.mark.parametrize("answer", ["narrower when nu = 3", "narrower as nu decreases", "narrower if nu is 3",
                                    "narrower while nu is small", "smaller band when nu = 3", "narrower towards nu = 3",
                                    "wider when nu = 3", "wider as nu decreases"])
def test_a_direction_under_a_condition_of_its_own_is_not_read(answer):
    with pytest.raises(Unreadable):
        read_word(answer, {"wider": WIDER, "narrower": NARROWER})


@pytest.mark.parametrize("answer", ["< 50", "<50", "> 50", ">= 50", "\u2265 50", "minimum 50", "at minimum 50",
                                    "50 minimum"])
def test_a_count_given_as_a_lower_bound_or_a_minimum_is_refused(answer):
    with pytest.raises(Unreadable, match="a bound"):
        read_count(answer)


@pytest.mark.parametrize("answer", ["<= 50", "\u2264 50", "at most 50", "up to 50", "I predict 50"])
def test_the_questions_own_bound_is_read(answer):
    assert read_count(answer) == 50


@pytest.mark.parametrize("answer, side", [("The variance factor is below 1", "below"), ("beta/n < 1", "below"),
                                          ("variance_scale_ < 1", "below"), ("below 1 without outliers", "below"),
                                          ("I predict below", "below"), ("My prediction: narrower", "narrower"),
                                          ("Answer: narrower", "narrower"), ("I predict narrower", "narrower")])
def test_a_prediction_with_a_preface_or_the_factors_name_is_read(answer, side):
    if side in ("above", "below"):
        assert read_side(answer) == side
    else:
        assert read_word(answer, {"wider": WIDER, "narrower": NARROWER}) == side


@pytest.mark.parametrize("answer, actions", [("no safe actions", []), ("all four", [0, 1, 2, 3])])
def test_all_or_none_of_the_actions_is_read(answer, actions):
    assert read_actions(answer) == actions



def test_the_moved_readers_still_import_from_parsing_with_a_warning():
    from sarsp_edu.teaching.exercises import parsing

    for name in ("read_count", "read_actions"):
        with pytest.warns(DeprecationWarning, match=f"parsing.{name} moved to"):
            assert getattr(parsing, name)("50" if name == "read_count" else "0, 2") in (50, [0, 2])


# -- the sixteenth cold pass: endings read only where they are the question's own; a count stated, not judged ----
@pytest.mark.parametrize("answer", ["narrower towards the GP but actually wider", "narrower without outliers"])
def test_a_direction_with_a_further_ending_is_not_read(answer):
    with pytest.raises(Unreadable):
        read_word(answer, {"wider": WIDER, "narrower": NARROWER})


@pytest.mark.parametrize("answer", ["below 1 at nu = 30", "below as nu grows"])
def test_a_side_under_exercise_2_6s_conditions_is_not_read(answer):
    with pytest.raises(Unreadable):
        read_side(answer)


@pytest.mark.parametrize("answer", ["50 is wrong", "50 is too high", "50 cannot fit", "Fifty is too high",
                                    "50 in a checkerboard pattern", "50 I reckon"])
def test_a_count_judged_or_followed_by_words_is_not_read(answer):
    with pytest.raises(Unreadable):
        read_count(answer)


def test_a_wrong_working_does_not_give_the_answer_away():
    with pytest.raises(Unreadable, match="its working does not give 25") as refused:
        read_count("25 = 10*10/2")
    assert "50" not in str(refused.value)


@pytest.mark.parametrize("answer, said", [("0, 2 (three actions)", "counts three actions where its list holds 2"),
                                          ("RIGHT = 1", "names action 1 as RIGHT")])
def test_an_action_count_or_name_that_disagrees_is_refused(answer, said):
    with pytest.raises(Unreadable, match=said):
        read_actions(answer)


@pytest.mark.parametrize("answer, actions", [("(0, 2)", [0, 2]), ("Safe actions: 0, 2", [0, 2]),
                                             ("Safe: 0 and 2", [0, 2]), ("0 as well as 2", [0, 2]),
                                             ("both 0 and 2", [0, 2]), ("RIGHT = 0 and LEFT = 2", [0, 2]),
                                             ("RIGHT/LEFT", [0, 2]), ("there are none", []), ("empty", []),
                                             ("none of the four", []), ("all 4", [0, 1, 2, 3]),
                                             ("every one", [0, 1, 2, 3]), ("all of the actions", [0, 1, 2, 3]),
                                             ("0 through 3", [0, 1, 2, 3]), ("0 and 2 (two actions)", [0, 2])])
def test_more_wordings_of_a_list_of_actions_are_read(answer, actions):
    assert read_actions(answer) == actions


@pytest.mark.parametrize("answer", ["The factor is 0.4", "The variance factor is 0.4", "It's 0.4",
                                    "variance_scale_ = 0.4", "beta/n = 0.67", "variance_scale_ is below 1",
                                    "beta_ / n < 1", "The fitted factor is below 1",
                                    "The variance factor stays below 1",
                                    "It decreases below 1", "It will drop below 1", "the factor will fall below one"])
def test_the_factor_named_or_falling_below_1_is_read(answer):
    assert read_side(answer) == "below"


@pytest.mark.parametrize("answer", ["The TP's band gets narrower", "Its band is narrower",
                                    "The band at nu = 30 is narrower", "At nu = 30 the band is narrower",
                                    "narrower for larger nu", "narrower at nu = 30.0", "narrower at 30",
                                    "I predict: narrower"])
def test_the_band_named_or_at_the_questions_nu_is_read(answer):
    assert read_word(answer, {"wider": WIDER, "narrower": NARROWER}) == "narrower"


@pytest.mark.parametrize("answer", [{"lambda < 1": np.inf, "lambda = 1": "1 (wrong: 0)", "lambda > 1": 0},
                                    {"lambda < 1": "inf", "lambda = 1": "1", "lambda > 1": "0, probably"},
                                    "inf, 1, 0 (the Gaussian decays too fast)", "inf, 1, 0?"])
def test_limits_with_asides_or_doubts_are_not_read(answer):
    with pytest.raises(Unreadable):
        read_limits(answer)


# -- the seventeenth cold pass: no action named is not 'none'; limits beyond a float; endings with a full stop -----
@pytest.mark.parametrize("answer", ["", ".", "and", "Safe actions:", "{}", "as well as"])  # '()' is the empty tuple
def test_an_answer_that_names_no_action_is_not_none(answer):
    with pytest.raises(Unreadable):
        read_actions(answer)


@pytest.mark.parametrize("value", ["1e400", "9e999", "1e-400"])
def test_a_limit_beyond_a_floats_range_is_not_read(value):
    with pytest.raises(Unreadable):
        read_limits({"lambda < 1": value, "lambda = 1": 1, "lambda > 1": 0})


def test_the_limits_are_exact_numbers():
    from sarsp_edu.teaching.exercises import _verdict

    assert _verdict("1.4", {"lambda < 1": np.inf, "lambda = 1": 1, "lambda > 1": 0})[0]
    for almost in ("0.9999999999", 1.0000000001):
        assert not _verdict("1.4", {"lambda < 1": np.inf, "lambda = 1": almost, "lambda > 1": 0})[0]


@pytest.mark.parametrize("answer", ["Narrower at nu = 30.", "narrower as nu grows.", "Narrower towards the GP.",
                                    "narrower towards the GP\u2019s band", "narrower as nu grows towards the GP",
                                    "narrower when nu is 30", "narrower if nu = 30", "narrower at nu of 30"])
def test_the_questions_own_endings_are_read_with_a_full_stop_or_one_after_another(answer):
    assert read_word(answer, {"wider": WIDER, "narrower": NARROWER}) == "narrower"


@pytest.mark.parametrize("answer", ["below 1 without outliers.", "Below without outliers!", "beta/n is below 1",
                                    "beta / n is below one", "beta_/n is below 1"])
def test_more_wordings_of_below_1_are_read(answer):
    assert read_side(answer) == "below"


@pytest.mark.parametrize("answer", ["50 = 10*10/2.", "5 x 10.", "A 10 x 10 grid can hold 50",
                                    "The 10 x 10 grid can hold 50", "50 on a 10 x 10 grid", "50 is the answer",
                                    "50 is my prediction", "The maximum is 50", "exactly 50", "max 50", "maximum 50",
                                    "50 at the most", "It's 50", "There can be 50", "50 out of 100", "fifty = 100/2",
                                    "fifty = 10*10/2", "50 = 10*10/2 cells", "(10*10)/2"])
def test_more_statements_of_the_count_are_read(answer):
    assert read_count(answer) == 50


# -- the eighteenth cold pass: two numbers across a dash, another grid's size, limits not exactly 0, 1 or infinity --
@pytest.mark.parametrize("answer", [{"lambda < 1": np.inf, "lambda = 1": 1, "lambda > 1": "0 - 5"},
                                    {"lambda < 1": np.inf, "lambda = 1": "0.99999999999999999999", "lambda > 1": 0},
                                    "inf, 0.99999999999999999999, 0",
                                    {"lambda < 1": np.inf, "lambda = 1": Fraction(999999999999999999, 10**18),
                                     "lambda > 1": 0},
                                    {"lambda < 1": np.inf, "lambda = 1": 1, "lambda > 1": Fraction(1, 10**400)},
                                    {"lambda < 1": Decimal("1e400"), "lambda = 1": 1, "lambda > 1": 0}])
def test_limits_not_exactly_zero_one_or_infinity_are_not_read(answer):
    with pytest.raises(Unreadable):
        read_limits(answer)


@pytest.mark.parametrize("answer", [{"lambda < 1": Decimal("Infinity"), "lambda = 1": Decimal(1),
                                     "lambda > 1": Fraction(0)},
                                    [np.inf, np.float64(1), np.int64(0)], "inf, 1, 0", "infinity; 1.0; 0"])
def test_exact_limits_of_any_type_are_read(answer):
    assert read_limits(answer) == {"<1": np.inf, "=1": 1.0, ">1": 0.0}


@pytest.mark.parametrize("answer", ["0.5 - -1", "0.9 - -0.5"])
def test_two_numbers_across_a_dash_are_not_a_side(answer):
    with pytest.raises(Unreadable):
        read_side(answer)


@pytest.mark.parametrize("answer", ["A 20 x 20 grid can hold 50", "50 in a 5 x 5 grid", "A 10 x 5 grid can hold 50"])
def test_another_grids_size_is_not_the_questions(answer):
    with pytest.raises(Unreadable):
        read_count(answer)


@pytest.mark.parametrize("answer", ["50 max", "50 exactly", "The most is 50", "The largest number is 50",
                                    "it is exactly 50", "It's exactly 50.", "max. 50", "50 on the board"])
def test_still_more_statements_of_the_count_are_read(answer):
    assert read_count(answer) == 50


@pytest.mark.parametrize("answer", ["0.4 without outliers", "The factor is 0.4 without outliers",
                                    "beta/n is 0.4 without outliers", "0.4 without outliers."])
def test_a_value_of_the_factor_without_outliers_is_read(answer):
    assert read_side(answer) == "below"


def test_a_list_with_an_ellipsis_anywhere_is_refused_as_going_on():
    # read as [0, 2] until the twentieth pass, which found '0 and 2 and ...' read so: an ellipsis may say the list
    # goes on, wherever it stands, and a refusal that names the form is safer than a list guessed short
    for answer in ("RIGHT and LEFT\u2026", "0, 2, \u2026.", "0, 2, ....", "0, 2, \u2026!", "0 and 2 and ...",
                   "RIGHT and LEFT and \u2026", "0, 2 & ...", "0, 2 and \u2026", "0, 2 and so on"):
        with pytest.raises(Unreadable, match="goes on"):
            read_actions(answer)


# -- the nineteenth cold pass: a NaN limit answered, not raised; counts beside 'all'; hedged limits; lists that go on --
def test_a_nan_limit_is_a_wrong_answer_not_an_error():
    from sarsp_edu.teaching.exercises import _verdict

    for answer in ({"lambda < 1": np.inf, "lambda = 1": 1, "lambda > 1": "nan"}, [np.inf, np.nan, 0], "inf, nan, 0"):
        right, reply = _verdict("1.4", answer)
        assert not right and reply


@pytest.mark.parametrize("answer", ["all (three actions)", "none (two actions)", "0, 2, \u2026", "0, 2, ...",
                                    "0, 2, etc."])
def test_all_or_none_with_another_count_or_a_list_that_goes_on_is_refused(answer):
    with pytest.raises(Unreadable):
        read_actions(answer)


@pytest.mark.parametrize("answer", ["Safe actions = 0, 2", "Safe actions - 0, 2", "Safe actions \u2013 0, 2",
                                    "safe actions \u2192 0, 2", "Safe actions are: 0, 2",
                                    "The safe actions are: 0 and 2"])
def test_a_list_after_a_label_is_read(answer):
    assert read_actions(answer) == [0, 2]


@pytest.mark.parametrize("value", ["about 1", "~1", "\u2248 1", "approximately 1", "roughly 1"])
def test_a_hedged_limit_is_not_exact(value):
    with pytest.raises(Unreadable, match="a limit is exact"):
        read_limits({"lambda < 1": np.inf, "lambda = 1": value, "lambda > 1": 0})


def test_exact_limits_in_sympy_floats_quotients_exponents_and_brackets_are_read():
    import sympy as sp

    for answer in ({"lambda < 1": np.inf, "lambda = 1": sp.Float(1), "lambda > 1": sp.Float(0)},
                   {"lambda < 1": np.inf, "lambda = 1": "3/3", "lambda > 1": "0e5"},
                   {"lambda < 1": "(inf)", "lambda = 1": "(1)", "lambda > 1": "(0)"}):
        assert read_limits(answer) == {"<1": np.inf, "=1": 1.0, ">1": 0.0}


@pytest.mark.parametrize("answer", ["(50)", "50 = (10*10)/2", "(10*10)/2 = 50", "50 = (10 x 10) / 2", "The max is 50",
                                    "The maximum number is 50", "The largest is 50", "50 is the max", "50 is the most",
                                    "The most it can hold is 50", "The maximum number of unsafe cells is 50",
                                    "The upper limit is 50", "The max number is fifty"])
def test_the_count_in_brackets_with_a_working_or_as_the_maximum_is_read(answer):
    assert read_count(answer) == 50


# -- the twentieth cold pass: hedges after a lead-in, counts for lists, whole numbers only exactly, more wordings --
@pytest.mark.parametrize("value", ["it is about 1", "it is about infinity", "it is approximately 0", "It is \u2248 1",
                                   "it is around 1"])
def test_a_limit_hedged_after_a_lead_in_is_not_exact(value):
    with pytest.raises(Unreadable, match="a limit is exact"):
        read_limits({"lambda < 1": np.inf, "lambda = 1": value, "lambda > 1": 0})
    with pytest.raises(Unreadable, match="a limit is exact"):
        read_limits(f"inf, {value}, 0")


@pytest.mark.parametrize("answer", ["3 actions", "three actions", "3 safe actions", "three safe actions",
                                    "three actions are safe", "2 actions are safe", "one action", "four moves"])
def test_a_count_of_actions_is_not_a_list_of_them(answer):
    with pytest.raises(Unreadable, match="it counts the safe actions"):
        read_actions(answer)


@pytest.mark.parametrize("answer", ["zero actions", "zero safe actions", "0 actions"])
def test_zero_actions_is_none(answer):
    assert read_actions(answer) == []


@pytest.mark.parametrize("answer", ["50.0000000000000001", "49.99999999999999999", "4.99999999999999999e1",
                                    Decimal("49.99999999999999999999"), Fraction(4999999999999999999999, 10**20)])
def test_a_count_that_only_rounds_to_a_whole_number_is_not_one(answer):
    with pytest.raises(Unreadable, match="not exactly 50"):
        read_count(answer)


def test_an_action_number_that_only_rounds_to_a_whole_number_is_not_one():
    import sympy as sp

    for answer in ("0, 1.99999999999999999999", [0, Decimal("1.99999999999999999999")],
                   [0, Fraction(199999999999999999999, 10**20)], [0, sp.Float("1.99999999999999999999", 30)]):
        with pytest.raises(Unreadable, match="not exactly 2"):
            read_actions(answer)


@pytest.mark.parametrize("answer", ["safe actions -> 0, 2", "Safe actions -> RIGHT, LEFT", "safe -> 0, 2",
                                    "actions -> 0 and 2", "safe actions => 0, 2", "Safe actions \u2014 0, 2",
                                    "0; 2", "0;2", "RIGHT; LEFT", "[0; 2]"])
def test_a_list_after_an_arrow_or_with_semicolons_is_read(answer):
    assert read_actions(answer) == [0, 2]


@pytest.mark.parametrize("answer", ["narrowed", "less broad", "not as broad", "getting narrower", "Its band narrows"])
def test_more_wordings_of_a_narrower_band_are_read(answer):
    assert read_word(answer, {"wider": WIDER, "narrower": NARROWER}) == "narrower"


@pytest.mark.parametrize("answer", ["widened", "more broad", "getting wider", "Its band widens"])
def test_the_same_wordings_of_a_wider_band_are_read(answer):
    assert read_word(answer, {"wider": WIDER, "narrower": NARROWER}) == "wider"


@pytest.mark.parametrize("answer", ["< 1.0", "<1.0", "< one"])
def test_a_comparison_with_one_written_otherwise_is_read(answer):
    assert read_side(answer) == "below"


def test_positive_infinity_and_a_bracketed_dividend_are_read():
    assert read_limits({"lambda < 1": "positive infinity", "lambda = 1": 1, "lambda > 1": 0})["<1"] == np.inf
    assert read_count("(100)/2") == 50


def test_a_limit_whose_text_cannot_be_made_is_refused_not_raised():
    class Stubborn:
        def __float__(self):
            return 1.0

        def __str__(self):
            raise RuntimeError("no text")

    from sarsp_edu.teaching.exercises import _verdict

    right, reply = _verdict("1.4", {"lambda < 1": np.inf, "lambda = 1": Stubborn(), "lambda > 1": 0})
    assert not right and reply


# -- the twenty-first cold pass: counts said with 'ones' or in other digits, 'it's' before a limit, past forms --
@pytest.mark.parametrize("answer", ["three safe ones", "3 safe ones", "the three safe ones", "3 ones are safe",
                                    "two safe ones", "\uff13 actions", "\u0663 actions", "\U0001d7d1 actions",
                                    "\uff12 actions", "\u0662 safe actions", "\uff14 safe moves"])
def test_a_count_in_any_words_or_digits_is_not_a_list(answer):
    with pytest.raises(Unreadable, match="it counts the safe actions"):
        read_actions(answer)


@pytest.mark.parametrize("answer, actions", [("two actions: 0 and 2", [0, 2]), ("the two actions 0 and 2", [0, 2]),
                                             ("three: 0, 1, 2", [0, 1, 2]), ("zero; two", [0, 2]),
                                             ("zero; 2", [0, 2]), ("safe \u21d2 0, 2", [0, 2]),
                                             ("safe --> 0, 2", [0, 2]), ("safe \u27f6 0, 2", [0, 2]),
                                             ("safe \u2013> 0, 2", [0, 2]), ("safe: -> 0, 2", [0, 2]),
                                             ("2 and 0", [0, 2])])
def test_a_list_after_its_count_or_an_arrow_is_read(answer, actions):
    assert read_actions(answer) == actions


def test_a_list_whose_count_disagrees_with_it_is_refused():
    with pytest.raises(Unreadable, match="counts three actions where its list holds 2"):
        read_actions("three actions: 0 and 2")


def test_its_before_a_limit_is_read():
    for answer in ({"lambda < 1": "it's infinity", "lambda = 1": "it's 1", "lambda > 1": "it\u2019s 0"},
                   "it's inf, it's 1, it's 0",
                   {"lambda < 1": "inf", "lambda = 1": "It's 1.", "lambda > 1": "it's zero"}):
        assert read_limits(answer) == {"<1": np.inf, "=1": 1.0, ">1": 0.0}


@pytest.mark.parametrize("answer", ["has narrowed", "it has narrowed", "became narrower", "it became narrower",
                                    "has become narrower", "got narrower", "it got narrower", "has gotten narrower",
                                    "grew narrower", "shrank", "it shrank", "has shrunk", "it has tightened"])
def test_a_narrower_band_in_the_past_or_perfect_is_read(answer):
    assert read_word(answer, {"wider": WIDER, "narrower": NARROWER}) == "narrower"


def test_a_negated_past_form_is_not_read():
    with pytest.raises(Unreadable):
        read_word("it has not narrowed", {"wider": WIDER, "narrower": NARROWER})


# -- the twenty-second cold pass: 'one' after a number word is an action; lead-ins one after another; past verbs --
@pytest.mark.parametrize("answer, actions", [("zero one two", [0, 1, 2]), ("[zero one two]", [0, 1, 2]),
                                             ("zero one", [0, 1]), ("three two one zero", [0, 1, 2, 3]),
                                             ("two one", [1, 2]), ("Two actions: [0, 2]", [0, 2]),
                                             ("two actions: (0, 2)", [0, 2]), ("2 actions: {0, 2}", [0, 2])])
def test_number_words_in_a_row_are_actions_and_a_bracketed_list_may_follow_its_count(answer, actions):
    assert read_actions(answer) == actions


@pytest.mark.parametrize("answer, why", [("1: LEFT", "names action 1 as LEFT"),
                                         ("1: 3", "write the safe actions alone")])
def test_a_bare_number_and_a_colon_is_not_read_as_a_count(answer, why):  # '2: LEFT' names action 2 (answer_readers)
    with pytest.raises(Unreadable, match=why):
        read_actions(answer)


@pytest.mark.parametrize("answer", ["the band has shrunk", "The band became narrower.", "The band got narrower!",
                                    "the band got narrower at nu = 30", "the band grew narrower",
                                    "its band has narrowed", "the TP's band has narrowed",
                                    "the band has become narrower", "the band got tighter", "the band has tightened",
                                    "its band got smaller"])
def test_a_band_named_before_a_past_form_is_read(answer):
    assert read_word(answer, {"wider": WIDER, "narrower": NARROWER}) == "narrower"


@pytest.mark.parametrize("answer", ["it fell below 1", "fell below one", "dropped below 1", "it went below 1",
                                    "went down below 1", "has fallen below 1", "it has dropped below 1",
                                    "it fell under 1", "has decreased below 1", "the factor fell below 1",
                                    "the factor dropped below one", "it shrank below 1", "the variance factor fell",
                                    "the variance factor falls", "the variance factor goes down"])
def test_a_past_verb_before_the_side_is_read(answer):
    assert read_side(answer) == "below"


@pytest.mark.parametrize("answer", ["the band has not narrowed", "never fell below 1"])
def test_a_negated_direction_is_still_refused(answer):
    with pytest.raises(Unreadable):
        read_word(answer, {"wider": WIDER, "narrower": NARROWER}) if "band" in answer else read_side(answer)


# -- the twenty-third cold pass: a sentence read whole (sentences.py): a verb that moves against its side, a
# question, and the wordings that dropping lead-ins one list after another missed --
_BANDS = {"wider": WIDER, "narrower": NARROWER}


@pytest.mark.parametrize("answer", ["rose below 1", "it rose below 1", "it has risen below 1", "grew below 1",
                                    "it went up below 1", "it climbed below 1", "increased below 1",
                                    "is it below 1", "does it fall below 1", "is the factor below 1"])
def test_a_verb_against_its_side_or_a_question_is_not_read_as_below(answer):
    with pytest.raises(Unreadable):
        read_side(answer)


@pytest.mark.parametrize("answer", ["it rose narrower", "it climbed narrower", "the band rose narrower",
                                    "it shrank wider", "the band widened narrower", "is the band narrower",
                                    "does the band narrow"])
def test_a_verb_against_its_band_or_a_question_is_not_read(answer):
    with pytest.raises(Unreadable):
        read_word(answer, _BANDS)


@pytest.mark.parametrize("answer", ["has grown narrower", "the band has fallen", "band narrowed", "the band's narrower",
                                    "the TP band has narrowed", "it has grown narrower", "the band is narrowing",
                                    "the band will narrow"])
def test_a_band_said_in_a_sentence_is_read(answer):
    assert read_word(answer, _BANDS) == "narrower"


@pytest.mark.parametrize("answer", ["it has sunk below 1", "it has come out below 1", "fell to below 1",
                                    "variance factor fell below 1", "it's below 1", "the TP's factor sank below one"])
def test_a_side_said_in_a_sentence_is_read(answer):
    assert read_side(answer) == "below"


@pytest.mark.parametrize("answer", ["band narrowed", "the band has tightened"])
def test_a_band_s_verb_is_no_side_of_1(answer):
    with pytest.raises(Unreadable):
        read_side(answer)


@pytest.mark.parametrize("answer, actions", [("1 safe one: 3", [3]), ("the one safe one: UP", [3]),
                                             ("two actions -> 0, 2", [0, 2]),
                                             ("two actions: ['RIGHT', 'LEFT']", [0, 2]), ("both: 0 and 2", [0, 2])])
def test_a_count_then_its_list_is_read_in_more_forms(answer, actions):
    assert read_actions(answer) == actions


def test_a_count_against_its_list_says_how_many_the_list_holds():
    with pytest.raises(Unreadable, match="counts two actions where its list holds 1"):
        read_actions("both: 0")


# -- the twenty-fourth cold pass: impossible factors, hedged and mis-totalled counts, the band at nu = 3 said
# instead, numpy-printed lists, asides that only repeat the count, and three coding cases no key separated --
@pytest.mark.parametrize("answer", ["0", "0.0", "-0.5", "-1", "-0.37", "-inf", "0.37 > 1", "2 < 1"])
def test_a_factor_at_or_below_0_or_a_false_comparison_is_no_side(answer):
    with pytest.raises(Unreadable):
        read_side(answer)


@pytest.mark.parametrize("answer", ["It's going to be below 1", "it'll be below 1", "it'll fall below 1", "0.37 < 1",
                                    "under unity", "it drops to 0.37", "Below, without outliers"])
def test_more_sentences_on_the_side_of_1_are_read(answer):
    assert read_side(answer) == "below"


@pytest.mark.parametrize("answer", ["It'll be narrower.", "it'll narrow", "the nu = 30 band is narrower",
                                    "narrower than nu = 3", "it narrows as nu goes from 3 to 30",
                                    "the band at nu = 30 is narrower than the band at nu = 3",
                                    "narrower, towards the GP", "narrower (nu = 30)", "narrower than the nu = 3 band",
                                    "wider at nu = 3", "wider with nu = 3", "the band at nu = 3 is wider",
                                    "at nu = 3 it is wider"])
def test_the_band_at_nu_30_or_at_nu_3_said_either_way_is_read(answer):
    assert read_band(answer) == "narrower"


@pytest.mark.parametrize("answer", ["narrower at nu = 3", "narrower with nu = 3", "the nu = 3 band is narrower",
                                    "the band at nu = 3 is narrower than at nu = 30"])
def test_the_band_at_nu_3_said_narrower_is_the_wrong_side(answer):
    assert read_band(answer) == "wider"


@pytest.mark.parametrize("answer", ["it stays narrow", "it stays the same width", "narrower at nu = 3.5",
                                    "narrower when nu = 1"])
def test_no_change_or_another_nu_is_not_read_as_a_band(answer):
    with pytest.raises(Unreadable):
        read_band(answer)


@pytest.mark.parametrize("answer", ["about 50", "around 50", "roughly 50", "~50", "\u224850", "about fifty",
                                    "roughly fifty cells", "50 of 64", "50 of the 64 cells", "50 of 10",
                                    "50 cells of 50", "50, 5 per row", "50 (or 25)"])
def test_a_hedged_count_a_count_of_another_grid_or_two_numbers_are_refused(answer):
    with pytest.raises(Unreadable):
        read_count(answer)


@pytest.mark.parametrize("answer", ["50, one colour of the chessboard", "50 (half the grid)", "50, half the grid",
                                    "half the grid: 50", "50 (a checkerboard)", "50 (exactly)", "fifty (50)",
                                    "The most unsafe cells it can hold is 50", "50 of the 100 cells",
                                    "50: one colour of a checkerboard", "50 (10 x 10 / 2)", "50 (100 / 2)"])
def test_a_count_with_an_aside_that_only_repeats_it_is_read(answer):
    assert read_count(answer) == 50


def test_two_numbers_are_said_to_be_two_numbers_not_a_reason():
    with pytest.raises(Unreadable, match="another number beside the count"):
        read_count("50, 5 per row")


@pytest.mark.parametrize("answer", ["[inf, 1, 0]", "[math.inf, 1, 0]", "(inf, 1, 0)", "(np.inf, 1, 0)"])
def test_three_limits_as_python_prints_a_list_are_read(answer):
    assert read_limits(answer) == {"<1": np.inf, "=1": 1.0, ">1": 0.0}


@pytest.mark.parametrize("answer", ["both -> 0, 2", "[ True False  True False]", "array([0, 2])",
                                    "(array([0, 2]),)", "[np.int64(0), np.int64(2)]", "0 and 2 (RIGHT and LEFT)",
                                    "[0, 2] (RIGHT and LEFT)", "array([0, 2], dtype=int64)"])
def test_a_list_as_numpy_prints_it_or_with_its_names_beside_it_is_read(answer):
    assert read_actions(answer) == [0, 2]


@pytest.mark.parametrize("answer, said", [("0, 2 and", "ends before its last action"),
                                          ("0 and 2 (RIGHT and UP)", "other actions in its brackets")])
def test_a_list_cut_off_or_named_otherwise_in_brackets_is_refused(answer, said):
    with pytest.raises(Unreadable, match=said):
        read_actions(answer)


def test_a_long_answer_is_quoted_not_counted():
    with pytest.raises(Unreadable, match="'the band at nu = 30 is narrower than the band at nu = 300'"):
        read_band("the band at nu = 30 is narrower than the band at nu = 300")


def _pull_cut_off_far_away(residual, nu, scale):
    r = np.asarray(residual, dtype=float)
    return np.where(np.abs(r) > 1000, 0.0, (nu + 1) * r / (nu * scale**2 + r**2))


def _backup_among_the_confident(mu_cost, var_cost, mu_reward, known_unsafe, d, variance_threshold):
    rewards = np.where(np.asarray(known_unsafe), -np.inf, np.asarray(mu_reward, dtype=float))
    confident = np.asarray(var_cost) <= variance_threshold
    safe = confident & (np.asarray(mu_cost) >= d) & ~np.asarray(known_unsafe)
    if safe.any():
        return int(np.argmax(np.where(safe, rewards, -np.inf))), False
    return int(np.argmax(np.where(confident, rewards, -np.inf) if confident.any() else rewards)), True


def _prefers_only_with_some_success(s1, s2, a):
    return bool(s1["cost_rate"] < s2["cost_rate"] and s1["task_success_rate"] > 0 and (
        s1["mean_reward"] >= s2["mean_reward"] or s1["task_success_rate"] >= s2["task_success_rate"]
        or s1["task_success_rate"] >= a))


@pytest.mark.parametrize("exercise, answer", [("2.7", _pull_cut_off_far_away), ("4.2", _backup_among_the_confident),
                                              ("6.2", _prefers_only_with_some_success)])
def test_the_cases_separate_three_slips_no_case_caught_before(exercise, answer):
    from sarsp_edu.teaching.exercises import is_right

    assert is_right(exercise, answer) is False


# -- the twenty-fifth cold pass: lists whose brackets do not close, the question's own conditions restated, a
# side denied beside the other, keys in words --
@pytest.mark.parametrize("answer", ["[0, 1, 3", "{0, 1, 3", "[0, 1, 3]]", "[[0, 1, 3]", "[ True  True False  True",
                                    "[0, 1"])
def test_brackets_that_do_not_make_one_list_are_refused(answer):
    with pytest.raises(Unreadable, match="brackets do not make one list"):
        read_actions(answer)


@pytest.mark.parametrize("answer, said", [("[0, 1, 3] with sigma*^2 = 10", [0, 1, 3]),
                                          ("[0, 1, 3] at d = 1", [0, 1, 3]),
                                          ("[0, 1, 3] with \u03c3*\u00b2 = 10", [0, 1, 3])])
def test_the_questions_own_setting_after_a_list_is_read(answer, said):
    assert read_actions(answer) == said


@pytest.mark.parametrize("answer", ["[0, 1, 3] with sigma*^2 = 0.8", "0 and 2 when sigma = 10"])
def test_another_setting_after_a_list_is_refused_and_said_to_be_another(answer):
    with pytest.raises(Unreadable, match="not another setting"):
        read_actions(answer)


@pytest.mark.parametrize("answer", ["without outliers it is below 1", "on clean data it is below 1",
                                    "below 1 on clean data", "the factor is less than 1 without the outliers",
                                    "Without outliers, below.", "1 is above it", "1 is larger than the factor",
                                    "below 1, not above", "it is below, not above"])
def test_the_side_with_the_questions_own_condition_or_from_1_is_read(answer):
    assert read_side(answer) == "below"


@pytest.mark.parametrize("answer", ["it goes up, below 1", "above, below"])
def test_two_sides_at_once_are_said_to_be_two(answer):
    with pytest.raises(Unreadable, match="names both"):
        read_side(answer)


def test_an_infinite_factor_is_no_side():
    with pytest.raises(Unreadable, match="positive, finite"):
        read_side("inf")


@pytest.mark.parametrize("answer", ["narrower, not wider", "narrower, but not wider"])
def test_a_band_with_the_other_side_denied_is_read(answer):
    assert read_band(answer) == "narrower"


@pytest.mark.parametrize("answer", ["on a 10x10 grid, 50", "on a 10 x 10 grid it is 50", "50 with no two 4-adjacent",
                                    "50 with no two touching", "50 cells with no two 4-adjacent", "50 of them"])
def test_a_count_with_the_questions_own_conditions_is_read(answer):
    assert read_count(answer) == 50


@pytest.mark.parametrize("answer", [{"lambda smaller than 1": "inf", "lambda equal to 1": 1,
                                     "lambda greater than 1": 0}, "inf, 1 and 0",
                                    {"lambda < 1": "math.inf", "lambda = 1": 1, "lambda > 1": 0}])
def test_limits_keyed_in_words_or_listed_with_and_are_read(answer):
    assert read_limits(answer) == {"<1": np.inf, "=1": 1.0, ">1": 0.0}


def test_a_huge_limit_is_read_as_the_float_it_is_and_judged():
    assert read_limits({"lambda < 1": 1e300, "lambda = 1": 1, "lambda > 1": 0})["<1"] == 1e300


def test_an_empty_buffer_separates_a_cap_that_fails_on_no_rows():
    from sarsp_edu.teaching.exercises import is_right

    def cap(X, y, cap):
        keep, seen = [], {}
        for i, row in enumerate(map(tuple, X)):
            seen[row] = seen.get(row, 0) + 1
            if seen[row] <= cap:
                keep.append(i)
        return X[np.array(keep)], y[np.array(keep)]  # indexing with an empty float array raises

    assert is_right("3.1", cap) is False


# -- the twenty-sixth cold pass: thresholds in no order, a clipped pull, the band at nu = 3 against itself, a hedged
# number, a reason beside a count, and more of the question's own words --
def _shares_of_sorted_thresholds(mu_cost, var_cost, d, thresholds):
    from sarsp_edu.teaching.exercises.records import _backup_shares

    return _backup_shares(mu_cost, var_cost, d, np.sort(np.asarray(thresholds)))


def _pull_clipped(residual, nu, scale):
    r = np.asarray(residual, dtype=float)
    return np.clip((nu + 1) * r / (nu * scale**2 + r**2), -10.0, 10.0)


@pytest.mark.parametrize("exercise, answer", [("6.3", _shares_of_sorted_thresholds), ("2.7", _pull_clipped)])
def test_the_cases_separate_sorted_thresholds_and_a_clipped_pull(exercise, answer):
    from sarsp_edu.teaching.exercises import is_right

    assert is_right(exercise, answer) is False


@pytest.mark.parametrize("reader, answer", [(read_band, "the band at nu = 3 is wider than at nu = 3"),
                                            (read_side, "about 0.37"), (read_side, "1 < 0.37"),
                                            (read_count, "50 because of the chessboard pattern"),
                                            (read_count, "50, not 50")])
def test_a_band_against_itself_a_hedged_number_and_a_reason_are_refused(reader, answer):
    with pytest.raises(Unreadable):
        reader(answer)


@pytest.mark.parametrize("reader, answer, expected", [
    (read_band, "wider at nu = 3 than at nu = 30", "narrower"), (read_band, "narrower, as nu grows", "narrower"),
    (read_side, "below (without outliers)", "below"), (read_side, "Below 1 \u2014 without outliers", "below"),
    (read_side, "1 > 0.37", "below"), (read_count, "50 (= 100/2)", 50), (read_count, "50, not 25", 50),
    (read_count, "50 (no two 4-adjacent)", 50), (read_count, "50 cells, no two adjacent", 50),
    (read_actions, "0, 2 with sigma*^2 = 10 and d = 1", [0, 2]), (read_actions, "RIGHT and LEFT (0 and 2)", [0, 2]),
    (read_actions, "0,2,", [0, 2]),
    (read_actions, "0, 2 (with sigma*^2 = 10)", [0, 2])])
def test_more_of_the_questions_own_words_and_emphasis_are_read(reader, answer, expected):
    assert reader(answer) == expected


@pytest.mark.parametrize("answer", [np.array([np.inf, 1.0, 0.0]), "[float('inf'), 1, 0]",
                                    "lambda < 1: inf, lambda = 1: 1, lambda > 1: 0", "inf, 1, 0, respectively",
                                    "The limits are inf, 1 and 0"])
def test_three_limits_in_more_of_pythons_and_a_students_forms_are_read(answer):
    assert read_limits(answer) == {"<1": np.inf, "=1": 1.0, ">1": 0.0}


@pytest.mark.parametrize("reader, answer, expected", [(read_side, "less then 1", "below"),
                                                      (read_side, "between 0 and 1", "below"),
                                                      (read_band, "it gets narrower and narrower", "narrower")])
def test_a_common_typo_and_a_repeated_comparative_are_read(reader, answer, expected):
    assert reader(answer) == expected


# -- the twenty-seventh cold pass: a verb and a number on two sides, hedges in brackets, a count in other tenses,
# a list with the other actions denied, the empty tuple, curly quotes --
@pytest.mark.parametrize("reader, answer", [(read_side, "it rises to 0.37"), (read_side, "it drops to 1.3"),
                                            (read_count, "50 (rounded)"), (read_count, "50 (estimate)"),
                                            (read_actions, "0 and 3, not 3")])
def test_a_verb_against_its_number_a_hedge_in_brackets_and_a_self_denial_are_refused(reader, answer):
    with pytest.raises(Unreadable):
        reader(answer)


@pytest.mark.parametrize("reader, answer, expected", [
    (read_count, "It'd be 50", 50), (read_count, "it would be 50", 50), (read_count, "it was 50", 50),
    (read_count, "It'll be 50", 50), (read_count, "They can hold 50", 50), (read_actions, "0 and 3, not 1", [0, 3]),
    (read_actions, "right and up, not down", [0, 3]), (read_actions, "()", []),
    (read_side, "\u2018below\u2019", "below"), (read_band, "narrower at 30 than at 3", "narrower"),
    (read_limits, {"0 < lambda < 1": "inf", "lambda = 1": 1, "lambda > 1": 0}, {"<1": np.inf, "=1": 1.0, ">1": 0.0})])
def test_more_tenses_emphasis_and_printed_forms_are_read(reader, answer, expected):
    assert reader(answer) == expected


# -- the forty-second cold pass: coding answers that passed with a bug the cases never reached --
def _distance_stopping_early(position, unsafe):
    import math

    best = math.dist(position, unsafe[0])
    for cell in unsafe[1:]:
        if math.dist(position, cell) >= best:
            break  # stops once a distance does not improve
        best = math.dist(position, cell)
    return best


def _distance_skipping_the_last(position, unsafe):
    import math

    return min(math.dist(position, cell) for cell in unsafe[:max(1, len(unsafe) - 1)])


def _corrects_with_a_partial_minimum(stop):
    def corrects(mu_cost, var_cost, action, d, was_backup):
        lowest = min(var_cost[:stop]) if stop > 0 else min(var_cost[-stop:])
        return bool(mu_cost[action] >= d or (var_cost[action] <= lowest and not was_backup))
    return corrects


@pytest.mark.parametrize("exercise, answer", [
    ("3.2", _distance_stopping_early), ("3.2", _distance_skipping_the_last),
    ("3.2", lambda position, unsafe: _distance_skipping_the_last(position, unsafe[:3])),
    ("4.3", _corrects_with_a_partial_minimum(3)), ("4.3", _corrects_with_a_partial_minimum(-3))])
def test_a_loop_over_some_of_the_cells_or_actions_is_refused(exercise, answer):
    right, reply = grade(exercise, EXERCISES[exercise], answer)
    assert not right, reply
