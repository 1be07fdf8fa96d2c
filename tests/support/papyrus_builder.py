"""Write EARL models in the XMI dialect of Eclipse Papyrus 6.x with SysML 1.6.

The builder produces what Papyrus saves in a ``model.uml`` file: an ``xmi:XMI`` root
(XMI 20131001, Eclipse UML2 5.x), the ``uml:Model`` with its packages, blocks, state
machines and activities, then the stereotype applications (``Blocks:Block``,
``Blocks:NestedConnectorEnd``, ``EARL:Agent`` ...) as children of the root.

It follows the EMF serialisation habits readers meet in real files: 23-character ids
(``_`` + 22 url-safe base64 characters), attribute order ``xmi:type``, ``xmi:id``,
``name`` then the metamodel's feature order, default values omitted (no
``kind="initial"``, no ``direction="in"``, no ``aggregation="none"``), ``<language>``
before ``<body>``, the redundant ``node`` list on activities and ``incoming`` /
``outgoing`` lists on activity nodes, two-space indentation, UTF-8.

Ids are derived from a hash of each element's qualified path (owner chain, element
kind and name), so building the same model twice gives byte-identical output and
adding an element does not change the ids of the others.

Every construct of ``docs/modelling-guide.md`` can be written. EARL stereotypes can be
switched off (``ModelBuilder(stereotypes=False)``) to build the name-suffix and
generalisation variants of a model; SysML's own stereotypes (``Block``,
``NestedConnectorEnd``) are always written.

Example::

    mb = ModelBuilder("Demo")
    types = mb.package("DataTypes")
    cmd = types.data_type("Command")
    cmd.field("speed", REAL)
    inst = mb.package("SystemInstance")
    cs = inst.block("Control", "ControlSubsystem")
    out = cs.output_buffer("command/ob", cmd)
    pf = cs.partial_transition_function("send/pf", writes=[out])
    fsm = cs.state_machine()
    run = fsm.state("run", initial=True)
    run.do_activity().stages([[pf]])
    data = mb.to_bytes()
"""

from __future__ import annotations

import base64
import hashlib
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from enum import Enum
from pathlib import Path
from typing import TypeVar, Union

__all__ = [
    "BOOLEAN",
    "EARL_BLOCK_CONCEPTS",
    "EARL_EPACKAGE_ID",
    "EARL_NS",
    "EARL_PROFILE_FILE",
    "EARL_PROFILE_ID",
    "EARL_STEREOTYPES",
    "INTEGER",
    "REAL",
    "STRING",
    "Activity",
    "ActivityNode",
    "Block",
    "Comment",
    "Connector",
    "Constraint",
    "DataType",
    "Element",
    "End",
    "ModelBuilder",
    "Multiplicity",
    "OpaqueBehavior",
    "Package",
    "Param",
    "Primitive",
    "Property",
    "State",
    "StateMachine",
    "Transition",
    "emf_id",
]

# ---- namespaces and external resources -------------------------------------------------

XMI_NS = "http://www.omg.org/spec/XMI/20131001"
XSI_NS = "http://www.w3.org/2001/XMLSchema-instance"
ECORE_NS = "http://www.eclipse.org/emf/2002/Ecore"
UML_NS = "http://www.eclipse.org/uml2/5.0.0/UML"
BLOCKS_NS = "http://www.eclipse.org/papyrus/sysml/1.6/SysML/Blocks"
UML2_ANNOTATION = "http://www.eclipse.org/uml2/2.0.0/UML"
PRIMITIVE_LIBRARY = "pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml"
SYSML_PROFILE = "pathmap://SysML16_PROFILES/SysML.profile.uml"
SYSML_EPACKAGE = "http://www.eclipse.org/papyrus/sysml/1.6/SysML"


def emf_id(key: str) -> str:
    """Return an EMF-style id (``_`` + 22 url-safe base64 characters) derived from ``key``."""
    digest = hashlib.sha256(key.encode("utf-8")).digest()[:16]
    return "_" + base64.urlsafe_b64encode(digest).decode("ascii")[:22]


# The EARL profile as Papyrus would reference it: the profile file, the id of its
# uml:Profile element and of the EPackage defined from it (the namespace URI of the
# stereotype applications embeds that id and the definition number 0).
EARL_PROFILE_FILE = "EARL.profile.uml"
EARL_PROFILE_ID = emf_id("EARL.profile.uml\numl:Profile\tEARL")
EARL_EPACKAGE_ID = emf_id("EARL.profile.uml\necore:EPackage\tEARL/0")
EARL_NS = f"http:///schemas/EARL/{EARL_EPACKAGE_ID}/0"

# EARL stereotype -> the UML metaclass it extends (the ``base_<Metaclass>`` attribute).
EARL_STEREOTYPES: Mapping[str, str] = {
    "System": "Class",
    "Robot": "Class",
    "Agent": "Class",
    "ControlSubsystem": "Class",
    "VirtualEffector": "Class",
    "RealEffector": "Class",
    "VirtualReceptor": "Class",
    "RealReceptor": "Class",
    "AgentGroup": "Class",
    "SubsystemGroup": "Class",
    "InputBuffer": "Port",
    "OutputBuffer": "Port",
    "InternalMemory": "Property",
    "InterSubsystemLink": "Connector",
    "InterAgentLink": "Connector",
    "FSM": "StateMachine",
    "FsmState": "State",
    "FsmTransition": "Transition",
    "BasicBehaviour": "Activity",
    "TransitionFunction": "Activity",
    "PartialTransitionFunction": "Behavior",
    "Predicate": "Constraint",
    "PrimitivePredicate": "Behavior",
    "Exclusion": "Constraint",
    "BufferGroup": "Constraint",
    "LtlProperty": "Constraint",
    "Configuration": "Constraint",
}

# Blocks of the EARL *Model* package used by the generalisation route.
EARL_BLOCK_CONCEPTS: tuple[str, ...] = (
    "System",
    "Robot",
    "Agent",
    "ControlSubsystem",
    "VirtualEffector",
    "RealEffector",
    "VirtualReceptor",
    "RealReceptor",
)


class Primitive(Enum):
    """A type of the UML primitive type library, written as an ``href``."""

    BOOLEAN = "Boolean"
    INTEGER = "Integer"
    REAL = "Real"
    STRING = "String"
    UNLIMITED_NATURAL = "UnlimitedNatural"

    @property
    def href(self) -> str:
        return f"{PRIMITIVE_LIBRARY}#{self.value}"


BOOLEAN = Primitive.BOOLEAN
INTEGER = Primitive.INTEGER
REAL = Primitive.REAL
STRING = Primitive.STRING

TypeRef = Union[Primitive, "DataType", "Block"]
_E = TypeVar("_E", bound="Element")


@dataclass(frozen=True)
class Multiplicity:
    """Bounds of a multiplicity element; ``upper=None`` is ``*``."""

    lower: int
    upper: int | None

    @classmethod
    def of(cls, spec: MultiplicitySpec) -> Multiplicity | None:
        """Accept ``None`` (1..1, nothing written), ``6``, ``"6"``, ``"0..1"``, ``"*"``, ``(0, None)``."""
        if spec is None or isinstance(spec, Multiplicity):
            return spec
        if isinstance(spec, int):
            return cls(spec, spec)
        if isinstance(spec, tuple):
            return cls(spec[0], spec[1])
        text = spec.strip()
        if text == "*":
            return cls(0, None)
        low, sep, high = text.partition("..")
        if not sep:
            return cls(int(low), int(low))
        return cls(int(low), None if high.strip() == "*" else int(high))

    @property
    def is_fixed(self) -> bool:
        return self.upper == self.lower


MultiplicitySpec = None | int | str | tuple[int, int | None] | Multiplicity


# ---- XML writing ---------------------------------------------------------------------


class _Node:
    """One XML element: qualified tag, ordered attributes, children or text."""

    __slots__ = ("tag", "attrs", "children", "text")

    def __init__(self, tag: str, attrs: Iterable[tuple[str, str | None]] = (), text: str | None = None):
        self.tag = tag
        self.attrs = [(k, v) for k, v in attrs if v is not None]
        self.children: list[_Node] = []
        self.text = text

    def add(self, child: _Node | None) -> _Node | None:
        if child is not None:
            self.children.append(child)
        return child

    def write(self, out: list[str], depth: int) -> None:
        pad = "  " * depth
        attrs = "".join(f' {k}="{_escape_attr(v)}"' for k, v in self.attrs)
        if self.text is not None:
            out.append(f"{pad}<{self.tag}{attrs}>{_escape_text(self.text)}</{self.tag}>\n")
        elif not self.children:
            out.append(f"{pad}<{self.tag}{attrs}/>\n")
        else:
            out.append(f"{pad}<{self.tag}{attrs}>\n")
            for child in self.children:
                child.write(out, depth + 1)
            out.append(f"{pad}</{self.tag}>\n")


def _escape_text(text: str) -> str:
    # EMF escapes & < " and CR in element content and keeps LF.
    return (
        text.replace("&", "&amp;").replace("<", "&lt;").replace('"', "&quot;").replace("\r", "&#xD;")
    )


def _escape_attr(text: str) -> str:
    return (
        text.replace("&", "&amp;")
        .replace("<", "&lt;")
        .replace('"', "&quot;")
        .replace("\n", "&#xA;")
        .replace("\r", "&#xD;")
        .replace("\t", "&#x9;")
    )


def _typed(tag: str, xmi_type: str | None, xmi_id: str | None, *attrs: tuple[str, str | None]) -> _Node:
    head: list[tuple[str, str | None]] = [("xmi:type", xmi_type), ("xmi:id", xmi_id)]
    return _Node(tag, [*head, *attrs])


def _ids(elements: Iterable[Element]) -> str | None:
    joined = " ".join(e.id for e in elements)
    return joined or None


def _type_attr(type_: TypeRef | None) -> str | None:
    return None if type_ is None or isinstance(type_, Primitive) else type_.id


def _type_child(type_: TypeRef | None) -> _Node | None:
    if isinstance(type_, Primitive):
        return _Node("type", [("xmi:type", "uml:PrimitiveType"), ("href", type_.href)])
    return None


def _multiplicity_children(node: _Node, owner_key: str, mult: Multiplicity | None) -> None:
    if mult is None:
        return
    lower = None if mult.lower == 0 else str(mult.lower)
    upper = "*" if mult.upper is None else str(mult.upper)
    node.add(_typed("lowerValue", "uml:LiteralInteger", emf_id(owner_key + "\nlowerValue"), ("value", lower)))
    node.add(
        _typed("upperValue", "uml:LiteralUnlimitedNatural", emf_id(owner_key + "\nupperValue"), ("value", upper))
    )


def _expression(tag: str, owner_key: str, body: str, language: str) -> _Node:
    node = _typed(tag, "uml:OpaqueExpression", emf_id(owner_key + "\n" + tag))
    node.add(_Node("language", text=language))
    node.add(_Node("body", text=body))
    return node


# ---- model elements ------------------------------------------------------------------


class Element:
    """A model element with a deterministic ``xmi:id`` and optional owned comments."""

    xmi_type = "uml:Element"
    kind = "Element"

    def __init__(self, builder: ModelBuilder, owner: Element | None, name: str | None, key_name: str | None = None):
        self.builder = builder
        self.owner = owner
        self.name = name
        prefix = owner.key + "\n" if owner is not None else ""
        self.key = f"{prefix}{self.kind}\t{key_name if key_name is not None else name}"
        self.id = builder._register(self.key)
        self.comments: list[Comment] = []

    def comment(self, body: str) -> Comment:
        """Attach an ``ownedComment`` annotating this element."""
        note = Comment(self.builder, self, body, len(self.comments) + 1)
        self.comments.append(note)
        return note

    def stereotype(self, name: str, tags: Mapping[str, str | int | bool] | None = None) -> None:
        """Apply the EARL stereotype ``name`` (skipped when the builder writes no EARL stereotypes)."""
        self.builder.apply_earl(self, name, tags)

    def _render(self, tag: str) -> _Node:  # pragma: no cover - every subclass overrides
        raise NotImplementedError

    def _comment_nodes(self, node: _Node) -> None:
        for note in self.comments:
            node.add(note._render("ownedComment"))

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.name!r} {self.id}>"


class Comment(Element):
    """A ``uml:Comment`` whose ``annotatedElement`` is its owner."""

    xmi_type = "uml:Comment"
    kind = "Comment"

    def __init__(self, builder: ModelBuilder, owner: Element, body: str, index: int):
        super().__init__(builder, owner, None, key_name=str(index))
        self.body = body

    def _render(self, tag: str) -> _Node:
        assert self.owner is not None
        node = _typed(tag, self.xmi_type, self.id, ("annotatedElement", self.owner.id))
        node.add(_Node("body", text=self.body))
        return node


class Package(Element):
    """A ``uml:Package`` holding packages, data types and blocks."""

    xmi_type = "uml:Package"
    kind = "Package"

    def __init__(self, builder: ModelBuilder, owner: Element | None, name: str):
        super().__init__(builder, owner, name)
        self.members: list[Element] = []

    def package(self, name: str) -> Package:
        """Create a nested package."""
        return self._own(Package(self.builder, self, name))

    def data_type(self, name: str) -> DataType:
        """Create a ``uml:DataType``; add its fields with :meth:`DataType.field`."""
        return self._own(DataType(self.builder, self, name))

    def block(
        self, name: str, stereotype: str | None = None, tags: Mapping[str, str | int | bool] | None = None
    ) -> Block:
        """Create a SysML block (``uml:Class`` + ``Blocks:Block``), optionally with an EARL stereotype."""
        block = self._own(Block(self.builder, self, name))
        if stereotype is not None:
            block.stereotype(stereotype, tags)
        return block

    def _own(self, element: _E) -> _E:
        self.members.append(element)
        return element

    def _render(self, tag: str) -> _Node:
        node = _typed(tag, self.xmi_type, self.id, ("name", self.name))
        self._comment_nodes(node)
        self._render_imports(node)
        for member in self.members:
            node.add(member._render("packagedElement"))
        return node

    def _render_imports(self, node: _Node) -> None:
        pass


class Model(Package):
    """The ``uml:Model`` root: imports the UML primitive types, carries the profile applications."""

    xmi_type = "uml:Model"
    kind = "Model"

    def _render(self, tag: str) -> _Node:
        node = super()._render(tag)
        if tag == "uml:Model":  # as a root child the element name carries the type
            node.attrs = [(k, v) for k, v in node.attrs if k != "xmi:type"]
        for application in self.builder._profile_applications():
            node.add(application)
        return node

    def _render_imports(self, node: _Node) -> None:
        imp = node.add(_typed("packageImport", "uml:PackageImport", emf_id(self.key + "\npackageImport")))
        assert imp is not None
        imp.add(_Node("importedPackage", [("xmi:type", "uml:Model"), ("href", f"{PRIMITIVE_LIBRARY}#_0")]))


class Property(Element):
    """A ``uml:Property`` or ``uml:Port``: a data type field, part, port (buffer) or value (memory)."""

    kind = "Property"

    def __init__(
        self,
        builder: ModelBuilder,
        owner: Element,
        name: str,
        type_: TypeRef | None,
        multiplicity: MultiplicitySpec = None,
        *,
        port: bool = False,
        composite: bool = False,
    ):
        self.kind = "Port" if port else "Property"
        self.xmi_type = "uml:Port" if port else "uml:Property"
        super().__init__(builder, owner, name)
        self.type = type_
        self.multiplicity = Multiplicity.of(multiplicity)
        self.is_port = port
        self.composite = composite or port

    def _render(self, tag: str) -> _Node:
        node = _typed(
            tag,
            self.xmi_type,
            self.id,
            ("name", self.name),
            ("type", _type_attr(self.type)),
            ("aggregation", "composite" if self.composite else None),
        )
        self._comment_nodes(node)
        node.add(_type_child(self.type))
        _multiplicity_children(node, self.key, self.multiplicity)
        return node


class DataType(Element):
    """A ``uml:DataType`` whose owned attributes are the fields of an EARL dataType."""

    xmi_type = "uml:DataType"
    kind = "DataType"

    def __init__(self, builder: ModelBuilder, owner: Element, name: str):
        super().__init__(builder, owner, name)
        self.fields: list[Property] = []

    def field(self, name: str, type_: TypeRef, multiplicity: MultiplicitySpec = None) -> Property:
        """Add a field; ``multiplicity`` 6 is a fixed array, ``"*"`` or ``"0..1"`` a variable one."""
        prop = Property(self.builder, self, name, type_, multiplicity)
        self.fields.append(prop)
        return prop

    def _render(self, tag: str) -> _Node:
        node = _typed(tag, self.xmi_type, self.id, ("name", self.name))
        self._comment_nodes(node)
        for prop in self.fields:
            node.add(prop._render("ownedAttribute"))
        return node


@dataclass(frozen=True)
class Param:
    """A behaviour parameter: ``direction`` is ``in`` (omitted in XMI), ``out``, ``inout`` or ``return``."""

    name: str
    type: TypeRef | None = None
    direction: str = "in"
    multiplicity: MultiplicitySpec = None


class _Parameter(Element):
    xmi_type = "uml:Parameter"
    kind = "Parameter"

    def __init__(self, builder: ModelBuilder, owner: Element, param: Param):
        if param.direction not in ("in", "out", "inout", "return"):
            raise ValueError(f"parameter {param.name!r}: unknown direction {param.direction!r}")
        super().__init__(builder, owner, param.name)
        self.param = param

    def _render(self, tag: str) -> _Node:
        p = self.param
        node = _typed(
            tag,
            self.xmi_type,
            self.id,
            ("name", p.name),
            ("type", _type_attr(p.type)),
            ("direction", None if p.direction == "in" else p.direction),
        )
        node.add(_type_child(p.type))
        _multiplicity_children(node, self.key, Multiplicity.of(p.multiplicity))
        return node


class OpaqueBehavior(Element):
    """A ``uml:OpaqueBehavior`` (pf) or ``uml:FunctionBehavior`` (pp) with parameters, language and body."""

    kind = "Behavior"

    def __init__(
        self,
        builder: ModelBuilder,
        owner: Element,
        name: str,
        params: Sequence[Param],
        body: str,
        language: str,
        *,
        function: bool = False,
    ):
        super().__init__(builder, owner, name)
        self.xmi_type = "uml:FunctionBehavior" if function else "uml:OpaqueBehavior"
        self.parameters = [_Parameter(builder, self, p) for p in params]
        self.body = body
        self.language = language

    def _render(self, tag: str) -> _Node:
        node = _typed(tag, self.xmi_type, self.id, ("name", self.name))
        self._comment_nodes(node)
        for param in self.parameters:
            node.add(param._render("ownedParameter"))
        node.add(_Node("language", text=self.language))
        node.add(_Node("body", text=self.body))
        return node


class Constraint(Element):
    """A ``uml:Constraint`` (guard, ``tc``/``ec``, exclusion) with an optional OpaqueExpression."""

    xmi_type = "uml:Constraint"
    kind = "Constraint"

    def __init__(
        self,
        builder: ModelBuilder,
        owner: Element,
        name: str | None,
        body: str | None,
        language: str = "EARL",
        constrained: Sequence[Element] = (),
    ):
        super().__init__(builder, owner, name, key_name=name or "guard")
        self.body = body
        self.language = language
        self.constrained = list(constrained)

    def _render(self, tag: str) -> _Node:
        node = _typed(
            tag, self.xmi_type, self.id, ("name", self.name), ("constrainedElement", _ids(self.constrained))
        )
        self._comment_nodes(node)
        if self.body is not None:
            node.add(_expression("specification", self.key, self.body, self.language))
        return node


@dataclass(frozen=True)
class End:
    """A connector end: ``role`` (a port or part) reached through ``path``.

    ``path`` lists the parts from the connector's owning block down to the part whose
    type owns ``role``, outer to inner: ``(cs,)`` inside an agent block,
    ``(robot, agent, cs)`` from a system block. The last part becomes ``partWithPort``;
    a path of two or more parts also gets a ``Blocks:NestedConnectorEnd``.
    """

    role: Property
    path: tuple[Property, ...] = ()

    @classmethod
    def at(cls, role: Property, *path: Property) -> End:
        """``End.at(port, robot_part, agent_part, cs_part)``."""
        return cls(role, tuple(path))


class _ConnectorEnd(Element):
    xmi_type = "uml:ConnectorEnd"
    kind = "End"

    def __init__(self, builder: ModelBuilder, owner: Element, index: int, end: End):
        super().__init__(builder, owner, None, key_name=str(index))
        self.end = end

    def _render(self, tag: str) -> _Node:
        part = self.end.path[-1] if self.end.path else None
        return _typed(
            tag,
            self.xmi_type,
            self.id,
            ("partWithPort", part.id if part is not None else None),
            ("role", self.end.role.id),
        )


class Connector(Element):
    """A ``uml:Connector`` owned by a block: a link from ``source`` (ob) to ``target`` (ib)."""

    xmi_type = "uml:Connector"
    kind = "Connector"

    def __init__(self, builder: ModelBuilder, owner: Element, name: str, source: End, target: End):
        super().__init__(builder, owner, name)
        self.ends = [_ConnectorEnd(builder, self, 1, source), _ConnectorEnd(builder, self, 2, target)]
        for end in self.ends:
            builder._nested_end(end)

    def _render(self, tag: str) -> _Node:
        node = _typed(tag, self.xmi_type, self.id, ("name", self.name))
        self._comment_nodes(node)
        for end in self.ends:
            node.add(end._render("end"))
        return node


class _Generalization(Element):
    xmi_type = "uml:Generalization"
    kind = "Generalization"

    def __init__(self, builder: ModelBuilder, owner: Element, general: Block):
        super().__init__(builder, owner, None, key_name=general.key)
        self.general = general

    def _render(self, tag: str) -> _Node:
        return _typed(tag, self.xmi_type, self.id, ("general", self.general.id))


class Block(Element):
    """A SysML block: parts, ports (buffers), values (memory), connectors, FSM, pf, pp, exclusions."""

    xmi_type = "uml:Class"
    kind = "Class"

    def __init__(self, builder: ModelBuilder, owner: Element, name: str):
        super().__init__(builder, owner, name)
        self.rules: list[Constraint] = []
        self.generalizations: list[_Generalization] = []
        self.attributes: list[Property] = []
        self.connectors: list[Connector] = []
        self.behaviors: list[Element] = []
        self.classifier_behavior: Element | None = None
        builder._apply(self, "Blocks", "Block", "base_Class")

    # -- structure

    def specialize(self, general: Block) -> None:
        """Add a ``uml:Generalization`` to ``general`` (the EARL generalisation route)."""
        self.generalizations.append(_Generalization(self.builder, self, general))

    def part(self, name: str, type_: Block, multiplicity: MultiplicitySpec = None) -> Property:
        """Add a part property (``aggregation="composite"``) typed by a block."""
        return self._attr(Property(self.builder, self, name, type_, multiplicity, composite=True))

    def port(
        self,
        name: str,
        type_: TypeRef,
        multiplicity: MultiplicitySpec = None,
        stereotype: str | None = None,
    ) -> Property:
        """Add a ``uml:Port``, optionally stereotyped (``InputBuffer``, ``OutputBuffer``)."""
        prop = self._attr(Property(self.builder, self, name, type_, multiplicity, port=True))
        if stereotype is not None:
            prop.stereotype(stereotype)
        return prop

    def input_buffer(self, name: str, type_: TypeRef, multiplicity: MultiplicitySpec = None) -> Property:
        """Add an Input Buffer: a port stereotyped ``«InputBuffer»``."""
        return self.port(name, type_, multiplicity, "InputBuffer")

    def output_buffer(self, name: str, type_: TypeRef, multiplicity: MultiplicitySpec = None) -> Property:
        """Add an Output Buffer: a port stereotyped ``«OutputBuffer»``."""
        return self.port(name, type_, multiplicity, "OutputBuffer")

    def value(
        self,
        name: str,
        type_: TypeRef,
        multiplicity: MultiplicitySpec = None,
        stereotype: str | None = None,
    ) -> Property:
        """Add a value property (not a port), optionally stereotyped."""
        prop = self._attr(Property(self.builder, self, name, type_, multiplicity))
        if stereotype is not None:
            prop.stereotype(stereotype)
        return prop

    def memory(self, name: str, type_: TypeRef, multiplicity: MultiplicitySpec = None) -> Property:
        """Add an Internal Memory: a value property stereotyped ``«InternalMemory»``."""
        return self.value(name, type_, multiplicity, "InternalMemory")

    def connector(self, name: str, source: End, target: End, stereotype: str | None = None) -> Connector:
        """Add a connector from ``source`` (output buffer end) to ``target`` (input buffer end)."""
        conn = Connector(self.builder, self, name, source, target)
        self.connectors.append(conn)
        if stereotype is not None:
            conn.stereotype(stereotype)
        return conn

    def _attr(self, prop: Property) -> Property:
        self.attributes.append(prop)
        return prop

    # -- behaviour

    def state_machine(self, name: str = "fsm", stereotype: str | None = "FSM") -> StateMachine:
        """Add a state machine with one region; the first one becomes the ``classifierBehavior``."""
        machine = StateMachine(self.builder, self, name)
        self.behaviors.append(machine)
        if self.classifier_behavior is None:
            self.classifier_behavior = machine
        if stereotype is not None:
            machine.stereotype(stereotype)
        return machine

    def activity(self, name: str, stereotype: str | None = None) -> Activity:
        """Add an owned activity (a shared basic behaviour, or a pf written as an activity)."""
        act = Activity(self.builder, self, name)
        self.behaviors.append(act)
        if stereotype is not None:
            act.stereotype(stereotype)
        return act

    def opaque_behavior(
        self,
        name: str,
        params: Sequence[Param] = (),
        body: str = "",
        language: str = "C++",
        *,
        function: bool = False,
        stereotype: str | None = None,
    ) -> OpaqueBehavior:
        """Add an owned ``uml:OpaqueBehavior`` (or ``uml:FunctionBehavior`` when ``function``)."""
        behavior = OpaqueBehavior(self.builder, self, name, params, body, language, function=function)
        self.behaviors.append(behavior)
        if stereotype is not None:
            behavior.stereotype(stereotype)
        return behavior

    def partial_transition_function(
        self,
        name: str,
        reads: Sequence[Property] = (),
        writes: Sequence[Property] = (),
        body: str = "",
        language: str = "C++",
    ) -> OpaqueBehavior:
        """Add a pf whose parameters are named after the buffers and memories it reads and writes.

        A read buffer gives an ``in`` parameter of the buffer's name, a written one an
        ``out`` parameter; a memory ``x/m`` becomes ``x/mi`` when read and ``x/mo`` when
        written. Types and multiplicities are copied from the buffer or memory.
        """
        params = [self._pf_param(p, "in") for p in reads] + [self._pf_param(p, "out") for p in writes]
        return self.opaque_behavior(name, params, body, language, stereotype="PartialTransitionFunction")

    @staticmethod
    def _pf_param(prop: Property, direction: str) -> Param:
        name = prop.name or ""
        if not prop.is_port and name.endswith("/m"):
            name += "i" if direction == "in" else "o"
        return Param(name, prop.type, direction, prop.multiplicity)

    def primitive_predicate(self, name: str, body: str, language: str = "EARL") -> OpaqueBehavior:
        """Add a pp: a ``uml:FunctionBehavior`` with a Boolean ``return`` parameter."""
        return self.opaque_behavior(
            name,
            [Param("return", BOOLEAN, "return")],
            body,
            language,
            function=True,
            stereotype="PrimitivePredicate",
        )

    def exclusion(
        self,
        name: str,
        predicates: Sequence[OpaqueBehavior] = (),
        body: str | None = None,
        stereotype: bool = True,
    ) -> Constraint:
        """Declare primitive predicates mutually exclusive.

        Writes an owned ``uml:Constraint`` with the predicates as ``constrainedElement``
        and, when ``body`` is given, an EARL specification such as
        ``exclusive(a/pp, b/pp)``; ``stereotype`` applies ``«Exclusion»``.
        """
        rule = Constraint(self.builder, self, name, body, "EARL", predicates)
        self.rules.append(rule)
        if stereotype:
            rule.stereotype("Exclusion")
        return rule

    def ltl_property(self, name: str, formula: str) -> Constraint:
        """An «LtlProperty» constraint: ``earl-m2t verify`` checks the LTL formula of its
        specification (language LTL)."""
        rule = Constraint(self.builder, self, name, formula, "LTL")
        self.rules.append(rule)
        rule.stereotype("LtlProperty")
        return rule

    def buffer_group(self, name: str, obligatory: Sequence[Property] = (),
                     optional: Sequence[Property] = ()) -> Constraint:
        """A «BufferGroup» constraint: the Input Buffers an iteration waits for and those it reads
        when new (tags holding the buffer names)."""
        return self._tagged_rule(name, "BufferGroup", {"obligatory": " ".join(p.name or "" for p in obligatory),
                                                       "optional": " ".join(p.name or "" for p in optional)})

    def configuration(self, name: str, agents: Sequence[str] = (), links: Sequence[str] = (),
                      switch_timeout: float | str | None = None) -> Constraint:
        """A «Configuration» constraint of a System block: the variable agents and inter-agent links
        present in it (tags holding their paths, separated by spaces) and its ``switchTimeout`` in
        seconds."""
        tags: dict[str, str] = {"agents": " ".join(agents), "links": " ".join(links)}
        if switch_timeout is not None:
            tags["switchTimeout"] = str(switch_timeout)
        return self._tagged_rule(name, "Configuration", tags)

    def _tagged_rule(self, name: str, stereotype: str, tags: Mapping[str, str]) -> Constraint:
        # UML requires a Constraint's specification: the tags in words (the tags are what counts)
        body = "; ".join(f"{tag}: {value}" for tag, value in tags.items() if value)
        rule = Constraint(self.builder, self, name, body, "Natural language")
        self.rules.append(rule)
        rule.stereotype(stereotype, tags)
        return rule

    def _render(self, tag: str) -> _Node:
        cb = self.classifier_behavior
        # a block whose behaviour is a state machine runs it on its own: Eclipse UML2's validation
        # wants such a classifier active (EMF writes isActive after classifierBehavior)
        active = "true" if isinstance(cb, StateMachine) and self.xmi_type == "uml:Class" else None
        node = _typed(tag, self.xmi_type, self.id, ("name", self.name), ("classifierBehavior", cb.id if cb else None),
                      ("isActive", active))
        self._comment_nodes(node)
        for rule in self.rules:
            node.add(rule._render("ownedRule"))
        for gen in self.generalizations:
            node.add(gen._render("generalization"))
        for prop in self.attributes:
            node.add(prop._render("ownedAttribute"))
        for conn in self.connectors:
            node.add(conn._render("ownedConnector"))
        for behavior in self.behaviors:
            node.add(behavior._render("ownedBehavior"))
        return node


# ---- state machines ------------------------------------------------------------------


class _Pseudostate(Element):
    xmi_type = "uml:Pseudostate"
    kind = "Pseudostate"

    def _render(self, tag: str) -> _Node:
        return _typed(tag, self.xmi_type, self.id)


class State(Element):
    """A ``uml:State``; its basic behaviour is the ``doActivity`` made by :meth:`do_activity`."""

    xmi_type = "uml:State"
    kind = "State"

    def __init__(self, builder: ModelBuilder, owner: Element, name: str):
        super().__init__(builder, owner, name)
        self.do: Activity | None = None

    def do_activity(
        self,
        name: str | None = None,
        tc: str | None = "FALSE",
        ec: str | None = "FALSE",
        stereotype: str | None = "BasicBehaviour",
    ) -> Activity:
        """Create the state's ``doActivity`` (default name ``<state>/bb``) with ``tc``/``ec`` rules."""
        if self.do is not None:
            raise ValueError(f"state {self.name!r} already has a doActivity")
        act = Activity(self.builder, self, name or f"{self.name}/bb")
        if tc is not None:
            act.condition("tc", tc)
        if ec is not None:
            act.condition("ec", ec)
        if stereotype is not None:
            act.stereotype(stereotype)
        self.do = act
        return act

    def _render(self, tag: str) -> _Node:
        node = _typed(tag, self.xmi_type, self.id, ("name", self.name))
        self._comment_nodes(node)
        if self.do is not None:
            node.add(self.do._render("doActivity"))
        return node


class Transition(Element):
    """A ``uml:Transition``; the guard is an owned Constraint with an EARL OpaqueExpression."""

    xmi_type = "uml:Transition"
    kind = "Transition"

    def __init__(
        self,
        builder: ModelBuilder,
        owner: Element,
        name: str | None,
        source: Element,
        target: Element,
        guard: str | None,
    ):
        super().__init__(builder, owner, name, key_name=name or f"{source.key}->{target.key}")
        self.source = source
        self.target = target
        self.guard = Constraint(builder, self, "ic", guard) if guard is not None else None

    def _render(self, tag: str) -> _Node:
        node = _typed(
            tag,
            self.xmi_type,
            self.id,
            ("name", self.name),
            ("guard", self.guard.id if self.guard else None),
            ("source", self.source.id),
            ("target", self.target.id),
        )
        self._comment_nodes(node)
        if self.guard is not None:
            node.add(self.guard._render("ownedRule"))
        return node


class StateMachine(Element):
    """A ``uml:StateMachine`` with one region (``Region1``), an initial pseudostate and states."""

    xmi_type = "uml:StateMachine"
    kind = "StateMachine"

    def __init__(self, builder: ModelBuilder, owner: Element, name: str):
        super().__init__(builder, owner, name)
        self.region_id = emf_id(self.key + "\nRegion\tRegion1")
        self.initial: _Pseudostate | None = None
        self.states: list[State] = []
        self.transitions: list[Transition] = []

    def state(self, name: str, initial: bool = False, stereotype: str | None = "FsmState") -> State:
        """Add a state; ``initial=True`` also adds the initial pseudostate and its transition."""
        st = State(self.builder, self, name)
        self.states.append(st)
        if stereotype is not None:
            st.stereotype(stereotype)
        if initial:
            if self.initial is not None:
                raise ValueError(f"state machine {self.name!r} already has an initial state")
            self.initial = _Pseudostate(self.builder, self, None, key_name="initial")
            self.transitions.insert(0, Transition(self.builder, self, None, self.initial, st, None))
        return st

    def transition(
        self,
        source: State,
        target: State,
        guard: str | None = None,
        name: str | None = None,
        priority: int = 0,
        stereotype: bool = True,
    ) -> Transition:
        """Add a transition named ``source,target/t`` by default; a non-zero ``priority`` is tagged."""
        tr = Transition(self.builder, self, name or f"{source.name},{target.name}/t", source, target, guard)
        self.transitions.append(tr)
        if stereotype:
            tr.stereotype("FsmTransition", {"priority": priority} if priority else None)
            if tr.guard is not None:
                tr.guard.stereotype("Predicate")
        return tr

    def _render(self, tag: str) -> _Node:
        node = _typed(tag, self.xmi_type, self.id, ("name", self.name))
        self._comment_nodes(node)
        region = node.add(_typed("region", "uml:Region", self.region_id, ("name", "Region1")))
        assert region is not None
        for tr in self.transitions:
            region.add(tr._render("transition"))
        if self.initial is not None:
            region.add(self.initial._render("subvertex"))
        for st in self.states:
            region.add(st._render("subvertex"))
        return node


# ---- activities ----------------------------------------------------------------------


class ActivityNode(Element):
    """An activity node: control node or ``CallBehaviorAction``."""

    kind = "ActivityNode"

    def __init__(self, builder: ModelBuilder, owner: Activity, xmi_type: str, name: str, behavior: Element | None):
        super().__init__(builder, owner, name)
        self.xmi_type = xmi_type
        self.behavior = behavior
        self.incoming: list[_ControlFlow] = []
        self.outgoing: list[_ControlFlow] = []

    def _render(self, tag: str) -> _Node:
        node = _typed(
            tag,
            self.xmi_type,
            self.id,
            ("name", self.name),
            ("incoming", _ids(self.incoming)),
            ("outgoing", _ids(self.outgoing)),
            ("behavior", self.behavior.id if self.behavior is not None else None),
        )
        self._comment_nodes(node)
        return node


class _ControlFlow(Element):
    xmi_type = "uml:ControlFlow"
    kind = "ControlFlow"

    def __init__(self, builder: ModelBuilder, owner: Activity, source: ActivityNode, target: ActivityNode):
        super().__init__(builder, owner, None, key_name=f"{source.name}->{target.name}")
        self.source = source
        self.target = target
        source.outgoing.append(self)
        target.incoming.append(self)

    def _render(self, tag: str) -> _Node:
        # Papyrus writes target before source (the metamodel's feature order).
        return _typed(tag, self.xmi_type, self.id, ("target", self.target.id), ("source", self.source.id))


class Activity(Element):
    """A ``uml:Activity``: a basic behaviour (``tc``/``ec`` rules) whose graph is the tf."""

    xmi_type = "uml:Activity"
    kind = "Activity"

    def __init__(self, builder: ModelBuilder, owner: Element, name: str):
        super().__init__(builder, owner, name)
        self.rules: list[Constraint] = []
        self.nodes: list[ActivityNode] = []
        self.edges: list[_ControlFlow] = []
        self._counters: dict[str, int] = {}

    def condition(self, name: str, body: str, language: str = "EARL", stereotype: bool = True) -> Constraint:
        """Add an owned rule, e.g. ``tc`` or ``ec``, with an EARL specification."""
        rule = Constraint(self.builder, self, name, body, language)
        self.rules.append(rule)
        if stereotype:
            rule.stereotype("Predicate")
        return rule

    def _control(self, kind: str) -> ActivityNode:
        count = self._counters.get(kind, 0) + 1
        self._counters[kind] = count
        node = ActivityNode(self.builder, self, f"uml:{kind}", f"{kind}{count}", None)
        self.nodes.append(node)
        return node

    def initial(self) -> ActivityNode:
        """Add an ``InitialNode`` (named ``InitialNode1`` ... as Papyrus does)."""
        return self._control("InitialNode")

    def fork(self) -> ActivityNode:
        """Add a ``ForkNode``."""
        return self._control("ForkNode")

    def join(self) -> ActivityNode:
        """Add a ``JoinNode``."""
        return self._control("JoinNode")

    def final(self) -> ActivityNode:
        """Add an ``ActivityFinalNode``."""
        return self._control("ActivityFinalNode")

    def call(self, behavior: Element, name: str | None = None) -> ActivityNode:
        """Add a ``CallBehaviorAction`` of ``behavior``, named after it by default."""
        node = ActivityNode(self.builder, self, "uml:CallBehaviorAction", name or behavior.name or "", behavior)
        self.nodes.append(node)
        return node

    def flow(self, source: ActivityNode, target: ActivityNode) -> None:
        """Add a ``ControlFlow`` from ``source`` to ``target``."""
        self.edges.append(_ControlFlow(self.builder, self, source, target))

    def stages(self, stages: Sequence[Sequence[Element]]) -> list[list[ActivityNode]]:
        """Build initial → stage 1 → stage 2 … → final, one call per behaviour.

        A stage of several behaviours is put between a fork and a join (they may run in
        parallel); a stage of one behaviour is a plain call. Returns the call actions.
        """
        calls: list[list[ActivityNode]] = []
        last = self.initial()
        for stage in stages:
            if not stage:
                continue
            actions = [self.call(b) for b in stage]
            calls.append(actions)
            if len(actions) == 1:
                self.flow(last, actions[0])
                last = actions[0]
                continue
            fork = self.fork()
            self.flow(last, fork)
            for action in actions:
                self.flow(fork, action)
            join = self.join()
            for action in actions:
                self.flow(action, join)
            last = join
        self.flow(last, self.final())
        return calls

    def _render(self, tag: str) -> _Node:
        node = _typed(tag, self.xmi_type, self.id, ("name", self.name), ("node", _ids(self.nodes)))
        self._comment_nodes(node)
        for rule in self.rules:
            node.add(rule._render("ownedRule"))
        for edge in self.edges:
            node.add(edge._render("edge"))
        for act_node in self.nodes:
            node.add(act_node._render("node"))
        return node


# ---- the builder ---------------------------------------------------------------------


@dataclass(frozen=True)
class _Application:
    prefix: str
    name: str
    id: str
    base_attr: str
    base_id: str
    tags: tuple[tuple[str, str], ...]

    def render(self) -> _Node:
        return _Node(
            f"{self.prefix}:{self.name}",
            [("xmi:id", self.id), (self.base_attr, self.base_id), *self.tags],
        )


class ModelBuilder:
    """Build one Papyrus model file.

    ``stereotypes=False`` writes no EARL stereotype (nor the EARL profile application),
    for suffix-only and generalisation-only variants. ``nested_path_includes_part_with_port``
    selects how ``Blocks:NestedConnectorEnd.propertyPath`` is written: the whole path down
    to and including the ``partWithPort`` (SysML 1.6, the default), or without it.
    """

    def __init__(
        self,
        name: str,
        *,
        stereotypes: bool = True,
        nested_path_includes_part_with_port: bool = True,
        profile_location: str = EARL_PROFILE_FILE,
    ):
        self.stereotypes = stereotypes
        self.nested_path_includes_part_with_port = nested_path_includes_part_with_port
        self.profile_location = profile_location
        self._keys: dict[str, str] = {}
        self._ids: set[str] = set()
        self._applications: list[_Application] = []
        self._application_index: dict[tuple[str, str, str], int] = {}  # (base id, prefix, name) → position
        self.model = Model(self, None, name)

    # -- building

    def package(self, name: str) -> Package:
        """Create a top-level package of the model."""
        return self.model.package(name)

    def comment(self, body: str) -> Comment:
        """Attach an ``ownedComment`` to the model."""
        return self.model.comment(body)

    def earl_model(self, name: str = "Model", concepts: Sequence[str] = EARL_BLOCK_CONCEPTS) -> dict[str, Block]:
        """Create the EARL *Model* package (blocks named after the concepts) for the generalisation route."""
        pkg = self.package(name)
        return {concept: pkg.block(concept) for concept in concepts}

    def apply_earl(self, element: Element, stereotype: str, tags: Mapping[str, str | int | bool] | None = None) -> None:
        """Apply an EARL stereotype to ``element``; a no-op when ``stereotypes`` is off."""
        if stereotype not in EARL_STEREOTYPES:
            raise ValueError(f"unknown EARL stereotype {stereotype!r}")
        if not self.stereotypes:
            return
        i = self._application_index.get((element.id, "EARL", stereotype))
        if i is not None:  # applied: add the tags
            app = self._applications[i]
            added = tuple((k, ("true" if v else "false") if isinstance(v, bool) else str(v))
                          for k, v in (tags or {}).items())
            self._applications[i] = replace(app, tags=(*app.tags, *added))
            return
        self._apply(element, "EARL", stereotype, f"base_{EARL_STEREOTYPES[stereotype]}", tags)

    # -- output

    def to_bytes(self) -> bytes:
        """Return the XMI document (UTF-8, deterministic)."""
        namespaces = [("xmi", XMI_NS), ("xsi", XSI_NS), ("Blocks", BLOCKS_NS)]
        schema = [f"{BLOCKS_NS} {SYSML_EPACKAGE}#//blocks"]
        if self.stereotypes:
            namespaces.append(("EARL", EARL_NS))
            schema.append(f"{EARL_NS} {self.profile_location}#{EARL_EPACKAGE_ID}")
        namespaces += [("ecore", ECORE_NS), ("uml", UML_NS)]
        root = _Node(
            "xmi:XMI",
            [("xmi:version", "20131001"), *((f"xmlns:{p}", uri) for p, uri in namespaces)]
            + [("xsi:schemaLocation", " ".join(schema))],
        )
        root.add(self.model._render("uml:Model"))
        for application in self._applications:
            root.add(application.render())
        out = ['<?xml version="1.0" encoding="UTF-8"?>\n']
        root.write(out, 0)
        return "".join(out).encode("utf-8")

    def write(self, path: str | Path) -> None:
        """Write :meth:`to_bytes` to ``path``."""
        Path(path).write_bytes(self.to_bytes())

    # -- internals

    def _register(self, key: str) -> str:
        if key in self._keys:
            raise ValueError("two elements share one qualified path: " + key.replace("\n", " :: "))
        new_id = emf_id(key)
        if new_id in self._ids:  # pragma: no cover - a 128-bit hash collision
            raise ValueError(f"id collision for {key!r}")
        self._keys[key] = new_id
        self._ids.add(new_id)
        return new_id

    def _apply(
        self,
        element: Element,
        prefix: str,
        name: str,
        base_attr: str,
        tags: Mapping[str, str | int | bool] | None = None,
        extra: Sequence[tuple[str, str]] = (),
    ) -> None:
        rendered = tuple(
            (k, ("true" if v else "false") if isinstance(v, bool) else str(v)) for k, v in (tags or {}).items()
        )
        app_id = self._register(f"{element.key}\nstereotype\t{prefix}:{name}")
        self._application_index.setdefault((element.id, prefix, name), len(self._applications))
        self._applications.append(_Application(prefix, name, app_id, base_attr, element.id, (*extra, *rendered)))

    def _nested_end(self, end: _ConnectorEnd) -> None:
        path = list(end.end.path)
        if len(path) < 2:
            return
        if not self.nested_path_includes_part_with_port:
            path = path[:-1]
        self._apply(
            end, "Blocks", "NestedConnectorEnd", "base_ConnectorEnd", extra=[("propertyPath", _ids(path) or "")]
        )

    def _profile_applications(self) -> list[_Node]:
        apps = [
            ("SysML", f"{SYSML_EPACKAGE}#/", f"{SYSML_PROFILE}#SysML"),
            ("Blocks", f"{SYSML_EPACKAGE}#//blocks", f"{SYSML_PROFILE}#SysML.package_packagedElement_Blocks"),
        ]
        if self.stereotypes:
            apps.append(
                ("EARL", f"{self.profile_location}#{EARL_EPACKAGE_ID}", f"{self.profile_location}#{EARL_PROFILE_ID}")
            )
        nodes = []
        for label, epackage, profile in apps:
            key = f"{self.model.key}\nProfileApplication\t{label}"
            node = _typed("profileApplication", "uml:ProfileApplication", emf_id(key))
            note = node.add(
                _typed("eAnnotations", "ecore:EAnnotation", emf_id(key + "\neAnnotations"), ("source", UML2_ANNOTATION))
            )
            assert note is not None
            note.add(_Node("references", [("xmi:type", "ecore:EPackage"), ("href", epackage)]))
            node.add(_Node("appliedProfile", [("xmi:type", "uml:Profile"), ("href", profile)]))
            nodes.append(node)
        return nodes

