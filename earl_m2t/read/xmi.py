"""Stage 1: an XMI file as a dialect-neutral index over its XML tree.

One pass over the tree indexes every element by ``xmi:id`` (skipping tool ``xmi:Extension``
blocks) and collects stereotype applications; references are resolved afterwards, on demand,
whichever of the four XMI encodings the tool used (IDREF attribute, IDREFS list, child with
``xmi:idref``, child with ``href``).
"""

from __future__ import annotations

import tomllib
import zipfile
from dataclasses import dataclass, field
from functools import cache
from typing import TypeAlias
from pathlib import Path

from lxml import etree

from earl_m2t.diagnostics import Diagnostic, ModelReadError, Severity
from earl_m2t.model.location import Location
from earl_m2t.read.safe_xml import parse_xml_file
from earl_m2t.resources import metamodel_path

Element: TypeAlias = etree._Element


@cache
def normalise_uri(uri: str) -> str:
    """Compare namespace URIs without scheme differences (http/https) or a trailing '/'."""
    uri = uri.strip()
    if uri.startswith("https://"):
        uri = "http://" + uri[len("https://") :]
    return uri.rstrip("/")


@dataclass(frozen=True)
class DialectTable:
    """The namespace tables of ``metamodel/xmi/dialects.toml``."""

    xmi_uris: frozenset[str]
    uml_eclipse_prefix: str
    uml_omg_prefixes: tuple[str, ...]
    sysml_prefixes: tuple[str, ...]
    sysml_v2_prefixes: tuple[str, ...]
    earl_prefixes: tuple[str, ...]
    implicit_types: dict[str, str]
    titles: dict[str, str]

    def __hash__(self) -> int:
        return id(self)

    def is_uml(self, uri: str) -> bool:
        uri = normalise_uri(uri)
        if uri.startswith(normalise_uri(self.uml_eclipse_prefix)) and uri.endswith("/UML"):
            return True
        return any(uri.startswith(normalise_uri(p)) for p in self.uml_omg_prefixes) and (
            "Profile" not in uri and not uri.endswith(("UMLDI", "UMLDC"))
        )

    def is_sysml(self, uri: str) -> bool:
        uri = normalise_uri(uri)
        return any(uri.startswith(normalise_uri(p)) for p in self.sysml_prefixes)

    def is_earl(self, uri: str) -> bool:
        uri = normalise_uri(uri)
        return any(uri.startswith(normalise_uri(p)) for p in self.earl_prefixes)

    def family(self, uri: str) -> str:
        """Which profile a stereotype namespace belongs to: ``earl``, ``sysml`` or ``other``."""
        return "earl" if self.is_earl(uri) else "sysml" if self.is_sysml(uri) else "other"


@cache
def dialect_table() -> DialectTable:
    data = tomllib.loads(metamodel_path("xmi", "dialects.toml").read_text(encoding="utf-8"))
    return DialectTable(
        xmi_uris=frozenset(normalise_uri(u) for u in data["xmi"]["uris"]),
        uml_eclipse_prefix=data["uml"]["eclipse_prefix"],
        uml_omg_prefixes=tuple(data["uml"]["omg_prefixes"]),
        sysml_prefixes=tuple(data["sysml"]["prefixes"]),
        sysml_v2_prefixes=tuple(data["sysml"]["sysml_v2_prefixes"]),
        earl_prefixes=tuple(data["earl"]["prefixes"]),
        implicit_types=dict(data["implicit_types"]),
        titles={name: d["title"] for name, d in data["dialects"].items()},
    )


@dataclass(frozen=True, slots=True)
class ExternalRef:
    """A reference into another resource (``href="lib.uml#id"``) that is not in this file."""

    href: str

    @property
    def fragment(self) -> str:
        return self.href.rpartition("#")[2]

    @property
    def resource(self) -> str:
        return self.href.partition("#")[0]


@dataclass(frozen=True, slots=True)
class StereotypeApplication:
    """``<Profile:Stereotype base_X="id" tag="value"/>``, indexed by the extended element."""

    profile_uri: str
    family: str  # "earl" | "sysml" | "other": which profile the namespace belongs to
    name: str
    base_id: str
    tags: dict[str, str]
    line: int


@dataclass
class RawModel:
    """A parsed XMI file: the tree, the id index and the stereotype applications."""

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

    def __post_init__(self) -> None:
        self._id_attr = f"{{{self.xmi_ns}}}id"
        self._idref_attr = f"{{{self.xmi_ns}}}idref"
        self._type_attr = f"{{{self.xmi_ns}}}type"

    # -- identity and location -------------------------------------------------------------
    def xmi_id(self, el: Element) -> str:
        return el.get(self._id_attr) or ""

    def location(self, el: Element) -> Location:
        return Location(self.file, el.sourceline or 0, 0, self.xmi_id(el))

    def name(self, el: Element) -> str:
        return el.get("name") or ""

    def uml_type(self, el: Element) -> str:
        """The UML metaclass of an element (``Class``, ``Port``…), from ``xmi:type`` or its feature."""
        declared = el.get(self._type_attr)
        if declared:
            return declared.rpartition(":")[2]
        tag = el.tag
        if isinstance(tag, str) and tag.startswith("{"):
            uri, _, local = tag[1:].partition("}")
            if uri == self.uml_ns:
                return local  # a root element such as <uml:Model>
            return ""
        return self.table.implicit_types.get(str(tag), "")

    # -- containment -----------------------------------------------------------------------
    def children(self, el: Element, feature: str, *types: str) -> list[Element]:
        """Contained children in ``feature`` (XML element name), optionally of given UML types."""
        found = []
        for child in el.iterchildren(feature):
            if not types or self.uml_type(child) in types:
                found.append(child)
        return found

    def owner(self, el: Element) -> Element | None:
        parent = el.getparent()
        return parent if parent is not None and parent is not self.root else None

    # -- references --------------------------------------------------------------------------
    def refs(self, el: Element, feature: str) -> list[Element | ExternalRef]:
        """All targets of a reference feature, in any of the four XMI encodings."""
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
                targets.append(self._resolve_href(href))
        return targets

    def ref(self, el: Element, feature: str) -> Element | ExternalRef | None:
        value = el.get(feature)
        if value and " " not in value:  # the common case: one IDREF attribute
            target = self.by_id.get(value)
            return target if target is not None else ExternalRef("#" + value)
        found = self.refs(el, feature)
        return found[0] if found else None

    def _resolve_href(self, href: str) -> Element | ExternalRef:
        resource, _, fragment = href.partition("#")
        if not resource:
            target = self.by_id.get(fragment)
            if target is not None:
                return target
        return ExternalRef(href)

    # -- stereotypes -------------------------------------------------------------------------
    def applied(self, el: Element) -> list[StereotypeApplication]:
        return self.stereotypes.get(self.xmi_id(el), [])

    def has_sysml(self, el: Element, name: str) -> bool:
        return any(
            app.family == "sysml" and app.name.lower() == name.lower()
            for app in self.applied(el)
        )

    # -- values ------------------------------------------------------------------------------
    def opaque_bodies(self, el: Element) -> list[tuple[str, str]]:
        """(language, body) pairs of an OpaqueExpression / OpaqueBehavior (bodies as children or attribute)."""
        bodies = [child.text or "" for child in el.iterchildren("body")]
        if not bodies and el.get("body") is not None:
            bodies = [el.get("body") or ""]
        languages = [child.text or "" for child in el.iterchildren("language")]
        if not languages and el.get("language") is not None:
            languages = [el.get("language") or ""]
        return [
            (languages[i] if i < len(languages) else "", body.replace("\r\n", "\n"))
            for i, body in enumerate(bodies)
        ]

    def body_location(self, el: Element) -> Location:
        """Where an expression's text starts: its first ``<body>`` child, else the element itself."""
        body = next(el.iterchildren("body"), None)
        line = (body.sourceline if body is not None else None) or el.sourceline or 0
        return Location(self.file, line, 0, self.xmi_id(el))


def load_raw_model(path: Path) -> RawModel:
    """Read an XMI file into a :class:`RawModel`; unreadable input raises :class:`ModelReadError`."""
    file = str(path)
    if path.is_dir():
        raise ModelReadError(file, "is a directory, not a model file")
    if not path.exists():
        raise ModelReadError(file, "no such file")
    if zipfile.is_zipfile(path):
        raise ModelReadError(
            file, "is a ZIP archive (a Cameo .mdzip project?); this format is not supported"
        )
    if path.suffix.lower() == ".sysml":
        raise ModelReadError(file, "SysML v2 textual models are not supported yet")
    tree = parse_xml_file(path)
    return index_tree(tree.getroot(), file)


def index_tree(root: Element, file: str) -> RawModel:
    """Build the id index and the stereotype table in one pass over the tree."""
    table = dialect_table()
    nsmap = {uri: prefix for prefix, uri in (root.nsmap or {}).items()}
    xmi_ns = _find_namespace(nsmap, table.xmi_uris)
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
    dialect = detect_dialect(root, uml_ns, xmi_ns)
    if dialect not in table.titles:
        raise ModelReadError(
            file, f"{dialect} XMI is not supported by this version of earl-m2t", root.sourceline or 0
        )

    by_id: dict[str, Element] = {}
    stereotypes: dict[str, list[StereotypeApplication]] = {}
    model_roots: list[Element] = []
    diagnostics: list[Diagnostic] = []
    id_attr = f"{{{xmi_ns}}}id"
    ext_tag = f"{{{xmi_ns}}}Extension"

    families: dict[str, str] = {}
    top_level = [root] if _namespace_of(root) == uml_ns else [c for c in root if isinstance(c.tag, str)]
    for top in top_level:
        top_uri = _namespace_of(top)
        if top.tag == ext_tag or normalise_uri(top_uri) in table.xmi_uris:
            continue
        if top_uri == uml_ns:
            model_roots.append(top)
            _index_subtree(top, id_attr, ext_tag, by_id, diagnostics, file)
        else:
            family = families.get(top_uri)
            if family is None:
                family = families[top_uri] = table.family(top_uri)
            app = _stereotype_application(top, top_uri, family)
            if app is not None:
                stereotypes.setdefault(app.base_id, []).append(app)
    if not model_roots:
        raise ModelReadError(file, "XMI file holds no UML model element", root.sourceline or 0)
    return RawModel(file, root, dialect, xmi_ns, uml_ns, by_id, stereotypes, model_roots, diagnostics)


def _index_subtree(
    top: Element,
    id_attr: str,
    ext_tag: str,
    by_id: dict[str, Element],
    diagnostics: list[Diagnostic],
    file: str,
) -> None:
    iterator = top.iter()
    for el in iterator:
        tag = el.tag
        if tag == ext_tag:
            # skip the tool's extension block entirely: its copies repeat model ids
            for _ in el.iterdescendants():
                next(iterator, None)
            continue
        ref_id = el.get(id_attr)
        if ref_id is None:
            continue
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


def _stereotype_application(el: Element, uri: str, family: str) -> StereotypeApplication | None:
    base_id = ""
    tags: dict[str, str] = {}
    for key, value in el.attrib.items():
        if key.startswith("base_"):
            base_id = value
        elif not key.startswith("{"):
            tags[key] = value
    if not base_id:
        for child in el:
            if isinstance(child.tag, str) and child.tag.startswith("base_"):
                base_id = next(
                    (v for k, v in child.attrib.items() if k.endswith("}idref")), ""
                )
    if not base_id:
        return None
    for child in el:
        if isinstance(child.tag, str) and not child.tag.startswith(("{", "base_")) and child.text:
            previous = tags.get(child.tag)
            tags[child.tag] = f"{previous} {child.text.strip()}" if previous else child.text.strip()
    return StereotypeApplication(uri, family, etree.QName(el).localname, base_id, tags, el.sourceline or 0)


def detect_dialect(root: Element, uml_ns: str, xmi_ns: str) -> str:
    """Which tool wrote the file: ``papyrus`` (Eclipse UML2), ``cameo`` or ``enterprise-architect``."""
    for doc in root.iterchildren(f"{{{xmi_ns}}}Documentation", f"{{{xmi_ns}}}documentation"):
        exporter = doc.get("exporter") or ""
        for child in doc:
            if isinstance(child.tag, str) and child.tag.endswith("exporter"):
                exporter = child.text or exporter
        if "Enterprise Architect" in exporter:
            return "enterprise-architect"
        if "MagicDraw" in exporter:
            return "cameo"
    if normalise_uri(uml_ns).startswith(normalise_uri(dialect_table().uml_eclipse_prefix)):
        nsmap = root.nsmap or {}
        if any("magicdraw" in (uri or "").lower() for uri in nsmap.values()):
            return "cameo-eclipse-uml2"
        return "papyrus"
    return "omg-xmi"


def _find_namespace(nsmap: dict[str, str | None], accepted: frozenset[str]) -> str:
    for uri in nsmap:
        if normalise_uri(uri) in accepted:
            return uri
    return ""


def _namespace_of(el: Element) -> str:
    tag = el.tag
    if isinstance(tag, str) and tag.startswith("{"):
        return tag[1:].partition("}")[0]
    return ""
