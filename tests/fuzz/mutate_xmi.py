"""Structural mutations of XMI trees: references rewired (dangling, to the element itself, to
its owner: a cycle), containment cycles the format allows (generalizations both ways, a package
importing itself, a region nested in itself through an href), stereotype applications moved to
another metaclass or swapped for another EARL stereotype, hostile numbers in multiplicities and
tagged values. Every choice draws from the ``random.Random`` given."""

from __future__ import annotations

import random
from collections.abc import Callable

from lxml import etree

XMI = "http://www.omg.org/spec/XMI/20131001"

# numbers broken models hold: huge, negative, not a number, beyond 32 and 64 bits, not numbers at all
HOSTILE_NUMBERS = (
    "1e300", "-1e300", "1e-300", "-1", "-0", "NaN", "nan", "inf", "-inf", "Infinity", "4294967296",
    "18446744073709551617", "99999999999999999999999999999999", "1024", "1025", "65536", "65537",
    "2147483648", "-2147483649", "0x10", "3.5", "1_000", "*", "", " 7 ", "٣", "9" * 400, "1e999",
)
EARL_STEREOTYPES = (
    "Agent", "System", "Robot", "Subsystem", "InputBuffer", "OutputBuffer", "Memory", "Behaviour",
    "Transition", "Priority", "Exclusive", "Receptor", "Effector", "ControlSubsystem", "VirtualReceptor",
    "VirtualEffector", "Condition", "BasicBehaviour", "FSM", "State",
)
BASE_ATTRIBUTES = (
    "base_Class", "base_Port", "base_Property", "base_StateMachine", "base_State", "base_Transition",
    "base_Constraint", "base_Behavior", "base_Activity", "base_DataType", "base_Signal", "base_Element",
)


def _id_of(element: etree._Element) -> str | None:
    """The element's ``xmi:id`` whatever the XMI version's namespace (EA writes XMI 2.1)."""
    return next((v for k, v in element.attrib.items() if k.endswith("}id") or k in ("xmi.id", "id")), None)


def _type_of(element: etree._Element) -> str:
    return next((v for k, v in element.attrib.items() if k.endswith("}type")), "")


def _keys(root: etree._Element) -> tuple[str, str]:
    """The ``xmi:id`` and ``xmi:type`` attribute names of the document's XMI namespace."""
    namespace = (root.nsmap or {}).get("xmi") or XMI
    return f"{{{namespace}}}id", f"{{{namespace}}}type"


def _new_id(rng: random.Random) -> str:
    return f"_fz{rng.randrange(1 << 40):x}"


def _namespace_of(root: etree._Element, prefix: str, default: str) -> str:
    found = root.nsmap.get(prefix) if root.nsmap else None
    return found or default


def rewire_reference(root: etree._Element, rng: random.Random) -> bool:
    """A reference (an attribute whose value is an id, or an href) made dangling, pointing at
    its own element, or at an ancestor of it (a cycle through containment)."""
    elements = [el for el in root.iter() if isinstance(el.tag, str)]
    ids = {value for el in elements if (value := _id_of(el))}
    candidates = [(el, key) for el in elements for key, value in el.attrib.items()
                  if not key.endswith(("}id", "}type")) and (key == "href" or value in ids)]
    if not candidates:
        return False
    element, key = rng.choice(candidates)
    ancestors = [a for a in element.iterancestors() if _id_of(a)]
    kind = rng.randrange(4)
    own = _id_of(element)
    if kind == 0 or (kind == 1 and not own) or (kind == 2 and not ancestors):
        value = rng.choice(("_missing", "_", "#", " ", "_a _b", _new_id(rng)))
    elif kind == 1:
        value = own or ""
    elif kind == 2:
        value = _id_of(rng.choice(ancestors)) or ""
    else:
        value = rng.choice(sorted(ids))
    if key == "href":
        value = rng.choice(("", "input.uml", "input.xmi")) + "#" + value
    element.set(key, value)
    return True


def _typed(root: etree._Element, *types: str) -> list[etree._Element]:
    return [el for el in root.iter() if isinstance(el.tag, str) and _id_of(el)
            and _type_of(el).split(":")[-1] in types]


def generalization_cycle(root: etree._Element, rng: random.Random) -> bool:
    """Two classifiers (or one) each the general of the other."""
    classes = _typed(root, "Class", "DataType", "Signal", "Block")
    if not classes:
        return False
    first = rng.choice(classes)
    second = rng.choice(classes)
    xmi_id, xmi_type = _keys(root)
    for special, general in ((first, second), (second, first)):
        etree.SubElement(special, "generalization", {xmi_type: "uml:Generalization", xmi_id: _new_id(rng),
                                                     "general": _id_of(general) or ""})
    return True


def package_imports_itself(root: etree._Element, rng: random.Random) -> bool:
    packages = _typed(root, "Package", "Model", "Profile")
    if not packages:
        return False
    package = rng.choice(packages)
    xmi_id, xmi_type = _keys(root)
    if rng.random() < 0.5:
        etree.SubElement(package, "packageImport", {xmi_type: "uml:PackageImport", xmi_id: _new_id(rng),
                                                    "importedPackage": _id_of(package) or ""})
    else:
        link = etree.SubElement(package, "packageImport", {xmi_type: "uml:PackageImport", xmi_id: _new_id(rng)})
        etree.SubElement(link, "importedPackage", {"href": f"input.uml#{_id_of(package)}"})
    return True


def region_in_itself(root: etree._Element, rng: random.Random) -> bool:
    """A region holding a state whose region is the first one again, by href or by id."""
    regions = _typed(root, "Region")
    if not regions:
        return False
    region = rng.choice(regions)
    xmi_id, xmi_type = _keys(root)
    state = etree.SubElement(region, "subvertex", {xmi_type: "uml:State", xmi_id: _new_id(rng), "name": "loop"})
    if rng.random() < 0.5:
        etree.SubElement(state, "region", {"href": f"#{_id_of(region)}"})
    else:
        etree.SubElement(state, "region", {xmi_type: "uml:Region", xmi_id: _id_of(region) or ""})
    return True


def _applications(root: etree._Element) -> list[etree._Element]:
    """The stereotype applications: elements with a ``base_…`` attribute, wherever the tool puts them."""
    return [el for el in root.iter() if isinstance(el.tag, str) and any(k.startswith("base_") for k in el.attrib)]


def swap_stereotype(root: etree._Element, rng: random.Random) -> bool:
    """An application moved to an element of another metaclass, its base attribute renamed, or
    its stereotype replaced by another EARL stereotype on the same element."""
    applications = _applications(root)
    if not applications:
        return False
    application = rng.choice(applications)
    base = next(k for k in application.attrib if k.startswith("base_"))
    kind = rng.randrange(3)
    if kind == 0:
        others = [value for el in root.iter() if isinstance(el.tag, str) and (value := _id_of(el))]
        application.set(base, rng.choice(others))
    elif kind == 1:
        value = application.attrib.pop(base)
        application.set(rng.choice(BASE_ATTRIBUTES), value)
    else:
        namespace = etree.QName(application).namespace
        earl = _namespace_of(root, "EARL", namespace or "http://earl")
        application.tag = f"{{{earl}}}{rng.choice(EARL_STEREOTYPES)}"
    return True


def hostile_number(root: etree._Element, rng: random.Random) -> bool:
    """A multiplicity bound, a literal's value or a tagged value made a hostile number."""
    places = [(el, "value") for el in root.iter() if isinstance(el.tag, str)
              and etree.QName(el).localname in ("lowerValue", "upperValue", "defaultValue", "specification")]
    places += [(el, key) for el in _applications(root) for key in el.attrib
               if not key.startswith("base_") and not key.endswith("}id")]
    if not places:
        return False
    element, key = rng.choice(places)
    element.set(key, rng.choice(HOSTILE_NUMBERS))
    return True


MUTATIONS: tuple[Callable[[etree._Element, random.Random], bool], ...] = (
    rewire_reference, rewire_reference, generalization_cycle, package_imports_itself, region_in_itself,
    swap_stereotype, swap_stereotype, hostile_number, hostile_number,
)


def mutate_structure(root: etree._Element, rng: random.Random) -> bool:
    """One structural change of the tree in place; False when the tree has nothing it applies to."""
    return rng.choice(MUTATIONS)(root, rng)
