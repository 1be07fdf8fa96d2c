"""Which tool wrote an XMI file, and which namespaces carry what: ``metamodel/xmi/dialects.toml``.

Everything here is matched on namespace URIs (normalised), on the exporter a file names and on
id shapes, never on namespace prefixes. The tables are data; this module only applies them.
"""

from __future__ import annotations

import re
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cache
from typing import Any, TypeAlias

from lxml import etree

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
class Dialect:
    """One row of ``[dialects]`` or ``[unsupported]``: how a tool's files are recognised."""

    name: str
    title: str
    exporters: tuple[str, ...] = ()
    eclipse_uml: bool = False
    namespace_markers: tuple[str, ...] = ()
    id_patterns: tuple[re.Pattern[str], ...] = ()
    message: str = ""  # for unsupported dialects: the one-line reason

    @property
    def has_markers(self) -> bool:
        return bool(self.namespace_markers or self.id_patterns)


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
    dialects: tuple[Dialect, ...] = ()
    unsupported: tuple[Dialect, ...] = ()
    earl_profile_names: frozenset[str] = frozenset()
    local_resource_prefixes: tuple[str, ...] = ()
    mdzip_members: tuple[str, ...] = ()
    wrapper_model_names: frozenset[str] = frozenset()
    stereotype_name_attributes: tuple[str, ...] = ()
    copy_features: frozenset[str] = frozenset()
    member_features: tuple[str, ...] = ()
    extension_extenders: tuple[str, ...] = ()
    extension_records: tuple[str, ...] = ()
    extension_unset: frozenset[str] = frozenset()
    extension_properties: dict[str, tuple[str, str]] = field(default_factory=dict)  # name -> (child path, attribute)
    body_language_property: str = ""
    connector_order_property: str = ""

    def __hash__(self) -> int:
        return id(self)

    def is_uml(self, uri: str) -> bool:
        uri = normalise_uri(uri)
        if uri.startswith(normalise_uri(self.uml_eclipse_prefix)) and uri.endswith("/UML"):
            return True
        return any(uri.startswith(normalise_uri(p)) for p in self.uml_omg_prefixes) and (
            "Profile" not in uri and not uri.endswith(("UMLDI", "UMLDC"))
        )

    def is_eclipse_uml(self, uri: str) -> bool:
        return normalise_uri(uri).startswith(normalise_uri(self.uml_eclipse_prefix))

    def is_sysml(self, uri: str) -> bool:
        uri = normalise_uri(uri)
        return any(uri.startswith(normalise_uri(p)) for p in self.sysml_prefixes)

    def is_earl(self, uri: str, extra: frozenset[str] = frozenset()) -> bool:
        """Whether a stereotype namespace is the EARL profile's; ``extra`` holds the URIs a file
        gives its EARL profile (see ``earl_profile_uris`` in :mod:`earl_m2t.read.stereotype_applications`)."""
        uri = normalise_uri(uri)
        return uri in extra or any(uri.startswith(normalise_uri(p)) for p in self.earl_prefixes)

    def family(self, uri: str, extra_earl: frozenset[str] = frozenset()) -> str:
        """Which profile a stereotype namespace belongs to: ``earl``, ``sysml`` or ``other``."""
        return "earl" if self.is_earl(uri, extra_earl) else "sysml" if self.is_sysml(uri) else "other"

    def dialect(self, name: str) -> Dialect | None:
        return next((d for d in self.dialects + self.unsupported if d.name == name), None)

    @property
    def names(self) -> tuple[str, ...]:
        """The dialects this version reads (the choices of ``--dialect``)."""
        return tuple(d.name for d in self.dialects)


def _dialect(name: str, row: dict[str, Any]) -> Dialect:
    return Dialect(
        name=name,
        title=row.get("title", name),
        exporters=tuple(row.get("exporters", ())),
        eclipse_uml=row.get("uml") == "eclipse",
        namespace_markers=tuple(row.get("namespace_markers", ())),
        id_patterns=tuple(re.compile(p) for p in row.get("id_patterns", ())),
        message=row.get("message", ""),
    )


@cache
def dialect_table() -> DialectTable:
    data = tomllib.loads(metamodel_path("xmi", "dialects.toml").read_text(encoding="utf-8"))
    dialects = tuple(_dialect(name, row) for name, row in data["dialects"].items())
    return DialectTable(
        xmi_uris=frozenset(normalise_uri(u) for u in data["xmi"]["uris"]),
        uml_eclipse_prefix=data["uml"]["eclipse_prefix"],
        uml_omg_prefixes=tuple(data["uml"]["omg_prefixes"]),
        sysml_prefixes=tuple(data["sysml"]["prefixes"]),
        sysml_v2_prefixes=tuple(data["sysml"]["sysml_v2_prefixes"]),
        earl_prefixes=tuple(data["earl"]["prefixes"]),
        implicit_types=dict(data["implicit_types"]),
        titles={d.name: d.title for d in dialects},
        dialects=dialects,
        unsupported=tuple(_dialect(name, row) for name, row in data.get("unsupported", {}).items()),
        earl_profile_names=frozenset(n.lower() for n in data["earl"].get("profile_names", ())),
        local_resource_prefixes=tuple(data.get("references", {}).get("local_resource_prefixes", ())),
        mdzip_members=tuple(data.get("mdzip", {}).get("model_members", ())),
        wrapper_model_names=frozenset(data.get("models", {}).get("wrapper_names", ())),
        stereotype_name_attributes=tuple(data.get("stereotypes", {}).get("name_attributes", ())),
        copy_features=frozenset(data.get("connector_ends", {}).get("copy_features", ())),
        member_features=tuple(data.get("connector_ends", {}).get("member_features", ())),
        **_extension(data.get("extension", {})),
    )


def _extension(section: dict[str, Any]) -> dict[str, Any]:
    """The ``[extension]`` table: whose ``xmi:Extension`` records are read, and which properties."""
    properties: dict[str, tuple[str, str]] = {}
    for name, where in section.get("properties", {}).items():
        path, _, attribute = str(where).partition("/@")
        if not path or not attribute:
            raise ValueError(f"dialects.toml [extension.properties] {name}: expected 'child/@attribute', got {where!r}")
        properties[name] = (path, attribute)
    uses = section.get("uses", {})
    for use, name in uses.items():
        if name not in properties:
            raise ValueError(f"dialects.toml [extension.uses] {use}: no property {name!r}")
    return {
        "extension_extenders": tuple(section.get("extenders", ())),
        "extension_records": tuple(section.get("records", ())),
        "extension_unset": frozenset(section.get("unset", ())),
        "extension_properties": properties,
        "body_language_property": uses.get("body_language", ""),
        "connector_order_property": uses.get("connector_order", ""),
    }


def exporter_of(root: Element, xmi_ns: str) -> str:
    """The tool a file names: ``xmi:Documentation`` exporter, else a root ``xmi:Extension`` extender."""
    for doc in root.iterchildren(f"{{{xmi_ns}}}Documentation", f"{{{xmi_ns}}}documentation"):
        exporter = doc.get("exporter") or ""
        for child in doc:
            if isinstance(child.tag, str) and etree.QName(child).localname == "exporter":
                exporter = (child.text or "").strip() or exporter
        if exporter:
            return exporter
    for ext in root.iterchildren(f"{{{xmi_ns}}}Extension"):
        extender = ext.get("extender") or ""
        if extender:
            return extender
    return ""


def detect_dialect(root: Element, uml_ns: str, xmi_ns: str, model_ids: Sequence[str] = ()) -> str:
    """Which tool wrote the file: a name of ``[dialects]`` or ``[unsupported]`` in dialects.toml.

    ``model_ids`` are a few ``xmi:id``s of the model (its root, its first packaged element), for
    dialects told apart by the shape of their ids.
    """
    table = dialect_table()
    exporter = exporter_of(root, xmi_ns)
    if exporter:
        for dialect in table.dialects + table.unsupported:
            if any(exporter.startswith(prefix) for prefix in dialect.exporters):
                return dialect.name
    if table.is_eclipse_uml(uml_ns):
        uris = [uri for uri in (root.nsmap or {}).values() if uri]
        eclipse = [d for d in table.dialects if d.eclipse_uml]
        for dialect in eclipse:
            if any(marker in uri for marker in dialect.namespace_markers for uri in uris):
                return dialect.name
            if any(p.match(model_id) for p in dialect.id_patterns for model_id in model_ids if model_id):
                return dialect.name
        fallback = next((d for d in eclipse if not d.has_markers), None)
        if fallback is not None:
            return fallback.name
    return "omg-xmi"
