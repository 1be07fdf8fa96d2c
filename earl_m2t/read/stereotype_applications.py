"""The stereotype applications of an XMI file, read into :class:`StereotypeApplication` records.

An application is a root-level element of a profile's namespace (``<Profile:Stereotype
base_X="id" tag="value"/>``; Enterprise Architect also writes them inside the ``uml:Model``),
found by :mod:`earl_m2t.read.xmi_index`. Its family (EARL, SysML or other) comes from its
namespace: the fixed URIs of ``dialects.toml``, and those the file itself gives its EARL
profile (:func:`earl_profile_uris`).
"""

from __future__ import annotations

from collections.abc import Iterable

from earl_m2t.read.dialects import normalise_uri
from earl_m2t.read.xmi import Element, ExternalRef, RawModel, StereotypeApplication, namespace_of


def stereotype_table(raw: RawModel, applications: Iterable[Element]) -> dict[str, list[StereotypeApplication]]:
    """The applications the given elements write, by the id of the element each extends.

    ``raw`` is indexed already (ids, ``earl_uris``); an element without a base is skipped.
    """
    table = raw.table
    earl_uris = raw.earl_uris
    name_attributes = table.stereotype_name_attributes
    idref_attr = f"{{{raw.xmi_ns}}}idref"
    stereotypes: dict[str, list[StereotypeApplication]] = {}
    kinds: dict[str, tuple[str, str, str]] = {}  # tag → (namespace, family, stereotype name)
    for top in applications:
        tag = top.tag
        kind = kinds.get(tag)
        if kind is None:
            uri = namespace_of(top)
            kind = kinds[tag] = (uri, table.family(uri, earl_uris), tag.rpartition("}")[2])
        app = _stereotype_application(raw, top, kind, name_attributes, idref_attr)
        if app is not None:
            stereotypes.setdefault(app.base_id, []).append(app)
    return stereotypes


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
                            name_attributes: tuple[str, ...], idref_attr: str) -> StereotypeApplication | None:
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
