"""Conditions parsed and resolved once: each guard, terminal and error condition and primitive
predicate body gets its expression, its replications written out, and its problems.

Syntax problems (an empty text, a form the predicate language cannot say, a parse error) stop
the parse; reference problems name what the subsystem's :class:`Scope` does not have, or a
value used as it cannot be (an array as a truth value, an index out of range, an instance past
its multiplicity). Subsystems alike in every name share one scope, so a text is resolved once
per scope, however many subsystems hold it.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Iterator, Mapping
from functools import lru_cache
from types import MappingProxyType

from earl_m2t.model.conditions import Condition, ConditionProblem, ConditionRole, ProblemKind
from earl_m2t.model.datatypes import DataType
from earl_m2t.model.elements import Buffer, Memory, PrimitivePredicate, Subsystem
from earl_m2t.model.location import Location
from earl_m2t.model.naming import instance_template, stem, suffix
from earl_m2t.model.scope import (
    MEMORY_SUFFIXES,
    NUMERIC,
    TRUTH_VALUED,
    Scope,
    StorageKind,
    replica_key,
)
from earl_m2t.predicate import (
    And,
    Compare,
    Expr,
    FieldRef,
    NewData,
    Not,
    Number,
    Or,
    PredicateRef,
    PredicateSyntaxError,
    Replicated,
    expand_replicated,
    walk,
)
from earl_m2t.predicate.known import parsed
from earl_m2t.predicate.transform import ExpansionRefused
from earl_m2t.predicate.unsayable import unsayable_reason

# (kind, message, line and column within the text) of a problem; line None: at the condition itself
RelativeProblem = tuple[ProblemKind, str, int | None, int]
RelativeProblems = tuple[RelativeProblem, ...]


@lru_cache(maxsize=65536)
def _parse(text: str) -> Expr | PredicateSyntaxError:
    return parsed(text)


def parse_condition(condition: Condition) -> tuple[Expr | None, ConditionProblem | None]:
    """The parsed expression of a condition, or the syntax problem that stops it."""
    expr, problem = _parse_text(condition.text, condition.role)
    return expr, _placed(problem, condition.location) if problem is not None else None


def _parse_text(text: str, role: ConditionRole) -> tuple[Expr | None, RelativeProblem | None]:
    what = role.description
    if not text.strip():
        return None, (ProblemKind.SYNTAX, f"empty {what}", None, 0)
    reason = unsayable_reason(text)
    if reason is not None:
        return None, (ProblemKind.SYNTAX, f"{what} is not in the predicate language ({reason})", None, 0)
    result = _parse(text)
    if isinstance(result, PredicateSyntaxError):
        return None, (ProblemKind.SYNTAX, f"{what} does not parse: {result.message}", result.line, result.column)
    return result, None


def _placed(problem: RelativeProblem, where: Location) -> ConditionProblem:
    """A problem found at a line and column of a condition's text, at its place in the model file."""
    kind, message, line, column = problem
    if line is None:
        return ConditionProblem(kind, message, where)
    return ConditionProblem(kind, message, Location(where.file, where.line + max(line - 1, 0), column, where.xmi_id))


class ConditionLifter:
    """Builds the scopes of a model's subsystems and resolves their conditions in them."""

    def __init__(self, datatypes: Mapping[str, DataType]) -> None:
        self.datatypes = datatypes  # the model's, complete for every type a buffer or memory names
        self._scopes: dict[tuple[object, ...], Scope] = {}
        # what a text that parses means in a scope, for the subsystems alike: (expr, expanded, problems)
        self._resolved: dict[tuple[Scope, str], tuple[Expr, Expr | None, RelativeProblems]] = {}

    def scope(self, buffers: Iterable[Buffer], memory: Iterable[Memory],
              predicates: Iterable[PrimitivePredicate]) -> Scope:
        """The scope of a subsystem with these elements; equal contents give the same scope."""
        buffers, memory = tuple(buffers), tuple(memory)
        storage: dict[str, tuple[StorageKind, str]] = {}
        for buf in buffers:
            kind = StorageKind.INPUT if buf.direction == "in" else StorageKind.OUTPUT
            for key in (buf.name, buf.template):
                storage.setdefault(key, (kind, buf.datatype))
        memories: dict[str, str] = {}
        for mem in memory:
            for key in (mem.name, mem.template):
                memories.setdefault(stem(key), mem.datatype)
        replicas: dict[str, int] = {}
        for item in buffers + memory:
            if item.index:
                key = replica_key(item.template)
                replicas[key] = replicas.get(key, 0) + 1
        names = frozenset(p.name for p in predicates)
        signature = (frozenset(storage.items()), frozenset(memories.items()), names, frozenset(replicas.items()))
        found = self._scopes.get(signature)
        if found is None:
            found = self._scopes[signature] = Scope(MappingProxyType(storage), MappingProxyType(memories), names,
                                                    MappingProxyType(replicas))
        return found

    def resolve(self, condition: Condition | None, scope: Scope) -> Condition | None:
        """``condition`` with its expression, expansion and problems in ``scope``."""
        if condition is None:
            return None
        return self.make(condition.text, condition.language, condition.location, condition.owner, condition.role,
                         scope)

    def make(self, text: str, language: str, where: Location, owner: str, role: ConditionRole,
             scope: Scope) -> Condition:
        """The condition written so, with its expression, expansion and problems in ``scope``."""
        key = (scope, text)
        known = self._resolved.get(key)
        if known is None:
            expr, problem = _parse_text(text, role)
            if expr is None:  # a syntax problem, worded after the condition's role
                assert problem is not None
                return Condition(text, language, where, owner, role, problems=(_placed(problem, where),))
            known = self._resolved[key] = self._resolve_expr(expr, scope)
        expr, expanded, relative = known
        problems = tuple(_placed(problem, where) for problem in relative) if relative else ()
        return Condition(text, language, where, owner, role, expr, expanded, problems)

    def _resolve_expr(self, expr: Expr, scope: Scope) -> tuple[Expr, Expr | None, RelativeProblems]:
        try:
            expanded: Expr | None = expand_replicated(expr, lambda node: scope.replication_count(node) or None)
        except ExpansionRefused as refused:
            return expr, None, ((ProblemKind.REFERENCE, refused.message, refused.line, refused.column),)
        found = ReferenceChecker(scope, self.datatypes).problems(expr)
        return expr, expanded, tuple((ProblemKind.REFERENCE, message, line, column) for message, line, column in found)

    def resolve_predicates(self, predicates: Iterable[PrimitivePredicate],
                           scope: Scope) -> tuple[PrimitivePredicate, ...]:
        return tuple(pp if pp.fun is None else PrimitivePredicate(pp.name, pp.path, self.resolve(pp.fun, scope),
                                                                  pp.language, pp.body, pp.location, pp.recognised_by)
                     for pp in predicates)


def resolve_subsystem(subsystem: Subsystem, datatypes: Mapping[str, DataType]) -> Subsystem:
    """A subsystem built outside the lift (an import, a test) with its scope and conditions
    resolved as the lift resolves them."""
    lifter = ConditionLifter(datatypes)
    scope = lifter.scope(subsystem.buffers, subsystem.memory, subsystem.predicates)
    fsm = subsystem.fsm
    if fsm is not None:
        fsm = dataclasses.replace(fsm, transitions=tuple(
            dataclasses.replace(t, condition=lifter.resolve(t.condition, scope)) for t in fsm.transitions))
    behaviours = tuple(dataclasses.replace(b, tc=lifter.resolve(b.tc, scope), ec=lifter.resolve(b.ec, scope))
                       for b in subsystem.behaviours)
    return dataclasses.replace(subsystem, fsm=fsm, behaviours=behaviours, scope=scope,
                               predicates=lifter.resolve_predicates(subsystem.predicates, scope))


class ReferenceChecker:
    """The reference problems of an expression in a scope."""

    def __init__(self, scope: Scope, datatypes: Mapping[str, DataType]) -> None:
        self.scope = scope
        self.datatypes = datatypes

    def problems(self, expr: Expr) -> Iterator[tuple[str, int, int]]:
        """(message, line, column in the text) of each problem."""
        truth_places, replicated = _places(expr)
        for node in walk(expr):
            for message in self._node_problems(node, id(node) in truth_places, id(node) in replicated):
                yield message, node.line, node.column

    def _node_problems(self, node: Expr | Number, truth_place: bool, in_replication: bool) -> Iterator[str]:
        """The problems of one node; ``truth_place``: its value is used as true or false;
        ``in_replication``: it is in the template of a replication (where K names each instance)."""
        if isinstance(node, Replicated):
            if not self.scope.replication_count(node):
                yield ("replicated form names no replicated buffer or memory "
                       "(expected names with K and a fixed multiplicity)")
        elif isinstance(node, PredicateRef):
            if self.scope.predicate(node.name) is None:
                ref = FieldRef(node.name)
                kind = self._kind(ref)
                if kind is None:
                    yield f"unknown primitive predicate '{node.name}'"
                elif message := self._instance_problem(node.name, in_replication):
                    yield message
                elif truth_place and kind not in TRUTH_VALUED:
                    yield _not_truth_valued(ref, kind)
        elif isinstance(node, NewData):
            if self.scope.storage_kind(node.ref.head) is not StorageKind.INPUT:
                yield f"newData() needs an input buffer, '{node.ref.head}' is not one"
        elif isinstance(node, FieldRef):
            message = self._field_problem(node) or self._instance_problem(node.head, in_replication)
            if message:
                yield message
            elif truth_place and (kind := self._kind(node)) not in TRUTH_VALUED:
                yield _not_truth_valued(node, kind)
        elif isinstance(node, Compare):
            for side in (node.left, node.right):
                if isinstance(side, FieldRef) and self._kind(side) not in (None, *NUMERIC):
                    yield f"'{_text(side)}' is not numeric and cannot be compared"

    def _kind(self, ref: FieldRef) -> str | None:
        return self.scope.field_kind(ref, self.datatypes)

    def _instance_problem(self, head: str, in_replication: bool) -> str:
        """What is wrong with naming a replicated buffer or memory so: an instance past its
        multiplicity (``windingCurrent9/m`` of six), or the template (``windingCurrentK/m``)
        outside a replication."""
        replicas = self.scope.replicas
        head_stem = stem(head)
        if replica_key(head) in replicas:
            if in_replication:
                return ""
            first = f"{head_stem[:-1]}1{head[len(head_stem):]}"
            return (f"'{head}' stands for each of {replicas[replica_key(head)]} instances: name one, "
                    f"as in '{first}', or write a replication (any K: …, all K: …, or the paper's … form)")
        template = instance_template(head)
        count = replicas.get(replica_key(template))
        if count is None or head_stem in self.scope.memory or head in self.scope.storage:
            return ""
        index = int(head_stem[len(stem(template)) - 1:])
        if 1 <= index <= count:
            return ""
        return f"'{head}' is no instance of '{template}': its instances are numbered 1 to {count}"

    def _field_problem(self, ref: FieldRef) -> str:
        head = ref.head
        storage, memory = self.scope.storage, self.scope.memory
        head_suffix = suffix(head)
        if head_suffix in ("ib", "ob") or (not head_suffix and head in storage):
            if head not in storage and instance_template(head) not in storage:
                return f"unknown buffer '{head}'"
            if ref.member not in (None, "msg"):
                return f"a buffer holds 'msg', not '{ref.member}'"
        elif head_suffix in MEMORY_SUFFIXES or stem(head) in memory:
            if stem(head) not in memory and stem(instance_template(head)) not in memory:
                return f"unknown memory '{head}'"
            if ref.member not in (None, "msg", "data"):
                return f"a memory holds 'data', not '{ref.member}'"
        else:
            return f"unknown buffer or memory '{head}'"
        typed = self.scope.type_path(ref, self.datatypes)
        if typed.problem:
            return f"'{_text(ref)}': {typed.problem}"
        if typed.kind is None:
            return f"'{_text(ref)}' names no field of its dataType"
        return ""


def _places(expr: Expr) -> tuple[set[int], set[int]]:
    """The ids of the nodes whose value is used as true or false (the whole condition, the
    operands of ¬, ∧ and ∨, the template of a replication), and of the nodes inside the
    template of a replication."""
    truth = {id(expr)}
    replicated: set[int] = set()
    for node in walk(expr):
        if isinstance(node, Not):
            truth.add(id(node.operand))
        elif isinstance(node, (And, Or)):
            truth.update(id(operand) for operand in node.operands)
        elif isinstance(node, Replicated):
            truth.add(id(node.template))
            replicated.update(id(inner) for inner in walk(node.template))
    return truth, replicated


def _not_truth_valued(ref: FieldRef, kind: str | None) -> str:
    what = {"array": "an array", "optional": "an optional value [0..1]", "struct": "a composite dataType",
            "enumeration": "an enumeration", "string": "a string"}.get(kind or "", f"of kind {kind}")
    return f"'{_text(ref)}' is {what}, not a boolean or a number, and cannot be a condition"


def _text(ref: FieldRef) -> str:
    return ".".join([ref.head] + ([ref.member] if ref.member else []) + list(ref.path))
