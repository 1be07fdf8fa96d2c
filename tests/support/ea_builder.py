"""Write EARL models as Enterprise Architect 16 exports them with "XMI 2.1".

The output follows EA's XMI 2.1 exporter: ``windows-1252`` encoding (characters outside
the code page as numeric character references), CRLF line ends, tab indentation,
``xmi:version="2.1"`` with ``http://schema.omg.org/spec/XMI/2.1`` and
``http://schema.omg.org/spec/UML/2.1``, ``<xmi:Documentation exporter="Enterprise Architect"
exporterVersion="6.5"/>``, a ``uml:Model`` named ``EA_Model`` that holds the exported package
and, after it, the stereotype applications (no ``xmi:id``), then the ``xmi:Extension
extender="Enterprise Architect"`` with EA's copies of elements and connectors (trimmed: the
activity nodes and control flows that EA also lists there, and the diagrams, are left out).

EA habits reproduced: ``EAID_``/``EAPK_`` GUID ids (third group in lower case) and the
ids EA derives from them (``EAID_LI000001_…`` multiplicity literals numbered through the
file, ``EAID_SC000000_``/``EAID_DS000000_`` connector ends, ``EAID_CO000000_``/
``EAID_OE000000_`` guards and their expressions, ``EAID_SR00000n_`` regions named
``EA_Region<n>``); every default written (``visibility``, ``isStatic`` … ``isDerivedUnion``,
``kind="local"`` on transitions, ``kind="initial"``, ``isSubmachineState``); types as
``<type xmi:idref>`` children, primitive types as ``EAJava_<name>`` defined under
``xmi:Extension/primitivetypes``; multiplicities on every attribute, as ``LiteralInteger``
(``-1`` in a ``LiteralUnlimitedNatural`` for ``*``); ports as ``ownedPort``; "ports on parts"
as ``qualifier`` copies of the type's ports under the part property, and nested parts of
an ibd as ``qualifier`` property copies, with connector ends pointing at the copies (no
``partWithPort``, no ``NestedConnectorEnd``) and the copies carrying the port's stereotypes;
guards inline (no ``guard`` reference) with the expression in a ``body=`` attribute and no
language, the same for opaque behaviours, whose language is the element's Language in its
extension record (``<code gentype="C++"/>``, ``"<none>"`` when unset, ``"Java"`` for classes);
no ``classifierBehavior``; ``incoming``/``outgoing`` ``xmi:idref`` children on vertices and
activity nodes; the children of a package, class, region or activity in Project Browser order,
a package's elements before its packages, each child followed by the connectors, transitions
or flows leaving it (so these come grouped by source, and only their ``ea_localid``, numbered
as they were created, keeps the order they were modelled in). The browser order is the model's:
the sample's modeller sorts the browser by hand as in the model (EA's free sort, alphabetical
sorting off), which gives every element its tree position, ``tpos="1"``, ``"2"`` …, and EA
exports in that order (by default EA sorts by type and name and leaves ``tpos="0"``).
SysML 1.4 MDG blocks as lower-case ``SysML1.4:block``; EARL stereotypes of the EA profile that
``earl-m2t profile --format ea`` writes (``xmlns:EARL="http://www.sparxsystems.com/profiles/EARL/1.0"``),
by its stereotype names (``EARL:ControlSubsystem``; a name with spaces would be written
``EARL:Control_Subsystem`` with the real name in ``__EAStereoName``), ``base_Attribute`` for a
stereotype on an attribute, tag defaults written out (``priority="0"``).

The model itself is the dialect-neutral one of ``cameo_builder`` (same API as
``papyrus_builder``); only the writer differs.
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterable
from dataclasses import dataclass, field

from tests.support.cameo_builder import (
    BOOLEAN,
    EARL_STEREOTYPES,
    INTEGER,
    REAL,
    STRING,
    Activity,
    ActivityNode,
    Applied,
    BaseModelBuilder,
    Block,
    Comment,
    Connector,
    Constraint,
    ControlFlow,
    DataType,
    Element,
    End,
    Multiplicity,
    OpaqueBehavior,
    Package,
    Param,
    Primitive,
    Property,
    Pseudostate,
    State,
    StateMachine,
    Transition,
    XmlNode,
    XmlStyle,
)

__all__ = [
    "BOOLEAN",
    "EARL_NS",
    "INTEGER",
    "REAL",
    "STRING",
    "End",
    "ModelBuilder",
    "Param",
    "ea_guid",
    "ea_stereotype_name",
]

XMI_NS = "http://schema.omg.org/spec/XMI/2.1"
UML_NS = "http://schema.omg.org/spec/UML/2.1"
EARL_NS = "http://www.sparxsystems.com/profiles/EARL/1.0"
SYSML_PREFIX = "SysML1.4"
SYSML_NS = "http://www.sparxsystems.com/profiles/SysML1.4/1.4"
CUSTOM_NS = "http://www.sparxsystems.com/profiles/thecustomprofile/1.0"
AUTHOR = "modeller"

# EA: double quotes, the XML entities it needs, newlines in attributes as &#xA;.
EA_STYLE = XmlStyle(
    quote='"',
    newline="\r\n",
    attr_escapes=(("&", "&amp;"), ("<", "&lt;"), (">", "&gt;"), ('"', "&quot;"), ("\n", "&#xA;"), ("\r", "&#xD;")),
    text_escapes=(("&", "&amp;"), ("<", "&lt;"), (">", "&gt;")),
)

# Tags of the EARL profile with their default value (EA copies defaults into each application)
# and the value list EA keeps in the tag's notes.
_TAG_DEFAULTS = {("FsmTransition", "priority"): "0"}
_TAG_NOTES = {("Agent", "declaredType"): "#NOTES#Values: C,CT,CE,CR,CET,CRT,CER,CERT&#xA;",
              ("Agent", "reactivation"): "#NOTES#Values: restart,resume&#xA;"}


def ea_guid(key: str) -> str:
    """The GUID part of an EA id, ``XXXXXXXX_XXXX_4xxx_YXXX_XXXXXXXXXXXX``, derived from ``key``."""
    h = hashlib.sha256(key.encode("utf-8")).hexdigest()
    variant = "89AB"[int(h[16], 16) % 4]
    return f"{h[0:8].upper()}_{h[8:12].upper()}_4{h[13:16]}_{variant}{h[17:20].upper()}_{h[20:32].upper()}"


def ea_stereotype_name(concept: str) -> str:
    """The stereotype of an EARL concept in the EA profile that ``earl-m2t profile --format ea``
    writes, as a modeller applying that profile in EA gets it: the concept's name, ``InputBuffer``."""
    return concept


def _tail(ea_id: str) -> str:
    """The last four groups of an EA id, reused by the ids EA derives from it."""
    return ea_id.split("_", 2)[2]


def _braced(ea_id: str) -> str:
    """``EAID_A_B_C_D_E`` as EA's ``{A-B-C-D-E}`` GUID."""
    return "{" + ea_id.split("_", 1)[1].replace("_", "-") + "}"


def _typed(tag: str, xmi_type: str, xmi_id: str, *attrs: tuple[str, str | None]) -> XmlNode:
    return XmlNode(tag, [("xmi:type", xmi_type), ("xmi:id", xmi_id), *attrs])


_APPEARANCE = "BackColor=-1;BorderColor=-1;BorderWidth=-1;FontColor=-1;VSwimLanes=1;HSwimLanes=1;BorderStyle=0;"
_PACKAGE_FLAGS: list[tuple[str, str | None]] = [
    ("iscontrolled", "FALSE"), ("isprotected", "FALSE"), ("usedtd", "FALSE"), ("logxml", "FALSE"),
    ("packageFlags", "isModel=1;"),
]  # fmt: skip
_FEATURE_FLAGS = (
    ("isStatic", "false"), ("isReadOnly", "false"), ("isDerived", "false"), ("isOrdered", "false"),
    ("isUnique", "true"), ("isDerivedUnion", "false"),
)  # fmt: skip


class ModelBuilder(BaseModelBuilder):
    """Build one Enterprise Architect 16 "XMI 2.1" export file."""

    def to_bytes(self) -> bytes:
        """Return the XMI document (windows-1252, CRLF, deterministic)."""
        return _EAWriter(self).render()


@dataclass
class _Copy:
    """A part or port shown on a part in an ibd: EA's ``qualifier`` copy of the original."""

    original: Property
    id: str
    children: dict[str, _Copy] = field(default_factory=dict)


def _in_model_order(copies: Iterable[_Copy]) -> list[_Copy]:
    """Copies of members of a part's type, in the order the type has its members."""

    def position(copy: _Copy) -> int:
        owner = copy.original.owner
        members: list[Property] = owner.attributes if isinstance(owner, Block) else []
        return next((n for n, member in enumerate(members) if member is copy.original), len(members))

    return sorted(copies, key=position)


@dataclass
class _Record:
    """One ``xmi:Extension/elements/element`` copy."""

    idref: str
    xmi_type: str
    name: str | None
    owner: str | None
    package: str
    stype: str
    stereotypes: list[str] = field(default_factory=list)
    tags: list[tuple[str, str]] = field(default_factory=list)
    attributes: list[Property] = field(default_factory=list)
    extra: list[tuple[str, str]] = field(default_factory=list)
    links: list[tuple[str, str, str, str]] = field(default_factory=list)  # (kind, id, start, end)
    note: str | None = None
    language: str | None = None  # the element's Language (EA's <code gentype>), when not the default


@dataclass
class _Link:
    """One ``xmi:Extension/connectors/connector`` copy."""

    id: str
    ea_type: str
    source: str
    target: str
    name: str | None = None
    stereotypes: list[str] = field(default_factory=list)
    tags: list[tuple[str, str]] = field(default_factory=list)
    guard: str | None = None


class _EAWriter:
    def __init__(self, builder: ModelBuilder):
        self.builder = builder
        self.ids: dict[str, str] = {}
        self.literals = 0
        self.apps: list[XmlNode] = []
        self.records: list[_Record] = []
        self.links: list[_Link] = []
        self.copies: dict[tuple[str, ...], str] = {}  # (block key, part names…, port name) -> copy id
        self.primitives: list[Primitive] = []
        self.regions: dict[str, int] = {}
        self.package_of: dict[str, str] = {}
        self.names: dict[str, tuple[str, str]] = {}  # id -> (EA type, name) for connector copies
        self.tree: dict[str, _Copy] = {}  # the copies on the parts of the block being written, by part key
        self.current_package = ""
        self.local_ids: dict[str, int] = {}
        self.tree_positions: dict[str, int] = {}

    # -- ids

    def id(self, element: Element) -> str:
        prefix = "EAPK_" if isinstance(element, Package) else "EAID_"
        return self._id(prefix, element.key)

    def _id(self, prefix: str, key: str) -> str:
        found = self.ids.get(prefix + key)
        if found is None:
            found = prefix + ea_guid(key)
            if found in self.ids.values():  # pragma: no cover - a hash collision
                raise ValueError(f"id collision for {key!r}")
            self.ids[prefix + key] = found
        return found

    def literal(self, owner_id: str) -> str:
        self.literals += 1
        return f"EAID_LI{self.literals:06d}_{_tail(owner_id)}"

    # -- document

    def render(self) -> bytes:
        builder = self.builder
        root = XmlNode(
            "xmi:XMI",
            [
                ("xmi:version", "2.1"),
                ("xmlns:uml", UML_NS),
                ("xmlns:xmi", XMI_NS),
                ("xmlns:thecustomprofile", CUSTOM_NS),
                *([("xmlns:EARL", EARL_NS)] if builder.stereotypes else []),
                (f"xmlns:{SYSML_PREFIX}", SYSML_NS),
            ],
        )
        root.sub("xmi:Documentation", [("exporter", "Enterprise Architect"), ("exporterVersion", "6.5")])
        model = root.sub("uml:Model", [("xmi:type", "uml:Model"), ("name", "EA_Model"), ("visibility", "public")])
        model.add(self.package(builder.model, None))
        for app in self.apps:
            model.add(app)
        root.add(self.extension())
        out = ['<?xml version="1.0" encoding="windows-1252"?>\r\n']
        root.write(out, 0, EA_STYLE)
        return "".join(out).encode("cp1252", errors="xmlcharrefreplace")

    # -- stereotype applications

    def stereotype(self, applied: Applied, base_id: str, element: Element) -> None:
        name = ea_stereotype_name(applied.name)
        metaclass = applied.metaclass
        if metaclass == "Property" and not (isinstance(element, Property) and element.is_port):
            metaclass = "Attribute"  # EA's metaclass for the attributes of a class
        tags = dict(applied.tags)
        for (stereo, tag), default in _TAG_DEFAULTS.items():
            if stereo == applied.name:
                tags.setdefault(tag, default)
        self.apps.append(XmlNode(
            f"EARL:{name.replace(' ', '_')}",
            [(f"base_{metaclass}", base_id), ("__EAStereoName", name if " " in name else None), *tags.items()],
        ))  # fmt: skip

    def stereotypes_of(self, element: Element, base_id: str | None = None) -> list[str]:
        """Apply ``element``'s EARL stereotypes (to ``base_id``, a copy, when given); their EA names."""
        for applied in element.applied:
            self.stereotype(applied, base_id or self.id(element), element)
        return [ea_stereotype_name(a.name) for a in element.applied]

    def tag_values(self, element: Element) -> list[tuple[str, str]]:
        values: list[tuple[str, str]] = []
        for applied in element.applied:
            given = dict(applied.tags)
            for (stereo, tag), default in _TAG_DEFAULTS.items():
                if stereo == applied.name:
                    given.setdefault(tag, default)
            for tag, value in given.items():
                values.append((tag, value + _TAG_NOTES.get((applied.name, tag), "")))
        return values

    # -- common parts

    def type_ref(self, node: XmlNode, type_: object) -> None:
        if isinstance(type_, Primitive):
            if type_ not in self.primitives:
                self.primitives.append(type_)
            node.sub("type", [("xmi:idref", f"EAJava_{type_.value}")])
        elif isinstance(type_, Element):
            node.sub("type", [("xmi:idref", self.id(type_))])

    def bounds(self, node: XmlNode, owner_id: str, mult: Multiplicity | None, always: bool) -> None:
        if mult is None:
            if not always:
                return
            mult = Multiplicity(1, 1)
        lower = [("xmi:type", "uml:LiteralInteger"), ("xmi:id", self.literal(owner_id)), ("value", str(mult.lower))]
        node.sub("lowerValue", lower)
        if mult.upper is None:  # EA writes * as -1
            upper = [("xmi:type", "uml:LiteralUnlimitedNatural"), ("xmi:id", self.literal(owner_id)), ("value", "-1")]
        else:
            upper = [("xmi:type", "uml:LiteralInteger"), ("xmi:id", self.literal(owner_id)), ("value", str(mult.upper))]
        node.sub("upperValue", upper)

    def record(
        self,
        element_id: str,
        xmi_type: str,
        name: str | None,
        owner: str | None,
        stype: str,
        *,
        stereotypes: Iterable[str] = (),
        tags: Iterable[tuple[str, str]] = (),
        attributes: Iterable[Property] = (),
        extra: Iterable[tuple[str, str]] = (),
        note: str | None = None,
        language: str | None = None,
    ) -> _Record:
        rec = _Record(
            element_id, xmi_type, name, owner, self.current_package, stype,
            list(stereotypes), list(tags), list(attributes), list(extra), note=note, language=language,
        )  # fmt: skip
        self.records.append(rec)
        self.names[element_id] = (stype, name or "")
        return rec

    def link(self, link: _Link) -> None:
        self.links.append(link)

    # -- packages and classifiers

    def package(self, pkg: Package, parent: str | None) -> XmlNode:
        pkg_id = self.id(pkg)
        outer, self.current_package = self.current_package, pkg_id
        node = _typed("packagedElement", "uml:Package", pkg_id, ("name", pkg.name), ("visibility", "public"))
        rec = self.record(pkg_id, "uml:Package", pkg.name, None, "Package")
        rec.extra.append(("parent", parent or ""))
        notes = [*pkg.comments]
        for member in pkg.members:
            if not isinstance(member, Package):
                notes += member.comments
        for note in notes:
            node.add(self.note(note))
        for member in pkg.members:  # the elements, then the packages
            if isinstance(member, DataType):
                node.add(self.data_type(member))
            elif isinstance(member, Block):
                node.add(self.block(member))
        for member in pkg.members:
            if isinstance(member, Package):
                node.add(self.package(member, pkg_id))
        self.current_package = outer
        return node

    def note(self, note: Comment) -> XmlNode:
        assert note.owner is not None
        note_id = self.id(note)
        node = _typed("ownedComment", "uml:Comment", note_id, ("body", note.body))
        node.sub("annotatedElement", [("xmi:idref", self.id(note.owner))])
        self.record(note_id, "uml:Note", None, None, "Note", note=note.body)
        return node

    def data_type(self, dt: DataType) -> XmlNode:
        dt_id = self.id(dt)
        node = _typed("packagedElement", "uml:DataType", dt_id, ("name", dt.name), ("visibility", "public"))
        self.record(dt_id, "uml:DataType", dt.name, None, "DataType", attributes=list(dt.fields))
        for prop in dt.fields:
            node.add(self.attribute(prop))
        return node

    def attribute(self, prop: Property) -> XmlNode:
        """An EA attribute: a data type field or a value property (memory)."""
        prop_id = self.id(prop)
        node = _typed(
            "ownedAttribute", "uml:Property", prop_id, ("name", prop.name), ("visibility", "public"), *_FEATURE_FLAGS
        )
        self.stereotypes_of(prop)
        self.type_ref(node, prop.type)
        self.bounds(node, prop_id, prop.multiplicity, always=True)
        return node

    def block(self, block: Block) -> XmlNode:
        block_id = self.id(block)
        node = _typed("packagedElement", "uml:Class", block_id, ("name", block.name), ("visibility", "public"),
                      ("isActive", "true" if block.classifier_behavior is not None else None))
        self.apps.append(XmlNode(f"{SYSML_PREFIX}:block", [("base_Class", block_id)]))
        earl = self.stereotypes_of(block)
        values = [p for p in block.attributes if p.is_value]
        self.record(
            block_id, "uml:Class", block.name, None, "Class", stereotypes=["block", *earl],
            tags=self.tag_values(block), attributes=values,
        )  # fmt: skip
        for prop in values:
            node.add(self.attribute(prop))
        self.plan_copies(block)
        children: list[object] = [p for p in block.attributes if not p.is_value]
        children += [*block.behaviors, *block.rules]
        placed: set[int] = set()
        for child in children:
            if isinstance(child, Property):
                node.add(self.port(child, block_id) if child.is_port else self.part(child, block))
                for conn in block.connectors:
                    first = conn.ends[0].end
                    if id(conn) not in placed and (first.path[0] if first.path else first.role) is child:
                        node.add(self.connector(conn, block))
                        placed.add(id(conn))
            elif isinstance(child, StateMachine):
                node.add(self.state_machine(child, block_id))
            elif isinstance(child, OpaqueBehavior):
                node.add(self.behavior(child, block_id))
            else:
                assert isinstance(child, Constraint)
                node.add(self.constraint("ownedRule", child, block_id))
        for conn in block.connectors:
            if id(conn) not in placed:
                node.add(self.connector(conn, block))
        return node

    # -- ports, parts and their copies

    def port(self, prop: Property, owner_id: str) -> XmlNode:
        prop_id = self.id(prop)
        node = _typed(
            "ownedPort", "uml:Port", prop_id, ("name", prop.name), ("visibility", "public"),
            ("aggregation", "composite"), ("isService", "true"), *_FEATURE_FLAGS,
        )  # fmt: skip
        earl = self.stereotypes_of(prop)
        self.record(
            prop_id, "uml:Port", prop.name, owner_id, "Port", stereotypes=earl,
            extra=[("propertyType", _braced(self.id(prop.type)) if isinstance(prop.type, Element) else "")],
        )  # fmt: skip
        self.type_ref(node, prop.type)
        self.bounds(node, prop_id, prop.multiplicity, always=False)
        return node

    def plan_copies(self, block: Block) -> None:
        """The ``qualifier`` copies an ibd of ``block`` needs: the ports of every connected part,
        and for a nested end the chain of part copies down to the part with the port."""
        self.tree = {}
        for conn in block.connectors:
            for end in conn.ends:
                path = end.end.path
                if not path:
                    continue
                outer = self.tree.setdefault(path[0].key, _Copy(path[0], self.id(path[0])))
                chain = outer
                names = [path[0].name or ""]
                for part in path[1:]:
                    names.append(part.name or "")
                    key = f"{block.key}\nEACopy\t{'/'.join(names)}"
                    chain = chain.children.setdefault(part.name or "", _Copy(part, self._id("EAID_", key)))
                part_type = path[-1].type
                assert isinstance(part_type, Block)
                for port in part_type.attributes:
                    if not port.is_port:
                        continue
                    if port.name not in chain.children:
                        key = f"{block.key}\nEACopy\t{'/'.join(names)}\t{port.name}"
                        chain.children[port.name or ""] = _Copy(port, self._id("EAID_", key))
                    self.copies[(block.key, *names, port.name or "")] = chain.children[port.name or ""].id

    def part(self, prop: Property, block: Block) -> XmlNode:
        prop_id = self.id(prop)
        node = _typed(
            "ownedAttribute", "uml:Property", prop_id, ("name", prop.name), ("visibility", "public"),
            ("aggregation", "composite"), *_FEATURE_FLAGS,
        )  # fmt: skip
        self.stereotypes_of(prop)
        self.record(
            prop_id, "uml:Part", prop.name, self.id(block), "Part",
            extra=[("propertyType", _braced(self.id(prop.type)) if isinstance(prop.type, Element) else "")],
        )  # fmt: skip
        self.type_ref(node, prop.type)
        self.bounds(node, prop_id, prop.multiplicity, always=False)
        copy = self.tree.get(prop.key)  # a part of the same name has copies of its own
        if copy is not None:
            for child in _in_model_order(copy.children.values()):
                node.add(self.qualifier(child, prop_id))
        return node

    def qualifier(self, copy: _Copy, owner_id: str) -> XmlNode:
        orig = copy.original
        attrs: list[tuple[str, str | None]] = [("name", orig.name), ("visibility", "public")]
        attrs += [("aggregation", "composite"), ("isService", "true" if orig.is_port else None)]
        node = _typed("qualifier", "uml:Port" if orig.is_port else "uml:Property", copy.id, *attrs, *_FEATURE_FLAGS)
        earl = self.stereotypes_of(orig, copy.id)
        kind = "Port" if orig.is_port else "Part"
        self.record(
            copy.id, f"uml:{kind}", orig.name, owner_id, kind, stereotypes=earl,
            extra=[
                ("propertyType", _braced(self.id(orig.type)) if isinstance(orig.type, Element) else ""),
                ("reusesProperty", _braced(self.id(orig))),
            ],
        )  # fmt: skip
        self.type_ref(node, orig.type)
        self.bounds(node, copy.id, orig.multiplicity, always=False)
        for child in _in_model_order(copy.children.values()):
            node.add(self.qualifier(child, copy.id))
        return node

    def end_role(self, end: End, block: Block) -> str:
        if not end.path:
            return self.id(end.role)
        return self.copies[(block.key, *(p.name or "" for p in end.path), end.role.name or "")]

    def connector(self, conn: Connector, block: Block) -> XmlNode:
        conn_id = self.id(conn)
        node = _typed("ownedConnector", "uml:Connector", conn_id, ("name", conn.name), ("visibility", "public"))
        roles = [self.end_role(end.end, block) for end in conn.ends]
        for prefix, role in zip(("EAID_SC000000_", "EAID_DS000000_"), roles):
            node.add(_typed("end", "uml:ConnectorEnd", prefix + _tail(conn_id), ("role", role)))
        earl = self.stereotypes_of(conn)
        self.link(_Link(conn_id, "Connector", roles[0], roles[1], conn.name, earl))
        return node

    # -- behaviours

    def behavior(self, behavior: OpaqueBehavior, owner_id: str) -> XmlNode:
        b_id = self.id(behavior)
        node = _typed(
            "ownedBehavior", "uml:OpaqueBehavior", b_id, ("name", behavior.name), ("visibility", "public"),
            ("body", behavior.body),
        )  # fmt: skip
        earl = self.stereotypes_of(behavior)
        self.record(
            b_id, "uml:OpaqueBehavior", behavior.name, owner_id, "OpaqueBehavior", stereotypes=earl,
            language=behavior.language,
        )  # fmt: skip
        for param in behavior.parameters:
            p = param.param
            p_id = self.id(param)
            pnode = node.add(_typed(
                "ownedParameter", "uml:Parameter", p_id, ("name", p.name), ("visibility", "public"),
                ("direction", p.direction), ("isStream", "false"), ("isException", "false"),
                ("isOrdered", "false"), ("isUnique", "true"),
            ))  # fmt: skip
            assert pnode is not None
            self.type_ref(pnode, p.type)
            self.bounds(pnode, p_id, param.multiplicity, always=False)
        return node

    def constraint(self, tag: str, rule: Constraint, owner_id: str) -> XmlNode:
        """A Constraint element (``tc``, ``ec``, an exclusion) owned by an activity or a class."""
        rule_id = self.id(rule)
        node = _typed(tag, "uml:Constraint", rule_id, ("name", rule.name), ("visibility", "public"))
        earl = self.stereotypes_of(rule)
        self.record(rule_id, "uml:Constraint", rule.name, owner_id, "Constraint", stereotypes=earl, note=rule.body)
        for element in rule.constrained:
            node.sub("constrainedElement", [("xmi:idref", self.id(element))])
        if rule.body is not None:
            spec_id = "EAID_OE000000_" + _tail(rule_id)
            node.sub("specification", [("xmi:type", "uml:OpaqueExpression"), ("xmi:id", spec_id), ("body", rule.body)])
        return node

    def state_machine(self, machine: StateMachine, owner_id: str) -> XmlNode:
        sm_id = self.id(machine)
        node = _typed("ownedBehavior", "uml:StateMachine", sm_id, ("name", machine.name), ("visibility", "public"))
        earl = self.stereotypes_of(machine)
        self.record(sm_id, "uml:StateMachine", machine.name, owner_id, "StateMachine", stereotypes=earl)
        n = self.regions.get(self.current_package, 0) + 1
        self.regions[self.current_package] = n
        region = node.sub("region", [
            ("xmi:type", "uml:Region"), ("xmi:id", f"EAID_SR{n:06d}_{_tail(self.current_package)}"),
            ("name", f"EA_Region{n}"), ("visibility", "public"),
        ])  # fmt: skip
        for vertex in machine.vertices():
            incoming = [t for t in machine.transitions if t.target is vertex]
            outgoing = [t for t in machine.transitions if t.source is vertex]
            region.add(self.vertex(vertex, sm_id, incoming, outgoing))
            for tr in outgoing:
                region.add(self.transition(tr))
        return node

    def vertex(self, vertex: Element, sm_id: str, incoming: list[Transition], outgoing: list[Transition]) -> XmlNode:
        v_id = self.id(vertex)
        if isinstance(vertex, Pseudostate):
            node = _typed(
                "subvertex", "uml:Pseudostate", v_id, ("name", "Initial"), ("visibility", "public"), ("kind", "initial")
            )
            self.record(v_id, "uml:StateNode", "Initial", sm_id, "StateNode", extra=[("nType", "3")])
        else:
            assert isinstance(vertex, State)
            node = _typed(
                "subvertex", "uml:State", v_id, ("name", vertex.name), ("visibility", "public"),
                ("isSubmachineState", "false"),
            )  # fmt: skip
            earl = self.stereotypes_of(vertex)
            self.record(v_id, "uml:State", vertex.name, sm_id, "State", stereotypes=earl)
        for tr in incoming:
            node.sub("incoming", [("xmi:idref", self.id(tr))])
        for tr in outgoing:
            node.sub("outgoing", [("xmi:idref", self.id(tr))])
        if isinstance(vertex, State) and vertex.do is not None:
            node.add(self.activity("doActivity", vertex.do, v_id))
        return node

    def transition(self, tr: Transition) -> XmlNode:
        tr_id = self.id(tr)
        node = _typed(
            "transition", "uml:Transition", tr_id, ("name", tr.name), ("visibility", "public"), ("kind", "local"),
            ("source", self.id(tr.source)), ("target", self.id(tr.target)),
        )  # fmt: skip
        earl = self.stereotypes_of(tr)
        if tr.guard is not None:
            # A guard is a property of EA's transition, not an element: it cannot carry a stereotype.
            guard = node.sub("guard", [("xmi:type", "uml:Constraint"), ("xmi:id", "EAID_CO000000_" + _tail(tr_id))])
            spec_id = "EAID_OE000000_" + _tail(tr_id)
            spec = [("xmi:type", "uml:OpaqueExpression"), ("xmi:id", spec_id), ("body", tr.guard.body)]
            guard.sub("specification", spec)
        self.link(_Link(
            tr_id, "StateFlow", self.id(tr.source), self.id(tr.target), tr.name, earl, self.tag_values(tr),
            tr.guard.body if tr.guard is not None else None,
        ))  # fmt: skip
        return node

    _NODE_NAMES = {"InitialNode": "ActivityInitial", "ActivityFinalNode": "ActivityFinal"}
    def activity(self, tag: str, act: Activity, owner_id: str) -> XmlNode:
        act_id = self.id(act)
        node = _typed(tag, "uml:Activity", act_id, ("name", act.name), ("visibility", "public"))
        earl = self.stereotypes_of(act)
        self.record(act_id, "uml:Activity", act.name, owner_id, "Activity", stereotypes=earl)
        children: list[object] = [*act.rules, *act.nodes]
        for child in children:
            if isinstance(child, Constraint):
                node.add(self.constraint("ownedRule", child, act_id))
                continue
            assert isinstance(child, ActivityNode)
            node.add(self.activity_node(child))
            for edge in child.outgoing:
                node.add(self.flow(edge))
        return node

    def node_name(self, act_node: ActivityNode) -> str | None:
        if act_node.node_type == "CallBehaviorAction":
            return act_node.name
        return self._NODE_NAMES.get(act_node.node_type)

    def activity_node(self, act_node: ActivityNode) -> XmlNode:
        n_id = self.id(act_node)
        name = self.node_name(act_node)
        node = _typed(
            "node", f"uml:{act_node.node_type}", n_id, ("name", name), ("visibility", "public"),
            ("behavior", self.id(act_node.behavior) if act_node.behavior is not None else None),
        )  # fmt: skip
        for edge in act_node.incoming:
            node.sub("incoming", [("xmi:idref", self.id(edge))])
        for edge in act_node.outgoing:
            node.sub("outgoing", [("xmi:idref", self.id(edge))])
        return node

    def flow(self, edge: ControlFlow) -> XmlNode:
        e_id = self.id(edge)
        node = _typed(
            "edge", "uml:ControlFlow", e_id, ("visibility", "public"),
            ("source", self.id(edge.source)), ("target", self.id(edge.target)),
        )  # fmt: skip
        node.sub("guard", [("xmi:type", "uml:LiteralBoolean"), ("xmi:id", self.literal(e_id)), ("value", "true")])
        node.sub("weight", [("xmi:type", "uml:LiteralInteger"), ("xmi:id", self.literal(e_id)), ("value", "0")])
        return node

    # -- xmi:Extension

    def stamp(self, key: str) -> str:
        """A creation time for ``key`` (deterministic), in EA's ``YYYY-MM-DD hh:mm:ss``."""
        h = int(hashlib.sha256(key.encode("utf-8")).hexdigest()[:8], 16)
        day = 3 + h % 20
        seconds = 8 * 3600 + (h // 20) % (9 * 3600)
        return f"2024-06-{day:02d} {seconds // 3600:02d}:{seconds // 60 % 60:02d}:{seconds % 60:02d}"

    def xrefs(self, guid_key: str, owner_id: str, stereotypes: list[str], kind: str = "element property") -> str | None:
        if not stereotypes:
            return None
        des = "".join(
            f"@STEREO;Name={s};FQName={SYSML_PREFIX if s == 'block' else 'EARL'}::{s};@ENDSTEREO;" for s in stereotypes
        )
        xid = _braced("EAID_" + ea_guid(guid_key))
        return (
            f"$XREFPROP=$XID={xid}$XID;$NAM=Stereotypes$NAM;$TYP={kind}$TYP;$VIS=Public$VIS;$PAR=0$PAR;"
            f"$DES={des}$DES;$CLT={_braced(owner_id)}$CLT;$SUP=<none>$SUP;$ENDXREF;"
        )

    def extension(self) -> XmlNode:
        ext = XmlNode("xmi:Extension", [("extender", "Enterprise Architect"), ("extenderID", "6.5")])
        elements = ext.sub("elements")
        self.local_ids = {rec.idref: n for n, rec in enumerate(self.records, start=1)}
        self.tree_positions = self.positions()
        for link in self.links:
            for rec in self.records:
                if rec.idref in (link.source, link.target):
                    rec.links.append((link.ea_type, link.id, link.source, link.target))
        attr_local = 0
        for rec in self.records:
            if rec.xmi_type == "uml:Package":
                elements.add(self.package_record(rec))
                continue
            el = elements.add(self.element_record(rec))
            assert el is not None
            if rec.attributes:
                attrs = el.sub("attributes")
                for position, prop in enumerate(rec.attributes):
                    attr_local += 1
                    attrs.add(self.attribute_record(prop, position, attr_local))
            if rec.links:
                links = el.sub("links")
                for kind, link_id, start, end in rec.links:
                    links.sub(kind, [("xmi:id", link_id), ("start", start), ("end", end)])
        connectors = ext.sub("connectors")
        created = self.connector_numbers()
        for link in self.links:
            connectors.add(self.connector_record(link, created[link.id]))
        prims = ext.sub("primitivetypes")
        outer = prims.sub("packagedElement", [
            ("xmi:type", "uml:Package"), ("xmi:id", "EAPrimitiveTypesPackage"),
            ("name", "EA_PrimitiveTypes_Package"), ("visibility", "public"),
        ])  # fmt: skip
        java = outer.sub("packagedElement", [
            ("xmi:type", "uml:Package"), ("xmi:id", "EAJavaTypesPackage"),
            ("name", "EA_Java_Types_Package"), ("visibility", "public"),
        ])  # fmt: skip
        for prim in self.primitives:
            java.sub("packagedElement", [
                ("xmi:type", "uml:PrimitiveType"), ("xmi:id", f"EAJava_{prim.value}"), ("name", prim.value),
                ("visibility", "public"),
            ])  # fmt: skip
        return ext

    def positions(self) -> dict[str, int]:
        """Each element's place among its siblings in the Project Browser, from 1: the tree position
        EA stores once the modeller orders the browser by hand (free sort), and the order it exports
        them in. Packages and elements are counted apart; notes, not in the browser, keep 0."""
        counters: dict[tuple[bool, str], int] = {}
        found: dict[str, int] = {}
        for rec in self.records:
            if rec.stype == "Note":
                continue
            is_package = rec.xmi_type == "uml:Package"
            parent = dict(rec.extra).get("parent", "") if is_package else rec.owner or rec.package
            if not parent:  # the exported package itself
                continue
            counters[(is_package, parent)] = found[rec.idref] = counters.get((is_package, parent), 0) + 1
        return found

    def connector_numbers(self) -> dict[str, int]:
        """EA's number (Connector_ID, ``ea_localid``) of each transition and connector, handed out as
        they are created: a block's connectors and a state machine's transitions in model order."""
        numbers: dict[str, int] = {}

        def visit(pkg: Package) -> None:
            for member in pkg.members:
                if isinstance(member, Package):
                    visit(member)
                elif isinstance(member, Block):
                    for conn in member.connectors:
                        numbers[self.id(conn)] = len(numbers) + 1
                    for behavior in member.behaviors:
                        for tr in behavior.transitions if isinstance(behavior, StateMachine) else ():
                            numbers[self.id(tr)] = len(numbers) + 1

        visit(self.builder.model)
        return numbers

    def project(self, el: XmlNode, created: str) -> None:
        el.sub("project", [
            ("author", AUTHOR), ("version", "1.0"), ("phase", "1.0"), ("created", created), ("modified", created),
            ("complexity", "1"), ("status", "Proposed"),
        ])  # fmt: skip

    def package_record(self, rec: _Record) -> XmlNode:
        created = self.stamp(rec.idref)
        parent = dict(rec.extra).get("parent", "")
        if not parent:  # the exported package itself
            el = XmlNode("element", [("xmi:idref", rec.idref)])
            el.sub("packageproperties")
            el.sub("paths")
            el.sub("times", [("created", created), ("modified", created)])
            el.sub("flags", _PACKAGE_FLAGS)
            return el
        el = XmlNode(
            "element", [("xmi:idref", rec.idref), ("xmi:type", "uml:Package"), ("name", rec.name), ("scope", "public")]
        )
        el.sub("model", [
            ("package2", "EAID_" + rec.idref.split("_", 1)[1]), ("package", parent),
            ("tpos", str(self.tree_positions.get(rec.idref, 0))),
            ("ea_localid", str(self.local_ids[rec.idref])), ("ea_eleType", "package"),
        ])  # fmt: skip
        el.sub("properties", [("isSpecification", "false"), ("sType", "Package"), ("nType", "0"), ("scope", "public")])
        self.project(el, created)
        el.sub("code", [("gentype", "Java")])
        el.sub("style", [("appearance", _APPEARANCE)])
        el.sub("tags")
        el.sub("xrefs")
        el.sub("extendedProperties", [("tagged", "0"), ("package_name", self.package_name(parent))])
        el.sub("packageproperties", [("version", "1.0")])
        el.sub("paths")
        el.sub("times", [("created", created), ("modified", created)])
        el.sub("flags", _PACKAGE_FLAGS)
        return el

    def element_record(self, rec: _Record) -> XmlNode:
        extra = dict(rec.extra)
        el = XmlNode(
            "element", [("xmi:idref", rec.idref), ("xmi:type", rec.xmi_type), ("name", rec.name), ("scope", "public")]
        )
        el.sub("model", [
            ("package", rec.package), ("owner", rec.owner), ("tpos", str(self.tree_positions.get(rec.idref, 0))),
            ("ea_localid", str(self.local_ids[rec.idref])), ("ea_eleType", "element"),
            ("classifier", extra.get("classifier")),
        ])  # fmt: skip
        el.sub("properties", [
            ("documentation", rec.note), ("isSpecification", "false"), ("sType", rec.stype),
            ("nType", extra.get("nType", "0")), ("scope", "public"),
            ("stereotype", rec.stereotypes[-1] if rec.stereotypes else None),
        ])  # fmt: skip
        self.project(el, self.stamp(rec.idref))
        default = "Java" if rec.stype in ("Class", "DataType") else "<none>"
        el.sub("code", [("gentype", rec.language or default)])
        el.sub("style", [("appearance", _APPEARANCE)])
        tags = el.sub("tags")
        for tag, value in rec.tags:
            tag_id = "EAID_" + ea_guid(f"{rec.idref}\ntag\t{tag}")
            tags.sub("tag", [("xmi:id", tag_id), ("name", tag), ("value", value), ("modelElement", rec.idref)])
        el.sub("xrefs", [("value", self.xrefs(f"{rec.idref}\nxref", rec.idref, rec.stereotypes))])
        el.sub("extendedProperties", [
            ("tagged", "0"), ("package_name", self.package_name(rec.package)),
            ("propertyType", extra.get("propertyType") or None), ("reusesProperty", extra.get("reusesProperty")),
        ])  # fmt: skip
        return el

    def package_name(self, package_id: str) -> str:
        for rec in self.records:
            if rec.idref == package_id:
                return rec.name or ""
        return ""

    def attribute_record(self, prop: Property, position: int, local_id: int) -> XmlNode:
        prop_id = self.id(prop)
        type_name = prop.type.value if isinstance(prop.type, Primitive) else getattr(prop.type, "name", "") or ""
        mult = prop.multiplicity or Multiplicity(1, 1)
        single = mult.is_fixed and mult.upper == 1
        node = XmlNode("attribute", [("xmi:idref", prop_id), ("name", prop.name), ("scope", "Public")])
        node.sub("initial")
        node.sub("documentation")
        node.sub("model", [("ea_localid", str(local_id)), ("ea_guid", _braced(prop_id))])
        node.sub("properties", [
            ("type", type_name), ("derived", "0"), ("collection", "false" if single else "true"),
            ("duplicates", "0"), ("changeability", "changeable"),
        ])  # fmt: skip
        node.sub("coords", [("ordered", "0")])
        node.sub("containment", [("containment", "Not Specified"), ("position", str(position))])
        names = [ea_stereotype_name(a.name) for a in prop.applied]
        node.sub("stereotype", [("stereotype", names[0] if names else None)])
        node.sub("bounds", [("lower", str(mult.lower)), ("upper", "*" if mult.upper is None else str(mult.upper))])
        node.sub("options")
        node.sub("style")
        node.sub("styleex", [("value", "volatile=0;")])
        node.sub("tags")
        node.sub("xrefs", [("value", self.xrefs(f"{prop_id}\nxref", prop_id, names, "attribute property"))])
        return node

    def connector_record(self, link: _Link, local_id: int) -> XmlNode:
        node = XmlNode("connector", [("xmi:idref", link.id)])
        for tag, end_id, navigable in (("source", link.source, False), ("target", link.target, True)):
            stype, name = self.names.get(end_id, ("", ""))
            end = node.sub(tag, [("xmi:idref", end_id)])
            end.sub("model", [("ea_localid", str(self.local_id(end_id))), ("type", stype), ("name", name or None)])
            end.sub("role", [("visibility", "Public"), ("targetScope", "instance")])
            end.sub("type", [("aggregation", "none"), ("containment", "Unspecified")])
            end.sub("constraints")
            end.sub("modifiers", [
                ("isOrdered", "false"), ("changeable", "none"), ("isNavigable", "true" if navigable else "false"),
            ])  # fmt: skip
            nav = "Navigable=Navigable;" if navigable else "Navigable=Unspecified;"
            style = "Union=0;Derived=0;AllowDuplicates=0;" + ("Owned=0;" + nav if link.ea_type == "Connector" else "")
            end.sub("style", [("value", style)])
            end.sub("documentation")
            end.sub("xrefs")
            end.sub("tags")
        node.sub("model", [("ea_localid", str(local_id))])
        node.sub("properties", [
            ("ea_type", link.ea_type), ("direction", "Source -> Destination"),
            ("stereotype", link.stereotypes[-1] if link.stereotypes else None),
        ])  # fmt: skip
        if link.ea_type == "Connector":
            node.sub("modifiers", [("isRoot", "false"), ("isLeaf", "false")])
        node.sub("documentation")
        node.sub("appearance", [
            ("linemode", "3"), ("linecolor", "-1"), ("linewidth", "0"), ("seqno", "0"), ("headStyle", "0"),
            ("lineStyle", "0"),
        ])  # fmt: skip
        node.sub("labels", [("mt", link.name if link.ea_type == "Connector" else None)])
        node.sub("extendedProperties", [
            ("virtualInheritance", "0"), ("privatedata1", link.name if link.ea_type == "StateFlow" else None),
            ("privatedata2", link.guard),
        ])  # fmt: skip
        node.sub("style")
        node.sub("xrefs", [("value", self.xrefs(f"{link.id}\nxref", link.id, link.stereotypes, "connector property"))])
        tags = node.sub("tags")
        for tag, value in link.tags:
            tag_id = "EAID_" + ea_guid(f"{link.id}\ntag\t{tag}")
            tags.sub("tag", [("xmi:id", tag_id), ("name", tag), ("value", value), ("modelElement", link.id)])
        return node

    def local_id(self, element_id: str) -> int:
        return self.local_ids.get(element_id, 0)


# The EARL concepts with their EA stereotype names, for readers of this module.
EA_STEREOTYPE_NAMES = {concept: ea_stereotype_name(concept) for concept in EARL_STEREOTYPES}
