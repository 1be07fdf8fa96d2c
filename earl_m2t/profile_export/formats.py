"""Template data for each tool format: ids, references and the tool's writing habits.

The templates in ``transforms/profile/<format>/`` only lay the data out; every decision
(ids, which optional element is written, escaping, order) is taken here, from the
format-neutral :class:`~earl_m2t.profile_export.spec.ProfileSpec`.

Ids are derived from names, never random, so the output is byte-identical from run to run
and an element keeps its id when others are added:

- ``papyrus``: EMF-style ids (``_`` + 22 url-safe base64 characters) hashed from the file
  name, the element kind and its qualified name; the uml:Profile and its EPackage get the
  ids the reference sample's ``EARL.profile.uml#…`` hrefs use;
- ``cameo``: the qualified name with dots (``EARL.Agent.base_Class``), like the ids of the
  OMG's normative profile files;
- ``ea``: the qualified name below the profile with dashes (``Agent-base_Class``), like the
  ids in Enterprise Architect's own profile XMI.
"""

from __future__ import annotations

import base64
import hashlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from earl_m2t.profile_export.spec import (
    DefaultValue,
    ProfileExportError,
    ProfileSpec,
    StereotypeSpec,
    TagSpec,
)
from earl_m2t.version import __version__

__all__ = ["CONTEXTS", "FORMATS", "Target", "emf_id", "papyrus_ns_uri"]

Context = dict[str, Any]

# Eclipse UML2 5.x (Papyrus)
PAPYRUS_METAMODEL = "pathmap://UML_METAMODELS/UML.metamodel.uml"
PAPYRUS_PRIMITIVES = "pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml"
ECORE_UML = "http://www.eclipse.org/uml2/5.0.0/UML"
ECORE_TYPES = "http://www.eclipse.org/uml2/5.0.0/Types"
# OMG UML 2.5 (Cameo, Enterprise Architect)
OMG_UML = "http://www.omg.org/spec/UML/20131001/UML.xmi"
OMG_PRIMITIVES = "http://www.omg.org/spec/UML/20131001/PrimitiveTypes.xmi"

_LITERAL_TYPES = {
    "integer": "uml:LiteralInteger",
    "real": "uml:LiteralReal",
    "string": "uml:LiteralString",
    "boolean": "uml:LiteralBoolean",
    "literal": "uml:InstanceValue",
}
# Values EMF and MagicDraw leave out because they are the feature's default.
_IMPLICIT_VALUES = {"integer": "0", "boolean": "false", "real": "0.0"}


@dataclass(frozen=True)
class Target:
    """One ``--format``: its template, the file it writes and its parameters (target.toml)."""

    name: str
    title: str
    template: str
    output: str
    uri: str = ""
    version: str = ""


def emf_id(key: str) -> str:
    """An EMF-style id (``_`` + 22 url-safe base64 characters) derived from ``key``."""
    digest = hashlib.sha256(key.encode("utf-8")).digest()[:16]
    return "_" + base64.urlsafe_b64encode(digest).decode("ascii")[:22]


def papyrus_ns_uri(profile_name: str, epackage_id: str) -> str:
    """The namespace of applications of a Papyrus-defined profile (definition number 0)."""
    return f"http:///schemas/{profile_name}/{epackage_id}/0"


# ---------------------------------------------------------------- the UML part (all formats)


@dataclass(frozen=True)
class _Habits:
    """How one tool writes the UML profile."""

    ident: Callable[[str, str], str]  # (kind, qualified name) -> xmi:id
    metaclass_href: Callable[[str], str]
    primitive_href: Callable[[str], str]
    extension_name: Callable[[str, str], str]  # (stereotype, metaclass) -> Extension name
    implicit_values: bool  # leave out values equal to the metamodel default (EMF, MagicDraw)
    bounds_always: bool  # write lowerValue/upperValue even for 1..1 (EA)


class _Ids:
    """Hands out ids and refuses duplicates (two names hashing or mapping to one id)."""

    def __init__(self, habits: _Habits) -> None:
        self.habits = habits
        self.seen: dict[str, str] = {}

    def __call__(self, kind: str, name: str) -> str:
        new = self.habits.ident(kind, name)
        key = f"{kind} {name}"
        if self.seen.get(new, key) != key:
            raise ProfileExportError(f"two profile elements get the id {new!r}: {self.seen[new]!r} and {key!r}")
        self.seen[new] = key
        return new


def _uml_context(spec: ProfileSpec, habits: _Habits) -> tuple[Context, _Ids]:
    ids = _Ids(habits)
    root = spec.name
    enum_ids = {e.name: ids("uml:Enumeration", f"{root}::{e.name}") for e in spec.enumerations}
    literal_ids = {
        (e.name, literal): ids("uml:EnumerationLiteral", f"{root}::{e.name}::{literal}")
        for e in spec.enumerations
        for literal in e.literals
    }
    stereotype_ids = {s.name: ids("uml:Stereotype", f"{root}::{s.name}") for s in spec.stereotypes}

    enumerations = [
        {
            "id": enum_ids[e.name],
            "name": e.name,
            "literals": [{"id": literal_ids[(e.name, lit)], "name": lit} for lit in e.literals],
        }
        for e in spec.enumerations
    ]
    stereotypes = []
    for stereotype in spec.stereotypes:
        qualified = f"{root}::{stereotype.name}"
        own = stereotype_ids[stereotype.name]
        extensions = []
        bases = []
        if stereotype.extends:
            metaclass = stereotype.extends
            extension_name = f"{root}::E_{stereotype.name}_{metaclass}"
            base_id = ids("uml:Property", f"{qualified}::base_{metaclass}")
            extension_id = ids("uml:Extension", extension_name)
            end_id = ids("uml:ExtensionEnd", f"{extension_name}::extension_{stereotype.name}")
            bases.append(
                {"id": base_id, "name": f"base_{metaclass}", "association": extension_id,
                 "href": habits.metaclass_href(metaclass), "metaclass": metaclass}
            )
            extensions.append(
                {"id": extension_id, "name": habits.extension_name(stereotype.name, metaclass),
                 "base_id": base_id, "stereotype_id": own,
                 "end": {"id": end_id, "name": f"extension_{stereotype.name}"}}
            )
        stereotypes.append(
            {
                "id": own,
                "name": stereotype.name,
                "abstract": stereotype.abstract,
                "comment": {"id": ids("uml:Comment", f"{qualified}::_comment"), "body": stereotype.doc},
                "generalizations": [
                    {"id": ids("uml:Generalization", f"{qualified}::_generalization::{general}"),
                     "general": stereotype_ids[general]}
                    for general in stereotype.generals
                ],
                "bases": bases,
                "tags": [_tag(t, qualified, ids, habits, enum_ids, literal_ids) for t in stereotype.tags],
                "extensions": extensions,
            }
        )
    profile = {
        "id": ids("uml:Profile", root),
        "name": root,
        "comment": {"id": ids("uml:Comment", f"{root}::_comment"), "body": spec.doc},
        "metamodel_import_id": ids("uml:PackageImport", f"{root}::_metamodelReference"),
    }
    return {"profile": profile, "enumerations": enumerations, "stereotypes": stereotypes}, ids


def _tag(
    tag: TagSpec,
    owner: str,
    ids: _Ids,
    habits: _Habits,
    enum_ids: dict[str, str],
    literal_ids: dict[tuple[str, str], str],
) -> Context:
    qualified = f"{owner}::{tag.name}"
    lower = upper = None
    if habits.bounds_always or (tag.lower, tag.upper) != (1, 1):
        lower_text = str(tag.lower)
        lower = {
            "id": ids("uml:LiteralInteger", f"{qualified}::_lowerValue"),
            "value": None if habits.implicit_values and lower_text == "0" else lower_text,
        }
        upper = {
            "id": ids("uml:LiteralUnlimitedNatural", f"{qualified}::_upperValue"),
            "value": "*" if tag.upper is None else str(tag.upper),
        }
    return {
        "id": ids("uml:Property", qualified),
        "name": tag.name,
        "type_id": enum_ids[tag.enumeration] if tag.enumeration else None,
        "type_href": habits.primitive_href(tag.primitive) if tag.primitive else None,
        "lower": lower,
        "upper": upper,
        "default": _default(tag, qualified, ids, habits, literal_ids),
    }


def _default(
    tag: TagSpec, qualified: str, ids: _Ids, habits: _Habits, literal_ids: dict[tuple[str, str], str]
) -> Context | None:
    default: DefaultValue | None = tag.default
    if default is None:
        return None
    xmi_type = _LITERAL_TYPES[default.kind]
    value: str | None
    if default.kind == "literal":
        assert tag.enumeration is not None
        attribute, value = "instance", literal_ids[(tag.enumeration, default.text)]
    else:
        implicit = habits.implicit_values and _IMPLICIT_VALUES.get(default.kind) == default.text
        attribute, value = "value", (None if implicit else default.text)
    return {
        "id": ids(xmi_type, f"{qualified}::_defaultValue"),
        "xmi_type": xmi_type,
        "attribute": attribute,
        "value": value,
    }


# ---------------------------------------------------------------- Papyrus


def papyrus_context(spec: ProfileSpec, target: Target) -> Context:
    """An Eclipse UML2 5.x ``.profile.uml`` as Papyrus saves a defined profile."""
    habits = _Habits(
        ident=lambda kind, name: emf_id(f"{target.output}\n{kind}\t{name}"),
        metaclass_href=lambda metaclass: f"{PAPYRUS_METAMODEL}#{metaclass}",
        primitive_href=lambda primitive: f"{PAPYRUS_PRIMITIVES}#{primitive}",
        extension_name=lambda stereotype, metaclass: f"E_{stereotype}_{metaclass}1",
        implicit_values=True,
        bounds_always=False,
    )
    context, ids = _uml_context(spec, habits)
    root = spec.name
    imports = [
        {"id": ids("uml:ElementImport", f"{root}::_metaclassReference::{m}"), "alias": m,
         "href": f"{PAPYRUS_METAMODEL}#{m}"}
        for m in spec.metaclasses
    ]
    context["profile"]["metaclass_imports"] = imports
    context["profile"]["metaclass_reference"] = " ".join(i["id"] for i in imports)
    context["profile"]["metamodel_href"] = f"{PAPYRUS_METAMODEL}#_0"
    context["profile"]["primitives_import_id"] = ids("uml:PackageImport", f"{root}::_primitiveTypes")
    context["profile"]["primitives_href"] = f"{PAPYRUS_PRIMITIVES}#_0"
    context["epackage"] = _epackage(spec, context, ids, target)
    return context


def _epackage(spec: ProfileSpec, uml: Context, ids: _Ids, target: Target) -> Context:
    """The Ecore definition of the profile (what Papyrus' "Define" stores in the profile)."""
    path = f"{spec.name}/0"
    epackage_id = ids("ecore:EPackage", path)
    enum_class_ids = {e["name"]: ids("ecore:EEnum", f"{path}/{e['name']}") for e in uml["enumerations"]}
    class_ids = {s["name"]: ids("ecore:EClass", f"{path}/{s['name']}") for s in uml["stereotypes"]}
    uml_ids = {s["name"]: s["id"] for s in uml["stereotypes"]}
    spec_by_name = {s.name: s for s in spec.stereotypes}

    enums = [
        {
            "id": enum_class_ids[e["name"]],
            "name": e["name"],
            "annotation": {"id": ids("ecore:EAnnotation", f"{path}/{e['name']}/_uml"), "references": e["id"]},
            "literals": [
                {"id": ids("ecore:EEnumLiteral", f"{path}/{e['name']}/{lit['name']}"), "name": lit["name"],
                 "value": str(index) if index else None}
                for index, lit in enumerate(e["literals"])
            ],
        }
        for e in uml["enumerations"]
    ]
    classes = []
    for stereotype in uml["stereotypes"]:
        name = stereotype["name"]
        source: StereotypeSpec = spec_by_name[name]
        features = [
            {"xmi_type": "ecore:EReference", "id": ids("ecore:EReference", f"{path}/{name}/{b['name']}"),
             "name": b["name"], "lower": "1", "upper": None, "default": None, "etype_id": None,
             "etype_xmi_type": "ecore:EClass", "etype_href": f"{ECORE_UML}#//{b['metaclass']}"}
            for b in stereotype["bases"]
        ]
        for tag in source.tags:
            upper = "-1" if tag.upper is None else (str(tag.upper) if tag.upper != 1 else None)
            features.append(
                {"xmi_type": "ecore:EAttribute", "id": ids("ecore:EAttribute", f"{path}/{name}/{tag.name}"),
                 "name": tag.name, "lower": str(tag.lower) if tag.lower else None, "upper": upper,
                 "default": tag.default.text if tag.default else None,
                 "etype_id": enum_class_ids[tag.enumeration] if tag.enumeration else None,
                 "etype_xmi_type": "ecore:EDataType",
                 "etype_href": f"{ECORE_TYPES}#//{tag.primitive}" if tag.primitive else None}
            )
        classes.append(
            {
                "id": class_ids[name],
                "name": name,
                "abstract": source.abstract,
                "super_types": " ".join(class_ids[g] for g in source.generals) or None,
                "annotation": {"id": ids("ecore:EAnnotation", f"{path}/{name}/_uml"), "references": uml_ids[name]},
                "features": features,
            }
        )
    version_path = f"{path}/_PapyrusVersion"
    details = [("Version", target.version), ("Comment", "Generated by earl-m2t from profiles/earl.sysml"),
               ("Copyright", ""), ("Date", ""), ("Author", "")]
    return {
        "annotation_id": ids("ecore:EAnnotation", f"{spec.name}/_definitions"),
        "id": epackage_id,
        "name": spec.name,
        "ns_uri": papyrus_ns_uri(spec.name, epackage_id),
        "ns_prefix": spec.name,
        "version": {
            "id": ids("ecore:EAnnotation", version_path),
            "details": [
                {"id": ids("ecore:EStringToStringMapEntry", f"{version_path}/{key}"), "key": key, "value": value}
                for key, value in details
            ],
        },
        "enums": enums,
        "classes": classes,
    }


# ---------------------------------------------------------------- Cameo / MagicDraw


def cameo_context(spec: ProfileSpec, target: Target) -> Context:
    """A UML 2.5 XMI profile as MagicDraw / Cameo exchange it (OMG UML 20131001)."""
    habits = _Habits(
        ident=lambda kind, name: name.replace("::", "."),
        metaclass_href=lambda metaclass: f"{OMG_UML}#{metaclass}",
        primitive_href=lambda primitive: f"{OMG_PRIMITIVES}#{primitive}",
        extension_name=lambda stereotype, metaclass: f"E_{stereotype}_{metaclass}",
        implicit_values=True,
        bounds_always=False,
    )
    context, ids = _uml_context(spec, habits)
    context["profile"]["uri"] = target.uri
    context["profile"]["metamodel_href"] = f"{OMG_UML}#_0"
    context["container"] = {"id": ids("uml:Model", f"{spec.name}::_container"), "name": f"{spec.name} profile"}
    context["exporter"] = _exporter()
    return context


# ---------------------------------------------------------------- Enterprise Architect


def _ea_id(profile_name: str, qualified: str) -> str:
    """``Agent``, ``Agent-base_Class``, ``EARL-_comment``: names below the profile, with dashes."""
    below = qualified.removeprefix(f"{profile_name}::")
    if below.startswith("_"):
        below = f"{profile_name}::{below}"
    return below.replace("::", "-")


def ea_context(spec: ProfileSpec, target: Target) -> Context:
    """A UML profile in the XMI that Enterprise Architect writes for profiles (XMI 2013)."""
    habits = _Habits(
        ident=lambda kind, name: _ea_id(spec.name, name),
        metaclass_href=lambda metaclass: f"{OMG_UML}#{metaclass}",
        primitive_href=lambda primitive: f"{OMG_UML}#{primitive}",
        extension_name=lambda stereotype, metaclass: f"A_{metaclass}_{stereotype}",
        implicit_values=False,
        bounds_always=True,
    )
    context, ids = _uml_context(spec, habits)
    context["profile"]["uri"] = target.uri
    context["profile"]["prefix"] = spec.name
    context["profile"]["version_note"] = f"{spec.name} Version:{target.version}\n{spec.doc}"
    context["profile"]["metamodel_href"] = OMG_UML.removesuffix("/UML.xmi")
    context["container"] = {"id": ids("uml:Model", "EA_Model"), "name": "EA_Model"}
    context["exporter"] = _exporter()
    return context


# EA's tagged value types for the UML primitive types of the tags.
_EA_TAG_TYPES = {"Integer": "int", "Real": "double", "Boolean": "boolean", "String": "string"}


def ea_mdg_context(spec: ProfileSpec, target: Target) -> Context:
    """An MDG Technology holding the profile as Enterprise Architect's ``<UMLProfile>``: each
    stereotype with the metaclasses it applies to, its more general stereotypes and its tags
    (EA keeps one text per tag: multi-valued tags list their values separated by spaces)."""
    literals = {e.name: e.literals for e in spec.enumerations}
    stereotypes = []
    for stereotype in spec.stereotypes:
        tags = []
        for tag in stereotype.tags:
            if tag.enumeration:
                kind, values = "enumeration", ",".join(literals[tag.enumeration])
            else:
                kind, values = _EA_TAG_TYPES.get(tag.primitive or "", "string"), ""
            many = " (several: separated by spaces)" if tag.upper is None or tag.upper > 1 else ""
            tags.append({"name": tag.name, "type": kind, "literals": values,
                         "default": tag.default.text if tag.default is not None else "",
                         "description": f"multiplicity {_multiplicity(tag)}{many}"})
        stereotypes.append({
            "name": stereotype.name,
            "notes": stereotype.doc,
            "abstract": stereotype.abstract,
            "generalizes": ",".join(stereotype.generals),
            "metaclasses": list(stereotype.metaclasses),
            "tags": tags,
        })
    version = target.version
    return {
        "technology": {"id": spec.name, "name": spec.name, "version": version, "notes": spec.doc},
        "profile": {"id": f"{spec.name}-{version}", "name": spec.name, "version": version, "notes": spec.doc},
        "stereotypes": stereotypes,
    }


def _multiplicity(tag: TagSpec) -> str:
    upper = "*" if tag.upper is None else str(tag.upper)
    return str(tag.lower) if upper == str(tag.lower) else f"{tag.lower}..{upper}"


def _exporter() -> Context:
    return {"name": "earl-m2t", "version": __version__}


CONTEXTS: dict[str, Callable[[ProfileSpec, Target], Context]] = {
    "papyrus": papyrus_context,
    "cameo": cameo_context,
    "ea": ea_context,
    "ea-mdg": ea_mdg_context,
}
# The values of --format, in the order the help lists them.
FORMATS: tuple[str, ...] = tuple(CONTEXTS)
