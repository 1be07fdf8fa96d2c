"""The samples in their three tool dialects: Papyrus, Cameo 2022x and Enterprise Architect 16.

``scripts/make_sample.py`` builds the pick-and-place model once and writes it with
``papyrus_builder``, ``cameo_builder`` and ``ea_builder``; ``scripts/make_two_arm.py`` and
``scripts/make_harmoniser.py`` do the same for the variable-structure samples. These tests check
that each file is deterministic, well-formed in its declared encoding, internally consistent
(every reference resolves) and that the three files of a sample carry the same model: the
structural counts below are computed by a small per-dialect helper and must agree. The
reference sample's files are looked at closer.
"""

from __future__ import annotations

import importlib.util
from collections import Counter
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest
from lxml import etree

from earl_m2t.profile_export.render import export_profile
from tests.support import cameo_builder, ea_builder

ROOT = Path(__file__).resolve().parents[2]

SAMPLES = ROOT / "samples" / "pick_and_place"
FILES = {
    "papyrus": SAMPLES / "pick_and_place.uml",
    "cameo": SAMPLES / "pick_and_place.cameo.xmi",
    "ea": SAMPLES / "pick_and_place.ea.xml",
}
# every sample written by a script, by sample: the script and its three files
SCRIPTS = {"pick_and_place": "make_sample.py", "two_arm": "make_two_arm.py", "harmoniser": "make_harmoniser.py"}


def _xmi_files(sample: str) -> dict[str, Path]:
    folder = ROOT / "samples" / sample
    return {"papyrus": folder / f"{sample}.uml", "cameo": folder / f"{sample}.cameo.xmi",
            "ea": folder / f"{sample}.ea.xml"}


SAMPLE_FILES = {sample: _xmi_files(sample) for sample in SCRIPTS}
ENCODINGS = {"papyrus": "UTF-8", "cameo": "UTF-8", "ea": "windows-1252"}
DIALECTS = list(FILES)

XMI_URIS = {"papyrus": "http://www.omg.org/spec/XMI/20131001", "cameo": "http://www.omg.org/spec/XMI/20131001",
            "ea": "http://schema.omg.org/spec/XMI/2.1"}  # fmt: skip
SYSML_BLOCK = {
    "papyrus": "{http://www.eclipse.org/papyrus/sysml/1.6/SysML/Blocks}Block",
    "cameo": f"{{{cameo_builder.SYSML_NS}}}Block",
    "ea": f"{{{ea_builder.SYSML_NS}}}block",
}

# Attributes holding one id (IDREF) or several (IDREFS) in the three files.
IDREF_ATTRS = {
    "type", "general", "classifierBehavior", "guard", "source", "target", "partWithPort", "role", "behavior",
    "annotatedElement", "constrainedElement", "incoming", "outgoing", "node", "propertyPath",
}  # fmt: skip


def _load_script(name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(name.removesuffix(".py"), ROOT / "scripts" / name)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def scripts() -> dict[str, ModuleType]:
    return {sample: _load_script(name) for sample, name in SCRIPTS.items()}


def _parse(path: Path) -> etree._Element:
    parser = etree.XMLParser(resolve_entities=False, no_network=True, huge_tree=True)
    return etree.fromstring(path.read_bytes(), parser)


@pytest.fixture(scope="module")
def roots() -> dict[str, etree._Element]:
    return {name: _parse(path) for name, path in FILES.items()}


# ---- the per-dialect counting helper ---------------------------------------------------------


class Sample:
    """One dialect's file, read with lxml: the model content (``xmi:Extension`` copies left out),
    the id index and the EARL stereotype applications."""

    def __init__(self, dialect: str, root: etree._Element):
        self.dialect = dialect
        self.root = root
        self.xmi = XMI_URIS[dialect]
        self.content = list(self._content(root))
        self.by_id = {el.get(self.XMI_ID): el for el in self.content if el.get(self.XMI_ID)}

    @property
    def XMI_ID(self) -> str:  # noqa: N802 - an attribute name
        return f"{{{self.xmi}}}id"

    @property
    def XMI_TYPE(self) -> str:  # noqa: N802
        return f"{{{self.xmi}}}type"

    def _content(self, el: etree._Element) -> Iterator[etree._Element]:
        for child in el:
            if not isinstance(child.tag, str) or child.tag == f"{{{self.xmi}}}Extension":
                continue
            yield child
            yield from self._content(child)

    def typed(self, xmi_type: str) -> list[etree._Element]:
        return [el for el in self.content if el.get(self.XMI_TYPE) == xmi_type]

    # -- stereotype applications

    def applications(self) -> list[etree._Element]:
        """Every stereotype application: root children after the model (Papyrus, Cameo) or the
        children of uml:Model after the packages (EA)."""
        holder = self.root
        if self.dialect == "ea":
            holder = next(el for el in self.root if etree.QName(el).localname == "Model")
        return [el for el in holder if isinstance(el.tag, str) and any(k.startswith("base_") for k in el.attrib)]

    @staticmethod
    def base(app: etree._Element) -> str:
        return next(v for k, v in app.attrib.items() if k.startswith("base_"))

    def earl_applications(self) -> list[tuple[str, etree._Element]]:
        """(EARL concept, application); EA's names are normalised (``Input Buffer`` → ``InputBuffer``)."""
        prefix = {"papyrus": "http:///schemas/EARL/", "cameo": cameo_builder.EARL_NS, "ea": ea_builder.EARL_NS}[
            self.dialect
        ]
        found = []
        for app in self.applications():
            qname = etree.QName(app)
            if not (qname.namespace or "").startswith(prefix):
                continue
            name = app.get("__EAStereoName") or qname.localname
            found.append((name.replace(" ", "").replace("_", ""), app))
        return found

    def is_copy(self, element_id: str) -> bool:
        """An EA ``qualifier``: the copy of a port or part shown on a part."""
        el = self.by_id.get(element_id)
        return el is not None and el.tag == "qualifier"

    # -- the counts

    def guard_text(self, transition: etree._Element) -> str | None:
        ref = transition.get("guard")
        guard = self.by_id[ref] if ref else transition.find("guard")
        if guard is None:
            return None
        spec = guard.find("specification")
        assert spec is not None
        return spec.get("body") if spec.get("body") is not None else spec.findtext("body")

    def counts(self) -> dict[str, Any]:
        earl = self.earl_applications()
        concepts = Counter(name for name, app in earl if not self.is_copy(self.base(app)))
        transitions = self.typed("uml:Transition")
        guards = sorted(t for t in (self.guard_text(tr) for tr in transitions) if t is not None)
        if self.dialect == "ea":
            # EA cannot stereotype a guard (it is a property of the transition, not an element):
            # every guard is an EARL initial condition, i.e. a Predicate, by construction.
            concepts["Predicate"] += len(guards)
        pf_ids = {self.base(app) for name, app in earl if name == "PartialTransitionFunction"}
        pfs = sorted(
            (self.by_id[pf].get("name"), tuple(sorted(self._parameters(self.by_id[pf])))) for pf in pf_ids
        )
        ports = [el for el in self.typed("uml:Port") if el.tag != "qualifier"]
        parts = [
            el for el in self.typed("uml:Property")
            if el.tag == "ownedAttribute" and el.get("aggregation") == "composite" and self._typed_by_block(el)
        ]  # fmt: skip
        return {
            "blocks": sum(1 for app in self.applications() if app.tag == SYSML_BLOCK[self.dialect]),
            "data types": len(self.typed("uml:DataType")),
            "ports": len(ports),
            "parts": len(parts),
            "connectors": len(self.typed("uml:Connector")),
            "state machines": len(self.typed("uml:StateMachine")),
            "states": len(self.typed("uml:State")),
            "transitions": len(transitions),
            "guards": guards,
            "activities": len(self.typed("uml:Activity")),
            "fork and join nodes": len(self.typed("uml:ForkNode")) + len(self.typed("uml:JoinNode")),
            "call behavior actions": len(self.typed("uml:CallBehaviorAction")),
            "pf parameters": pfs,
            "stereotype applications per EARL concept": dict(sorted(concepts.items())),
        }

    @staticmethod
    def _parameters(behavior: etree._Element) -> Iterator[tuple[str | None, str]]:
        """(name, direction) of each parameter; ``in`` is the default Papyrus and Cameo leave out."""
        for param in behavior.iter("ownedParameter"):
            yield param.get("name"), param.get("direction") or "in"

    def _typed_by_block(self, prop: etree._Element) -> bool:
        ref = prop.get("type")
        if ref is None:
            child = prop.find("type")
            ref = child.get(f"{{{self.xmi}}}idref") if child is not None else None
        blocks = {self.base(app) for app in self.applications() if app.tag == SYSML_BLOCK[self.dialect]}
        return ref in blocks

    # -- references

    def references(self) -> Iterator[tuple[str, str]]:
        """(attribute, id) for every local reference in the model content."""
        for el in self.content:
            if el.tag == "eAnnotations":  # EMF annotations: ``source`` is a URI there
                continue
            for attr, value in el.attrib.items():
                if attr == f"{{{self.xmi}}}idref" or attr in IDREF_ATTRS:
                    for ref in value.split():
                        yield attr, ref
        for app in self.applications():
            for attr, value in app.attrib.items():
                if attr.startswith("base_") or attr == "propertyPath":
                    for ref in value.split():
                        yield attr, ref


@pytest.fixture(scope="module")
def samples(roots: dict[str, etree._Element]) -> dict[str, Sample]:
    return {name: Sample(name, root) for name, root in roots.items()}


@pytest.fixture(scope="module")
def every_sample() -> dict[tuple[str, str], Sample]:
    """Every scripted sample's file, by (sample, dialect)."""
    return {(sample, dialect): Sample(dialect, _parse(path))
            for sample, files in SAMPLE_FILES.items() for dialect, path in files.items()}


EVERY = [(sample, dialect) for sample in SAMPLE_FILES for dialect in DIALECTS]


# ---- the tests ---------------------------------------------------------------------------------


@pytest.mark.parametrize(("sample", "dialect"), EVERY)
def test_two_builds_of_each_dialect_are_byte_identical(scripts: dict[str, ModuleType], sample: str,
                                                      dialect: str) -> None:
    script = scripts[sample]
    assert script.build(dialect=dialect) == script.build(dialect=dialect)


@pytest.mark.parametrize(("sample", "dialect"), EVERY)
def test_the_committed_files_are_what_the_script_writes(scripts: dict[str, ModuleType], sample: str,
                                                       dialect: str) -> None:
    expected = scripts[sample].build(dialect=dialect)
    assert SAMPLE_FILES[sample][dialect].read_bytes() == expected, f"run: python scripts/{SCRIPTS[sample]}"


@pytest.mark.parametrize(("sample", "dialect"), EVERY)
def test_each_file_is_well_formed_in_its_declared_encoding(sample: str, dialect: str) -> None:
    data = SAMPLE_FILES[sample][dialect].read_bytes()
    tree = etree.ElementTree(etree.fromstring(data, etree.XMLParser(resolve_entities=False, no_network=True)))
    assert tree.docinfo.encoding == ENCODINGS[dialect]
    data.decode("cp1252" if dialect == "ea" else "utf-8")  # every byte belongs to the declared encoding
    if dialect == "ea":
        assert data.count(b"\r\n") == data.count(b"\n"), "Enterprise Architect writes CRLF line ends"
        # characters outside windows-1252 (the sample's ∧, ∨, →) are character references
        text = SAMPLE_FILES[sample]["papyrus"].read_text(encoding="utf-8")
        outside = sorted({char for char in text if not _in_cp1252(char)})
        assert [char for char in outside if f"&#{ord(char)};".encode("ascii") not in data] == []


def _in_cp1252(char: str) -> bool:
    try:
        char.encode("cp1252")
    except UnicodeEncodeError:
        return False
    return True


@pytest.mark.parametrize(("sample", "dialect"), EVERY)
def test_every_reference_resolves_inside_the_file(every_sample: dict[tuple[str, str], Sample], sample: str,
                                                  dialect: str) -> None:
    found = every_sample[sample, dialect]
    known = set(found.by_id)
    if dialect == "ea":  # EA defines the primitive types it uses under xmi:Extension/primitivetypes
        known |= {el.get(found.XMI_ID) for el in found.root.iter("packagedElement") if el.get(found.XMI_ID)}
    refs = list(found.references())
    assert len(refs) > 200
    dangling = sorted({f"{attr}={ref}" for attr, ref in refs if ref not in known})
    assert not dangling, dangling[:10]


@pytest.mark.parametrize(("sample", "dialect"), EVERY)
def test_ids_of_the_model_content_are_unique(every_sample: dict[tuple[str, str], Sample], sample: str,
                                             dialect: str) -> None:
    found = every_sample[sample, dialect]
    ids = Counter(el.get(found.XMI_ID) for el in found.content if el.get(found.XMI_ID))
    assert [i for i, n in ids.items() if n > 1] == []


@pytest.mark.parametrize("sample", SAMPLE_FILES)
def test_the_three_dialects_carry_the_same_model(every_sample: dict[tuple[str, str], Sample], sample: str) -> None:
    counts = {dialect: every_sample[sample, dialect].counts() for dialect in DIALECTS}
    papyrus = counts["papyrus"]
    for dialect in ("cameo", "ea"):
        for key, value in papyrus.items():
            assert counts[dialect][key] == value, f"{dialect}: {key}"


def test_the_shared_counts_are_those_of_the_paper_sample(samples: dict[str, Sample]) -> None:
    counts = samples["papyrus"].counts()
    assert (counts["blocks"], counts["data types"], counts["ports"], counts["parts"]) == (12, 12, 24, 11)
    assert (counts["connectors"], counts["state machines"], counts["states"], counts["transitions"]) == (12, 7, 11, 17)
    assert (counts["activities"], counts["fork and join nodes"], counts["call behavior actions"]) == (11, 16, 23)
    assert len(counts["guards"]) == 10 and counts["guards"].count("emergencyStop/pp.fun ∨ inError()") == 3
    assert len(counts["pf parameters"]) == 14
    assert dict(counts["pf parameters"])["jointMove/pf"] == (
        ("manipulatorCommand/ib", "in"), ("motionFinished/mo", "out"),
        ("motorControllerStateK/ib", "in"), ("windingCurrentK/mo", "out"),
    )  # fmt: skip
    assert counts["stereotype applications per EARL concept"] == {
        "System": 1, "Robot": 1, "Agent": 3, "ControlSubsystem": 3, "VirtualEffector": 2, "RealEffector": 2,
        "InputBuffer": 12, "OutputBuffer": 12, "InternalMemory": 11, "InterSubsystemLink": 8, "InterAgentLink": 4,
        "FSM": 7, "FsmState": 11, "FsmTransition": 10, "BasicBehaviour": 11, "PartialTransitionFunction": 14,
        # Predicate: the guards, tc and ec
        "PrimitivePredicate": 6, "Predicate": 10 + 2 * 11, "Exclusion": 1, "BufferGroup": 1,
            "LtlProperty": 1,  # the emergency-stop property verify proves
    }  # fmt: skip


def test_the_cameo_file_has_magicdraw_s_shape(samples: dict[str, Sample]) -> None:
    data = FILES["cameo"].read_bytes()
    assert data.startswith(b"<?xml version='1.0' encoding='UTF-8'?>\n<xmi:XMI xmlns:uml=")
    assert b"xmi:version" not in data and b'"' not in data.replace(b"&quot;", b"")
    sample = samples["cameo"]
    assert [etree.QName(el).localname for el in sample.root[:4]] == ["Documentation", "Extension", "Model", "Extension"]
    plugins, hrefs = sample.root.findall(f"{{{sample.xmi}}}Extension")
    assert plugins.find("plugin") is not None and hrefs.find("stereotypesHREFS") is not None
    for app in sample.applications():
        assert app.get(sample.XMI_ID, "").startswith(sample.base(app) + "_application")
    nodes = [el for el in sample.content if el.tag == "node"]
    assert nodes and not any(el.get("incoming") or el.get("outgoing") for el in nodes)
    expressions = sample.typed("uml:OpaqueExpression")
    assert expressions and all([c.tag for c in e] == ["body", "language"] for e in expressions)
    custom = Counter(etree.QName(app).localname for app in sample.applications()
                     if etree.QName(app).namespace == cameo_builder.MD_CUSTOM_NS)  # fmt: skip
    assert custom == {"PartProperty": 11, "ValueProperty": 11}


def test_the_ea_file_has_enterprise_architect_s_shape(samples: dict[str, Sample]) -> None:
    sample = samples["ea"]
    root = sample.root
    assert root.get(f"{{{sample.xmi}}}version") == "2.1"
    doc = root.find(f"{{{sample.xmi}}}Documentation")
    assert doc is not None and doc.get("exporter") == "Enterprise Architect" and doc.get("exporterVersion") == "6.5"
    apps = sample.applications()
    assert apps and not any(app.get(sample.XMI_ID) for app in apps)
    assert all(etree.QName(app).localname == "block" for app in apps if app.tag == SYSML_BLOCK["ea"])
    # the EARL stereotypes are those of the EA profile `earl-m2t profile --format ea` writes, by name
    earl = [app for app in apps if etree.QName(app).namespace == ea_builder.EARL_NS]
    assert earl and {etree.QName(app).localname for app in earl} <= ea_profile_stereotypes()
    assert not any(app.get("__EAStereoName") for app in earl)
    ends = [el for el in sample.content if el.tag == "end"]
    assert ends and not any(el.get("partWithPort") for el in ends)
    roles = {el.get("role") for el in ends}
    assert len(roles) == 24 and all(sample.is_copy(r or "") for r in roles)  # every end is on a part
    guards = [el for el in sample.content if el.tag == "guard" and el.getparent().tag == "transition"]
    assert guards and all(g.find("specification").get("body") for g in guards)
    assert not any(tr.get("guard") for tr in sample.typed("uml:Transition"))
    ext = root.find(f"{{{sample.xmi}}}Extension")
    assert ext is not None and ext.get("extender") == "Enterprise Architect"
    assert [child.tag for child in ext] == ["elements", "connectors", "primitivetypes"]


@pytest.mark.parametrize("sample", SAMPLE_FILES)
def test_the_ea_files_apply_stereotypes_of_the_ea_profile(every_sample: dict[tuple[str, str], Sample],
                                                          sample: str) -> None:
    found = every_sample[sample, "ea"]
    earl = {etree.QName(app).localname for app in found.applications()
            if etree.QName(app).namespace == ea_builder.EARL_NS}
    assert earl and earl <= ea_profile_stereotypes()


def ea_profile_stereotypes() -> set[str]:
    """The names of the stereotypes a modeller can apply from the generated EA profile."""
    ((_, data),) = export_profile("ea").items()
    root = etree.fromstring(data)
    xmi_type = "{http://www.omg.org/spec/XMI/20131001}type"
    return {
        el.get("name") or "" for el in root.iter("packagedElement")
        if el.get(xmi_type) == "uml:Stereotype" and el.get("isAbstract") != "true"
    }


def _ea_records(sample: Sample, kind: str) -> dict[str, etree._Element]:
    ext = sample.root.find(f"{{{sample.xmi}}}Extension")
    assert ext is not None
    holder = ext.find(kind)
    assert holder is not None
    return {rec.get(f"{{{sample.xmi}}}idref") or "": rec for rec in holder}


def test_the_ea_file_is_in_model_order_with_the_tree_positions_of_a_free_sorted_browser(
    samples: dict[str, Sample],
) -> None:
    """EA exports in Project Browser order; the elements under each owner have the tree positions
    1, 2 … in the order of the file (packages counted apart; notes are not in the browser)."""
    sample = samples["ea"]
    records = _ea_records(sample, "elements")
    checked = 0
    for parent in sample.root.iter():
        for packages in (True, False):
            positions = []
            for child in parent:
                rec = records.get(child.get(sample.XMI_ID) or "")
                model = rec.find("model") if rec is not None else None
                if model is None or child.get(sample.XMI_TYPE) == "uml:Comment":
                    continue
                if (child.get(sample.XMI_TYPE) == "uml:Package") == packages:
                    positions.append(int(model.get("tpos") or "0"))
            assert positions == list(range(1, len(positions) + 1)), parent.get("name")
            checked += len(positions)
    positioned = [rec for rec in records.values() if rec.find("model[@tpos]") is not None]
    assert checked == sum(1 for rec in positioned if rec.find("model[@tpos='0']") is None) > 150
    # the model's order, not EA's default (by type, then name): a state machine's initial state first
    region = next(el for el in sample.content if el.tag == "region")
    assert [v.get(sample.XMI_TYPE) for v in region.iterchildren("subvertex")][0] == "uml:Pseudostate"


def test_the_ea_file_numbers_transitions_and_connectors_as_they_were_created(samples: dict[str, Sample]) -> None:
    """Transitions and connectors come after their source element, grouped; their ``ea_localid``
    keeps the order they were modelled in."""
    sample = samples["ea"]
    connectors = _ea_records(sample, "connectors")

    def numbers(elements: list[etree._Element]) -> list[int]:
        found = []
        for el in elements:
            model = connectors[el.get(sample.XMI_ID) or ""].find("model")  # the record's own, not an end's
            assert model is not None
            found.append(int(model.get("ea_localid") or "0"))
        return found

    system = next(el for el in sample.typed("uml:Class") if el.get("name") == "PickAndPlaceSystem")
    links = list(system.iterchildren("ownedConnector"))
    assert [link.get("name") for link in links] == [
        "manip/a,task/a", "grip/a,task/a", "task/a,manip/a", "task/a,grip/a"]
    assert sorted(numbers(links)) != numbers(links)
    for region in (el for el in sample.content if el.tag == "region"):
        transitions = list(region.iterchildren("transition"))
        sources = [tr.get("source") for tr in transitions]
        assert sources == sorted(sources, key=sources.index)  # grouped by source vertex
    assert len(connectors) == len(sample.typed("uml:Transition")) + len(sample.typed("uml:Connector"))


def test_the_ea_file_keeps_behaviour_languages_in_the_element_records(samples: dict[str, Sample]) -> None:
    """EA's ``body=`` has no language: the element's Language (``<code gentype>``) carries it."""
    sample = samples["ea"]
    records = _ea_records(sample, "elements")
    languages: dict[str, set[str]] = {}
    for concept, app in sample.earl_applications():
        if concept in ("PartialTransitionFunction", "PrimitivePredicate"):
            behaviour = sample.by_id[sample.base(app)]
            assert behaviour.get(sample.XMI_TYPE) == "uml:OpaqueBehavior" and behaviour.get("body") is not None
            assert behaviour.find("language") is None and behaviour.get("language") is None
            code = records[sample.base(app)].find("code")
            assert code is not None
            languages.setdefault(concept, set()).add(code.get("gentype") or "")
    assert languages == {"PartialTransitionFunction": {"C++"}, "PrimitivePredicate": {"EARL"}}
