"""What the names in one subsystem's conditions stand for: its buffers, memory, primitive
predicates and replicated instances, and the types of the values a path names.

The lift builds one scope per distinct content (the instances of a replicated subsystem, and
subsystems alike in every name, share one) and keeps it on the subsystem.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from enum import StrEnum

from earl_m2t.model.datatypes import DataType, Field
from earl_m2t.model.naming import instance_template, stem, suffix
from earl_m2t.predicate.ast import FieldRef, Replicated
from earl_m2t.predicate.walk import walk

MEMORY_SUFFIXES = frozenset({"m", "mi", "mo"})
BUFFER_SUFFIXES = frozenset({"ib", "ob"})
NUMERIC = frozenset({"integer", "real"})
TRUTH_VALUED = NUMERIC | {"boolean"}  # a number in a boolean place means "is not 0"


class StorageKind(StrEnum):
    INPUT = "ib"
    OUTPUT = "ob"


@dataclass(frozen=True, slots=True)
class PathType:
    """The kind of the value a path names (a primitive kind, ``struct``, ``enumeration``, or
    ``array`` / ``optional`` for an array field named without an index; None when unknown),
    and what is wrong with its indexes ("" for nothing)."""

    kind: str | None
    problem: str = ""


@dataclass(frozen=True, eq=False, slots=True)
class Scope:
    storage: Mapping[str, tuple[StorageKind, str]]  # buffer name and template -> (kind, dataType key)
    memory: Mapping[str, str]  # memory stem (of its name and template) -> dataType key
    predicates: frozenset[str]  # primitive predicate names
    replicas: Mapping[str, int]  # replica_key of a replicated buffer or memory -> its number of instances

    def predicate(self, name: str) -> str | None:
        """The primitive predicate a reference names (``x``, ``x/pp``), or None."""
        for candidate in (name, f"{name}/pp", stem(name) + "/pp" if name.endswith("/pp") else ""):
            if candidate in self.predicates:
                return candidate
        return None

    def replication_count(self, node: Replicated) -> int:
        """The number of instances a replication stands for; 0 when its names agree on none."""
        counts = {self.replicas.get(replica_key(instance_template(ref.head)), 0)
                  for ref in walk(node.template) if isinstance(ref, FieldRef)}
        counts.discard(0)
        return counts.pop() if len(counts) == 1 else 0

    def storage_kind(self, head: str) -> StorageKind | None:
        """Whether a name is an Input or an Output Buffer (an instance by its template too)."""
        found = self.storage.get(head) or self.storage.get(instance_template(head))
        return found[0] if found is not None else None

    def datatype_of(self, head: str) -> str | None:
        """The dataType key of the buffer or memory a name stands for, or None."""
        for key in (head, instance_template(head)):
            if key in self.storage:
                return self.storage[key][1]
        for key in (stem(head), stem(instance_template(head))):
            if key in self.memory:
                return self.memory[key]
        return None

    def type_path(self, ref: FieldRef, datatypes: Mapping[str, DataType]) -> PathType:
        """The type of the value ``ref`` names, typed as the generated code reads it.

        An index is 0-based: ``q[5]`` is the last of a ``q [6]``. A fixed array inside the
        path needs an index; a variable-length or optional one without an index is read
        through its first element (as ``newData`` of the path checks it is there)."""
        datatype_key = self.datatype_of(ref.head)
        if datatype_key is None:
            return PathType(None)
        datatype = datatypes.get(datatype_key)
        found: Field | None = None
        indexed = False
        for position, segment in enumerate(ref.path):
            if datatype is None or datatype.kind != "struct":
                return PathType(None)
            name, indexed, index = _segment(segment)
            found = datatype.field_named(name)
            if found is None:
                return PathType(None)
            if indexed:
                problem = _index_problem(found, index)
                if problem:
                    return PathType(None, problem)
            elif found.is_fixed_array and position < len(ref.path) - 1:
                return PathType(None, f"'{name}' is an array of {found.upper}: index it, as in {name}[0]")
            datatype = datatypes.get(found.type)
        if found is not None and found.is_array and not indexed:
            return PathType("optional" if (found.lower, found.upper) == (0, 1) else "array")
        return PathType(kind_of(datatype))

    def field_kind(self, ref: FieldRef, datatypes: Mapping[str, DataType]) -> str | None:
        """The kind of the value at the end of a field path (see :class:`PathType`)."""
        return self.type_path(ref, datatypes).kind


def replica_key(name: str) -> str:
    """How a replicated buffer or memory is looked up: a buffer by its name (``stateK/ib``), a
    memory by its stem, as ``windingCurrentK/m``, ``/mi`` and ``/mo`` name the same memory."""
    return name if suffix(name) in BUFFER_SUFFIXES else stem(name)


def kind_of(datatype: DataType | None) -> str | None:
    if datatype is None:
        return None
    if datatype.kind == "primitive":
        return datatype.primitive
    return datatype.kind


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
