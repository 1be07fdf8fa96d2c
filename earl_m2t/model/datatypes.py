"""DataTypes of the lifted model: primitives, enumerations and composites with their fields."""

from __future__ import annotations

from dataclasses import dataclass, field

from earl_m2t.model.kinds import DataTypeKind
from earl_m2t.model.location import Location


@dataclass(frozen=True, slots=True)
class Field:
    """A field of a composite dataType; ``upper`` None means unbounded (``*``)."""

    name: str
    type: str  # key into EarlModel.datatypes, or "" when unresolved
    lower: int
    upper: int | None
    location: Location
    type_ref: str = ""  # the reference as written when it did not resolve (rule D001)

    @property
    def is_array(self) -> bool:
        """Fixed ``[n]`` or variable (``[*]``, ``[0..n]``, optional ``[0..1]``) array."""
        return self.upper is None or self.upper > 1 or self.lower != self.upper

    @property
    def is_fixed_array(self) -> bool:
        return self.upper is not None and self.upper > 1 and self.lower == self.upper


@dataclass(frozen=True, slots=True)
class DataType:
    """A primitive, enumeration or composite (possibly nested) dataType."""

    name: str
    qualified_name: str
    kind: DataTypeKind
    primitive: str = ""  # "boolean" | "integer" | "real" | "string" for primitives
    fields: tuple[Field, ...] = ()
    literals: tuple[str, ...] = ()
    location: Location = field(default_factory=lambda: Location("<builtin>"))

    def field_named(self, name: str) -> Field | None:
        return next((f for f in self.fields if f.name == name), None)


@dataclass(frozen=True, slots=True)
class DataTypeNamesake:
    """DataTypes of one package that have one name.

    The lift keeps one dataType per qualified name, and only those the model uses; it records
    here each name a package gives to several of its dataTypes, one of them used, so that rule
    S012 can report the second."""

    qualified_name: str  # the name they have in their package
    locations: tuple[Location, ...]  # of each, in model order
