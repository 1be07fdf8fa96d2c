"""The lifted model as a tree of elements, built by walking its dataclasses.

Every field of an element is either compared (rendered as text), a child element (a
dataclass with an identity: ``path``, a dataType's ``qualified_name``, or a ``name`` inside
its owner), flattened (a dataclass without identity, such as a state's activation:
``activation.group``) or ignored (``metamodel/diff/presentation.toml``). So a field added to
the model is compared without any change here.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from earl_m2t.element_tree.presentation import presentation
from earl_m2t.model.conditions import Condition
from earl_m2t.model.elements import EarlModel
from earl_m2t.model.location import Location


@dataclass(frozen=True)
class Node:
    """One model element: what it is, how it is matched, what is compared."""

    cls: str  # the dataclass name (elements of different classes are never matched)
    kind: str  # what it is called in EARL terms ("input buffer", "transition")
    key: str  # its identity inside its owner
    path: str  # the element path shown to the user
    xmi_id: str
    location: Location
    values: tuple[tuple[str, str], ...]  # (field, value as text), compared
    children: tuple[Node, ...]
    # the path with replicated instances named by their template (manip/a.motorControllerK/ve.fsm),
    # which the instances of one replicated element share
    template_path: str = ""

    @property
    def value_map(self) -> dict[str, str]:
        return dict(self.values)


def model_tree(model: EarlModel) -> Node:
    """The model as a tree; its root is the model itself."""
    return _node(model, "", "", "")


def _identity(obj: Any) -> str | None:
    for attribute in ("path", "qualified_name", "name"):
        value = getattr(obj, attribute, None)
        if isinstance(value, str) and value:
            return value
    return None


def _is_element(value: Any) -> bool:
    return (dataclasses.is_dataclass(value) and not isinstance(value, (type, Condition, Location))
            and _identity(value) is not None)


def _node(obj: Any, owner_path: str, owner_key_prefix: str, owner_template_path: str) -> Node:
    spec = presentation()
    cls = type(obj).__name__
    identity = _identity(obj) or ""
    own_path = getattr(obj, "path", "") or getattr(obj, "qualified_name", "") or (
        f"{owner_path}.{identity}" if owner_path else identity)
    key = identity.removeprefix(owner_key_prefix) if owner_key_prefix and identity.startswith(owner_key_prefix) \
        else identity
    template = getattr(obj, "template", "")
    segment = template if isinstance(template, str) and template and template != key else key
    template_path = (f"{owner_template_path}.{segment}" if owner_key_prefix and identity.startswith(owner_key_prefix)
                     else own_path if segment == key else segment)
    kind = spec.kinds.get(cls, cls)
    for field_name, labels in spec.kind_by_field.get(cls, {}).items():
        kind = labels.get(str(getattr(obj, field_name, "")), kind)
    values: list[tuple[str, str]] = []
    children: list[Node] = []
    child_prefix = f"{own_path}." if own_path else ""
    for name, value in _fields(obj):
        if name in spec.ignored or value == ():  # an empty collection compares as a missing value
            continue
        elements = _elements_in(value)
        if elements is not None:
            children.extend(_node(element, own_path, child_prefix, template_path) for element in elements)
        else:
            values.extend(_flatten(name, value))
    location = getattr(obj, "location", None)
    if not isinstance(location, Location):
        location = Location(getattr(obj, "file", "") or "")
    return Node(cls, kind, key, own_path, location.xmi_id, location, tuple(values), tuple(children), template_path)


def _fields(obj: Any) -> list[tuple[str, Any]]:
    return [(f.name, getattr(obj, f.name)) for f in dataclasses.fields(obj)]


def _elements_in(value: Any) -> list[Any] | None:
    """The child elements a field holds, or None when it holds a value."""
    if isinstance(value, Mapping):
        items = list(value.values())
    elif isinstance(value, tuple):
        items = list(value)
    else:
        items = [value]
    if items and all(_is_element(item) for item in items):
        return items
    return [] if not items and isinstance(value, Mapping) else None


def _flatten(name: str, value: Any) -> list[tuple[str, str]]:
    if dataclasses.is_dataclass(value) and not isinstance(value, (type, Condition)):
        return [pair for sub_name, sub_value in _fields(value)
                if sub_name not in presentation().ignored
                for pair in _flatten(f"{name}.{sub_name}", sub_value)]
    return [(name, text(value))]


def text(value: Any) -> str:
    """A field value as the diff shows it."""
    if value is None:  # shown as "(none)", like a missing value
        return ""
    if isinstance(value, Condition):
        return value.text
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, tuple):
        if value and all(isinstance(item, tuple) for item in value):
            return "; ".join(", ".join(text(i) for i in item) for item in value)
        return ", ".join(text(item) for item in value)
    return str(value)
