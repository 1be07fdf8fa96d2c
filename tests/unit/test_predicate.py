"""The EARL predicate language: parsing, printing, rewriting, evaluation, errors."""

from __future__ import annotations

import itertools

import pytest
from textx.exceptions import TextXError

from earl_m2t.predicate import (
    And,
    Compare,
    Const,
    FieldRef,
    NewData,
    Not,
    Number,
    Or,
    PredicateRef,
    PredicateSyntaxError,
    Replicated,
    evaluate,
    expand_replicated,
    format_predicate,
    parse_predicate,
    references,
    substitute_index,
    walk,
)
from earl_m2t.predicate.parser import _metamodel
from earl_m2t.resources import metamodel_path
from tests.support.calls import counted_calls

# ---------------------------------------------------------------------------- helpers


def P(name: str) -> PredicateRef:
    return PredicateRef(name)


def F(head: str, member: str | None = None, *path: str) -> FieldRef:
    return FieldRef(head, member, tuple(path))


ESTOP = P("emergencyStop/pp")
NEW_JOINT = P("newJointPos/pp")
NEW_OPER = P("newOperationalPos/pp")
FINISHED = P("motionFinished/pp")
MOTOR_ESTOP = F("motorControllerStateK/ib", "msg", "emergencyStopCommand")
MANIP_ESTOP = F("manipulatorCommand/ib", "msg", "emergencyStopCommand")

# ---------------------------------------------------------------------------- the paper

# Table 5 as printed in the paper (spaces around '/', '...' for the ellipsis).
TABLE_5 = {
    "emergencyStop/pp": (
        "manipulatorCommand / ib.msg.emergencyStopCommand ∨ "
        "motorControllerState1 / ib.msg.emergencyStopCommand ∨ ... ∨ "
        "motorControllerStateN / ib.msg.emergencyStopCommand",
        Or((MANIP_ESTOP, Replicated("or", MOTOR_ESTOP))),
    ),
    "motionFinished/pp": ("motionFinished / mi.msg", F("motionFinished/mi", "msg")),
    "newJointPos/pp": (
        "newData(manipulatorCommand / ib.msg.jointPosSetpoint)",
        NewData(F("manipulatorCommand/ib", "msg", "jointPosSetpoint")),
    ),
    "newOperationalPos/pp": (
        "newData(manipulatorCommand / ib.msg.operationalPosSetpoint)",
        NewData(F("manipulatorCommand/ib", "msg", "operationalPosSetpoint")),
    ),
    "false/pp": ("FALSE", Const(False)),
}

# Table 6: initial conditions of the transitions, then terminal conditions.
TABLE_6 = {
    "idle,jointMove/t": ("newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun", And((NEW_JOINT, Not(ESTOP)))),
    "jointMove,jointMove/t": ("newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun", And((NEW_JOINT, Not(ESTOP)))),
    "idle,operationalMove/t": ("newOperationalPos/pp.fun ∧ ¬emergencyStop/pp.fun", And((NEW_OPER, Not(ESTOP)))),
    "operationalMove,operationalMove/t": (
        "newOperationalPos/pp.fun ∧ ¬emergencyStop/pp.fun",
        And((NEW_OPER, Not(ESTOP))),
    ),
    "jointMove,idle/t": ("¬emergencyStop/pp.fun", Not(ESTOP)),
    "operationalMove,idle/t": ("¬emergencyStop/pp.fun", Not(ESTOP)),
    "i,emergencyStop/t": ("emergencyStop/pp.fun", ESTOP),
    "idle/bb": (
        "newJointPos/pp.fun ∨ newOperationalPos/pp.fun ∨ emergencyStop/pp.fun",
        Or((NEW_JOINT, NEW_OPER, ESTOP)),
    ),
    "jointMove/bb": ("motionFinished/pp.fun ∨ emergencyStop/pp.fun", Or((FINISHED, ESTOP))),
    "operationalMove/bb": ("motionFinished/pp.fun ∨ emergencyStop/pp.fun", Or((FINISHED, ESTOP))),
    "emergencyStop/bb": ("false/pp.fun", P("false/pp")),
}


@pytest.mark.parametrize("pp", TABLE_5)
def test_every_primitive_predicate_of_table_5_parses_as_printed_in_the_paper(pp: str) -> None:
    text, expected = TABLE_5[pp]
    assert parse_predicate(text) == expected


@pytest.mark.parametrize("element", TABLE_6)
def test_every_condition_of_table_6_parses_as_printed_in_the_paper(element: str) -> None:
    text, expected = TABLE_6[element]
    assert parse_predicate(text) == expected


def test_table_5_emergency_stop_prints_back_in_the_papers_form() -> None:
    expr = parse_predicate(TABLE_5["emergencyStop/pp"][0])
    assert format_predicate(expr) == (
        "manipulatorCommand/ib.msg.emergencyStopCommand ∨ "
        "motorControllerState1/ib.msg.emergencyStopCommand ∨ … ∨ "
        "motorControllerStateN/ib.msg.emergencyStopCommand"
    )
    assert format_predicate(expr, "ascii") == (
        "manipulatorCommand/ib.msg.emergencyStopCommand or "
        "any K: motorControllerStateK/ib.msg.emergencyStopCommand"
    )


def test_table_6_conditions_print_without_fun_and_with_the_papers_symbols() -> None:
    assert format_predicate(parse_predicate(TABLE_6["idle,jointMove/t"][0])) == (
        "newJointPos/pp ∧ ¬emergencyStop/pp"
    )
    assert format_predicate(parse_predicate(TABLE_6["idle,jointMove/t"][0]), "ascii") == (
        "newJointPos/pp and not emergencyStop/pp"
    )


# ---------------------------------------------------------------------------- operators


@pytest.mark.parametrize(
    "text",
    [
        "a ∧ b ∨ ¬c",
        "a and b or not c",
        "a && b || !c",
        "a∧b∨¬c",
        "a and b ∨ !c",
        "(a ∧ b) ∨ (¬c)",
        "((a && b)) || not (c)",
    ],
)
def test_both_notations_and_any_mix_of_them_give_the_same_tree(text: str) -> None:
    assert parse_predicate(text) == Or((And((P("a"), P("b"))), Not(P("c"))))


def test_not_binds_tighter_than_and_which_binds_tighter_than_or() -> None:
    assert parse_predicate("a ∨ b ∧ ¬c ∧ d ∨ e") == Or(
        (P("a"), And((P("b"), Not(P("c")), P("d"))), P("e"))
    )
    assert parse_predicate("¬a ∧ b") == And((Not(P("a")), P("b")))


def test_parentheses_override_precedence() -> None:
    assert parse_predicate("(a ∨ b) ∧ c") == And((Or((P("a"), P("b"))), P("c")))
    assert parse_predicate("¬(a ∧ b)") == Not(And((P("a"), P("b"))))


def test_chains_are_flattened_also_across_redundant_parentheses() -> None:
    flat = And((P("a"), P("b"), P("c"), P("d")))
    assert parse_predicate("a ∧ b ∧ c ∧ d") == flat
    assert parse_predicate("(a ∧ b) ∧ (c ∧ (d))") == flat
    assert parse_predicate("a ∨ (b ∨ c)") == Or((P("a"), P("b"), P("c")))


def test_double_negation_is_kept() -> None:
    assert parse_predicate("¬¬a") == Not(Not(P("a")))
    assert parse_predicate("not not a") == Not(Not(P("a")))


@pytest.mark.parametrize("text", ["TRUE", "true", "True", "tRuE"])
def test_true_is_a_constant_in_any_case(text: str) -> None:
    assert parse_predicate(text) == Const(True)


@pytest.mark.parametrize("text", ["FALSE", "false", "False"])
def test_false_is_a_constant_in_any_case(text: str) -> None:
    assert parse_predicate(text) == Const(False)


def test_a_primitive_predicate_named_false_is_not_the_constant() -> None:
    assert parse_predicate("false/pp") == P("false/pp")
    assert parse_predicate("false/pp.fun ∨ FALSE") == Or((P("false/pp"), Const(False)))
    assert parse_predicate("false.fun") == P("false")


def test_whitespace_and_newlines_may_stand_anywhere_between_tokens() -> None:
    text = "\r\n  newJointPos/pp.fun\r\n\t∧\n ¬ emergencyStop / pp . fun  \r\n"
    assert parse_predicate(text) == And((NEW_JOINT, Not(ESTOP)))


# ---------------------------------------------------------------------------- names


def test_a_bare_name_is_a_predicate_reference_resolved_later() -> None:
    assert parse_predicate("emergencyStop") == P("emergencyStop")
    assert parse_predicate("emergencyStop.fun") == P("emergencyStop")


def test_fun_is_optional_and_dropped() -> None:
    assert parse_predicate("emergencyStop/pp.fun") == parse_predicate("emergencyStop/pp") == ESTOP


@pytest.mark.parametrize("suffix", ["ib", "ob", "m", "mi", "mo"])
def test_a_buffer_or_memory_without_member_is_a_field_reference(suffix: str) -> None:
    assert parse_predicate(f"x/{suffix}") == F(f"x/{suffix}")


def test_other_suffixes_without_member_are_predicate_references() -> None:
    assert parse_predicate("x/pp") == P("x/pp")
    assert parse_predicate("x/zz") == P("x/zz")


def test_field_references_have_a_head_a_member_and_a_path() -> None:
    assert parse_predicate("manipulatorCommand/ib.msg.emergencyStopCommand") == MANIP_ESTOP
    assert parse_predicate("motionFinished/mi.msg") == F("motionFinished/mi", "msg")
    assert parse_predicate("motionFinished/m.data") == F("motionFinished/m", "data")
    assert parse_predicate("state/ib.msg.pose.position.x") == F(
        "state/ib", "msg", "pose", "position", "x"
    )
    assert parse_predicate("currentJointPos/mi.data.q") == F("currentJointPos/mi", "data", "q")


def test_a_path_segment_may_carry_an_array_index() -> None:
    assert parse_predicate("currentJointPos/mi.data.q[2] > 0") == Compare(
        ">", F("currentJointPos/mi", "data", "q[2]"), Number(0)
    )


def test_reference_nodes_split_their_names() -> None:
    assert ESTOP.base == "emergencyStop" and ESTOP.suffix == "pp"
    assert P("emergencyStop").suffix is None
    assert MANIP_ESTOP.base == "manipulatorCommand" and MANIP_ESTOP.suffix == "ib"


# ---------------------------------------------------------------------------- newData and comparisons


def test_new_data_takes_a_field_reference() -> None:
    assert parse_predicate("newData(manipulatorCommand/ib.msg.jointPosSetpoint)") == NewData(
        F("manipulatorCommand/ib", "msg", "jointPosSetpoint")
    )
    assert parse_predicate("newData(state/ib)") == NewData(F("state/ib"))


def test_new_data_combines_with_other_operators() -> None:
    assert parse_predicate("newData(a/ib.msg.x) ∧ ¬newData(b/ib.msg)") == And(
        (NewData(F("a/ib", "msg", "x")), Not(NewData(F("b/ib", "msg"))))
    )


def test_a_predicate_named_new_data_is_still_a_predicate() -> None:
    assert parse_predicate("newData/pp ∧ a") == And((P("newData/pp"), P("a")))


@pytest.mark.parametrize(
    ("written", "normalised"),
    [("<", "<"), ("<=", "<="), (">", ">"), (">=", ">="), ("==", "=="), ("!=", "!="),
     ("=", "=="), ("≤", "<="), ("≥", ">="), ("≠", "!=")],
)
def test_comparison_operators_are_normalised(written: str, normalised: str) -> None:
    expected = Compare(normalised, F("state/ib", "msg", "speed"), Number(0.5))
    assert parse_predicate(f"state/ib.msg.speed {written} 0.5") == expected
    assert parse_predicate(f"state/ib.msg.speed{written}0.5") == expected


@pytest.mark.parametrize(
    ("literal", "value"),
    [("3", 3.0), ("-3", -3.0), ("+3", 3.0), ("0.5", 0.5), (".5", 0.5), ("2.", 2.0),
     ("-1.5e-3", -0.0015), ("1E6", 1e6)],
)
def test_numeric_literals_are_ints_floats_negatives_and_exponents(literal: str, value: float) -> None:
    assert parse_predicate(f"x/mi.data > {literal}") == Compare(">", F("x/mi", "data"), Number(value))


def test_a_number_may_stand_left_and_fields_on_both_sides() -> None:
    assert parse_predicate("0 < a/ib.msg.v") == Compare("<", Number(0), F("a/ib", "msg", "v"))
    assert parse_predicate("a/ib.msg.v != b/mi.data") == Compare(
        "!=", F("a/ib", "msg", "v"), F("b/mi", "data")
    )


def test_comparisons_bind_tighter_than_boolean_operators() -> None:
    assert parse_predicate("¬a/ib.msg.v >= 1 ∧ b") == And(
        (Not(Compare(">=", F("a/ib", "msg", "v"), Number(1))), P("b"))
    )


# ---------------------------------------------------------------------------- replication

REPLICATED_ESTOP = Replicated("or", MOTOR_ESTOP, "K")


@pytest.mark.parametrize(
    "text",
    [
        "motorControllerState1/ib.msg.emergencyStopCommand ∨ … ∨ motorControllerStateN/ib.msg.emergencyStopCommand",
        "motorControllerState1/ib.msg.emergencyStopCommand or ... or motorControllerStateN/ib.msg.emergencyStopCommand",
        "motorControllerState1/ib.msg.emergencyStopCommand || … || motorControllerStateN/ib.msg.emergencyStopCommand",
        "any K: motorControllerStateK/ib.msg.emergencyStopCommand",
        "∃K: motorControllerStateK/ib.msg.emergencyStopCommand",
        "∃ K : (motorControllerStateK/ib.msg.emergencyStopCommand)",
    ],
)
def test_the_ellipsis_and_the_quantifier_forms_give_the_same_tree(text: str) -> None:
    assert parse_predicate(text) == REPLICATED_ESTOP


@pytest.mark.parametrize(
    "text",
    [
        "emergencyStopCommand1/mi.data ∧ … ∧ emergencyStopCommandN/mi.data",
        "emergencyStopCommand1/mi.data and ... && emergencyStopCommandN/mi.data",
        "all K: emergencyStopCommandK/mi.data",
        "∀K: emergencyStopCommandK/mi.data",
    ],
)
def test_a_replicated_conjunction_has_both_forms_too(text: str) -> None:
    assert parse_predicate(text) == Replicated("and", F("emergencyStopCommandK/mi", "data"))


def test_the_ellipsis_form_is_one_operand_of_a_bigger_chain() -> None:
    table_5 = TABLE_5["emergencyStop/pp"][0]
    quantified = ("manipulatorCommand/ib.msg.emergencyStopCommand ∨ "
                  "(any K: motorControllerStateK/ib.msg.emergencyStopCommand)")
    assert parse_predicate(table_5) == parse_predicate(quantified) == Or((MANIP_ESTOP, REPLICATED_ESTOP))
    assert parse_predicate("a1 ∨ … ∨ aN ∨ b") == Or((Replicated("or", P("aK")), P("b")))
    assert parse_predicate("x ∧ a1 ∧ … ∧ aN ∧ y") == And((P("x"), Replicated("and", P("aK")), P("y")))
    assert parse_predicate("x ∨ a1 ∧ … ∧ aN") == Or((P("x"), Replicated("and", P("aK"))))


def test_the_replicated_template_may_be_a_compound_expression() -> None:
    expected = Replicated("or", And((F("aK/ib", "msg", "on"), Not(P("b")))))
    assert parse_predicate("a1/ib.msg.on ∧ ¬b ∨ … ∨ aN/ib.msg.on ∧ ¬b") == expected
    assert parse_predicate("(a1/ib.msg.on ∧ ¬b) ∨ … ∨ (aN/ib.msg.on ∧ ¬b)") == expected
    assert parse_predicate("any K: aK/ib.msg.on ∧ ¬b") == expected


def test_only_names_that_change_from_1_to_n_carry_the_placeholder() -> None:
    assert parse_predicate("a1 ∧ motor1/ib ∨ … ∨ aN ∧ motor1/ib") == Replicated(
        "or", And((P("aK"), F("motor1/ib")))
    )


def test_the_quantifier_body_reaches_as_far_right_as_possible() -> None:
    assert parse_predicate("x ∧ any K: aK ∨ b") == And(
        (P("x"), Replicated("or", Or((P("aK"), P("b")))))
    )
    assert parse_predicate("x ∧ (any K: aK) ∨ b") == Or(
        (And((P("x"), Replicated("or", P("aK")))), P("b"))
    )


def test_the_quantifier_keeps_its_variable() -> None:
    assert parse_predicate("all J: motorJ/ib.msg.ok") == Replicated("and", F("motorJ/ib", "msg", "ok"), "J")


# ---------------------------------------------------------------------------- substitution and expansion


def test_substitute_index_replaces_the_placeholder_before_the_suffix() -> None:
    assert substitute_index(MOTOR_ESTOP, "K", 3) == F("motorControllerState3/ib", "msg", "emergencyStopCommand")
    assert substitute_index(P("emergencyStopCommandK"), "K", 2) == P("emergencyStopCommand2")


def test_substitute_index_touches_only_the_trailing_index_position() -> None:
    expr = parse_predicate("Kinematics/ib.msg.K ∧ aKb/pp ∧ K/pp ∧ newData(xK/ib.msg.vK) ∧ yK/mi.data < 2")
    assert substitute_index(expr, "K", 7) == parse_predicate(
        "Kinematics/ib.msg.K ∧ aKb/pp ∧ K/pp ∧ newData(x7/ib.msg.vK) ∧ y7/mi.data < 2"
    )


def test_substitute_index_leaves_a_nested_replication_over_the_same_variable_alone() -> None:
    inner = Replicated("and", P("bK"))
    assert substitute_index(And((P("aK"), inner)), "K", 1) == And((P("a1"), inner))


def test_expand_replicated_joins_the_instances_into_the_surrounding_chain() -> None:
    expr = parse_predicate(TABLE_5["emergencyStop/pp"][0])
    counts: list[Replicated] = []

    def count_for(node: Replicated) -> int:
        counts.append(node)
        return 3

    expanded = expand_replicated(expr, count_for)
    assert expanded == Or(
        (MANIP_ESTOP,)
        + tuple(F(f"motorControllerState{k}/ib", "msg", "emergencyStopCommand") for k in (1, 2, 3))
    )
    assert counts == [REPLICATED_ESTOP]


def test_expand_replicated_leaves_nodes_without_a_count() -> None:
    expr = parse_predicate("a ∧ all K: bK")
    assert expand_replicated(expr, lambda node: None) == expr


def test_expand_replicated_handles_one_and_zero_instances() -> None:
    assert expand_replicated(parse_predicate("x ∧ any K: aK"), lambda node: 1) == And((P("x"), P("a1")))
    assert expand_replicated(parse_predicate("any K: aK"), lambda node: 0) == Const(False)
    assert expand_replicated(parse_predicate("all K: aK"), lambda node: 0) == Const(True)
    with pytest.raises(ValueError):
        expand_replicated(parse_predicate("any K: aK"), lambda node: -1)


def test_expand_replicated_expands_a_compound_template() -> None:
    expr = parse_predicate("all K: aK/ib.msg.ok ∨ newData(bK/ib.msg)")
    assert expand_replicated(expr, lambda node: 2) == parse_predicate(
        "(a1/ib.msg.ok ∨ newData(b1/ib.msg)) ∧ (a2/ib.msg.ok ∨ newData(b2/ib.msg))"
    )


# ---------------------------------------------------------------------------- walking


def test_walk_visits_every_node_parents_first_in_text_order() -> None:
    expr = parse_predicate("a ∧ ¬newData(b/ib.msg) ∨ c/ib.msg.v > 2")
    kinds = [type(node).__name__ for node in walk(expr)]
    assert kinds == ["Or", "And", "PredicateRef", "Not", "NewData", "FieldRef",
                     "Compare", "FieldRef", "Number"]


def test_references_include_new_data_comparisons_and_templates() -> None:
    expr = parse_predicate(TABLE_5["emergencyStop/pp"][0] + " ∨ newData(x/ib.msg) ∨ y/mi.data >= 1 ∨ z/pp")
    assert list(references(expr)) == [
        MANIP_ESTOP, MOTOR_ESTOP, F("x/ib", "msg"), F("y/mi", "data"), P("z/pp"),
    ]


# ---------------------------------------------------------------------------- evaluation


@pytest.mark.parametrize(("new_joint", "estop"), list(itertools.product([False, True], repeat=2)))
def test_evaluate_follows_the_truth_table(new_joint: bool, estop: bool) -> None:
    values = {"newJointPos/pp": new_joint, "emergencyStop/pp": estop}
    expr = parse_predicate(TABLE_6["idle,jointMove/t"][0])
    result = evaluate(expr, lambda ref: values[ref.name], lambda ref: None, lambda ref: False)
    assert result is (new_joint and not estop)
    terminal = parse_predicate("newJointPos/pp ∨ emergencyStop/pp ∨ FALSE")
    assert evaluate(terminal, lambda ref: values[ref.name], lambda ref: None, lambda ref: False) is (
        new_joint or estop
    )


def test_evaluate_reads_fields_new_data_and_comparisons() -> None:
    fields = {("state/ib", ("speed",)): 0.7, ("flag/mi", ()): True}
    fresh = {"cmd/ib"}

    def field_value(ref: FieldRef) -> object:
        return fields[(ref.head, ref.path)]

    def new_data(ref: FieldRef) -> bool:
        return ref.head in fresh

    def run(text: str) -> bool:
        return evaluate(parse_predicate(text), lambda ref: False, field_value, new_data)

    assert run("state/ib.msg.speed >= 0.5") is True
    assert run("state/ib.msg.speed < 0.5") is False
    assert run("0.7 == state/ib.msg.speed") is True
    assert run("flag/mi.data ∧ newData(cmd/ib.msg.x)") is True
    assert run("newData(other/ib.msg)") is False


def test_evaluate_short_circuits_from_left_to_right() -> None:
    asked: list[str] = []

    def predicate_value(ref: PredicateRef) -> bool:
        asked.append(ref.name)
        return ref.name == "a"

    assert evaluate(parse_predicate("a ∨ b"), predicate_value, lambda r: None, lambda r: False)
    assert asked == ["a"]


def test_evaluate_refuses_a_replication_that_was_not_expanded() -> None:
    with pytest.raises(ValueError, match="expand"):
        evaluate(parse_predicate("any K: aK"), lambda r: True, lambda r: None, lambda r: False)
    expanded = expand_replicated(parse_predicate("any K: aK"), lambda node: 2)
    assert evaluate(expanded, lambda r: r.name == "a2", lambda r: None, lambda r: False)


# ---------------------------------------------------------------------------- printing

ROUND_TRIP = [
    *(text for text, _ in TABLE_5.values()),
    *(text for text, _ in TABLE_6.values()),
    "a ∨ b ∧ ¬c",
    "(a ∨ b) ∧ c",
    "¬(a ∧ b) ∨ ¬¬c",
    "TRUE ∧ false.fun ∧ x/ib.fun ∧ x/mo ∧ not.fun ∧ any.fun",
    "newData(a/ib.msg.x) ∧ newData(b/ib)",
    "s/ib.msg.pose.position.x >= -1.5e-3 ∧ 2 != q/mi.data.q[3] ∧ v/ib.msg.v < 1e20",
    "x ∨ a1 ∨ … ∨ aN ∨ y",
    "x ∧ a1 ∧ … ∧ aN ∧ y",
    "a1 ∧ … ∧ aN ∨ b1 ∧ … ∧ bN",
    "a1 ∨ … ∨ aN ∨ a1 ∨ … ∨ aN",
    "(a1 ∨ … ∨ aN) ∧ ¬(b1 ∨ … ∨ bN)",
    "(a1 ∨ c) ∧ … ∧ (aN ∨ c)",
    "any K: aK ∨ b",
    "x ∧ (any K: aK ∨ b) ∧ y",
    "¬(all J: aJ) ∨ b",
    "any K: all J: aKJ/ib.msg ∧ bK",
    "all K: K/pp ∨ motorK/ib",
]


@pytest.mark.parametrize("style", ["unicode", "ascii"])
@pytest.mark.parametrize("text", ROUND_TRIP)
def test_printing_and_parsing_again_gives_the_same_tree(text: str, style: str) -> None:
    expr = parse_predicate(text)
    assert parse_predicate(format_predicate(expr, style)) == expr  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("text", "unicode", "ascii"),
    [
        ("(a ∨ b) ∧ c", "(a ∨ b) ∧ c", "(a or b) and c"),
        ("a ∨ (b ∧ c)", "a ∨ b ∧ c", "a or b and c"),
        ("((¬(a)))", "¬a", "not a"),
        ("¬(a ∨ b)", "¬(a ∨ b)", "not (a or b)"),
        ("true ∨ FALSE", "TRUE ∨ FALSE", "true or false"),
        ("x/ib.msg.v = 3.0", "x/ib.msg.v == 3", "x/ib.msg.v == 3"),
        ("x ∧ ∃K: aK", "x ∧ (a1 ∨ … ∨ aN)", "x and any K: aK"),
        ("(∃K: aK) ∧ x", "(a1 ∨ … ∨ aN) ∧ x", "(any K: aK) and x"),
        ("∀J: aJ", "∀J: aJ", "all J: aJ"),
        ("(∀J: aJ) ∧ b", "(∀J: aJ) ∧ b", "(all J: aJ) and b"),
    ],
)
def test_printing_uses_the_fewest_parentheses(text: str, unicode: str, ascii: str) -> None:
    expr = parse_predicate(text)
    assert format_predicate(expr) == unicode
    assert format_predicate(expr, "ascii") == ascii


def test_printing_rejects_an_unknown_style() -> None:
    with pytest.raises(ValueError):
        format_predicate(P("a"), "latex")  # type: ignore[arg-type]


# ---------------------------------------------------------------------------- positions and equality


def test_nodes_carry_the_line_and_column_of_their_first_character() -> None:
    expr = parse_predicate("newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun")
    assert isinstance(expr, And)
    assert (expr.line, expr.column) == (1, 1)
    negation = expr.operands[1]
    assert isinstance(negation, Not)
    assert negation.column == 22
    assert negation.operand.column == 23


def test_positions_count_lines_and_ignore_carriage_returns() -> None:
    expr = parse_predicate("a ∧\r\n  newData(\n  b/ib.msg)")
    assert isinstance(expr, And)
    new_data = expr.operands[1]
    assert isinstance(new_data, NewData)
    assert (new_data.line, new_data.column) == (2, 3)
    assert (new_data.ref.line, new_data.ref.column) == (3, 3)


def test_positions_do_not_take_part_in_equality_or_hashing() -> None:
    a, b = parse_predicate("a ∧ b"), parse_predicate("  a\n∧   b")
    assert a == b and hash(a) == hash(b)
    assert PredicateRef("x", line=2, column=5) == P("x")
    assert len({parse_predicate("x ∨ y"), parse_predicate("x or y")}) == 1


def test_nodes_are_immutable() -> None:
    with pytest.raises(AttributeError):
        P("a").name = "b"  # type: ignore[misc]


# ---------------------------------------------------------------------------- errors


@pytest.mark.parametrize(
    ("text", "line", "column", "message"),
    [
        ("a ∧ ∧ b", 1, 5, "expected a predicate name or '(' at column 5, found '∧'"),
        ("emergencyStop/pp ∧ ∧ x", 1, 20, "expected a predicate name or '(' at column 20, found '∧'"),
        ("(a ∧ b", 1, 7, "expected ')' or an operator at column 7, found the end of the text"),
        ("((a ∧ b)", 1, 9, "expected ')' or an operator at column 9, found the end of the text"),
        ("a ∧ b)", 1, 6, "expected an operator or the end of the text at column 6, found ')'"),
        ("newData(x/pp", 1, 13, "expected ')' at column 13, found the end of the text"),
        ("a b", 1, 3, "expected an operator or the end of the text at column 3, found 'b'"),
        ("x/ib.foo", 1, 6, "expected 'msg', 'data' or 'fun' at column 6, found 'foo'"),
        ("a <=", 1, 5, "expected a field reference or a number at column 5, found the end of the text"),
        ("3", 1, 2, "expected a comparison operator at column 2, found the end of the text"),
        ("a ∧\n  ∨ b", 2, 3, "expected a predicate name or '(' at line 2, column 3, found '∨'"),
        ("a ∨", 1, 4, "expected a predicate name or '(' at column 4, found the end of the text"),
    ],
)
def test_syntax_errors_name_what_was_expected_and_where(text: str, line: int, column: int, message: str) -> None:
    with pytest.raises(PredicateSyntaxError) as caught:
        parse_predicate(text)
    assert (caught.value.line, caught.value.column) == (line, column)
    assert caught.value.message == message
    assert str(caught.value) == message


@pytest.mark.parametrize("text", ["", "   ", "\r\n\t"])
def test_empty_text_is_an_error(text: str) -> None:
    with pytest.raises(PredicateSyntaxError, match="empty") as caught:
        parse_predicate(text)
    assert (caught.value.line, caught.value.column) == (1, 1)


@pytest.mark.parametrize(
    ("text", "column", "fragment"),
    [
        ("a2 ∨ … ∨ aN", 1, "must use index 1"),
        ("x ∨ motor0/ib ∨ … ∨ motorN/ib", 5, "must use index 1"),
        ("a1 ∨ … ∨ a3", 10, "must use index N"),
        ("a1/ib.msg.x ∨ … ∨ aN/ib.msg.y", 19, "does not repeat"),
        ("a1 ∨ … ∨ bN", 10, "does not repeat"),
        ("a1 ∧ c ∨ … ∨ aN ∧ d", 19, "does not repeat"),
        ("a1 ∨ … ∨ newData(aN/ib)", 10, "does not repeat"),
        ("a ∨ … ∨ a", 5, "no replicated name"),
        ("… ∨ aN", 1, "'…' must stand between two operands"),
        ("a1 ∨ …", 6, "'…' must stand between two operands"),
        ("a1 ∨ … ∧ aN", 6, "'…' must stand between two operands"),
        ("a1 ∨ … ∨ … ∨ aN", 6, "'…' must stand between two operands"),
        ("a1 ∨ … ∨ aN ∨ … ∨ bN", 15, "'…' must stand between two operands"),
        ("any K: a ∨ b", 1, "names no replicated instance"),
    ],
)
def test_malformed_replications_are_syntax_errors_with_a_column(text: str, column: int, fragment: str) -> None:
    with pytest.raises(PredicateSyntaxError) as caught:
        parse_predicate(text)
    assert caught.value.column == column
    assert fragment in caught.value.message
    assert f"column {column}" in caught.value.message


@pytest.mark.parametrize(
    "text",
    ["newData(x/pp.fun)", "x/pp.fun < 3", "2 >= y.fun"],
)
def test_a_predicate_with_fun_is_rejected_where_a_field_is_needed(text: str) -> None:
    with pytest.raises(PredicateSyntaxError, match="not the predicate"):
        parse_predicate(text)


@pytest.mark.parametrize("text", ["a ∧ ∧ b", "(", "x/", "any K:", "a1 ∨ … ∨ bN", "¬"])
def test_textx_exceptions_never_escape(text: str) -> None:
    with pytest.raises(PredicateSyntaxError) as caught:
        parse_predicate(text)
    assert not isinstance(caught.value, TextXError)
    assert caught.value.__cause__ is None


# ---------------------------------------------------------------------------- grammar and speed


def test_the_grammar_is_data_and_its_metamodel_is_built_once() -> None:
    assert metamodel_path("grammar", "predicate.tx").is_file()
    assert _metamodel() is _metamodel()


def test_parsing_a_200_term_expression_is_linear() -> None:
    """The work of a parse, counted in Python function calls (deterministic, unlike a time on a
    loaded machine), grows linearly with the number of terms."""
    def text(n: int) -> str:
        return " ∨ ".join(f"(s{i}/ib.msg.v >= {i}.5 ∧ ¬p{i}/pp.fun)" for i in range(n))

    parse_predicate(text(2))  # build the metamodel first

    def calls(n: int) -> int:
        expr, count = counted_calls(lambda: parse_predicate(text(n)))
        assert isinstance(expr, Or) and len(expr.operands) == n
        return count

    small, large = calls(100), calls(200)
    assert large < 2.2 * small  # linear: no quadratic (or exponential) blow-up
