"""B rules: FSMs, states, transitions and the conditions they carry (paper Figs. 3, 5; Tables 5, 6)."""

from __future__ import annotations

from collections.abc import Iterator

from earl_m2t.analysis.guards import MAX_OVERLAPS_PER_STATE
from earl_m2t.analysis.shared_guards import SharedGuards, shared_guards
from earl_m2t.check.rule import Finding, rule
from earl_m2t.model.conditions import ProblemKind
from earl_m2t.model.elements import EarlModel, State
from earl_m2t.model.graph import unreachable_states
from earl_m2t.predicate import BuiltIn, BuiltInPredicate, walk


@rule("B001")
def fsm_initial_state_count(model: EarlModel) -> Iterator[Finding]:
    for sub in model.definitions():
        if sub.fsm is None:
            yield Finding(f"subsystem {sub.path} has no state machine (its FSM)", sub.location, sub.path)
            continue
        fsm = sub.fsm
        if sub.fsm_count > 1:
            yield Finding(f"subsystem {sub.path} owns {sub.fsm_count} state machines; its FSM is the "
                          "classifier behaviour (else the first one), the others are ignored", fsm.location,
                          fsm.path)
        initials = fsm.initial_states
        if not initials:
            yield Finding(f"{fsm.path} has no initial state (no transition from an initial pseudostate)",
                          fsm.location, fsm.path)
        elif len(initials) > 1:
            shown = ", ".join(name or "(nowhere)" for name in initials)
            yield Finding(f"{fsm.path} has {len(initials)} initial states ({shown})", fsm.location, fsm.path)
        elif not initials[0]:
            yield Finding(f"{fsm.path}: the initial pseudostate leads to no state", fsm.location, fsm.path)


@rule("B003")
def transition_leaves_fsm(model: EarlModel) -> Iterator[Finding]:
    for sub in model.definitions():
        if sub.fsm is None:
            continue
        for tr in sub.fsm.transitions:
            ends = []
            if tr.source_foreign:
                ends.append(f"source {tr.source or '?'}")
            if tr.target_foreign:
                ends.append(f"destination {tr.target or '?'}")
            if ends:
                yield Finding(f"transition {tr.path}: {' and '.join(ends)} is not a state of {sub.fsm.path}",
                              tr.location, tr.path)


@rule("B004")
def unreachable_state(model: EarlModel) -> Iterator[Finding]:
    for sub in model.definitions():
        if sub.fsm is None:
            continue
        for name in unreachable_states(sub.fsm):
            state = sub.fsm.state(name)
            assert state is not None
            yield Finding(f"state {state.path} cannot be reached from the initial state {sub.fsm.initial}",
                          state.location, state.path)


@rule("B005")
def predicate_unknown_reference(model: EarlModel) -> Iterator[Finding]:
    for sub in model.definitions():
        for condition in sub.conditions():
            for found in condition.problems:
                if found.kind is ProblemKind.REFERENCE:
                    column = f" (column {found.location.column})" if found.location.column else ""
                    yield Finding(f"{condition.owner}: {found.message}{column}", found.location, condition.owner)
        for exclusion in sub.exclusions:
            for name in exclusion.predicates:
                if sub.scope is None or sub.scope.predicate(name) is None:
                    yield Finding(f"exclusion '{exclusion.name}' of {sub.path} names unknown primitive predicate "
                                  f"'{name}'", exclusion.location, f"{sub.path}.{exclusion.name}")


@rule("B008")
def predicate_syntax_error(model: EarlModel) -> Iterator[Finding]:
    for sub in model.definitions():
        for condition in sub.conditions():
            problem = condition.syntax_problem
            if problem is not None:
                yield Finding(f"{condition.owner}: {problem.message}", problem.location, condition.owner)


def _guarded_states(model: EarlModel) -> Iterator[tuple[SharedGuards, int, State]]:
    for sub in model.definitions():
        if sub.fsm is None or not sub.fsm.states:
            continue
        guards = shared_guards(model, sub)  # B006 and B007 ask the same subsystem
        for position, state in enumerate(sub.fsm.states):
            yield guards, position, state


@rule("B006")
def transitions_overlap(model: EarlModel) -> Iterator[Finding]:
    for guards, position, state in _guarded_states(model):
        overlaps = guards.overlaps(position)
        for found in overlaps:
            first, second = found.first, found.second
            yield Finding(f"{first.name} and {second.name} can both fire when {found.witness} (both priority "
                          f"{first.priority}, leaving {state.path}: model order picks {first.name})",
                          first.location, first.path)
        if len(overlaps) == MAX_OVERLAPS_PER_STATE:
            yield Finding(f"{state.path}: the first {MAX_OVERLAPS_PER_STATE} overlapping pairs of transitions "
                          "leaving this state are reported; any further pairs were not analysed",
                          state.location, state.path)


@rule("B007")
def termination_without_transition(model: EarlModel) -> Iterator[Finding]:
    for guards, position, state in _guarded_states(model):
        gap = guards.gap(position)
        if gap is None:
            continue
        bb = state.behaviours[0]
        if gap.transitions:
            what = f"none of its {len(gap.transitions)} outgoing transitions is enabled"
        else:
            what = "no transition leaves it"
        yield Finding(f"{state.path}: {bb} can terminate (tc holds, ec does not) when {gap.witness}, and then "
                      f"{what}: the subsystem stays in {state.name} and runs {bb} again", state.location, state.path)


@rule("B012")
def error_condition_reads_in_error(model: EarlModel) -> Iterator[Finding]:
    for sub in model.definitions():
        for bb in sub.behaviours:
            ec = bb.ec
            if ec is None or ec.expr is None:
                continue
            if any(isinstance(node, BuiltIn) and node.name == BuiltInPredicate.IN_ERROR for node in walk(ec.expr)):
                yield Finding(f"the error condition of {bb.path} reads inError(), which there is the value of "
                              "the previous iteration (false in a state's first): the error condition of the "
                              "current one is being computed", ec.location, bb.path)
