"""The OCL-like constraint language: parsing, evaluation, errors."""

from __future__ import annotations

from dataclasses import dataclass, field

import pytest

from earl_m2t.deep_stack import call_with_deep_stack
from earl_m2t.ocl import (
    Invariant,
    OclEvaluationError,
    OclSyntaxError,
    check,
    evaluate,
    parse_expression,
    parse_invariants,
)
from tests.support.calls import counted_calls

# ---------------------------------------------------------------------------- model objects


@dataclass(eq=False)
class Buffer:
    name: str
    data_type: str | None = "Int32"


@dataclass(eq=False)
class Subsystem:
    name: str
    kind: str
    inputs: list[Buffer] = field(default_factory=list)
    outputs: list[Buffer] = field(default_factory=list)
    priority: int = 0


@dataclass(eq=False)
class Agent:
    name: str
    cs: list[Subsystem] = field(default_factory=list)
    ve: list[Subsystem] = field(default_factory=list)
    re: list[Subsystem] = field(default_factory=list)
    vr: list[Subsystem] = field(default_factory=list)
    rr: list[Subsystem] = field(default_factory=list)
    leader: Agent | None = None

    @property
    def subsystems(self) -> tuple[Subsystem, ...]:
        return (*self.cs, *self.ve, *self.re, *self.vr, *self.rr)


@dataclass(eq=False)
class Robot:
    name: str
    agents: list[Agent] = field(default_factory=list)


@dataclass(eq=False)
class System:
    robots: list[Robot] = field(default_factory=list)
    agents: list[Agent] = field(default_factory=list)


def make_agent(name: str = "manip", ve: int = 1, rr: int = 0) -> Agent:
    cs = Subsystem("control", "cs", [Buffer("cmd")], [Buffer("status")])
    effectors = [
        Subsystem(f"motor{i}", "ve", [Buffer("in")], [Buffer("out", None)]) for i in range(ve)
    ]
    real = [Subsystem(f"driver{i}", "re", [Buffer("in")]) for i in range(ve)]
    receptors = [Subsystem(f"camera{i}", "rr", [], [Buffer("image")]) for i in range(rr)]
    return Agent(name, [cs], effectors, real, [], receptors)


def ev(text: str, self_obj: object = None, **variables: object) -> object:
    return evaluate(parse_expression(text), self_obj, variables)


RULES = """\
-- structural rules of the EARL metamodel
context Agent inv S004: self.vr->notEmpty() = self.rr->notEmpty()
context Agent inv S003: self.cs->size() = 1
context Subsystem inv S008_ve: self.kind = 've' implies (self.inputs->notEmpty() and self.outputs->notEmpty())
context System inv S001: self.robots->notEmpty()
context Agent inv team_limit: self.ve->size() <= 8
context Subsystem inv naming: self.name.matches('^[a-z][A-Za-z0-9]*$')
"""


# ---------------------------------------------------------------------------- invariant files


def test_an_invariant_file_gives_context_name_source_and_position_of_each_invariant() -> None:
    invariants = parse_invariants(RULES, "rules.ocl")
    assert [(i.context, i.name, i.line, i.column) for i in invariants] == [
        ("Agent", "S004", 2, 1),
        ("Agent", "S003", 3, 1),
        ("Subsystem", "S008_ve", 4, 1),
        ("System", "S001", 5, 1),
        ("Agent", "team_limit", 6, 1),
        ("Subsystem", "naming", 7, 1),
    ]
    assert invariants[0].source == "self.vr->notEmpty() = self.rr->notEmpty()"
    assert all(isinstance(i, Invariant) for i in invariants)


def test_the_catalogue_rules_hold_on_a_well_formed_agent_and_fail_on_a_broken_one() -> None:
    rules = {i.name: i for i in parse_invariants(RULES)}
    good = make_agent()
    assert check(rules["S003"], good) and check(rules["S004"], good)
    assert check(rules["team_limit"], good)
    assert all(check(rules["naming"], s) for s in good.subsystems)
    assert check(rules["S008_ve"], good.ve[0]) and check(rules["S008_ve"], good.re[0])
    broken = make_agent(rr=1, ve=9)
    broken.cs.append(Subsystem("second", "cs"))
    broken.ve[0].outputs.clear()
    assert not check(rules["S003"], broken)
    assert not check(rules["S004"], broken)
    assert not check(rules["team_limit"], broken)
    assert not check(rules["S008_ve"], broken.ve[0])
    assert not check(rules["naming"], Subsystem("Motor_1", "ve"))
    assert check(rules["S001"], System([Robot("r", [good])]))
    assert not check(rules["S001"], System())


def test_an_empty_file_and_a_file_of_comments_have_no_invariants() -> None:
    assert parse_invariants("") == []
    assert parse_invariants("-- nothing here\n   -- still nothing\n") == []


def test_an_invariant_may_span_lines_and_carry_trailing_comments() -> None:
    text = (
        "context Agent inv spread:\n"
        "    self.ve->notEmpty()  -- at least one\n"
        "    implies self.re->notEmpty()\n"
        "-- next rule\n"
        "context Agent inv other: true\n"
    )
    first, second = parse_invariants(text)
    assert first.source == "self.ve->notEmpty()  -- at least one\n    implies self.re->notEmpty()"
    assert check(first, make_agent())
    assert (second.line, second.column) == (5, 1)


def test_an_invariant_name_may_start_with_a_digit_and_a_context_may_be_qualified() -> None:
    (invariant,) = parse_invariants("context Model::Agent inv 1st_rule: true")
    assert (invariant.context, invariant.name) == ("Model::Agent", "1st_rule")


def test_invariants_are_frozen() -> None:
    (invariant,) = parse_invariants("context A inv x: true")
    with pytest.raises(AttributeError):
        invariant.name = "y"  # type: ignore[misc]


def test_check_requires_a_boolean_result() -> None:
    (invariant,) = parse_invariants("context Agent inv count: self.ve->size()")
    with pytest.raises(OclEvaluationError, match="count.*Boolean"):
        check(invariant, make_agent())


# ---------------------------------------------------------------------------- literals


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("42", 42),
        ("3.5", 3.5),
        ("1e3", 1000.0),
        ("2.5E-1", 0.25),
        ("-7", -7),
        ("'robot'", "robot"),
        (r"'it\'s'", "it's"),
        (r"'a\\b'", "a\\b"),
        ("''", ""),
        ("true", True),
        ("false", False),
        ("null", None),
    ],
)
def test_literals_evaluate_to_python_values(text: str, value: object) -> None:
    result = ev(text)
    assert result == value and type(result) is type(value)


# ---------------------------------------------------------------------------- operators


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("1 + 2", 3),
        ("5 - 7", -2),
        ("3 * 4", 12),
        ("7 / 2", 3.5),
        ("1 + 2 * 3", 7),
        ("(1 + 2) * 3", 9),
        ("10 - 2 - 3", 5),
        ("12 / 2 / 3", 2.0),
        ("- (2 + 3)", -5),
        ("2 - -3", 5),
        ("'ab' + 'cd'", "abcd"),
    ],
)
def test_arithmetic_follows_the_usual_precedence(text: str, value: object) -> None:
    assert ev(text) == value


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ("1 = 1", True),
        ("1 = 2", False),
        ("1 <> 2", True),
        ("'a' <> 'a'", False),
        ("1 < 2", True),
        ("2 > 3", False),
        ("2 <= 2", True),
        ("3 >= 4", False),
        ("'abc' < 'abd'", True),
        ("1 = 1.0", True),
        ("null = null", True),
        ("1 + 1 = 2", True),
        ("1 < 2 = true", True),
    ],
)
def test_comparisons(text: str, value: bool) -> None:
    assert ev(text) is value


@pytest.mark.parametrize(
    ("a", "b", "and_", "or_", "xor", "implies"),
    [
        (True, True, True, True, False, True),
        (True, False, False, True, True, False),
        (False, True, False, True, True, True),
        (False, False, False, False, False, True),
    ],
)
def test_boolean_operators_follow_their_truth_tables(
    a: bool, b: bool, and_: bool, or_: bool, xor: bool, implies: bool
) -> None:
    assert ev("a and b", a=a, b=b) is and_
    assert ev("a or b", a=a, b=b) is or_
    assert ev("a xor b", a=a, b=b) is xor
    assert ev("a implies b", a=a, b=b) is implies
    assert ev("not a", a=a) is (not a)


def test_not_binds_tighter_than_and() -> None:
    # (not a) and b, not not (a and b)
    assert ev("not a and b", a=False, b=True) is True
    assert ev("not a and b", a=True, b=False) is False


def test_implies_binds_looser_than_and() -> None:
    # a implies (b and c), not (a implies b) and c
    assert ev("a implies b and c", a=False, b=True, c=False) is True


def test_comparison_binds_tighter_than_and_or() -> None:
    assert ev("1 < 2 and 3 > 2") is True
    assert ev("x = 1 or x = 2", x=2) is True


def test_arithmetic_binds_tighter_than_comparison() -> None:
    assert ev("1 + 2 * 3 = 7") is True
    assert ev("2 * 3 > 5 and 10 - 4 <= 6") is True
    assert ev("not (1 + 1 = 3)") is True


def test_and_or_xor_share_one_level_and_associate_to_the_left() -> None:
    # (true or false) and false = false; true or (false and false) would be true
    assert ev("true or false and false") is False
    assert ev("false and true or true") is True


def test_implies_chains_associate_to_the_left() -> None:
    # (false implies false) implies false = false
    assert ev("false implies false implies false") is False


def test_and_or_implies_do_not_evaluate_a_decided_right_side() -> None:
    agent = make_agent()
    assert ev("false and self.missing", agent) is False
    assert ev("true or self.missing", agent) is True
    assert ev("false implies self.missing", agent) is True


def test_keywords_are_whole_words() -> None:
    assert ev("android", android=1) == 1
    assert ev("notes and order", notes=True, order=True) is True
    assert ev("selfish", selfish="x") == "x"


# ---------------------------------------------------------------------------- if and let


def test_if_then_else_chooses_a_branch() -> None:
    assert ev("if 1 < 2 then 'yes' else 'no' endif") == "yes"
    assert ev("if x then 1 else if y then 2 else 3 endif endif", x=False, y=False) == 3


def test_let_binds_a_variable_for_its_body() -> None:
    assert ev("let n = 2 + 3 in n * n") == 25
    assert ev("let n = self.ve->size() in n = 1 and n > 0", make_agent()) is True


def test_let_shadows_and_restores_an_outer_variable() -> None:
    assert ev("(let x = 2 in x) + x", x=10) == 12


def test_let_in_an_iterator_body() -> None:
    agent = make_agent(ve=3)
    text = "self.ve->forAll(s | let n = s.name in n.startsWith('motor'))"
    assert ev(text, agent) is True


# ---------------------------------------------------------------------------- navigation


def test_navigation_reads_attributes_and_properties() -> None:
    agent = make_agent()
    assert ev("self.name", agent) == "manip"
    assert ev("self.cs->first().name", agent) == "control"
    assert len(ev("self.subsystems", agent)) == 3  # type: ignore[arg-type]


def test_navigation_on_a_collection_flattens_the_results() -> None:
    system = System([Robot("r1", [make_agent("a"), make_agent("b", ve=2)]), Robot("r2")])
    subsystems = ev("self.robots.agents.subsystems", system)
    assert isinstance(subsystems, tuple) and len(subsystems) == 3 + 5
    assert ev("self.robots.agents.name", system) == ("a", "b")
    assert ev("self.robots.agents.ve.outputs.data_type", system) == ()  # nulls are dropped
    assert ev("self.robots.agents.cs.outputs.name", system) == ("status", "status")


def test_navigation_from_null_gives_null() -> None:
    agent = make_agent()
    assert ev("self.leader.name", agent) is None
    assert ev("self.leader.name.oclIsUndefined()", agent) is True
    agent.leader = make_agent("boss")
    assert ev("self.leader.name", agent) == "boss"


def test_a_member_name_after_a_dot_may_be_a_keyword() -> None:
    @dataclass
    class Odd:
        context: int = 1
        self: int = 2

    assert ev("self.context + self.self", Odd()) == 3


def test_a_missing_attribute_is_an_error_naming_the_attribute_and_the_type() -> None:
    with pytest.raises(OclEvaluationError, match=r"Agent has no attribute 'vee'"):
        ev("self.vee->size()", make_agent())
    with pytest.raises(OclEvaluationError, match=r"Subsystem has no attribute 'nmae'"):
        ev("self.ve.nmae", make_agent())


def test_an_unknown_variable_is_an_error() -> None:
    with pytest.raises(OclEvaluationError, match="unknown variable 'x'"):
        ev("x + 1")


def test_variables_are_passed_by_the_caller_and_self_is_the_object() -> None:
    expression = parse_expression("self.ve->size() <= limit")
    assert evaluate(expression, make_agent(ve=3), {"limit": 4}) is True
    assert evaluate(expression, make_agent(ve=5), {"limit": 4}) is False
    assert evaluate(parse_expression("self"), 7, {"self": 8}) == 7


# ---------------------------------------------------------------------------- collections


def test_collection_operations() -> None:
    items = [3, 1, 3, 2]
    assert ev("c->notEmpty()", c=items) is True
    assert ev("c->isEmpty()", c=items) is False
    assert ev("c->size()", c=items) == 4
    assert ev("c->includes(2)", c=items) is True
    assert ev("c->includes(5)", c=items) is False
    assert ev("c->excludes(5)", c=items) is True
    assert ev("c->sum()", c=items) == 9
    assert ev("c->first()", c=items) == 3
    assert ev("c->last()", c=items) == 2
    assert ev("c->asSet()", c=items) == (3, 1, 2)
    assert ev("c->count(3)", c=items) == 2
    assert ev("c->min()", c=items) == 1 and ev("c->max()", c=items) == 3
    assert ev("c->includesAll(d)", c=items, d=(1, 2)) is True
    assert ev("c->excludesAll(d)", c=items, d=(7, 2)) is False
    assert ev("c->union(d)", c=items, d=[9]) == (3, 1, 3, 2, 9)
    assert ev("c->asSequence()", c=items) == (3, 1, 3, 2)


def test_collection_operations_on_empty_collections() -> None:
    assert ev("c->sum()", c=[]) == 0
    assert ev("c->first()", c=()) is None
    assert ev("c->last()", c=set()) is None
    assert ev("c->max()", c=[]) is None
    assert ev("c->isEmpty()", c=frozenset()) is True


def test_arrow_on_a_single_value_sees_a_one_element_collection_and_on_null_an_empty_one() -> None:
    assert ev("5->size()") == 1
    assert ev("'text'->first()") == "text"
    assert ev("null->isEmpty()") is True
    assert ev("self.leader->size()", make_agent()) == 0


def test_collection_results_are_tuples() -> None:
    assert isinstance(ev("c->select(x | x > 1)", c=[1, 2, 3]), tuple)
    assert isinstance(ev("c->collect(x | x)", c={1}), tuple)
    assert isinstance(ev("c->asSet()", c=[1, 1]), tuple)


def test_as_set_compares_equal_regardless_of_order() -> None:
    assert ev("a->asSet() = b->asSet()", a=[1, 2, 2], b=(2, 1)) is True
    assert ev("a->asSet() = b", a=[1, 2], b={2, 1}) is True
    assert ev("a = b", a=[1, 2], b=(2, 1)) is False
    assert ev("a = b", a=[1, 2], b=(1, 2)) is True  # a list and a tuple are both sequences


def test_as_set_works_on_unhashable_elements() -> None:
    @dataclass
    class Point:  # eq=True and not frozen: unhashable
        x: int

    assert ev("c->asSet()->size()", c=[Point(1), Point(1), Point(2)]) == 2


def test_sum_of_non_numbers_is_an_error() -> None:
    with pytest.raises(OclEvaluationError, match="sum"):
        ev("c->sum()", c=["a"])


# ---------------------------------------------------------------------------- iterators


def test_iterators() -> None:
    c = [1, 2, 3, 4]
    assert ev("c->forAll(x | x > 0)", c=c) is True
    assert ev("c->forAll(x | x > 1)", c=c) is False
    assert ev("c->exists(x | x = 3)", c=c) is True
    assert ev("c->exists(x | x = 9)", c=c) is False
    assert ev("c->select(x | x > 2)", c=c) == (3, 4)
    assert ev("c->reject(x | x > 2)", c=c) == (1, 2)
    assert ev("c->collect(x | x * 10)", c=c) == (10, 20, 30, 40)
    assert ev("c->any(x | x > 2)", c=c) == 3
    assert ev("c->any(x | x > 9)", c=c) is None
    assert ev("c->one(x | x = 2)", c=c) is True
    assert ev("c->one(x | x > 2)", c=c) is False
    assert ev("c->isUnique(x | x)", c=c) is True
    assert ev("c->isUnique(x | x - x)", c=c) is False


def test_iterators_on_empty_collections() -> None:
    assert ev("c->forAll(x | false)", c=[]) is True
    assert ev("c->exists(x | true)", c=[]) is False
    assert ev("c->one(x | true)", c=[]) is False
    assert ev("c->select(x | true)", c=[]) == ()


def test_collect_flattens_collections_and_drops_nulls() -> None:
    system = System(agents=[make_agent("a", ve=2), make_agent("b", ve=1)])
    assert ev("self.agents->collect(a | a.ve)->size()", system) == 3
    assert ev("self.agents->collect(a | a.leader)", system) == ()


def test_nested_iterators_see_outer_variables_and_restore_them() -> None:
    text = "a->forAll(x | b->exists(y | y = x * 2))"
    assert ev(text, a=[1, 2], b=[2, 4, 6]) is True
    assert ev("c->collect(x | c->select(y | y < x)->size())", c=[1, 2, 3]) == (0, 1, 2)
    assert ev("c->exists(x | x = 3) and x = 'outer'", c=[3], x="outer") is True


def test_iterators_over_model_elements() -> None:
    agent = make_agent(ve=2, rr=1)
    assert ev("self.subsystems->select(s | s.kind = 've').name", agent) == ("motor0", "motor1")
    assert ev("self.subsystems->isUnique(s | s.name)", agent) is True
    text = (
        "self.subsystems->forAll(s | s.inputs->union(s.outputs)"
        "->forAll(b | not b.data_type.oclIsUndefined()))"
    )
    assert ev(text, agent) is False
    text = "self.subsystems.outputs->reject(b | b.data_type.oclIsUndefined())->size()"
    assert ev(text, agent) == 2


def test_an_iterator_body_must_be_boolean_where_a_condition_is_expected() -> None:
    with pytest.raises(OclEvaluationError, match="forAll.*Boolean"):
        ev("c->forAll(x | x)", c=[1])


# ---------------------------------------------------------------------------- strings


def test_string_operations() -> None:
    assert ev("s.size()", s="motor") == 5
    assert ev("s.startsWith('mo')", s="motor") is True
    assert ev("s.endsWith('or')", s="motor") is True
    assert ev("s.endsWith('x')", s="motor") is False
    assert ev("s.toUpper()", s="Motor") == "MOTOR"
    assert ev("s.toLower()", s="Motor") == "motor"
    assert ev("s.concat('1')", s="motor") == "motor1"
    assert ev("s.oclIsUndefined()", s="motor") is False
    assert ev("s.oclIsUndefined()", s=None) is True


def test_matches_requires_the_whole_string_to_match_the_regular_expression() -> None:
    assert ev("s.matches('[a-z]+')", s="motor") is True
    assert ev("s.matches('[a-z]+')", s="motor1") is False
    assert ev("s.matches('^[a-z][A-Za-z0-9]*$')", s="motorController3") is True
    assert ev(r"s.matches('\\d+(,\\d+)*')", s="1,22,333") is True
    assert ev("s.matches('it\\'s.*')", s="it's fine") is True


def test_an_invalid_regular_expression_is_an_evaluation_error() -> None:
    with pytest.raises(OclEvaluationError, match="regular expression"):
        ev("s.matches('[a-')", s="x")


def test_string_operations_on_a_collection_apply_to_each_element() -> None:
    agent = make_agent(ve=2)
    assert ev("self.ve.name.toUpper()", agent) == ("MOTOR0", "MOTOR1")
    assert ev("self.ve.name.matches('motor[0-9]')->forAll(b | b)", agent) is True


# ---------------------------------------------------------------------------- evaluation errors


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("1 and true", "'and' expects a Boolean, got Integer"),
        ("not 'x'", "'not' expects a Boolean, got String"),
        ("if 1 then 2 else 3 endif", "'if' expects a Boolean"),
        ("1 < 'a'", "'<' cannot compare Integer with String"),
        ("1 + 'a'", "'+' cannot add Integer and String"),
        ("true * 2", "'*' expects a number, got Boolean"),
        ("1 / 0", "division by zero"),
        ("-'a'", "unary '-' expects a number"),
        ("n.toUpper()", "toUpper() expects a String, got Integer"),
        ("null.size()", "size() expects a String, got null"),
    ],
)
def test_type_errors_are_evaluation_errors(text: str, message: str) -> None:
    with pytest.raises(OclEvaluationError) as caught:
        ev(text, n=1)
    assert message in str(caught.value)


def test_not_applies_to_the_comparison_only_through_parentheses() -> None:
    with pytest.raises(OclEvaluationError, match="'not' expects a Boolean"):
        ev("not 1 + 1 = 2")


# ---------------------------------------------------------------------------- syntax errors


@pytest.mark.parametrize(
    ("text", "line", "column", "message"),
    [
        ("context A inv x: 1 +", 1, 21, "unexpected end of input; expected an expression"),
        ("contxt A inv x: true", 1, 1, "unexpected 'contxt'; expected 'context'"),
        ("context A inv : true", 1, 15, "expected an invariant name"),
        ("context A inv x true", 1, 17, "unexpected 'true'; expected ':'"),
        ("-- rules\ncontext A inv x:\n  (1 + 2", 3, 9, "expected an operator, '->', '.' or ')'"),
        ("context A inv x: a b", 1, 20, "unexpected 'b'"),
        ("context A inv x: a->forAll(v | )", 1, 32, "unexpected ')'; expected an expression"),
        ("context A inv x: if a then b endif", 1, 30, "unexpected 'endif'"),
        ("context A inv x: 'abc", 1, 18, "unterminated string 'abc"),
        ("context A inv x: a->frAll(v | v)", 1, 19, "unknown iterator 'frAll'"),
        ("context A inv x: a->sise()", 1, 19, "unknown operation '->sise()'"),
        ("context A inv x: a.notEmpty()", 1, 19, "did you mean '->notEmpty'"),
        ("context A inv x: a->forAll(true)", 1, 19, "iterator 'forAll' needs a variable"),
        ("context A inv x: a->includes()", 1, 19, "takes 1 argument, got 0"),
        ("context A inv x: a.__class__", 1, 19, "not a navigable attribute"),
        ("context A inv x: 1\ncontext A inv x: 2", 2, 1, "duplicate invariant 'x'"),
        ("context A inv x: let in = 1 in 2", 1, 22, "expected a name"),
    ],
)
def test_syntax_errors_carry_file_line_column_and_a_readable_message(
    text: str, line: int, column: int, message: str
) -> None:
    with pytest.raises(OclSyntaxError) as caught:
        parse_invariants(text, "rules.ocl")
    error = caught.value
    assert message in error.message
    assert (error.file, error.line, error.column) == ("rules.ocl", line, column)
    assert "\n" not in error.message and "textx" not in error.message.lower()
    assert str(error) == f"rules.ocl:{line}:{column}: {error.message}"
    assert isinstance(error, Exception) and error.__cause__ is None


def test_a_single_expression_reports_syntax_errors_at_its_own_lines() -> None:
    with pytest.raises(OclSyntaxError) as caught:
        parse_expression("self.ve\n  ->size(")
    assert (caught.value.line, caught.value.column) == (2, 10)
    with pytest.raises(OclSyntaxError, match="expected an expression"):
        parse_expression("context A inv x: true")
    with pytest.raises(OclSyntaxError, match="end of input; expected an expression"):
        parse_expression("")


def test_an_invariant_file_cannot_hold_a_bare_expression() -> None:
    with pytest.raises(OclSyntaxError, match="expected 'context'"):
        parse_invariants("__expression__ true")
    with pytest.raises(OclSyntaxError):
        parse_invariants("self.ve->size() = 1")


@pytest.mark.parametrize(("body", "message", "where"), [
    ("(" * 201 + "true" + ")" * 201, r"nested more than 200 levels deep \('\('\)", (2, 30 + 200)),
    ("not " * 201 + "true", r"more than 200 prefix operators in a row \('not'\)", (2, 30)),
    ("1 + " * 10_000 + "1 > 0", "an invariant of more than 10000 operators", (2, 1)),
    ("let a = 1 in " * 5_000 + "true", r"nested too deeply to parse \('if … endif' or 'let … in'", (1, 1)),
    ("if true then " * 3_000 + "true" + " else true endif" * 3_000, "nested too deeply to parse", (1, 1)),
], ids=["parentheses", "nots", "operators", "lets", "ifs"])
def test_a_rule_nested_or_chained_past_the_limits_is_one_syntax_error(body: str, message: str,
                                                                     where: tuple[int, int]) -> None:
    text = "-- severity: error\ncontext Agent inv team.deep: " + body
    with pytest.raises(OclSyntaxError, match=message) as caught:
        call_with_deep_stack(lambda: parse_invariants(text, "team.ocl"))
    assert (caught.value.file, caught.value.line, caught.value.column) == ("team.ocl", *where)


def test_a_rule_as_deep_as_allowed_parses_and_holds() -> None:
    deepest = "(" * 200 + "not " * 100 + "not false" + ")" * 200  # 'not ' * 101 in a row: within 200
    (invariant,) = call_with_deep_stack(lambda: parse_invariants(f"context Agent inv team.deep: {deepest}"))
    assert check(invariant, Subsystem("s", "ve", [], [])) is True
    assert call_with_deep_stack(lambda: evaluate(parse_expression("let a = 1 in " * 150 + "a = 1"), None)) is True


# ---------------------------------------------------------------------------- speed


def test_an_invariant_costs_the_same_few_calls_for_every_object() -> None:
    """Checking an invariant is a small constant work per object, counted in Python function
    calls (deterministic, unlike a time on a loaded machine): 100,000 objects run in about
    0.1 s on a developer machine."""
    (invariant,) = parse_invariants(
        "context Subsystem inv S008_ve: self.kind = 've' implies "
        "(self.inputs->notEmpty() and self.outputs->notEmpty())"
    )

    def calls(count: int) -> int:
        objects = [Subsystem(f"s{i}", "ve", [Buffer("i")], [Buffer("o")]) for i in range(count)]
        passed, made = counted_calls(lambda: all(check(invariant, obj) for obj in objects))
        assert passed
        return made

    small, large = calls(1_000), calls(10_000)
    assert large <= 10 * small + 100  # linear in the objects
    assert large / 10_000 <= PER_OBJECT_CALLS, large / 10_000


PER_OBJECT_CALLS = 40  # Python calls per object checked, with a margin over the interpreter's
