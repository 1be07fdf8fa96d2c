"""Stage 1: an XMI file as a dialect-neutral index over its XML tree.

One pass over the tree indexes every element by ``xmi:id`` (skipping tool ``xmi:Extension``
blocks) and collects stereotype applications; references are resolved afterwards, on demand,
whichever of the four XMI encodings the tool used (IDREF attribute, IDREFS list, child with
``xmi:idref``, child with ``href``).

A ``.mdzip`` project (:mod:`earl_m2t.read.mdzip`) gives one or two documents (model and shared
model), indexed as one model; every location names the member it comes from. Which tool wrote
the file is decided by :mod:`earl_m2t.read.dialects`, from the tables of ``dialects.toml``.

Other model files the model references (``href="types.uml#id"``) are read by
:mod:`earl_m2t.read.resources`, each into a model of its own; a reference into one resolves to
the element there, and every method below answers for an element of such a file from that
file's own ids, stereotypes and namespaces (its location names that file).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol, TypeAlias

from lxml import etree

from earl_m2t.diagnostics import Diagnostic, ModelReadError, Severity
from earl_m2t.model.location import Location
from earl_m2t.read.bounded import open_regular
from earl_m2t.read.dialects import DialectTable, detect_dialect, dialect_table, normalise_uri
from earl_m2t.read.early import take_parsed
from earl_m2t.read.extension import ExtensionIndex, in_connector_order
from earl_m2t.read.libraries import classify
from earl_m2t.read.mdzip import is_archive, read_model_members
from earl_m2t.read.safe_xml import parse_xml_bytes, parse_xml_stream
from earl_m2t.sysml2.files import is_sysml2

Element: TypeAlias = etree._Element

__all__ = [
    "DialectTable",
    "Element",
    "ExternalRef",
    "RawModel",
    "StereotypeApplication",
    "detect_dialect",
    "dialect_table",
    "index_documents",
    "index_tree",
    "normalise_uri",
    "read_raw_model",
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
        if parent is None or (parent.getparent() is None and _namespace_of(parent) != self._home(el).uml_ns):
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


# -- loading -------------------------------------------------------------------------------------


def read_raw_model(path: Path, dialect: str | None = None) -> RawModel:
    """Read one XMI file or ``.mdzip`` project, leaving its references into other files unresolved."""
    file = str(path)
    if is_sysml2(path):
        raise ModelReadError(file, "is SysML v2 text, not XMI")
    early = take_parsed(path)  # parsed while the command was importing (earl_m2t.read.early)
    if early is not None:
        return index_tree(early.getroot(), file, dialect)
    with open_regular(path) as stream:  # a regular file within the size limit, or an error
        if is_archive(stream):
            members = read_model_members(stream, file)
            documents = [(parse_xml_bytes(m.data, m.file).getroot(), m.file) for m in members]
            return index_documents(documents, dialect)
        tree = parse_xml_stream(stream, file)
    return index_tree(tree.getroot(), file, dialect)


def index_tree(root: Element, file: str, dialect: str | None = None) -> RawModel:
    """Build the id index and the stereotype table in one pass over the tree."""
    return index_documents([(root, file)], dialect)


@dataclass
class _Document:
    root: Element
    file: str
    xmi_ns: str
    uml_ns: str
    model_roots: list[Element]
    applications: list[Element]  # root-level elements of other namespaces: stereotype applications


def index_documents(documents: Sequence[tuple[Element, str]], dialect: str | None = None) -> RawModel:
    """Index one model held in one or more documents (the first is the main one).

    ``dialect`` overrides detection; detection looks at the first document only.
    """
    table = dialect_table()
    docs = [_document(root, file, table) for root, file in documents]
    main = docs[0]
    model_roots = [top for doc in docs for top in doc.model_roots]
    if not model_roots:
        raise ModelReadError(main.file, "XMI file holds no UML model element", main.root.sourceline or 0)
    if dialect is None:
        dialect = detect_dialect(main.root, main.uml_ns, main.xmi_ns, _sample_ids(model_roots[0], main.xmi_ns))
        if dialect not in table.titles:
            known = table.dialect(dialect)
            message = known.message if known is not None and known.message else f"{dialect} XMI is not supported"
            raise ModelReadError(main.file, message, main.root.sourceline or 0)
    elif dialect not in table.titles:
        raise ModelReadError(main.file, f"unknown dialect '{dialect}' (known: {', '.join(table.names)})")

    by_id: dict[str, Element] = {}
    diagnostics: list[Diagnostic] = []
    profile_applications: list[Element] = []
    ext_tags = frozenset(f"{{{uri}}}Extension" for uri in _spellings(table.xmi_uris))
    external_hrefs: list[tuple[Element, Element]] = []
    for doc in docs:
        id_attr = f"{{{doc.xmi_ns}}}id"
        for top in doc.model_roots:
            _index_subtree(top, id_attr, ext_tags, by_id, profile_applications, external_hrefs, diagnostics,
                           doc.file)
    raw = RawModel(main.file, main.root, dialect, main.xmi_ns, main.uml_ns, by_id, {}, model_roots, diagnostics,
                   table, tuple((d.root, d.file) for d in docs), external_hrefs=external_hrefs)
    raw.earl_uris = earl_profile_uris(raw, profile_applications)
    kinds: dict[str, tuple[str, str, str]] = {}  # tag → (namespace, family, stereotype name)
    name_attributes = table.stereotype_name_attributes
    for doc in docs:
        for top in doc.applications:
            tag = top.tag
            kind = kinds.get(tag)
            if kind is None:
                uri = _namespace_of(top)
                kind = kinds[tag] = (uri, table.family(uri, raw.earl_uris), tag.rpartition("}")[2])
            app = _stereotype_application(raw, top, kind, name_attributes)
            if app is not None:
                raw.stereotypes.setdefault(app.base_id, []).append(app)
    return raw


def _sample_ids(model: Element, xmi_ns: str) -> tuple[str, ...]:
    """The ids of a model root and of its first packaged element, for detection by id shape."""
    id_attr = f"{{{xmi_ns}}}id"
    first = next(model.iterchildren("packagedElement"), None)
    return (model.get(id_attr) or "", first.get(id_attr) or "" if first is not None else "")


def _document(root: Element, file: str, table: DialectTable) -> _Document:
    """Check one document's namespaces and split its top level into models and stereotype applications."""
    nsmap = {uri: prefix for prefix, uri in (root.nsmap or {}).items() if uri}
    xmi_ns = next((uri for uri in nsmap if normalise_uri(uri) in table.xmi_uris), "")
    uml_ns = next((uri for uri in nsmap if table.is_uml(uri)), "")
    root_uri = _namespace_of(root)
    if any(normalise_uri(root_uri).startswith(normalise_uri(p)) for p in table.sysml_v2_prefixes):
        raise ModelReadError(file, "SysML v2 XMI (.sysmlx) is not supported", root.sourceline or 0)
    if not xmi_ns:
        raise ModelReadError(
            file, f"not an XMI file (root element <{etree.QName(root).localname}> has no XMI namespace)",
            root.sourceline or 0,
        )
    if not uml_ns:
        raise ModelReadError(file, "XMI file without a UML model (no UML namespace declared)", root.sourceline or 0)
    model_roots: list[Element] = []
    applications: list[Element] = []
    top_level = [root] if root_uri == uml_ns else [c for c in root if isinstance(c.tag, str)]
    kind_of_tag: dict[str, str] = {}  # a file has thousands of applications of a few stereotypes
    for top in top_level:
        kind = kind_of_tag.get(top.tag)
        if kind is None:
            top_uri = _namespace_of(top)
            if normalise_uri(top_uri) in table.xmi_uris:
                kind = "xmi"  # xmi:Documentation, and every root-level xmi:Extension (tool data, repeated ids)
            else:
                kind = "model" if top_uri == uml_ns else "application"
            kind_of_tag[top.tag] = kind
        if kind == "model":
            model_roots.append(top)
        elif kind == "application":
            applications.append(top)
    for model in model_roots:  # Enterprise Architect "XMI 2.1" writes them inside the uml:Model
        for child in model:
            uri = _namespace_of(child)
            if uri and uri != uml_ns and normalise_uri(uri) not in table.xmi_uris:
                applications.append(child)
    return _Document(root, file, xmi_ns, uml_ns, model_roots, applications)


def _spellings(uris: frozenset[str]) -> set[str]:
    """The spellings a normalised namespace URI may have in a file (http/https, trailing '/')."""
    found: set[str] = set()
    for uri in uris:
        for variant in (uri, "https://" + uri.removeprefix("http://")):
            found.update((variant, variant + "/"))
    return found


def _index_subtree(
    top: Element,
    id_attr: str,
    ext_tags: frozenset[str],
    by_id: dict[str, Element],
    profile_applications: list[Element],
    external_hrefs: list[tuple[Element, Element]],
    diagnostics: list[Diagnostic],
    file: str,
) -> None:
    """One pass over a model root: the id index, the profile applications, and the elements
    whose href leaves the file (references to other resources, followed later)."""
    iterator = top.iter()
    for el in iterator:
        tag = el.tag
        if tag in ext_tags:
            # skip the tool's extension block entirely: its copies repeat model ids
            for _ in el.iterdescendants():
                next(iterator, None)
            continue
        href = el.get("href")
        if href and href[0] != "#":
            external_hrefs.append((top, el))
        ref_id = el.get(id_attr)
        if ref_id is None:
            continue
        if tag == "profileApplication":
            profile_applications.append(el)
        if ref_id in by_id:
            diagnostics.append(
                Diagnostic(
                    "R002",
                    Severity.WARNING,
                    f"duplicate xmi:id '{ref_id}' on <{el.tag}> '{el.get('name') or ''}' "
                    f"(first used on line {by_id[ref_id].sourceline})",
                    Location(file, el.sourceline or 0, 0, ref_id),
                    el.get("name") or ref_id,
                )
            )
            continue
        by_id[ref_id] = el


def earl_profile_uris(raw: RawModel, profile_applications: list[Element]) -> frozenset[str]:
    """The namespace URIs a file gives its EARL profile, beyond the fixed ones of dialects.toml.

    A profile named EARL (``[earl] profile_names``), reached through a profileApplication or
    defined in the file, contributes its ``URI`` attribute; one in another resource contributes
    the resource its href names (MagicDraw writes a profile's href under its URI, as for
    ``http://www.omg.org/spec/SysML/20181001/SysML.xmi#SysML``) and is known by name from the
    referentPath beside the href.
    """
    names = raw.table.earl_profile_names
    uris: set[str] = set()

    def add(profile: Element) -> None:
        uri = (profile.get("URI") or "").strip()
        if uri and raw.name(profile).strip().lower() in names:
            uris.add(normalise_uri(uri))

    for application in profile_applications:
        for target in raw.refs(application, "appliedProfile"):
            if not isinstance(target, ExternalRef):
                add(target)
            elif target.name.lower() in names and "://" in target.resource:
                resource = normalise_uri(target.resource)
                uris.update((resource, resource.removesuffix(".xmi")))
    for top in raw.model_roots:
        for el in top.iter("packagedElement"):
            if el.get("URI") and raw.uml_type(el) == "Profile":
                add(el)
    return frozenset(uris)


def _stereotype_application(raw: RawModel, el: Element, kind: tuple[str, str, str],
                            name_attributes: tuple[str, ...]) -> StereotypeApplication | None:
    """The application ``el`` writes; ``kind`` is its tag's (namespace, family, stereotype name)."""
    uri, family, name = kind
    base_id = ""
    tags: dict[str, str] = {}
    for key, value in el.items():
        if key.startswith("base_"):
            base_id = value
        elif key in name_attributes:
            name = value.strip() or name
        elif not key.startswith("{"):
            tags[key] = value
    has_children = len(el) > 0
    if not base_id and has_children:
        for child in el:
            if isinstance(child.tag, str) and child.tag.startswith("base_"):
                base_id = next(
                    (v for k, v in child.attrib.items() if k.endswith("}idref")), ""
                ) or raw.local_fragment(child.get("href") or "")
    if not base_id:
        return None
    if has_children:
        idref_attr = raw._idref_attr
        for child in el:
            child_tag = child.tag
            if not isinstance(child_tag, str) or child_tag.startswith(("{", "base_")):
                continue
            href = child.get("href")
            value = child.get(idref_attr) or (raw.local_fragment(href) or href.replace(" ", "%20") if href else "")
            value = value or (child.text or "").strip()
            if value:
                previous = tags.get(child_tag)
                tags[child_tag] = f"{previous} {value}" if previous else value
    return StereotypeApplication(uri, family, name, base_id, tags, el.sourceline or 0)


def _namespace_of(el: Element) -> str:
    tag = el.tag
    if isinstance(tag, str) and tag.startswith("{"):
        return tag[1:].partition("}")[0]
    return ""
