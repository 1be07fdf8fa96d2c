"""Enterprise Architect profile files: a ``<UMLProfile>`` or an MDG Technology holding
``<UMLProfiles><UMLProfile>…``. Only what makes a stereotype an EARL concept is read: the
profile's name (``<Documentation name="SPSys">``) and each ``<Stereotype name="PhyAgent"
generalizes="EARL::Agent" baseStereotypes="EARL::Agent">``."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from types import MappingProxyType

from lxml import etree

from earl_m2t.diagnostics import ModelReadError
from earl_m2t.read.safe_xml import parse_xml_file
from earl_m2t.read.xmi import Element, stereotype_key
from earl_m2t.stereotypes.vocabulary import SpecialisingProfile, specialising_profile_settings


def is_profile_root(root: Element) -> bool:
    """True for the root element of an EA profile or MDG Technology file."""
    return etree.QName(root).localname in specialising_profile_settings()["roots"]


def read_profile_file(path: Path, earl_concept: Callable[[str], str]) -> tuple[SpecialisingProfile, ...]:
    """The profiles of an EA profile or MDG Technology file; ``earl_concept`` names the concept
    of an EARL stereotype (``Agent``, ``ContSubsys`` …). Raises ModelReadError."""
    root = parse_xml_file(path).getroot()
    if not is_profile_root(root):
        roots = " or ".join(f"<{r}>" for r in specialising_profile_settings()["roots"])
        raise ModelReadError(str(path), f"not an Enterprise Architect profile file ({roots} expected, "
                                        f"found <{etree.QName(root).localname}>)", root.sourceline or 0)
    profiles = [root] if etree.QName(root).localname == "UMLProfile" else list(root.iter("UMLProfile"))
    return tuple(_profile(str(path), element, earl_concept) for element in profiles)


def _profile(file: str, element: Element, earl_concept: Callable[[str], str]) -> SpecialisingProfile:
    documentation = element.find("Documentation")
    name = (documentation.get("name") if documentation is not None else None) or ""
    if not name.strip():
        raise ModelReadError(file, "the profile has no name (<Documentation name=\"…\">)", element.sourceline or 0)
    qualifiers = {q.lower() for q in specialising_profile_settings()["earl_qualifiers"]}
    bases: dict[str, list[str]] = {}
    for stereotype in element.iter("Stereotype"):
        own = (stereotype.get("name") or "").strip()
        if own:
            written = f"{stereotype.get('generalizes') or ''},{stereotype.get('baseStereotypes') or ''}"
            bases[stereotype_key(own)] = [b.strip() for b in written.split(",") if b.strip()]
    concepts: dict[str, str] = {}

    is_earl = name.strip().lower() in qualifiers  # the EARL profile itself (an EARL MDG)

    def resolve(key: str, seen: frozenset[str]) -> str:
        if key in concepts:
            return concepts[key]
        if is_earl and earl_concept(key):
            return earl_concept(key)
        for base in bases.get(key, ()):
            qualifier, _, base_name = base.rpartition("::")
            if qualifier.lower() in qualifiers or (not qualifier and is_earl):
                concept = earl_concept(base_name)
            elif qualifier.lower() in ("", name.lower()) and stereotype_key(base_name) not in seen:
                concept = resolve(stereotype_key(base_name), seen | {key})
            else:
                concept = ""
            if concept:
                return concept
        return ""

    for key in bases:
        concept = resolve(key, frozenset({key}))
        if concept:
            concepts[key] = concept
    return SpecialisingProfile(name.strip(), file, MappingProxyType(concepts))
