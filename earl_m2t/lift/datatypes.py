"""DataTypes: primitive (recognised by name), enumerations and composite, nested types."""

from __future__ import annotations

import tomllib
from functools import cache

from earl_m2t.diagnostics import Diagnostic, Severity
from earl_m2t.lift.replication import multiplicity
from earl_m2t.model.datatypes import DataType, DataTypeNamesake, Field
from earl_m2t.model.kinds import DataTypeKind
from earl_m2t.model.limits import MAX_ARRAY
from earl_m2t.model.location import Location
from earl_m2t.read.xmi import Element, ExternalRef, RawModel
from earl_m2t.resources import metamodel_path

BUILTIN = Location("<builtin>")
_STRUCT_TYPES = ("DataType", "Class", "Signal", "InterfaceBlock")
_DATATYPE_TYPES = frozenset({"DataType", "Enumeration", "PrimitiveType"})


@cache
def primitive_names() -> dict[str, str]:
    """Map every known primitive type name to its kind (boolean, integer, real, string)."""
    table = tomllib.loads(metamodel_path("tables", "primitive-types.toml").read_text("utf-8"))
    return {name: kind for kind, row in table.items() for name in row["names"]}


def primitive_kind(name: str) -> str:
    names = primitive_names()
    if name in names:
        return names[name]
    for sep in ("#", "/", "-", ".", "_"):
        tail = name.rpartition(sep)[2]
        if tail in names:
            return names[tail]
    tail = name.removesuffix("_PackageableElement").rpartition("-")[2]
    return names.get(tail, "")


class DataTypeLifter:
    """Lifts type references on demand, memoised, into ``datatypes`` keyed by qualified name."""

    def __init__(self, raw: RawModel) -> None:
        self.raw = raw
        self.datatypes: dict[str, DataType] = {}
        self._keys: dict[int, str] = {}
        self._taken: dict[str, Element] = {}  # qualified name -> the element that has it
        self.diagnostics: list[Diagnostic] = []  # R008: an array beyond its bound
        self.namesakes: list[DataTypeNamesake] = []  # rule S012: a name twice in one package
        self._members: dict[int, dict[str, list[Element]]] = {}  # id of a package -> its members by name

    def type_of(self, typed: Element) -> tuple[str, str]:
        """(datatype key, unresolved reference text) for a typed element (property, port, parameter)."""
        ref = self.raw.ref(typed, "type")
        if ref is None:
            return "", ""
        if isinstance(ref, ExternalRef):
            # a type of a known library (metamodel/xmi/libraries.toml), or an id the tool leaves
            # undefined (Enterprise Architect's EAJava_int), by the href's fragment, else by the
            # target's name when the file states it; a type of a file not at hand stays unresolved
            if ref.library or not ref.resource:
                for name in (ref.fragment, ref.name):
                    kind = primitive_kind(name) if name else ""
                    if kind:
                        return self._builtin(name, kind), ""
            return "", ref.href
        return self.lift(ref), ""

    def _builtin(self, name: str, kind: str) -> str:
        canonical = {"boolean": "Boolean", "integer": "Integer", "real": "Real", "string": "String"}[kind]
        if canonical not in self.datatypes:
            self.datatypes[canonical] = DataType(canonical, canonical, DataTypeKind.PRIMITIVE, kind, location=BUILTIN)
        return canonical

    def lift(self, el: Element) -> str:
        key = self._keys.get(id(el))
        if key is not None:
            return key
        raw = self.raw
        uml_type = raw.uml_type(el)
        name = raw.name(el)
        natural, qualified = self._qualified_name(el)
        self._keys[id(el)] = qualified  # set first: recursive types must terminate (D002 finds them)
        location = raw.location(el)
        self._compare_namesakes(el, name, natural)
        if uml_type == "PrimitiveType":
            kind = primitive_kind(name) or "real"
            self.datatypes[qualified] = DataType(name, qualified, DataTypeKind.PRIMITIVE, kind, location=location)
        elif uml_type == "Enumeration":
            literals = tuple(raw.name(lit) for lit in raw.children(el, "ownedLiteral"))
            self.datatypes[qualified] = DataType(name, qualified, DataTypeKind.ENUMERATION, literals=literals,
                                                 location=location)
        elif uml_type in _STRUCT_TYPES and primitive_kind(name) and not raw.children(el, "ownedAttribute"):
            self.datatypes[qualified] = DataType(name, qualified, DataTypeKind.PRIMITIVE, primitive_kind(name),
                                                 location=location)
        else:
            fields = []
            for attr in raw.children(el, "ownedAttribute"):
                if raw.uml_type(attr) not in ("Property", ""):
                    continue
                type_key, unresolved = self.type_of(attr)
                lower, upper = multiplicity(raw, attr)
                if upper is not None and upper > MAX_ARRAY:
                    field_path = f"{qualified}.{raw.name(attr)}"
                    self.diagnostics.append(Diagnostic(
                        "R008", Severity.ERROR, f"field {field_path}: an array of {upper} elements, more than the "
                        f"{MAX_ARRAY} earl-m2t generates", raw.location(attr), field_path))
                fields.append(Field(raw.name(attr), type_key, lower, upper, raw.location(attr), unresolved))
            self.datatypes[qualified] = DataType(name, qualified, DataTypeKind.STRUCT, fields=tuple(fields),
                                                 location=location)
        return qualified

    def _qualified_name(self, el: Element) -> tuple[str, str]:
        """Its name qualified by its packages and blocks, and the key of its dataType: the same
        name, unless another element has it (then qualified with its model's name too)."""
        names = [self.raw.name(el) or self.raw.xmi_id(el)]
        owner = self.raw.owner(el)
        while owner is not None and self.raw.uml_type(owner) and not self.raw.is_model(owner):
            names.append(self.raw.name(owner))
            owner = self.raw.owner(owner)
        qualified = key = "::".join(reversed(names))
        if self._taken.setdefault(qualified, el) is not el and owner is not None and self.raw.name(owner):
            # another element, of another file, has that name: qualify it with its model's name
            key = f"{self.raw.name(owner)}::{qualified}"
            self._taken.setdefault(key, el)
        return qualified, key

    def _compare_namesakes(self, el: Element, name: str, qualified: str) -> None:
        """Record the dataTypes of its package named as it is (rule S012), once per package and
        name: one key holds one dataType, and those the model does not use are never lifted."""
        owner = self.raw.owner(el)
        if owner is None or not name:
            return
        members = self._members.get(id(owner))
        if members is None:
            members = self._members[id(owner)] = {}
            for child in owner.iterchildren():
                if isinstance(child.tag, str) and child.get("name"):
                    members.setdefault(child.get("name") or "", []).append(child)
        types = _DATATYPE_TYPES | {self.raw.uml_type(el)}
        same = [member for member in members.pop(name, ()) if self.raw.uml_type(member) in types]
        if len(same) > 1:
            self.namesakes.append(DataTypeNamesake(qualified, tuple(self.raw.location(member) for member in same)))
