"""A parsed SysML v2 model as the UML tree the XMI lift reads (Eclipse UML2 / Papyrus form).

EARL is recognised once, by the lift: this module and the writers it uses only say in UML
what the SysML v2 text says, element by element, so that stereotypes, generalisations, name
suffixes, replication, links, FSMs and transition-function stages follow the same rules
whatever the input.

- ``part def X :> Agent`` (a definition of the EARL profile, ``EARL::Model``) is the
  stereotype «Agent» applied to the block X, with the tags its ``:>> tag = value;`` features
  set; ``:> Y`` of a definition of the model is a generalisation; ``#Agent`` and
  ``@Priority { priority = 1; }`` apply stereotypes too (:mod:`earl_m2t.sysml2.uml`);
- attribute and enumeration definitions are dataTypes; part, port and attribute usages are
  UML properties and ports; a port typed by ``InputBuffer``/``OutputBuffer`` takes its
  dataType from ``:>> msg : T``;
- behaviours are written by :mod:`earl_m2t.sysml2.behaviours` (pf, pp, shared bb),
  :mod:`earl_m2t.sysml2.fsm` (state machines) and :mod:`earl_m2t.sysml2.activity` (stages);
- ``connect``, ``interface … connect``, ``flow … from … to`` are connectors, ends reached
  through several parts becoming SysML «NestedConnectorEnd»s.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from earl_m2t.profile_types import Profile
from earl_m2t.read.xmi import Element, StereotypeApplication
from earl_m2t.sysml2.behaviours import BehaviourWriter
from earl_m2t.sysml2.fsm import FsmWriter, Later
from earl_m2t.sysml2.parser import identification, location, members, name_segments, rule
from earl_m2t.sysml2.scope import Resolved, Scope
from earl_m2t.sysml2.texts import message_type, redefined_values
from earl_m2t.sysml2.uml import ID, Block, UmlWriter

DEFAULT_FSM_NAME = "fsm"
PROPERTY_USAGES = frozenset({"part", "attribute", "item"})


@dataclass
class Built:
    model: Element
    stereotypes: dict[str, list[StereotypeApplication]]


def build_xmi(root: Any, file: str, profile: Profile) -> Built:
    """The UML model (a ``uml:Model`` element) and the stereotype applications of a parsed model.

    One top-level package is the model; otherwise the model is named after the file.
    """
    return _Builder(file, profile).build(root)


class _Builder:
    def __init__(self, file: str, profile: Profile) -> None:
        self.file = file
        self.scope = Scope(profile)
        self.uml = UmlWriter(self.scope)
        self.later: Later = []
        self.behaviours = BehaviourWriter(self.uml, self.scope, self.later)
        self.fsm = FsmWriter(self.uml, self.scope, self.later)
        self.blocks: dict[int, Block] = {}

    def build(self, root: Any) -> Built:
        top = list(members(root))
        self.scope.index(top)
        self._reserve(top, "")
        packages = [m for m in top if rule(m) == "Package"]
        content = [m for m in top if rule(m) not in ("Package", "Import", "Alias")]
        if len(packages) == 1 and not content:
            (package,) = packages
            name = identification(package)[1] or Path(self.file).stem
            body, line = list(members(package)), location(package)[0]
        else:
            name, body, line = Path(self.file).stem, top, 1
        model = self.uml.model(name, line)
        self._namespace(model, body)
        for step in self.later:
            step()
        return Built(model, self.uml.stereotypes)

    def _reserve(self, elements: Iterable[Any], prefix: str) -> None:
        """Ids for every package and definition, by qualified name, before any is written."""
        for element in elements:
            if rule(element) in ("Package", "Definition"):
                name = identification(element)[1] or ""
                qualified = f"{prefix}::{name}" if prefix else name
                self.uml.reserve(element, qualified)
                self._reserve(members(element), qualified)

    # -- packages and definitions -------------------------------------------------------
    def _namespace(self, parent: Element, body: Iterable[Any]) -> None:
        for member in body:
            kind = rule(member)
            if kind == "Package":
                package = self.uml.child(parent, "packagedElement", "Package", member, identification(member)[1] or "")
                self._namespace(package, members(member))
            elif kind == "Definition":
                self._definition(parent, "packagedElement", member)
            elif kind in ("Documentation", "CommentElement"):
                self.uml.comment(parent, member)

    def _definition(self, parent: Element, feature: str, node: Any) -> None:
        name = identification(node)[1] or ""
        if node.kind == "part":
            self._block(parent, feature, node, name)
        elif node.kind == "attribute":
            self._datatype(parent, feature, node, name)
        elif node.kind == "enum":
            enumeration = self.uml.child(parent, feature, "Enumeration", node, name)
            for member in members(node):
                literal = identification(member)[1] if rule(member) == "Usage" else None
                if literal:
                    self.uml.child(enumeration, "ownedLiteral", "EnumerationLiteral", member, literal)

    def _datatype(self, parent: Element, feature: str, node: Any, name: str) -> None:
        fields = [m for m in members(node) if rule(m) == "Usage" and identification(m)[1]]
        supertypes = [self.scope.resolve(s) for s in node.supertypes]
        if not fields and any(s.primitive for s in supertypes):
            self.uml.child(parent, feature, "PrimitiveType", node, name)
            return
        datatype = self.uml.child(parent, feature, "DataType", node, name)
        for supertype in supertypes:
            self.uml.generalise(datatype, supertype)
        for member in fields:
            attribute = self.uml.child(datatype, "ownedAttribute", "Property", member, identification(member)[1] or "")
            self.uml.set_type(attribute, self.scope.typing(member))
            self.uml.multiplicity(attribute, member)

    # -- blocks -------------------------------------------------------------------------
    def _block(self, parent: Element, feature: str, node: Any, name: str) -> None:
        element = self.uml.child(parent, feature, "Class", node, name)
        block = self.blocks[id(node)] = Block(node, element)
        tags = redefined_values(node)
        direct = False
        for supertype in node.supertypes:
            target = self.scope.resolve(supertype)
            if target.concept:
                self.uml.apply(element, target.concept, tags, location(node)[0])
                direct = True
            else:
                self.uml.generalise(element, target)
        inherited = "" if direct else self.scope.concept_of(node)
        if inherited and tags:  # tags are values of the stereotype: give them one
            self.uml.apply(element, inherited, tags, location(node)[0])
        elif inherited:
            self.uml.generalise_concept(element, inherited)
        self.uml.annotations(element, node)
        for member in members(node):
            self._block_member(block, member)

    def _block_member(self, block: Block, member: Any) -> None:
        kind = rule(member)
        if kind == "Definition":
            if member.kind == "action":
                self.behaviours.action_definition(block, member)
            elif member.kind in ("calc", "constraint"):
                self.behaviours.predicate(block, member)
            elif member.kind == "state":
                self.fsm.state_machine(block, member, identification(member)[1] or DEFAULT_FSM_NAME)
            else:
                self._definition(block.element, "nestedClassifier", member)
        elif kind == "Usage":
            self._block_usage(block, member)
        elif kind == "MetadataUsage" and member.about:
            self.behaviours.exclusion(block, member)
        elif kind == "MetadataUsage":
            self.behaviours.tagged_constraint(block, member)
            self.behaviours.ltl_property(block, member)
        elif kind in ("ConnectorUsage", "FlowUsage"):
            self.later.append(lambda: self._connector(block, member))

    def _block_usage(self, block: Block, usage: Any) -> None:
        name = identification(usage)[1] or ""
        if usage.kind == "state":
            self.fsm.state_machine(block, usage, name or DEFAULT_FSM_NAME)
            return
        if not name:
            return  # `:>> tag = value;` (a tag of the block's stereotype) and the like
        if usage.kind == "port" or (usage.kind is None and usage.direction):
            block.members[name] = (self._port(block, usage, name), None)
        elif usage.kind in PROPERTY_USAGES or usage.kind is None:
            target = self.scope.typing(usage)
            element = self.uml.child(block.element, "ownedAttribute", "Property", usage, name)
            self.uml.set_type(element, target)
            if usage.kind == "part":
                element.set("aggregation", "composite")
            self.uml.multiplicity(element, usage)
            self.uml.annotations(element, usage)
            block.members[name] = (element, target.node if target is not None else None)

    def _port(self, block: Block, usage: Any, name: str) -> Element:
        """A buffer port: typed by InputBuffer/OutputBuffer (or a port definition specialising
        one) with ``:>> msg : T``, or directly by its dataType (then its name says the kind)."""
        port = self.uml.child(block.element, "ownedAttribute", "Port", usage, name)
        port.set("aggregation", "composite")
        target = self.scope.typing(usage)
        concept = ""
        message: Resolved | None = None
        declared = message_type(usage)
        if target is not None and target.concept:
            concept = target.concept
        elif target is not None and target.node is not None and target.node.kind == "port":
            concept = self.scope.concept_of(target.node)
            declared = declared or next(
                (found for found in map(message_type, self.scope.ancestry(target.node)) if found), None)
        else:
            message = target
        if declared is not None:
            message = self.scope.resolve(declared)
        if concept:
            self.uml.apply(port, concept, {}, location(usage)[0])
        self.uml.set_type(port, message)
        self.uml.multiplicity(port, usage)
        self.uml.annotations(port, usage)
        return port

    # -- connectors ---------------------------------------------------------------------
    def _connector(self, block: Block, node: Any) -> None:
        declaration = getattr(node, "declaration", None)
        name = identification(declaration)[1] if declaration is not None else None
        connector = self.uml.child(block.element, "ownedConnector", "Connector", node, name or "")
        target = self.scope.typing(node) if declaration is not None else None
        if target is not None and target.concept:
            self.uml.apply(connector, target.concept, {}, location(node)[0])
        self.uml.annotations(connector, node)
        for chain in (node.source, node.target):
            end = self.uml.child(connector, "end", "ConnectorEnd", None)
            role, parts = self._end(block, name_segments(chain))
            if role is not None:
                end.set("role", role.get(ID) or "")
            if parts:
                end.set("partWithPort", parts[-1].get(ID) or "")
            if len(parts) > 1:
                self.uml.nested_end(end, [p.get(ID) or "" for p in parts])

    def _end(self, block: Block, segments: tuple[str, ...]) -> tuple[Element | None, list[Element]]:
        """The port (or property) a feature chain ends at, and the parts it goes through."""
        parts: list[Element] = []
        current: Block | None = block
        for segment in segments[:-1]:
            if current is None or segment not in current.members:
                return None, parts
            element, type_node = current.members[segment]
            parts.append(element)
            current = self.blocks.get(id(type_node)) if type_node is not None else None
        if current is None or not segments or segments[-1] not in current.members:
            return None, parts
        return current.members[segments[-1]][0], parts
