"""Conditions in context: parse a subsystem's predicates and resolve what they name.

Used by the checker (B005, B008) and by generators, which need the resolved expression.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Iterator

from earl_m2t.model.elements import Condition, DataType, EarlModel, Subsystem
from earl_m2t.model.location import Location
from earl_m2t.predicate import (
    Compare,
    Expr,
    FieldRef,
    NewData,
    Number,
    PredicateRef,
    PredicateSyntaxError,
    Replicated,
    substitute_index,
    walk,
)
from earl_m2t.predicate.known import parsed

NUMERIC = frozenset({"integer", "real"})
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
        self._templates: dict[str, int] = {}
        for item in list(subsystem.buffers) + list(subsystem.memory):
            if item.index:
                self._templates[item.template] = self._templates.get(item.template, 0) + 1
        # Everything a condition's problems depend on besides its text: subsystems alike in it
        # (replicated agents) share the answers, kept with the model (the data types are its own).
        self._signature = (frozenset(self._storage.items()), frozenset(self._memory.items()),
                           self._predicate_names, frozenset(self._templates.items()))
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
        counts = {self._templates.get(_template_head(ref.head), 0)
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
            known = tuple((message, node.line, node.column) for node in walk(expr)
                          for message in self._node_problems(node))
            if shareable:
                self._known_problems[key] = known
        return known

    def _node_problems(self, node: Expr | Number) -> Iterator[str]:
        if isinstance(node, Replicated):
            if not self.replication_count(node):
                yield ("replicated form names no replicated buffer or memory "
                       "(expected names with K and a fixed multiplicity)")
        elif isinstance(node, PredicateRef):
            if self.predicate(node.name) is None and self._field_kind(FieldRef(node.name)) is None:
                yield f"unknown primitive predicate '{node.name}'"
        elif isinstance(node, NewData):
            kind = self._storage.get(node.ref.head, ("", ""))[0] or self._storage.get(_template_head(node.ref.head), ("", ""))[0]
            if kind != "ib":
                yield f"newData() needs an input buffer, '{node.ref.head}' is not one"
        elif isinstance(node, FieldRef):
            message = self._check_field(node)
            if message:
                yield message
        elif isinstance(node, Compare):
            for side in (node.left, node.right):
                if isinstance(side, FieldRef) and self._field_kind(side) not in (None, *NUMERIC):
                    yield f"'{_text(side)}' is not numeric and cannot be compared"

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
        if self._field_kind(ref) is None:
            return f"'{_text(ref)}' names no field of its dataType"
        return ""

    def field_kind(self, ref: FieldRef) -> str | None:
        """The primitive kind of a field (``boolean``, ``integer``, ``real`` …), None if unknown."""
        return self._field_kind(ref)

    def _field_kind(self, ref: FieldRef) -> str | None:
        """The primitive kind at the end of a field path ('struct' for composites), None if unknown."""
        datatype_key = self._datatype_of(ref.head)
        if datatype_key is None:
            return None
        datatype = self.model.datatypes.get(datatype_key)
        for segment in ref.path:
            if datatype is None or datatype.kind != "struct":
                return None
            field = datatype.field_named(segment.partition("[")[0])
            if field is None:
                return None
            datatype = self.model.datatypes.get(field.type)
        return _kind(datatype)

    def _datatype_of(self, head: str) -> str | None:
        for key in (head, _template_head(head)):
            if key in self._storage:
                return self._storage[key][1]
        for key in (_stem(head), _stem(_template_head(head))):
            if key in self._memory:
                return self._memory[key]
        return None


def _kind(datatype: DataType | None) -> str | None:
    if datatype is None:
        return None
    if datatype.kind == "primitive":
        return datatype.primitive
    return datatype.kind


def _stem(name: str) -> str:
    return name.rpartition("/")[0] if "/" in name else name


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
