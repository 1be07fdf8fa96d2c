"""Compile a parsed EARL predicate (:mod:`earl_m2t.predicate` AST) into a C++ expression.

No text substitution: the expression tree is walked, every name is resolved against the
subsystem (:class:`Symbols`) and the dataTypes, and replications (``a1 ∨ … ∨ aN``) are
expanded with the subsystem's multiplicities first.

- ``TRUE``/``FALSE`` → ``true``/``false``; ``¬``, ``∧``, ``∨`` → ``!``, ``&&``, ``||``
- a primitive predicate → a call of its generated member function (``emergencyStop_pp()``)
- a buffer field → ``data_.port.msg().field`` (the last value received or to be sent),
  a memory field → ``data_.memory.field``; a numeric value in a boolean place means ``!= 0``
- ``inError()``, ``behaviourOk()`` → the runtime's members of the same names (``leaving()``
  → the runtime's ``leaving()`` in a model with configurations, ``false`` otherwise)
- ``newData(ib.msg.a.b)`` → the buffer's ``newData()`` and, for every optional or
  variable-length field along the path, that it is not empty in the value received
- comparisons compare the C++ values; an array index in a path is copied as written (0-based)
"""

from __future__ import annotations

from dataclasses import dataclass

from earl_m2t.gen.errors import GenError
from earl_m2t.model.conditions import Condition
from earl_m2t.model.datatypes import DataType, Field
from earl_m2t.model.elements import EarlModel, Subsystem
from earl_m2t.model.naming import stem
from earl_m2t.model.variability import is_variable
from earl_m2t.predicate import (
    And,
    BuiltIn,
    BuiltInPredicate,
    Compare,
    Const,
    Expr,
    FieldRef,
    NewData,
    Not,
    Number,
    Or,
    PredicateRef,
    Replicated,
    format_predicate,
)

NUMERIC = ("integer", "real")
# the built-ins the runtime's earl::Health answers (earl/health.hpp)
_HEALTH = {BuiltInPredicate.IN_ERROR: "inError()", BuiltInPredicate.BEHAVIOUR_OK: "behaviourOk()"}


@dataclass(frozen=True)
class Storage:
    """A buffer instance or memory instance as C++ sees it."""

    cpp: str  # ``data_.motorControllerStateK_ib[2]``
    datatype: str  # key into the model's datatypes
    kind: str  # "ib" | "ob" | "m"


@dataclass
class Symbols:
    """What the names of one subsystem's conditions refer to."""

    storage: dict[str, Storage]  # buffer instance names, and memory stems (``motionFinished``)
    predicates: dict[str, str]  # primitive predicate name -> C++ call (``emergencyStop_pp()``)
    field_names: dict[tuple[str, str], str]  # (datatype key, field name) -> C++ member
    unbounded_capacity: int  # elements of a [*] field in C++ (target.toml [capacities])


class ExprCompiler:
    """Compiles the conditions of one subsystem."""

    def __init__(self, model: EarlModel, subsystem: Subsystem, symbols: Symbols) -> None:
        assert subsystem.scope is not None, "a lifted subsystem"
        self.model = model
        self.scope = subsystem.scope
        self.symbols = symbols
        self.switching = is_variable(model)  # the subsystems have the runtime's leaving()
        self._where = ""

    def compile(self, condition: Condition, where: str) -> str:
        """The C++ boolean expression of a condition of the subsystem (its replications
        written out); ``where`` names it in errors."""
        if condition.expanded is None:
            problem = condition.syntax_problem
            raise GenError(f"{where}: {problem.message if problem else 'does not parse'}")
        self._where = where
        return self._bool(condition.expanded)

    # ------------------------------------------------------------------ booleans

    def _bool(self, node: Expr) -> str:
        if isinstance(node, Const):
            return "true" if node.value else "false"
        if isinstance(node, Not):
            return f"!{self._bool(node.operand)}"
        if isinstance(node, (And, Or)):
            joiner = " && " if isinstance(node, And) else " || "
            return "(" + joiner.join(self._bool(o) for o in node.operands) + ")"
        if isinstance(node, PredicateRef):
            name = self.scope.predicate(node.name)
            if name is not None:
                return self.symbols.predicates[name]
            return self._field_bool(FieldRef(node.name, line=node.line, column=node.column))
        if isinstance(node, FieldRef):
            return self._field_bool(node)
        if isinstance(node, NewData):
            return self._new_data(node.ref)
        if isinstance(node, Compare):
            return f"({self._operand(node.left)} {node.op} {self._operand(node.right)})"
        if isinstance(node, BuiltIn) and node.name == BuiltInPredicate.LEAVING:
            return "leaving()" if self.switching else "false"  # without configurations nothing leaves
        if isinstance(node, BuiltIn) and node.name in _HEALTH:
            return _HEALTH[node.name]
        if isinstance(node, Replicated):
            raise self._error(f"'{format_predicate(node)}' names no replicated buffer or memory")
        raise self._error(f"unsupported expression {node!r}")

    def _field_bool(self, ref: FieldRef) -> str:
        cpp, kind = self._value(ref)
        if kind == "boolean":
            return cpp
        if kind in NUMERIC:
            return f"({cpp} != 0)"
        raise self._error(f"'{format_predicate(ref)}' is not a boolean or a number")

    def _operand(self, node: FieldRef | Number) -> str:
        if isinstance(node, Number):
            return repr(int(node.value)) if float(node.value).is_integer() else repr(float(node.value))
        cpp, kind = self._value(node)
        if kind not in NUMERIC:
            raise self._error(f"'{format_predicate(node)}' is not numeric and cannot be compared")
        return cpp

    def _new_data(self, ref: FieldRef) -> str:
        storage = self._storage(ref)
        if storage.kind != "ib":
            raise self._error(f"newData() needs an input buffer, '{ref.head}' is not one")
        parts = [f"{storage.cpp}.newData()"]
        for cpp, field in self._walk(ref, storage)[1]:
            if field.is_array and not field.is_fixed_array:
                parts.append(f"!{cpp}.empty()")
        return parts[0] if len(parts) == 1 else "(" + " && ".join(parts) + ")"

    # ------------------------------------------------------------------ values

    def _storage(self, ref: FieldRef) -> Storage:
        head = ref.head
        found = self.symbols.storage.get(head) or self.symbols.storage.get(f"m:{stem(head)}")
        if found is None:
            raise self._error(f"unknown buffer or memory '{head}'")
        return found

    def _walk(self, ref: FieldRef, storage: Storage) -> tuple[str, list[tuple[str, Field]]]:
        """The C++ of the value ``ref`` names, and (C++ of each field along the path, field)."""
        cpp = f"{storage.cpp}.msg()" if storage.kind in ("ib", "ob") else storage.cpp
        datatype: DataType | None = self.model.datatypes.get(storage.datatype)
        steps: list[tuple[str, Field]] = []
        for position, segment in enumerate(ref.path):
            name, bracket, index = segment.partition("[")
            field = datatype.field_named(name) if datatype is not None and datatype.kind == "struct" else None
            if field is None or datatype is None:
                raise self._error(f"'{format_predicate(ref)}' names no field '{name}'")
            cpp += "." + self.symbols.field_names[(datatype.qualified_name, field.name)]
            steps.append((cpp, field))
            if bracket:
                cpp += f"[{self._index(ref, field, int(index.rstrip(']').strip()))}]"
            elif field.is_array and position < len(ref.path) - 1:
                if field.is_fixed_array:
                    raise self._error(f"'{format_predicate(ref)}': index the array '{name}'")
                cpp += "[0]"  # through an optional value: its (default) content when absent
            datatype = self.model.datatypes.get(field.type)
        return cpp, steps

    def _index(self, ref: FieldRef, field: Field, index: int) -> int:
        """An index the C++ value has room for (rule B005 reports the model's own bounds)."""
        if not field.is_array:
            raise self._error(f"'{format_predicate(ref)}': '{field.name}' is not an array and cannot be indexed")
        room = field.upper if field.upper is not None else self.symbols.unbounded_capacity
        if index >= room:
            why = "" if field.upper is not None else " ([capacities] unbounded_array of the target)"
            raise self._error(f"'{format_predicate(ref)}': index {index} is out of range: "
                              f"'{field.name}' holds at most {room}{why}")
        return index

    def _value(self, ref: FieldRef) -> tuple[str, str]:
        storage = self._storage(ref)
        cpp, steps = self._walk(ref, storage)
        if not steps:
            return cpp, _kind(self.model.datatypes.get(storage.datatype))
        field = steps[-1][1]
        if field.is_array and "[" not in ref.path[-1]:
            return cpp, "array"
        return cpp, _kind(self.model.datatypes.get(field.type))

    def _error(self, message: str) -> GenError:
        return GenError(f"{self._where}: cannot compile the condition: {message}")


def _kind(datatype: DataType | None) -> str:
    if datatype is None:
        return "unknown"
    return datatype.primitive if datatype.kind == "primitive" else datatype.kind
