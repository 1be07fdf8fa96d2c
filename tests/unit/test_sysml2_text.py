"""The pieces of SysML v2 reading and writing: conditions between SysML v2 expressions and
the predicate language, textual representation bodies, names, and how constructs outside
the subset are named."""

from __future__ import annotations

import pytest

from earl_m2t.convert.names import expression, quoted
from earl_m2t.sysml2.conditions import NotACondition, predicate_text
from earl_m2t.sysml2.parser import members, parse_text, rule, unwrap
from earl_m2t.sysml2.subset import outside_constructs
from earl_m2t.sysml2.texts import representation_text


def condition(text: str) -> str:
    (constraint,) = members(parse_text(f"constraint c {{ {text} }}", model=True))
    (result,) = members(constraint)
    assert rule(result) == "ResultExpression"
    return predicate_text(unwrap(result.expression))


@pytest.mark.parametrize(("written", "read"), [
    ("'newJointPos/pp'() and not 'emergencyStop/pp'()", "newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun"),
    ("'newJointPos/pp'.fun and not 'emergencyStop/pp'.fun", "newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun"),
    ("a or b and c", "a ∨ b ∧ c"),
    ("(a or b) and c", "(a ∨ b) ∧ c"),
    ("not (a and b)", "¬(a ∧ b)"),
    ("true or false", "TRUE ∨ FALSE"),
    ("'state/ib'.msg.speed >= 0.5", "state/ib.msg.speed >= 0.5"),
    ("newData('cmd/ib'.msg.setpoint)", "newData(cmd/ib.msg.setpoint)"),
    # a sequence counts from 1 (#), the predicate language's index from 0
    ("'pos/ib'.msg.q#(6) > 0.5", "pos/ib.msg.q[5] > 0.5"),
    ("'cmd/ib'.msg.setpoint#(1).q#(2) < 1", "cmd/ib.msg.setpoint[0].q[1] < 1"),
])
def test_a_sysml_v2_expression_reads_as_predicate_text(written: str, read: str) -> None:
    assert condition(written) == read


def test_a_sequence_has_no_element_0() -> None:
    with pytest.raises(NotACondition, match=r"#\(0\): the elements of a sequence are numbered from 1"):
        condition("'pos/ib'.msg.q#(0) > 0.5")


def test_two_names_without_an_operator_are_no_expression() -> None:
    (constraint,) = members(parse_text("constraint c { a b }", model=True))
    assert [rule(m) for m in members(constraint)] == ["OutsideSubset"]


@pytest.mark.parametrize("text", [
    "newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun",
    "motionFinished/pp.fun ∨ emergencyStop/pp.fun",
    "FALSE",
    "newData(manipulatorCommand/ib.msg.jointPosSetpoint)",
    "(a/pp.fun ∨ b/pp.fun) ∧ ¬c/pp.fun",
    "state/ib.msg.speed >= 0.5",
    "pos/ib.msg.q[5] > 0.5",
    "newData(cmd/ib.msg.setpoint[0].q[1])",
])
def test_predicate_text_is_written_as_an_expression_that_reads_back_the_same(text: str) -> None:
    written = expression(text)
    assert written is not None and condition(written) == text


def test_a_primitive_predicate_is_invoked_not_navigated() -> None:
    """`x/pp` is a `calc def`, not a feature: SysML v2 tools accept `'x/pp'()` as a Boolean
    guard, not `'x/pp'.fun`."""
    assert expression("a/pp.fun ∧ ¬b/pp.fun") == "'a/pp'() and not 'b/pp'()"
    assert expression("newData(c/ib.msg.x) ∨ d/m") == "newData('c/ib'.msg.x) or 'd/m'"


@pytest.mark.parametrize("text", [
    "a/ib.msg.x ∨ … ∨ b/ib.msg.x",  # the paper's ellipsis
    "any K: motorControllerStateK/ib.msg.emergencyStopCommand",
    "a/pp.fun∧b/pp.fun",  # reads back with spaces: not the same text
    "a && b",
    "taskAborted/pp",  # a calculation definition, not a Boolean
    "motionFinished/mi.msg",  # a memory access of a function, not a feature of the subsystem
    "temperature/mi.data < 19.5",
    "x/mo.data ∧ a/pp.fun",
])
def test_predicate_text_no_expression_says_exactly_is_kept_as_text(text: str) -> None:
    assert expression(text) is None


@pytest.mark.parametrize(("name", "written"), [
    ("cs", "cs"), ("manip/a", "'manip/a'"), ("filter", "'filter'"), ("it's", "'it\\'s'"), ("2x", "'2x'"),
])
def test_names_are_quoted_when_they_must_be(name: str, written: str) -> None:
    assert quoted(name) == written


@pytest.mark.parametrize(("body", "text"), [
    ("/* // one line */", "// one line"),
    ("/*\n * first\n *     indented\n */", "first\n    indented"),
    ("/* if (x) {\n          y();\n      } */", "if (x) {\n    y();\n}"),
    ("/**/", ""),
])
def test_the_text_of_a_textual_representation(body: str, text: str) -> None:
    assert representation_text(body) == text


def test_constructs_outside_the_subset_are_named_by_their_leading_words() -> None:
    root = parse_text(
        "package P {\n"
        "    part def A {\n"
        "        perform action x;\n"
        "        mass = 1750 [kg];\n"
        "        attribute m : Real default 2 [kg];\n"
        "        constraint c { m * 2 > 3 }\n"
        "        requirement r;\n"
        "    }\n"
        "    use case def U { subject s; }\n"
        "}\n",
        model=True,
    )
    found = [(o.construct, o.line, o.column) for o in outside_constructs(root)]
    assert found == [
        ("perform action", 3, 9),
        ("feature mass with a value expression", 4, 9),
        ("attribute with a value expression", 5, 9),
        ("expression", 6, 24),
        ("requirement", 7, 9),
        ("use case", 9, 5),
    ]


def test_a_construct_read_in_part_is_named_by_the_part_outside_the_subset() -> None:
    root = parse_text(
        "state def S {\n"
        "    state a parallel { state b; }\n"
        "    transition t first a accept go then a;\n"
        "    transition a do send x then a;\n"
        "    exhibit state e;\n"
        "}\n",
        model=True,
    )
    assert [o.construct for o in outside_constructs(root)] == [
        "state … parallel", "transition … accept", "transition … do"]
