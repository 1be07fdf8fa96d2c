"""Writing the UML tree (Eclipse UML2 form) for a parsed SysML v2 model: elements with ids and
source lines, stereotype applications, types, multiplicities, bodies and comments.

Ids are the qualified names of the elements (``PickAndPlace::DataTypes::Vector3``), made
unique with ``#2``, ``#3`` …; the line of each element is the line of the text it comes from.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from lxml import etree

from earl_m2t.read.xmi import Element, StereotypeApplication
from earl_m2t.sysml2.parser import location, members, multiplicity, rule
from earl_m2t.sysml2.scope import OWNED_METADATA_CONCEPTS, Resolved, Scope
from earl_m2t.sysml2.texts import ConditionText, metadata_tags, representation_text

XMI_NS = "http://www.omg.org/spec/XMI/20131001"
UML_NS = "http://www.eclipse.org/uml2/5.0.0/UML"
EARL_URI = "http:///schemas/EARL/sysml-v2/0"
SYSML_BLOCKS_URI = "http://www.eclipse.org/papyrus/sysml/1.6/SysML/Blocks"
PRIMITIVE_HREF = "pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml#"
PROFILE_HREF = "earl.sysml#"  # the EARL definitions, by name (profiles/earl.sysml, EARL::Model)
ID = f"{{{XMI_NS}}}id"
TYPE = f"{{{XMI_NS}}}type"


@dataclass
class Block:
    """A UML class being written: its members by name (for connector ends) and its owned
    behaviours by name (for calls, exclusions)."""

    node: Any
    element: Element
    members: dict[str, tuple[Element, Any]] = field(default_factory=dict)  # name -> (element, type node)
    behaviours: dict[str, str] = field(default_factory=dict)  # behaviour name -> xmi id


LXML_LAST_LINE = 65_535  # lxml keeps an element's line in 16 bits, as it does when it parses XMI


def set_line(element: Element, line: int) -> None:
    """``element`` written at ``line`` of the text; past lxml's last line, at that line (an XMI
    file parsed by lxml reports its later elements so too)."""
    element.sourceline = min(line, LXML_LAST_LINE)


class UmlWriter:
    def __init__(self, scope: Scope) -> None:
        self.scope = scope
        self.stereotypes: dict[str, list[StereotypeApplication]] = {}
        self._ids: dict[int, str] = {}
        self._used: set[str] = set()
        self._last: dict[str, int] = {}  # wanted id -> the last number tried for it

    # -- ids ----------------------------------------------------------------------------
    def new_id(self, wanted: str) -> str:
        # an id is one token: references to ids are whitespace-separated lists (a quoted name
        # such as 'System Instance' would otherwise refer to two ids)
        wanted = "".join("_" if c.isspace() else c for c in wanted)
        candidate, n = wanted, self._last.get(wanted, 1)
        while candidate in self._used:  # resumes where the last id wanted as ``wanted`` ended: linear
            n += 1
            candidate = f"{wanted}#{n}"
        self._last[wanted] = n
        self._used.add(candidate)
        return candidate

    def reserve(self, node: Any, qualified_name: str) -> None:
        """Give a definition its id before it is written, so that types may refer to it."""
        self._ids.setdefault(id(node), self.new_id(qualified_name or "_"))

    def id_of(self, node: Any) -> str | None:
        return self._ids.get(id(node))

    # -- elements -----------------------------------------------------------------------
    def model(self, name: str, line: int) -> Element:
        model = etree.Element(f"{{{UML_NS}}}Model", nsmap={"xmi": XMI_NS, "uml": UML_NS})
        model.set(ID, self.new_id(name))
        model.set("name", name)
        set_line(model, line)
        return model

    def child(self, parent: Element, feature: str, uml_type: str, node: Any, name: str = "") -> Element:
        """A new element ``<feature xmi:type="uml:T" name=…>`` under ``parent``, for ``node``
        (None: an element the text only implies, on its parent's line)."""
        child = etree.SubElement(parent, feature)
        child.set(TYPE, f"uml:{uml_type}")
        if node is not None:
            known = self._ids.get(id(node))
            if known is None:
                known = self._ids[id(node)] = self.new_id(f"{parent.get(ID)}::{name or rule(node)}")
            child.set(ID, known)
            set_line(child, location(node)[0])
        else:
            child.set(ID, self.new_id(f"{parent.get(ID)}::{uml_type}"))
            child.sourceline = parent.sourceline
        if name:
            child.set("name", name)
        return child

    def comment(self, owner: Element, node: Any) -> None:
        comment = self.child(owner, "ownedComment", "Comment", node)
        comment.set("annotatedElement", owner.get(ID) or "")
        etree.SubElement(comment, "body").text = representation_text(node.body)

    def body(self, element: Element, language: str, text: str, line: int) -> None:
        """``<language>`` and ``<body>`` of an opaque behaviour or expression."""
        etree.SubElement(element, "language").text = language
        body = etree.SubElement(element, "body")
        body.text = text
        set_line(body, line or element.sourceline)

    def constraint(self, owner: Element, name: str, condition: ConditionText, node: Any) -> Element:
        """A Constraint ``name`` whose specification is the condition's text."""
        language, text, line = condition
        constraint = self.child(owner, "ownedRule", "Constraint", None, name)
        set_line(constraint, line or location(node)[0])
        specification = self.child(constraint, "specification", "OpaqueExpression", None)
        self.body(specification, language, text, line)
        return constraint

    # -- stereotypes --------------------------------------------------------------------
    def apply(self, element: Element, concept: str, tags: dict[str, str], line: int) -> None:
        """Apply the EARL stereotype ``concept``; applied twice, the tags are merged."""
        base = element.get(ID) or ""
        applications = self.stereotypes.setdefault(base, [])
        for i, existing in enumerate(applications):
            if existing.family == "earl" and existing.name == concept:
                merged = {**existing.tags, **tags}
                applications[i] = StereotypeApplication(EARL_URI, "earl", concept, base, merged, existing.line)
                return
        applications.append(StereotypeApplication(EARL_URI, "earl", concept, base, dict(tags), line))

    def annotations(self, element: Element, node: Any) -> None:
        """What annotates a usage or definition: stereotypes through ``#X`` and ``@X { tag = v; }``,
        and its ``doc`` and ``comment``s (where ``earl-m2t: ignore[…]`` suppressions are read)."""
        for prefix in getattr(node, "prefixMetadata", None) or []:
            concept = self.scope.metadata_concept(prefix.type)
            if concept:
                self.apply(element, concept, {}, location(node)[0])
        for member in members(node):
            kind = rule(member)
            if kind == "MetadataUsage" and not member.about:
                self.metadata(element, member)
            elif kind in ("Documentation", "CommentElement"):
                self.comment(element, member)

    def metadata(self, element: Element, member: Any) -> None:
        """``@X { tag = v; }`` on ``element``: the stereotype X applies, with those tags (metadata
        that stands for an element of its own, such as a buffer group, is written elsewhere)."""
        concept = self.scope.metadata_concept(member.type)
        if concept and concept not in OWNED_METADATA_CONCEPTS:
            tags = {**self.scope.metadata_flags(member.type), **metadata_tags(member)}
            self.apply(element, concept, tags, location(member)[0])

    def nested_end(self, end: Element, path: list[str]) -> None:
        """SysML «NestedConnectorEnd» with the property path from the connector's owner."""
        base = end.get(ID) or ""
        self.stereotypes.setdefault(base, []).append(StereotypeApplication(
            SYSML_BLOCKS_URI, "sysml", "NestedConnectorEnd", base, {"propertyPath": " ".join(path)},
            end.sourceline or 0))

    # -- types and multiplicities -------------------------------------------------------
    def generalise(self, element: Element, target: Resolved) -> None:
        general = self.id_of(target.node) if target.node is not None else None
        if general:
            generalization = etree.SubElement(element, "generalization")
            generalization.set(TYPE, "uml:Generalization")
            generalization.set(ID, self.new_id(f"{element.get(ID)}::generalization"))
            generalization.set("general", general)
            generalization.sourceline = element.sourceline

    def generalise_concept(self, element: Element, concept: str) -> None:
        """A generalisation of the EARL definition ``concept`` (``href="…#Agent"``): how a
        definition that specialises it through the model's own definitions is recognised."""
        generalization = etree.SubElement(element, "generalization")
        generalization.set(TYPE, "uml:Generalization")
        generalization.set(ID, self.new_id(f"{element.get(ID)}::generalization"))
        generalization.sourceline = element.sourceline
        general = etree.SubElement(generalization, "general")
        general.set(TYPE, "uml:Class")
        general.set("href", PROFILE_HREF + concept)

    def set_type(self, element: Element, target: Resolved | None) -> None:
        """A definition of the model by id; a primitive type or an unknown name by href."""
        if target is None:
            return
        if target.node is not None:
            element.set("type", self.id_of(target.node) or "")
            return
        typ = etree.SubElement(element, "type")
        if target.primitive:
            typ.set(TYPE, "uml:PrimitiveType")
            typ.set("href", PRIMITIVE_HREF + target.primitive)
        else:
            typ.set("href", target.text or target.concept)
        typ.sourceline = element.sourceline

    def multiplicity(self, element: Element, usage: Any) -> None:
        declaration = getattr(usage, "declaration", None)
        try:
            bounds = multiplicity(declaration) if declaration is not None else None
        except ValueError:
            bounds = None
        if bounds is None:
            return
        lower, upper = bounds
        for feature, uml_type, value in (("lowerValue", "LiteralInteger", str(lower)),
                                         ("upperValue", "LiteralUnlimitedNatural",
                                          "*" if upper is None else str(upper))):
            bound = etree.SubElement(element, feature)
            bound.set(TYPE, f"uml:{uml_type}")
            bound.set(ID, self.new_id(f"{element.get(ID)}::{feature}"))
            bound.set("value", value)
