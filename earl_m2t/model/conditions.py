"""Conditions in context: parse a subsystem's predicates and resolve what they name.

Used by the checker (B005, B008) and by generators, which need the resolved expression.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Iterator

from earl_m2t.model.elements import Condition, DataType, EarlModel, Field, Subsystem
from earl_m2t.model.location import Location
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
    substitute_index,
    walk,
)
from earl_m2t.predicate.known import parsed
from earl_m2t.predicate.unsayable import unsayable_reason

NUMERIC = frozenset({"integer", "real"})
TRUTH_VALUED = NUMERIC | {"boolean"}  # a number in a boolean place means "is not 0"
_PROBLEMS_KEY = "condition-problems"  # EarlModel.derived: B005's answers by resolver signature and text
MEMORY_SUFFIXES = frozenset({"m", "mi", "mo"})


@dataclass(frozen=True, slots=True)
class Problem:
    code: str  # "B008" syntax, "B005" unknown reference
    message: str
    location: Location


@lru_cache(maxsize=65536)
def _parse(text: str) -> Expr | PredicateSyntaxError:
    return parsed(text)


def parse_condition(condition: Condition) -> tuple[Expr | None, Problem | None]:
    """The parsed expression of a condition, or the B008 problem that stops it."""
    if not condition.text.strip():
        return None, Problem("B008", f"empty {_role(condition.role)}", condition.location)
    reason = unsayable_reason(condition.text)
    if reason is not None:
        return None, Problem("B008", f"{_role(condition.role)} is not in the predicate language ({reason})",
                             condition.location)
    result = _parse(condition.text)
    if isinstance(result, PredicateSyntaxError):
        loc = condition.location
        position = Location(loc.file, loc.line + max(result.line - 1, 0), result.column, loc.xmi_id)
        return None, Problem("B008", f"{_role(condition.role)} does not parse: {result.message}", position)
    return result, None


def _role(role: str) -> str:
    return {
        "ic": "initial condition",
        "tc": "terminal condition",
        "ec": "error condition",
        "fun": "primitive predicate body",
        "exclusion": "exclusion",
    }.get(role, "condition")


class ConditionResolver:
    """Resolves predicate names, buffers, memory and fields against one subsystem."""

    def __init__(self, model: EarlModel, subsystem: Subsystem) -> None:
        self.model = model
        self.subsystem = subsystem
        self._storage: dict[str, tuple[str, str]] = {}  # name or template -> (kind, datatype)
        for buf in subsystem.buffers:
            for key in (buf.name, buf.template):
                self._storage.setdefault(key, ("ib" if buf.direction == "in" else "ob", buf.datatype))
        self._memory: dict[str, str] = {}
        for mem in subsystem.memory:
            for key in (mem.name, mem.template):
                self._memory.setdefault(_stem(key), mem.datatype)
        self._predicate_names = frozenset(p.name for p in subsystem.predicates)
        # instances of each replicated buffer or memory, by _replica_key of its template
        self._replicas: dict[str, int] = {}
        for item in list(subsystem.buffers) + list(subsystem.memory):
            if item.index:
                key = _replica_key(item.template)
                self._replicas[key] = self._replicas.get(key, 0) + 1
        # Everything a condition's problems depend on besides its text: subsystems alike in it
        # (replicated agents) share the answers, kept with the model (the data types are its own).
        self._signature = (frozenset(self._storage.items()), frozenset(self._memory.items()),
                           self._predicate_names, frozenset(self._replicas.items()))
        shared = model.derived.setdefault(_PROBLEMS_KEY, {})
        self._known_problems: dict[tuple[object, str], tuple[tuple[str, int, int], ...]] = shared  # type: ignore[assignment]

    def predicate(self, name: str) -> str | None:
        """The primitive predicate a reference names (``x``, ``x/pp``), or None."""
        names = self._predicate_names
        for candidate in (name, f"{name}/pp", _stem(name) + "/pp" if name.endswith("/pp") else ""):
            if candidate in names:
                return candidate
        return None

    def replication_count(self, node: Replicated) -> int:
        counts = {self._replicas.get(_replica_key(_template_head(ref.head)), 0)
                  for ref in walk(node.template) if isinstance(ref, FieldRef)}
        counts.discard(0)
        return counts.pop() if len(counts) == 1 else 0

    def problems(self, expr: Expr, condition: Condition) -> Iterator[Problem]:
        """The B005 problems of ``expr``, the parsed text of ``condition``."""
        loc = condition.location
        for message, line, column in self._relative_problems(expr, condition.text):
            yield Problem("B005", message, Location(loc.file, loc.line + max(line - 1, 0), column, loc.xmi_id))

    def _relative_problems(self, expr: Expr, text: str) -> tuple[tuple[str, int, int], ...]:
        """(message, line, column in the text) of each problem."""
        key = (self._signature, text)
        shareable = _parse(text) is expr  # the answer belongs to the text only if expr is its parse
        known = self._known_problems.get(key) if shareable else None
        if known is None:
            truth_places, replicated = _places(expr)
            known = tuple((message, node.line, node.column) for node in walk(expr)
                          for message in self._node_problems(node, id(node) in truth_places,
                                                             id(node) in replicated))
            if shareable:
                self._known_problems[key] = known
        return known

    def _node_problems(self, node: Expr | Number, truth_place: bool, in_replication: bool) -> Iterator[str]:
        """The problems of one node; ``truth_place``: its value is used as true or false;
        ``in_replication``: it is in the template of a replication (where K names each instance)."""
        if isinstance(node, Replicated):
            if not self.replication_count(node):
                yield ("replicated form names no replicated buffer or memory "
                       "(expected names with K and a fixed multiplicity)")
        elif isinstance(node, PredicateRef):
            if self.predicate(node.name) is None:
                ref = FieldRef(node.name)
                kind = self._field_kind(ref)
                if kind is None:
                    yield f"unknown primitive predicate '{node.name}'"
                elif message := self._instance_problem(node.name, in_replication):
                    yield message
                elif truth_place and kind not in TRUTH_VALUED:
                    yield _not_truth_valued(ref, kind)
        elif isinstance(node, NewData):
            kind = self._storage.get(node.ref.head, ("", ""))[0] or self._storage.get(_template_head(node.ref.head), ("", ""))[0]
            if kind != "ib":
                yield f"newData() needs an input buffer, '{node.ref.head}' is not one"
        elif isinstance(node, FieldRef):
            message = self._check_field(node) or self._instance_problem(node.head, in_replication)
            if message:
                yield message
            elif truth_place and (kind := self._field_kind(node)) not in TRUTH_VALUED:
                yield _not_truth_valued(node, kind)
        elif isinstance(node, Compare):
            for side in (node.left, node.right):
                if isinstance(side, FieldRef) and self._field_kind(side) not in (None, *NUMERIC):
                    yield f"'{_text(side)}' is not numeric and cannot be compared"

    def _instance_problem(self, head: str, in_replication: bool) -> str:
        """What is wrong with naming a replicated buffer or memory so: an instance past its
        multiplicity (``windingCurrent9/m`` of six), or the template (``windingCurrentK/m``)
        outside a replication."""
        stem = _stem(head)
        if _replica_key(head) in self._replicas:
            if in_replication:
                return ""
            first = f"{stem[:-1]}1{head[len(stem):]}"
            return (f"'{head}' stands for each of {self._replicas[_replica_key(head)]} instances: name one, "
                    f"as in '{first}', or write a replication (any K: …, all K: …, or the paper's … form)")
        template = _template_head(head)
        count = self._replicas.get(_replica_key(template))
        if count is None or stem in self._memory or head in self._storage:
            return ""
        index = int(stem[len(_stem(template)) - 1:])
        if 1 <= index <= count:
            return ""
        return f"'{head}' is no instance of '{_template_head(head)}': its instances are numbered 1 to {count}"

    def _check_field(self, ref: FieldRef) -> str:
        head = ref.head
        suffix = head.rpartition("/")[2] if "/" in head else ""
        if suffix in ("ib", "ob") or (not suffix and head in self._storage):
            if head not in self._storage and _template_head(head) not in self._storage:
                return f"unknown buffer '{head}'"
            if ref.member not in (None, "msg"):
                return f"a buffer holds 'msg', not '{ref.member}'"
        elif suffix in MEMORY_SUFFIXES or _stem(head) in self._memory:
            if _stem(head) not in self._memory and _stem(_template_head(head)) not in self._memory:
                return f"unknown memory '{head}'"
            if ref.member not in (None, "msg", "data"):
                return f"a memory holds 'data', not '{ref.member}'"
        else:
            return f"unknown buffer or memory '{head}'"
        kind, problem = self._walk_path(ref)
        if problem:
            return f"'{_text(ref)}': {problem}"
        if kind is None:
            return f"'{_text(ref)}' names no field of its dataType"
        return ""

    def field_kind(self, ref: FieldRef) -> str | None:
        """The primitive kind of a field (``boolean``, ``integer``, ``real`` …), None if unknown."""
        return self._field_kind(ref)

    def _field_kind(self, ref: FieldRef) -> str | None:
        """The kind of the value at the end of a field path: a primitive kind, 'struct',
        'enumeration', or 'array' ('optional' for [0..1]) for an array field named without an
        index; None if unknown."""
        return self._walk_path(ref)[0]

    def _walk_path(self, ref: FieldRef) -> tuple[str | None, str]:
        """(the kind of the value ``ref`` names, what is wrong with its indexes or "").

        An index is 0-based, as in the generated code: ``q[5]`` is the last of a ``q [6]``. A
        fixed array inside the path needs an index; a variable-length or optional one without
        an index is read through its first element (as ``newData`` of the path checks it is
        there)."""
        datatype_key = self._datatype_of(ref.head)
        if datatype_key is None:
            return None, ""
        datatype = self.model.datatypes.get(datatype_key)
        field: Field | None = None
        indexed = False
        for position, segment in enumerate(ref.path):
            if datatype is None or datatype.kind != "struct":
                return None, ""
            name, indexed, index = _segment(segment)
            field = datatype.field_named(name)
            if field is None:
                return None, ""
            if indexed:
                problem = _index_problem(field, index)
                if problem:
                    return None, problem
            elif field.is_fixed_array and position < len(ref.path) - 1:
                return None, f"'{name}' is an array of {field.upper}: index it, as in {name}[0]"
            datatype = self.model.datatypes.get(field.type)
        if field is not None and field.is_array and not indexed:
            return ("optional" if (field.lower, field.upper) == (0, 1) else "array"), ""
        return _kind(datatype), ""

    def _datatype_of(self, head: str) -> str | None:
        for key in (head, _template_head(head)):
            if key in self._storage:
                return self._storage[key][1]
        for key in (_stem(head), _stem(_template_head(head))):
            if key in self._memory:
                return self._memory[key]
        return None


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


def _segment(segment: str) -> tuple[str, bool, int]:
    """``q[2]`` → ("q", True, 2); ``q`` → ("q", False, 0)."""
    name, bracket, rest = segment.partition("[")
    return name, bool(bracket), int(rest.rstrip("]").strip() or 0) if bracket else 0


def _index_problem(field: Field, index: int) -> str:
    if not field.is_array:
        return f"'{field.name}' is not an array and cannot be indexed"
    if field.upper is not None and index >= field.upper:
        size = f"has {field.upper} element" if field.is_fixed_array else f"holds at most {field.upper} element"
        plural = "" if field.upper == 1 else "s"
        return f"index {index} is out of range: '{field.name}' {size}{plural} (indexes start at 0)"
    return ""


def _kind(datatype: DataType | None) -> str | None:
    if datatype is None:
        return None
    if datatype.kind == "primitive":
        return datatype.primitive
    return datatype.kind


def _stem(name: str) -> str:
    return name.rpartition("/")[0] if "/" in name else name


def _replica_key(name: str) -> str:
    """How a replicated buffer or memory is looked up: a buffer by its name (``stateK/ib``), a
    memory by its stem, as ``windingCurrentK/m``, ``/mi`` and ``/mo`` name the same memory."""
    suffix = name.rpartition("/")[2] if "/" in name else ""
    return name if suffix in ("ib", "ob") else _stem(name)


def _template_head(head: str) -> str:
    """``motorControllerState3/ib`` → ``motorControllerStateK/ib`` (the template of an instance)."""
    stem, slash, suffix = head.partition("/")
    digits = len(stem) - len(stem.rstrip("0123456789"))
    if digits and digits < len(stem):
        return f"{stem[:-digits]}K{slash}{suffix}"
    return head


def _text(ref: FieldRef) -> str:
    return ".".join([ref.head] + ([ref.member] if ref.member else []) + list(ref.path))


def conditions_of(subsystem: Subsystem) -> Iterator[Condition]:
    """Every condition a subsystem holds: guards, tc/ec, primitive predicate bodies."""
    if subsystem.fsm is not None:
        for tr in subsystem.fsm.transitions:
            if tr.condition is not None:
                yield tr.condition
    for bb in subsystem.behaviours:
        for cond in (bb.tc, bb.ec):
            if cond is not None:
                yield cond
    for pp in subsystem.predicates:
        if pp.fun is not None:
            yield pp.fun


__all__ = ["ConditionResolver", "Problem", "conditions_of", "parse_condition", "substitute_index"]
