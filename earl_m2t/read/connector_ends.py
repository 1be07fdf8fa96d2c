"""Where a connector end attaches, whichever way the tool wrote it.

UML and SysML: ``role`` is the connected port or property, ``partWithPort`` the part whose
type owns that port, and a SysML «NestedConnectorEnd» gives the ``propertyPath`` from the
connector's owner down to that part. Enterprise Architect writes neither ``partWithPort`` nor
a NestedConnectorEnd: it keeps copies of the ports (and, for deeper ends, of the nested parts)
of a part's type under the part property and points ``role`` at the innermost copy. A copy is
mapped back to its part and, by name, to the member of the part's type it stands for
(``[connector_ends]`` of ``dialects.toml``).
"""

from __future__ import annotations

from dataclasses import dataclass

from earl_m2t.read.xmi import Element, ExternalRef, RawModel


@dataclass(frozen=True, slots=True)
class EndTarget:
    """The definitions a connector end attaches to.

    ``path`` lists the properties from the connector's owner inwards, ``part_with_port`` last
    when there is one; it is empty when the end is not nested deeper than one part.
    """

    role: Element | None
    part_with_port: Element | None
    path: tuple[Element, ...] = ()


def resolve_end(raw: RawModel, end: Element) -> EndTarget:
    role = _element(raw.ref(end, "role"))
    if role is not None and raw.is_copy(role):
        return _from_copy(raw, role)
    return EndTarget(role, _element(raw.ref(end, "partWithPort")), _property_path(raw, end))


def _element(target: Element | ExternalRef | None) -> Element | None:
    return None if target is None or isinstance(target, ExternalRef) else target


def _property_path(raw: RawModel, end: Element) -> tuple[Element, ...]:
    app = raw.sysml_application(end, "NestedConnectorEnd")
    if app is None:
        return ()
    path = (raw.element_by_id(i, end) for i in app.tags.get("propertyPath", "").split())
    return tuple(p for p in path if p is not None)


def _from_copy(raw: RawModel, copy: Element) -> EndTarget:
    """Climb from the copy through copies of nested parts to the real part, then descend by name."""
    copies = [copy]
    holder = copy.getparent()
    while holder is not None and raw.is_copy(holder):
        copies.append(holder)
        holder = holder.getparent()
    if holder is None or raw.uml_type(holder) != "Property":
        return EndTarget(None, None)
    resolved = [holder]
    for each in reversed(copies):
        member = member_named(raw, resolved[-1], raw.name(each), raw.uml_type(each))
        if member is None:
            return EndTarget(None, None)
        resolved.append(member)
    role, above = resolved[-1], tuple(resolved[:-1])
    part = above[-1] if raw.uml_type(role) == "Port" else None
    return EndTarget(role, part, above if len(above) > 1 else ())


def member_named(raw: RawModel, prop: Element, name: str, uml_type: str) -> Element | None:
    """The member of a property's type, or of the type's generals, with this name and UML type."""
    start = _element(raw.ref(prop, "type"))
    queue = [start] if start is not None else []
    seen: set[int] = set()
    while queue:
        typ = queue.pop(0)
        if id(typ) in seen:
            continue
        seen.add(id(typ))
        for feature in raw.table.member_features:
            for member in raw.children(typ, feature, uml_type):
                if raw.name(member) == name:
                    return member
        for generalization in raw.children(typ, "generalization"):
            general = _element(raw.ref(generalization, "general"))
            if general is not None:
                queue.append(general)
    return None
