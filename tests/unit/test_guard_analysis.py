"""Exact guard analysis (B006, B007): agreement with brute-force enumeration, exclusions,
priorities, comparisons and the text of counterexamples."""

from __future__ import annotations

import itertools
import random
from pathlib import Path

import pytest

from earl_m2t.analysis.guards import MAX_OVERLAPS_PER_STATE, GuardAnalysis, describe
from earl_m2t.model.elements import EarlModel, Subsystem
from earl_m2t.predicate import Expr, FieldRef, PredicateRef, evaluate, parse_predicate
from tests.support.fsm_builder import build

ROOT = Path(__file__).resolve().parents[2]


def _overlaps(model: EarlModel, sub: Subsystem) -> dict[str, list[tuple[str, str, str]]]:
    analysis = GuardAnalysis(sub, model.datatypes)
    assert sub.fsm is not None
    return {s.name: [(o.first.name, o.second.name, o.witness) for o in analysis.overlaps(s)] for s in sub.fsm.states}


def _gaps(model: EarlModel, sub: Subsystem) -> dict[str, str | None]:
    analysis = GuardAnalysis(sub, model.datatypes)
    assert sub.fsm is not None
    found = {s.name: analysis.gap(s) for s in sub.fsm.states}
    return {name: gap.witness if gap else None for name, gap in found.items()}


# ---- the paper's manipulator FSM (Table 6) -------------------------------------------------

PREDICATES = {
    "emergencyStop/pp": "in/ib.msg.b0 ∨ in/ib.msg.b1",
    "motionFinished/pp": "in/ib.msg.b2",
    "newJointPos/pp": "newData(in/ib.msg.b3)",
    "newOperationalPos/pp": "newData(in/ib.msg.b4)",
    "false/pp": "FALSE",
}
STATES = {
    "idle": ("newJointPos ∨ newOperationalPos ∨ emergencyStop", "FALSE"),
    "jointMove": ("motionFinished ∨ emergencyStop", None),
    "emergencyStop": ("false", None),
}


def _manipulator(self_priority: int = 1, exclusive: bool = True, with_stop: bool = True) -> tuple[EarlModel, Subsystem]:
    transitions = [
        ("idle", "jointMove", "newJointPos ∧ ¬emergencyStop", 0),
        ("jointMove", "jointMove", "newJointPos ∧ ¬emergencyStop", self_priority),
        ("idle", "emergencyStop", "newOperationalPos ∧ ¬emergencyStop", 0),  # stands for operationalMove
        ("jointMove", "idle", "¬emergencyStop", 0),
        ("jointMove", "emergencyStop", "emergencyStop", 2),
    ]
    if with_stop:
        transitions.append(("idle", "emergencyStop", "emergencyStop", 2))
    exclusions = [("newJointPos/pp", "newOperationalPos/pp")] if exclusive else []
    return build(PREDICATES, STATES, transitions, exclusions)


def test_the_paper_fsm_with_priorities_and_exclusion_is_deterministic_and_complete() -> None:
    model, sub = _manipulator()
    assert _overlaps(model, sub) == {"idle": [], "jointMove": [], "emergencyStop": []}
    assert _gaps(model, sub) == {"idle": None, "jointMove": None, "emergencyStop": None}


def test_without_the_exclusion_the_two_moves_out_of_idle_overlap() -> None:
    model, sub = _manipulator(exclusive=False)
    assert _overlaps(model, sub)["idle"] == [
        ("idle,jointMove/t", "idle,emergencyStop/t", "newJointPos ∧ newOperationalPos ∧ ¬emergencyStop")]


def test_without_the_priority_the_self_transition_ties_with_the_way_back() -> None:
    model, sub = _manipulator(self_priority=0)
    assert _overlaps(model, sub)["jointMove"] == [
        ("jointMove,jointMove/t", "jointMove,idle/t", "newJointPos ∧ motionFinished ∧ ¬emergencyStop")]


def test_a_higher_priority_transition_resolves_the_overlap() -> None:
    # both moves hold together, but then a priority-3 transition takes over whenever they do
    model, sub = build(PREDICATES, {"idle": ("TRUE", None), "other": ("FALSE", None)}, [
        ("idle", "other", "newJointPos", 0),
        ("idle", "other", "newOperationalPos", 0),
        ("idle", "other", "newJointPos ∧ newOperationalPos", 3),
    ])
    assert _overlaps(model, sub)["idle"] == []
    model, sub = build(PREDICATES, {"idle": ("TRUE", None), "other": ("FALSE", None)}, [
        ("idle", "other", "newJointPos", 0),
        ("idle", "other", "newOperationalPos", 0),
        ("idle", "other", "newJointPos ∧ newOperationalPos ∧ emergencyStop", 3),
    ])
    assert _overlaps(model, sub)["idle"] == [
        ("idle,other/t", "idle,other#1/t", "newJointPos ∧ newOperationalPos ∧ ¬emergencyStop")]


def test_different_priorities_never_overlap() -> None:
    model, sub = build(PREDICATES, {"idle": ("TRUE", None), "other": ("FALSE", None)},
                       [("idle", "other", "TRUE", 0), ("idle", "other", "TRUE", 1)])
    assert _overlaps(model, sub)["idle"] == []


def test_missing_emergency_transition_leaves_a_gap() -> None:
    model, sub = _manipulator(with_stop=False)
    assert _gaps(model, sub) == {"idle": "emergencyStop", "jointMove": None, "emergencyStop": None}


def test_a_state_that_never_terminates_has_no_gap_and_no_overlap() -> None:
    model, sub = build(PREDICATES, {"run": ("false", "FALSE"), "other": ("FALSE", None)},
                       [("run", "other", "TRUE", 0), ("run", "other", "TRUE", 0)])
    assert _gaps(model, sub)["run"] is None
    assert _overlaps(model, sub)["run"] == []


def test_error_termination_is_not_a_gap() -> None:
    # tc can only hold together with ec: the behaviour then ends with an error
    model, sub = build(PREDICATES, {"run": ("emergencyStop", "emergencyStop"), "other": ("FALSE", None)}, [])
    assert _gaps(model, sub)["run"] is None


def test_a_state_without_transitions_whose_tc_can_hold_has_a_gap() -> None:
    model, sub = build(PREDICATES, {"run": ("motionFinished ∧ ¬emergencyStop", None)}, [])
    assert _gaps(model, sub)["run"] == "motionFinished ∧ ¬emergencyStop"


def test_missing_guard_is_true_and_missing_tc_is_false() -> None:
    model, sub = build(PREDICATES, {"run": ("TRUE", None), "stay": (None, None)},
                       [("run", "stay", None, 0), ("run", "stay", "motionFinished", 0)])
    assert _overlaps(model, sub)["run"] == [("run,stay/t", "run,stay#1/t", "motionFinished")]
    assert _gaps(model, sub) == {"run": None, "stay": None}


def test_comparisons_of_one_field_are_related() -> None:
    states = {"run": ("TRUE", None), "other": ("FALSE", None)}
    model, sub = build({}, states, [("run", "other", "in/ib.msg.v >= 0.5", 0),
                                    ("run", "other", "in/ib.msg.v < 0.5", 0)])
    assert _overlaps(model, sub)["run"] == []
    assert _gaps(model, sub)["run"] is None
    # integers: nothing lies strictly between 1 and 2
    model, sub = build({}, states, [("run", "other", "in/ib.msg.n > 1 ∧ in/ib.msg.n < 2", 0)])
    assert _gaps(model, sub)["run"] == "TRUE"  # the guard never holds
    # a constant on the left is the same comparison
    model, sub = build({}, states, [("run", "other", "0.5 <= in/ib.msg.v", 0),
                                    ("run", "other", "in/ib.msg.v < 0.5", 0)])
    assert _gaps(model, sub)["run"] is None


def test_user_code_predicates_are_opaque_atoms_and_cycles_stop() -> None:
    predicates = {"ready/pp": None, "loopA/pp": "loopB ∨ in/ib.msg.b0", "loopB/pp": "loopA ∧ in/ib.msg.b1"}
    model, sub = build(predicates, {"run": ("ready", None), "other": ("FALSE", None)},
                       [("run", "other", "ready ∧ loopA", 0)])
    assert _gaps(model, sub)["run"] == "ready ∧ ¬loopA"


def test_unanalysable_conditions_are_skipped() -> None:
    states = {"run": ("TRUE", None), "other": ("FALSE", None)}
    model, sub = build(PREDICATES, states, [("run", "other", "TRUE", 0), ("run", "other", "unknownThing", 0),
                                            ("run", "other", "motionFinished ∧ ∧", 0)])
    assert _overlaps(model, sub)["run"] == []  # the only pair left out: both others do not resolve / parse
    assert _gaps(model, sub)["run"] is None
    broken = dict(PREDICATES, **{"motionFinished/pp": "in/ib.msg.nope"})
    model, sub = build(broken, states, [("run", "other", "TRUE", 0), ("run", "other", "motionFinished", 0)])
    assert _overlaps(model, sub)["run"] == []


def test_replicated_forms_are_expanded() -> None:
    model, sub = build({}, {"run": ("any K: in/ib.msg.bK", None), "other": ("FALSE", None)},
                       [("run", "other", "in/ib.msg.b0", 0)])
    # 'in/ib' is not replicated: the form names nothing to replicate (B005), so it is skipped
    assert _gaps(model, sub)["run"] is None


def test_describe() -> None:
    assert describe([]) == "TRUE"
    assert describe([("a", False), ("b", True), ("x > 1", False)]) == "b ∧ ¬a ∧ ¬(x > 1)"


# ---- exactness: random FSMs against brute-force enumeration --------------------------------

BOOLEANS = 3
TERMS = ["in/ib.msg.b0", "in/ib.msg.b1", "in/ib.msg.b2", "newData(in/ib.msg.b0)", "in/ib.msg.v > 1",
         "in/ib.msg.v <= 2", "in/ib.msg.v == 1.5", "in/ib.msg.n >= 2", "in/ib.msg.n != 1", "user"]
VALUES_V = (0.0, 1.0, 1.5, 2.0, 3.0)  # one value in every region the constants make
VALUES_N = (0, 1, 2, 3)


def _random_formula(rng: random.Random, leaves: list[str], depth: int = 2) -> str:
    if depth == 0 or rng.random() < 0.3:
        leaf = rng.choice(leaves)
        return f"¬{leaf}" if rng.random() < 0.3 and " " not in leaf else leaf
    op = rng.choice([" ∧ ", " ∨ "])
    parts = [_random_formula(rng, leaves, depth - 1) for _ in range(rng.randint(2, 3))]
    return "(" + op.join(parts) + ")"


def _random_case(seed: int) -> tuple[EarlModel, Subsystem]:
    rng = random.Random(seed)
    predicates: dict[str, str | None] = {"user/pp": None}
    for i in range(3):
        predicates[f"p{i}/pp"] = _random_formula(rng, TERMS[:-1], depth=1)
    leaves = ["p0", "p1", "p2", "user", *TERMS[:-1]]
    states = {"s": (_random_formula(rng, leaves), rng.choice([None, "FALSE", _random_formula(rng, leaves, 1)])),
              "t": ("FALSE", None)}
    transitions = [("s", "t", _random_formula(rng, leaves), rng.choice([0, 0, 1]))
                   for _ in range(rng.randint(1, 5))]
    exclusions = [("p0/pp", "p1/pp", "user/pp")] if rng.random() < 0.5 else []
    return build(predicates, states, transitions, exclusions, booleans=BOOLEANS)


class BruteForce:
    """Truth of conditions under every assignment of the atoms."""

    def __init__(self, sub: Subsystem) -> None:
        self.sub = sub
        self.bodies = {p.name.partition("/")[0]: None if p.fun is None else parse_predicate(p.fun.text)
                       for p in sub.predicates}

    def assignments(self) -> itertools.product:
        return itertools.product(*([(False, True)] * (BOOLEANS + 2)), VALUES_V, VALUES_N)

    def truth(self, expr: Expr, assignment: tuple) -> bool:
        *bits, v, n = assignment
        booleans, fresh, user = bits[:BOOLEANS], bits[BOOLEANS], bits[BOOLEANS + 1]

        def field(ref: FieldRef) -> object:
            name = ref.path[0] if ref.path else ""
            return {"v": v, "n": n}.get(name, booleans[int(name[1:])] if name.startswith("b") else None)

        def predicate(ref: PredicateRef) -> bool:
            body = self.bodies[ref.name.partition("/")[0]]
            return user if body is None else self.truth(body, assignment)

        return evaluate(expr, predicate, field, lambda ref: fresh)

    def allowed(self, assignment: tuple) -> bool:
        for exclusion in self.sub.exclusions:
            if sum(self.truth(PredicateRef(name), assignment) for name in exclusion.predicates) > 1:
                return False
        return True


def _text(condition: object, missing: str) -> str:
    return missing if condition is None else condition.text  # type: ignore[attr-defined]


@pytest.mark.parametrize("seed", range(150))
def test_agrees_with_brute_force(seed: int) -> None:
    model, sub = _random_case(seed)
    assert sub.fsm is not None
    brute = BruteForce(sub)
    bb = sub.behaviours[0]
    tc, ec = parse_predicate(_text(bb.tc, "FALSE")), parse_predicate(_text(bb.ec, "FALSE"))
    out = [t for t in sub.fsm.transitions if t.source == "s"]
    ics = {t.name: parse_predicate(_text(t.condition, "TRUE")) for t in out}
    worlds = [a for a in brute.assignments() if brute.allowed(a)]
    truth = [{**{n: brute.truth(ic, a) for n, ic in ics.items()}, "#tc": brute.truth(tc, a), "#ec": brute.truth(ec, a)}
             for a in worlds]

    analysis = GuardAnalysis(sub, model.datatypes)
    state = sub.fsm.states[0]
    found = {(o.first.name, o.second.name): o.witness for o in analysis.overlaps(state)}
    expected = set()
    for a, b in itertools.combinations(out, 2):
        if a.priority != b.priority:
            continue
        higher = [t.name for t in out if t.priority > a.priority]
        if any(w[a.name] and w[b.name] and (w["#tc"] or w["#ec"]) and not any(w[h] for h in higher) for w in truth):
            expected.add((a.name, b.name))
    assert set(found) == expected

    gap = analysis.gap(state)
    has_gap = any(w["#tc"] and not w["#ec"] and not any(w[n] for n in ics) for w in truth)
    assert (gap is not None) == has_gap

    # every counterexample implies its query, and no literal of it can be dropped
    def query_gap(w: dict) -> bool:
        return w["#tc"] and not w["#ec"] and not any(w[n] for n in ics)

    checks = [(text, lambda w, a=a, b=b: w[a] and w[b] and (w["#tc"] or w["#ec"])
               and not any(w[t.name] for t in out if t.priority > next(x for x in out if x.name == a).priority))
              for (a, b), text in found.items()]
    if gap is not None:
        checks.append((gap.witness, query_gap))
    for text, query in checks:
        literals = [] if text == "TRUE" else text.split(" ∧ ")
        cube = [parse_predicate(lit) for lit in literals]  # pp names and terms are predicate text
        holding = [w for a, w in zip(worlds, truth) if all(brute.truth(c, a) for c in cube)]
        assert holding and all(query(w) for w in holding), text
        for i in range(len(cube)):
            weaker = [w for a, w in zip(worlds, truth) if all(brute.truth(c, a) for c in cube[:i] + cube[i + 1:])]
            assert not all(query(w) for w in weaker), f"{text}: literal {literals[i]} can be dropped"


def test_overlaps_of_one_state_stop_at_the_limit() -> None:
    """A state with n transitions of one priority has n(n-1)/2 overlapping pairs: a hostile
    model with hundreds of them must not cost hundreds of thousands of solver calls."""
    states = {"idle": ("TRUE", None), **{f"s{k}": ("FALSE", None) for k in range(12)}}
    model, sub = build(PREDICATES, states, [("idle", f"s{k}", None, 0) for k in range(12)])
    assert sub.fsm is not None
    idle = sub.fsm.states[0]
    analysis = GuardAnalysis(sub, model.datatypes)
    assert len(list(analysis.overlaps(idle, limit=1000))) == 12 * 11 // 2
    assert len(list(analysis.overlaps(idle))) == MAX_OVERLAPS_PER_STATE < 66
