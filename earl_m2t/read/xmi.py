"""Stage 1: an XMI file as a dialect-neutral model over its XML tree.

:class:`RawModel` holds the tree, the index of every element by ``xmi:id`` and the stereotype
applications (built in one pass by :mod:`earl_m2t.read.xmi_index`, the applications read by
:mod:`earl_m2t.read.stereotype_applications`), and answers the later stages' questions about
an element: its UML type, its children, its location, its stereotypes, what the tool keeps
about it. References are resolved on demand, whichever of the four XMI encodings the tool used
(IDREF attribute, IDREFS list, child with ``xmi:idref``, child with ``href``).

A ``.mdzip`` project (:mod:`earl_m2t.read.mdzip`) gives one or two documents (model and shared
model), indexed as one model; every location names the member it comes from.

Other model files the model references (``href="types.uml#id"``) are read by
:mod:`earl_m2t.read.resources`, each into a model of its own; a reference into one resolves to
the element there, and every method below answers for an element of such a file from that
file's own ids, stereotypes and namespaces (its location names that file).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol, TypeAlias

from lxml import etree

from earl_m2t.diagnostics import Diagnostic
from earl_m2t.model.location import Location
from earl_m2t.read.dialects import DialectTable, dialect_table
from earl_m2t.read.extension import ExtensionIndex, in_connector_order
from earl_m2t.read.libraries import classify

Element: TypeAlias = etree._Element

__all__ = [
    "Element",
    "ExternalRef",
    "RawModel",
    "StereotypeApplication",
    "namespace_of",
    "stereotype_key",
]


@dataclass(frozen=True, slots=True)
class ExternalRef:
    """A reference into another resource (``href="lib.uml#id"``) that is not in this file.

    ``path`` is the target's qualified name when the file states it (MagicDraw writes a
    ``referenceExtension referentPath='SysML::Libraries::PrimitiveValueTypes::Real'`` beside
    every href into a used project), else "". ``library`` is the kind of library the href
    points into (``primitive-types``, ``value-types`` … of ``metamodel/xmi/libraries.toml``),
    "" when it is none: its target is then known by name only.
    """

    href: str
    path: str = ""
    library: str = ""

    @property
    def fragment(self) -> str:
        return self.href.rpartition("#")[2]

    @property
    def resource(self) -> str:
        return self.href.partition("#")[0]

    @property
    def name(self) -> str:
        """The target's own name, the last segment of ``path`` ("" when unknown)."""
        return self.path.rpartition("::")[2].strip()


def stereotype_key(name: str) -> str:
    """A stereotype name as tools may spell it, reduced for comparison: Enterprise Architect
    writes ``Input_Buffer`` (or ``Input Buffer`` in ``__EAStereoName``) and ``block``."""
    return name.replace("_", "").replace(" ", "").lower()


@dataclass(frozen=True, slots=True)
class StereotypeApplication:
    """``<Profile:Stereotype base_X="id" tag="value"/>``, indexed by the extended element.

    Tag values given as child elements are joined with spaces: text as written, references
    as the target's id (``xmi:idref``, or the fragment of an href into this file) or, for an
    href into another resource, the href itself with spaces escaped as ``%20``.
    """

    profile_uri: str
    family: str  # "earl" | "sysml" | "other": which profile the namespace belongs to
    name: str
    base_id: str
    tags: dict[str, str]
    line: int


class Resolver(Protocol):
    """The files a model references (:class:`earl_m2t.read.resources.ResourceSet`)."""

    def model_of(self, el: Element) -> RawModel | None:
        """The model an element was read from, None when it is the only one."""

    def element(self, raw: RawModel, resource: str, fragment: str) -> Element | None:
        """The element ``resource#fragment`` names, the resource relative to ``raw``'s file."""


@dataclass
class RawModel:
    """A parsed XMI file: the tree, the id index and the stereotype applications.

    A model may come from several documents (a ``.mdzip``'s model and shared model): ``root``
    and ``file`` are the first one's, ``documents`` lists every (root, file) pair.
    """

    file: str
    root: Element
    dialect: str
    xmi_ns: str
    uml_ns: str
    by_id: dict[str, Element]
    stereotypes: dict[str, list[StereotypeApplication]]
    model_roots: list[Element]
    diagnostics: list[Diagnostic] = field(default_factory=list)
    table: DialectTable = field(default_factory=dialect_table)
    documents: tuple[tuple[Element, str], ...] = ()
    earl_uris: frozenset[str] = frozenset()  # the file's own EARL profile URIs (normalised)
    _extension: ExtensionIndex | None = field(default=None, init=False, repr=False, compare=False)
    resolver: Resolver | None = None  # the other files it references, once they are read
    # (model root, element) for each element outside tool extension blocks whose href names
    # another resource, in document order: collected by the index pass
    external_hrefs: list[tuple[Element, Element]] = field(default_factory=list)

    def __post_init__(self) -> None:
        self._id_attr = f"{{{self.xmi_ns}}}id"
        self._idref_attr = f"{{{self.xmi_ns}}}idref"
        self._type_attr = f"{{{self.xmi_ns}}}type"
        self._referent_path = f"{{{self.xmi_ns}}}Extension/referenceExtension"
        if not self.documents:
            self.documents = ((self.root, self.file),)

    def _home(self, el: Element) -> RawModel:
        """The model an element was read from: this one, or another file it references."""
        if self.resolver is None:
            return self
        return self.resolver.model_of(el) or self

    # -- identity and location -------------------------------------------------------------
    def xmi_id(self, el: Element) -> str:
        if self.resolver is None:  # the common case, answered without a call
            return el.get(self._id_attr) or ""
        return el.get(self._home(el)._id_attr) or ""

    def file_of(self, el: Element) -> str:
        """The file (or archive member) an element was read from."""
        home = self._home(el)
        if len(home.documents) == 1:
            return home.file
        root = el.getroottree().getroot()
        return next((file for doc, file in home.documents if doc is root), home.file)

    def location(self, el: Element) -> Location:
        if self.resolver is None and len(self.documents) == 1:  # one file: no lookups (a hot path)
            return Location(self.file, el.sourceline or 0, 0, el.get(self._id_attr) or "")
        return Location(self.file_of(el), el.sourceline or 0, 0, self.xmi_id(el))

    def name(self, el: Element) -> str:
        return el.get("name") or ""

    # -- models ------------------------------------------------------------------------------
    def is_wrapper(self, el: Element) -> bool:
        """A tool's export wrapper, not a model of the user's (``[models] wrapper_names``)."""
        return self.uml_type(el) == "Model" and self.name(el) in self.table.wrapper_model_names

    def models(self) -> list[Element]:
        """The user's models: the UML roots, or the packages a tool's wrapper holds."""
        found: list[Element] = []
        for root in self.model_roots:
            if self.is_wrapper(root):
                found.extend(self.children(root, "packagedElement", "Package", "Model") or [root])
            else:
                found.append(root)
        return found

    def is_model(self, el: Element) -> bool:
        """Whether qualified names stop at this element: a uml:Model, or a package a wrapper holds."""
        if self.uml_type(el) == "Model":
            return True
        parent = el.getparent()
        return parent is not None and el.tag == "packagedElement" and self.is_wrapper(parent)

    @property
    def model_name(self) -> str:
        return next((self.name(m) for m in self.models() if self.name(m)), "")

    def uml_type(self, el: Element) -> str:
        """The UML metaclass of an element (``Class``, ``Port``…), from ``xmi:type`` or its feature."""
        home = self if self.resolver is None else self._home(el)
        declared = el.get(home._type_attr)
        if declared:
            return declared.rpartition(":")[2]
        tag = el.tag
        if isinstance(tag, str) and tag.startswith("{"):
            uri, _, local = tag[1:].partition("}")
            if uri == home.uml_ns:
                return local  # a root element such as <uml:Model>
            return ""
        return self.table.implicit_types.get(str(tag), "")

    # -- containment -----------------------------------------------------------------------
    def children(self, el: Element, feature: str, *types: str) -> list[Element]:
        """Contained children in ``feature`` (XML element name), optionally of given UML types."""
        if not types:
            return list(el.iterchildren(feature))
        uml_type = self.uml_type
        return [child for child in el.iterchildren(feature) if uml_type(child) in types]

    def owner(self, el: Element) -> Element | None:
        """The containing element; None at the top (the ``xmi:XMI`` wrapper is nobody's owner)."""
        parent = el.getparent()
        if parent is None or (parent.getparent() is None and namespace_of(parent) != self._home(el).uml_ns):
            return None
        return parent

    def is_copy(self, el: Element) -> bool:
        """A tool's copy of a member of a part's type, kept under the part (``[connector_ends]``)."""
        return el.tag in self.table.copy_features and self.uml_type(el) in ("Port", "Property")

    # -- references --------------------------------------------------------------------------
    def refs(self, el: Element, feature: str) -> list[Element | ExternalRef]:
        """All targets of a reference feature, in any of the four XMI encodings."""
        home = self._home(el)
        if home is not self:
            return home.refs(el, feature)
        targets: list[Element | ExternalRef] = []
        value = el.get(feature)
        if value:
            for ref_id in value.split():
                target = self.by_id.get(ref_id)
                targets.append(target if target is not None else ExternalRef("#" + ref_id))
            if not len(el):
                return targets
        idref_attr = self._idref_attr
        for child in el.iterchildren(feature):
            ref_id = child.get(idref_attr)
            href = child.get("href")
            if ref_id:
                target = self.by_id.get(ref_id)
                targets.append(target if target is not None else ExternalRef("#" + ref_id))
            elif href:
                targets.append(self._resolve_href(href, child))
        return targets

    def ref(self, el: Element, feature: str) -> Element | ExternalRef | None:
        value = el.get(feature)
        if value and " " not in value:  # the common case: one IDREF attribute
            target = self._home(el).by_id.get(value)
            return target if target is not None else ExternalRef("#" + value)
        found = self.refs(el, feature)
        return found[0] if found else None

    def local_fragment(self, href: str) -> str:
        """The id an href names in this file ("#id", MagicDraw's "local:/PROJECT-…#id"), else ""."""
        resource, _, fragment = href.partition("#")
        if fragment in self.by_id and (not resource or resource.startswith(self.table.local_resource_prefixes)):
            return fragment
        return ""

    def element_by_id(self, ref_id: str, near: Element) -> Element | None:
        """The element with an xmi:id in the file ``near`` was read from."""
        return self._home(near).by_id.get(ref_id)

    def _resolve_href(self, href: str, el: Element | None = None) -> Element | ExternalRef:
        local = self.local_fragment(href)
        if local:
            return self.by_id[local]
        path = ""
        if el is not None and len(el):
            referent = el.find(self._referent_path)
            path = (referent.get("referentPath") or "") if referent is not None else ""
        resource, _, fragment = href.partition("#")
        if not resource or resource.startswith(self.table.local_resource_prefixes):
            return ExternalRef(href, path)
        named = classify(resource)
        if named.kind == "file" and self.resolver is not None:
            target = self.resolver.element(self, resource, fragment)
            if target is not None:
                return target
        return ExternalRef(href, path, named.library)

    # -- stereotypes -------------------------------------------------------------------------
    def applied(self, el: Element) -> list[StereotypeApplication]:
        home = self._home(el)
        return home.stereotypes.get(el.get(home._id_attr) or "", [])

    def sysml_application(self, el: Element, name: str) -> StereotypeApplication | None:
        """The application of a SysML stereotype to an element, the name compared as :func:`stereotype_key` does."""
        key = stereotype_key(name)
        return next(
            (app for app in self.applied(el) if app.family == "sysml" and stereotype_key(app.name) == key), None
        )

    def has_sysml(self, el: Element, name: str) -> bool:
        return self.sysml_application(el, name) is not None

    # -- the tool's own records (xmi:Extension) ----------------------------------------------
    def extension_property(self, el: Element, name: str) -> str:
        """A property the tool keeps about ``el`` in its ``xmi:Extension`` (``[extension]`` of
        dialects.toml: EA's ``language``, ``created``); "" when it says nothing."""
        home = self._home(el)
        if home is not self:
            return home.extension_property(el, name)
        if self._extension is None:
            self._extension = ExtensionIndex.read((root for root, _ in self.documents), self.xmi_ns, self.table)
        return self._extension.get(self.xmi_id(el), name)

    def body_language(self, el: Element) -> str:
        """The language the tool keeps for an opaque behaviour or expression outside it (an
        expression's is its Constraint's); "" when none. See ``[extension.uses] body_language``."""
        name = self.table.body_language_property
        if not name:
            return ""
        language = self.extension_property(el, name)
        if not language and self.uml_type(el) == "OpaqueExpression":
            owner = self.owner(el)
            if owner is not None and self.uml_type(owner) == "Constraint":
                language = self.extension_property(owner, name)
        return language

    def in_connector_order(self, elements: list[Element]) -> list[Element]:
        """Transitions or connectors in the order the tool created them when it keeps one
        (``[extension.uses] connector_order``), else as given (document order)."""
        name = self.table.connector_order_property
        if not name or len(elements) < 2:
            return elements
        return in_connector_order(elements, [self.extension_property(el, name) for el in elements])

    # -- values ------------------------------------------------------------------------------
    def opaque_bodies(self, el: Element) -> list[tuple[str, str]]:
        """(language, body) pairs of an OpaqueExpression / OpaqueBehavior (bodies as children or attribute).

        ``body`` and ``language`` are parallel lists whatever their order in the file (Papyrus
        writes the languages first, Cameo the bodies). Without any language, the one the tool
        keeps elsewhere (:meth:`body_language`: Enterprise Architect's element Language) applies.
        """
        bodies: list[str] = []
        languages: list[str] = []
        for child in el:  # one pass over the children for both features
            tag = child.tag
            if tag == "body":
                bodies.append(child.text or "")
            elif tag == "language":
                languages.append(child.text or "")
        if not bodies and el.get("body") is not None:
            bodies = [el.get("body") or ""]
        if not languages and el.get("language") is not None:
            languages = [el.get("language") or ""]
        if bodies and not languages:
            fallback = self.body_language(el)
            languages = [fallback] * len(bodies) if fallback else []
        return [
            (languages[i] if i < len(languages) else "", body.replace("\r\n", "\n"))
            for i, body in enumerate(bodies)
        ]

    def body_location(self, el: Element) -> Location:
        """Where an expression's text starts: its first ``<body>`` child, else the element itself."""
        body = next(el.iterchildren("body"), None)
        line = (body.sourceline if body is not None else None) or el.sourceline or 0
        return Location(self.file_of(el), line, 0, self.xmi_id(el))


def namespace_of(el: Element) -> str:
    """The namespace URI of an element's tag ("" for none)."""
    tag = el.tag
    if isinstance(tag, str) and tag.startswith("{"):
        return tag[1:].partition("}")[0]
    return ""
