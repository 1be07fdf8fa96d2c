"""``earl-m2t profile``: the generated profile files, the writer, and the reader round trip."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from lxml import etree

from earl_m2t import resources
from earl_m2t.diagnostics import ModelReadError
from earl_m2t.output import OutputError, write_files
from earl_m2t.profile import load_profile
from earl_m2t.profile_export import FORMATS, ProfileExportError, profile_spec
from earl_m2t.profile_export.render import export_profile, load_targets
from earl_m2t.read.dialects import dialect_table
from earl_m2t.read.loader import load_raw_model
from tests.support.papyrus_builder import EARL_EPACKAGE_ID, EARL_NS, EARL_PROFILE_ID

ROOT = Path(__file__).resolve().parents[1]

SAMPLE_DIR = ROOT / "samples" / "pick_and_place"
SAMPLE = SAMPLE_DIR / "pick_and_place.uml"
SAMPLE_PROFILE = SAMPLE_DIR / "EARL.profile.uml"

XMI_URIS = ("http://www.omg.org/spec/XMI/20131001",)
XMI = XMI_URIS[0]
XMI_ID, XMI_IDREF, XMI_TYPE = f"{{{XMI}}}id", f"{{{XMI}}}idref", f"{{{XMI}}}type"
ECORE = "http://www.eclipse.org/emf/2002/Ecore"
UML2_ANNOTATION = "http://www.eclipse.org/uml2/2.0.0/UML"

# Attributes that hold one id (IDREF) or several (IDREFS) in the generated files.
IDREF_ATTRS = {
    "annotatedElement", "association", "general", "type", "memberEnd", "metaclassReference",
    "metamodelReference", "references", "eSuperTypes", "eType", "instance",
}
# Where hrefs may point: the UML / Ecore standard metamodels and primitive type libraries.
STANDARD_HREFS = (
    "pathmap://UML_METAMODELS/UML.metamodel.uml#",
    "pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml#",
    "http://www.eclipse.org/uml2/5.0.0/UML#//",
    "http://www.eclipse.org/uml2/5.0.0/Types#//",
    "http://www.omg.org/spec/UML/20131001/UML.xmi#",
    "http://www.omg.org/spec/UML/20131001/PrimitiveTypes.xmi#",
)
EA_METAMODEL_HREF = "http://www.omg.org/spec/UML/20131001"  # EA's metamodelReference import


def earl(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=120)


# The formats written as UML profiles in XMI (ea-mdg is EA's own XML: tests/test_profile_ea_mdg.py).
XMI_FORMATS = tuple(name for name in FORMATS if name != "ea-mdg")


@pytest.fixture(scope="module")
def generated() -> dict[str, tuple[str, bytes]]:
    """format → (file name, bytes), from profiles/earl.sysml."""
    out = {}
    for name in FORMATS:
        ((file_name, data),) = export_profile(name).items()
        out[name] = (file_name, data)
    return out


# ---------------------------------------------------------------- reading a profile back


@dataclass
class Stereotype:
    element: etree._Element
    name: str
    abstract: bool
    generals: list[str] = field(default_factory=list)  # stereotype names
    bases: dict[str, str] = field(default_factory=dict)  # base_X attribute -> metaclass
    tags: dict[str, etree._Element] = field(default_factory=dict)
    comment: str = ""


@dataclass
class UmlProfile:
    root: etree._Element
    element: etree._Element  # the uml:Profile
    by_id: dict[str, etree._Element]
    stereotypes: dict[str, Stereotype]
    enumerations: dict[str, list[str]]

    def all_generals(self, name: str) -> list[str]:
        found: list[str] = []
        frontier = list(self.stereotypes[name].generals)
        while frontier:
            general = frontier.pop(0)
            if general not in found:
                found.append(general)
                frontier.extend(self.stereotypes[general].generals)
        return found

    def effective_bases(self, name: str) -> dict[str, str]:
        bases: dict[str, str] = {}
        for owner in (name, *self.all_generals(name)):
            bases.update(self.stereotypes[owner].bases)
        return bases

    def effective_tags(self, name: str) -> dict[str, etree._Element]:
        tags: dict[str, etree._Element] = {}
        for owner in (*reversed(self.all_generals(name)), name):
            tags.update(self.stereotypes[owner].tags)
        return tags


def xmi_type(el: etree._Element) -> str:
    return el.get(XMI_TYPE) or ""


def ref_ids(el: etree._Element, feature: str) -> list[str]:
    """Targets of a reference in any of the encodings the generated files use."""
    ids = (el.get(feature) or "").split()
    for child in el.iterchildren(feature):
        if child.get(XMI_IDREF):
            ids.append(child.get(XMI_IDREF) or "")
    return ids


def type_of(prop: etree._Element, by_id: dict[str, etree._Element]) -> str:
    """The name of a property's type: a local element's name or an href's fragment."""
    local = ref_ids(prop, "type")
    if local:
        return by_id[local[0]].get("name") or ""
    child = prop.find("type")
    assert child is not None and child.get("href"), etree.tostring(prop)
    return (child.get("href") or "").rpartition("#")[2]


def comment_of(el: etree._Element) -> str:
    comment = el.find("ownedComment")
    if comment is None:
        return ""
    body = comment.find("body")
    return body.text or "" if body is not None else comment.get("body") or ""


def read_profile(data: bytes) -> UmlProfile:
    root = etree.fromstring(data)
    by_id = {el.get(XMI_ID) or "": el for el in root.iter() if el.get(XMI_ID)}
    if etree.QName(root).localname == "Profile":
        profile = root
    else:
        (profile,) = [el for el in root.iter("packagedElement") if xmi_type(el) == "uml:Profile"]
    stereotypes: dict[str, Stereotype] = {}
    enumerations: dict[str, list[str]] = {}
    for el in profile.iterchildren("packagedElement"):
        if xmi_type(el) == "uml:Enumeration":
            enumerations[el.get("name") or ""] = [lit.get("name") or "" for lit in el.iterchildren("ownedLiteral")]
        if xmi_type(el) != "uml:Stereotype":
            continue
        stereotype = Stereotype(el, el.get("name") or "", el.get("isAbstract") == "true", comment=comment_of(el))
        for gen in el.iterchildren("generalization"):
            (general,) = ref_ids(gen, "general")
            stereotype.generals.append(by_id[general].get("name") or "")
        for prop in el.iterchildren("ownedAttribute"):
            name = prop.get("name") or ""
            if name.startswith("base_"):
                assert ref_ids(prop, "association"), f"{stereotype.name}.{name} has no extension"
                stereotype.bases[name] = type_of(prop, by_id)
            else:
                stereotype.tags[name] = prop
        stereotypes[stereotype.name] = stereotype
    return UmlProfile(root, profile, by_id, stereotypes, enumerations)


def bounds(prop: etree._Element) -> tuple[int, int | None]:
    """Multiplicity of a property, UML defaults (1..1, value 0 when left out) applied."""
    lower_el, upper_el = prop.find("lowerValue"), prop.find("upperValue")
    lower = 1 if lower_el is None else int(lower_el.get("value") or "0")
    if upper_el is None:
        return lower, 1
    upper = upper_el.get("value") or "0"
    return lower, None if upper == "*" else int(upper)


def default_of(prop: etree._Element, by_id: dict[str, etree._Element]) -> str | None:
    default = prop.find("defaultValue")
    if default is None:
        return None
    if xmi_type(default) == "uml:InstanceValue":
        (literal,) = ref_ids(default, "instance")
        return by_id[literal].get("name")
    implicit = {"uml:LiteralInteger": "0", "uml:LiteralBoolean": "false", "uml:LiteralReal": "0.0"}
    return default.get("value", implicit.get(xmi_type(default), ""))


# ---------------------------------------------------------------- the command


def test_target_toml_defines_every_format() -> None:
    targets = load_targets()
    assert tuple(targets) == FORMATS == ("papyrus", "cameo", "ea", "ea-mdg")
    assert targets["papyrus"].output == "EARL.profile.uml"
    for target in targets.values():
        assert (resources.data_dir("transforms") / "profile" / target.template).is_file()
        assert target.template.startswith(f"{target.name}/")


@pytest.mark.parametrize("name", FORMATS)
def test_the_command_writes_the_profile_then_leaves_it_alone(name: str, tmp_path: Path) -> None:
    out = tmp_path / "out"
    first = earl("profile", "--format", name, "-o", str(out))
    assert first.returncode == 0, first.stderr
    assert first.stderr == ""
    (line,) = first.stdout.splitlines()
    file_name = load_targets()[name].output
    assert line == f"wrote {out / file_name}"
    written = out / file_name
    assert [p.name for p in out.iterdir()] == [file_name]  # no temporary file left behind
    before = written.stat()

    second = earl("profile", "--format", name, "-o", str(out))
    assert second.returncode == 0, second.stderr
    assert second.stdout.splitlines() == [f"unchanged {out / file_name}"]
    after = written.stat()
    assert (after.st_ino, after.st_mtime_ns) == (before.st_ino, before.st_mtime_ns)

    written.write_bytes(b"stale")
    third = earl("profile", "--format", name, "-o", str(out))
    assert third.stdout.splitlines() == [f"wrote {out / file_name}"]
    assert written.read_bytes() == export_profile(name)[file_name]


def test_output_is_byte_identical_across_runs(tmp_path: Path) -> None:
    for run in ("a", "b"):
        for name in FORMATS:
            assert earl("profile", "--format", name, "-o", str(tmp_path / run)).returncode == 0
    for path in (tmp_path / "a").iterdir():
        assert path.read_bytes() == (tmp_path / "b" / path.name).read_bytes(), path.name


def test_a_bad_format_is_one_line_and_exit_2(tmp_path: Path) -> None:
    result = earl("profile", "--format", "rhapsody", "-o", str(tmp_path))
    assert result.returncode == 2
    assert result.stdout == ""
    assert len(result.stderr.strip().splitlines()) == 1 and "rhapsody" in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_an_unwritable_folder_is_one_line_and_exit_2(tmp_path: Path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    for target in (blocker, blocker / "sub"):
        result = earl("profile", "--format", "papyrus", "-o", str(target))
        assert result.returncode == 2, result.stdout
        assert result.stdout == ""
        (line,) = result.stderr.splitlines()
        assert line.startswith("earl-m2t: profile: ") and str(blocker) in line
    assert blocker.read_text() == "not a folder"


# ---------------------------------------------------------------- the writer


def test_write_files_reports_written_and_unchanged(tmp_path: Path) -> None:
    report = write_files(tmp_path, {"a.txt": b"one", "sub/b.txt": b"two"})
    assert report.written == ("a.txt", "sub/b.txt") and report.unchanged == ()
    assert (tmp_path / "sub" / "b.txt").read_bytes() == b"two"
    report = write_files(tmp_path, {"a.txt": b"one", "sub/b.txt": b"changed"})
    assert report.written == ("sub/b.txt",) and report.unchanged == ("a.txt",)
    assert report.lines() == [f"unchanged {tmp_path / 'a.txt'}", f"wrote {tmp_path / 'sub/b.txt'}"]
    assert sorted(p.name for p in tmp_path.rglob("*")) == ["a.txt", "b.txt", "sub"]


def test_write_files_keeps_the_mode_of_a_replaced_file(tmp_path: Path) -> None:
    target = tmp_path / "tool.sh"
    target.write_bytes(b"old")
    target.chmod(0o750)
    write_files(tmp_path, {"tool.sh": b"new"})
    assert target.read_bytes() == b"new" and (target.stat().st_mode & 0o777) == 0o750


@pytest.mark.parametrize("bad", ["/etc/passwd", "../outside.txt", "a/../../outside.txt", "", ".", "a\\b", "C:/x"])
def test_write_files_rejects_paths_leaving_the_folder(bad: str, tmp_path: Path) -> None:
    out = tmp_path / "out"
    with pytest.raises(OutputError):
        write_files(out, {"fine.txt": b"x", bad: b"x"})
    assert not (out / "fine.txt").exists()  # nothing is written when one path is bad
    assert not (tmp_path / "outside.txt").exists()


def test_write_files_does_not_follow_a_link_out_of_the_folder(tmp_path: Path) -> None:
    out, elsewhere = tmp_path / "out", tmp_path / "elsewhere"
    out.mkdir()
    elsewhere.mkdir()
    (out / "link").symlink_to(elsewhere, target_is_directory=True)
    with pytest.raises(OutputError, match="outside"):
        write_files(out, {"link/x.txt": b"x"})
    assert list(elsewhere.iterdir()) == []


def test_write_files_refuses_a_path_given_twice(tmp_path: Path) -> None:
    with pytest.raises(OutputError, match="twice"):
        write_files(tmp_path, {"a/b.txt": b"1", "a/./b.txt": b"2"})


# ---------------------------------------------------------------- every generated file


@pytest.mark.parametrize("name", XMI_FORMATS)
def test_generated_file_is_well_formed_and_self_contained(name: str, generated: dict[str, tuple[str, bytes]]) -> None:
    _, data = generated[name]
    root = etree.fromstring(data)  # well-formed, or this raises
    assert data.endswith(b">\n") and b"\r" not in data
    ids = [el.get(XMI_ID) for el in root.iter() if el.get(XMI_ID)]
    assert len(ids) == len(set(ids)), "duplicate xmi:id"
    known = set(ids)
    for el in root.iter():
        if not isinstance(el.tag, str):
            continue
        for attribute in IDREF_ATTRS & set(el.attrib):
            for target in (el.get(attribute) or "").split():
                assert target in known, f"{el.tag}@{attribute}={target} does not resolve"
        if el.get(XMI_IDREF):
            assert el.get(XMI_IDREF) in known, f"{el.tag} xmi:idref={el.get(XMI_IDREF)} does not resolve"
        href = el.get("href")
        if href is not None:
            assert href.startswith(STANDARD_HREFS) or (name == "ea" and href == EA_METAMODEL_HREF), href


@pytest.mark.parametrize("name", XMI_FORMATS)
def test_every_concept_has_its_stereotype(name: str, generated: dict[str, tuple[str, bytes]]) -> None:
    profile = load_profile()
    uml = read_profile(generated[name][1])
    assert set(uml.stereotypes) == set(profile.concepts)
    assert uml.enumerations == {enum: list(literals) for enum, literals in profile.enums.items()}
    for concept in profile.concepts.values():
        stereotype = uml.stereotypes[concept.name]
        assert stereotype.abstract == concept.abstract, concept.name
        assert stereotype.generals == list(concept.supertypes), concept.name
        assert stereotype.comment == concept.doc, concept.name
        if concept.abstract:
            continue
        # exactly one stereotype of that name, applicable to exactly its metaclass
        same_name = [el for el in uml.root.iter("packagedElement")
                     if xmi_type(el) == "uml:Stereotype" and el.get("name") == concept.name]
        assert len(same_name) == 1, concept.name
        assert uml.effective_bases(concept.name) == {f"base_{concept.metaclass}": concept.metaclass}, concept.name
        tags = uml.effective_tags(concept.name)
        expected = profile.tags(concept.name)
        assert sorted(tags) == sorted(f.name for f in expected), concept.name
        for feature in expected:
            prop = tags[feature.name]
            assert type_of(prop, uml.by_id) == feature.type, f"{concept.name}.{feature.name}"
            assert bounds(prop) == (feature.lower, feature.upper), f"{concept.name}.{feature.name}"
            expected_default = None if feature.default is None else str(feature.default)
            assert default_of(prop, uml.by_id) == expected_default, f"{concept.name}.{feature.name}"


def test_the_profile_has_the_tags_the_reader_knows(generated: dict[str, tuple[str, bytes]]) -> None:
    for name in XMI_FORMATS:
        uml = read_profile(generated[name][1])
        assert set(uml.effective_tags("Agent")) == {"declaredType", "reactivation", "host"}
        assert type_of(uml.effective_tags("Agent")["declaredType"], uml.by_id) == "AgentType"
        reactivation = uml.effective_tags("Agent")["reactivation"]
        assert type_of(reactivation, uml.by_id) == "Reactivation" and default_of(reactivation, uml.by_id) == "restart"
        assert set(uml.effective_tags("Configuration")) == {"agents", "links", "switchTimeout"}
        priority = uml.effective_tags("FsmTransition")["priority"]
        assert type_of(priority, uml.by_id) == "Integer" and default_of(priority, uml.by_id) == "0"
        assert uml.effective_bases("ControlSubsystem") == {"base_Class": "Class"}
        assert uml.stereotypes["Subsystem"].abstract and uml.stereotypes["Link"].abstract


def test_the_profile_is_read_from_earl_sysml_not_from_a_copy(tmp_path: Path) -> None:
    text = resources.profile_path().read_text(encoding="utf-8")
    extra = '''
        part def <gw> Gateway :> Subsystem {
            doc /* A test-only concept. */
            @Stereotype { metaclass = "Class"; }
            #Tag attribute rate : Real default 1.5;
            #Tag attribute label : String[0..*];
        }
'''
    marker = "        // ---------------------------------------------------------- buffers and memory"
    assert marker in text
    changed = tmp_path / "earl.sysml"
    changed.write_text(text.replace(marker, extra + marker), encoding="utf-8")
    profile = load_profile(changed)
    for name in XMI_FORMATS:
        ((_, data),) = export_profile(name, profile).items()
        uml = read_profile(data)
        gateway = uml.stereotypes["Gateway"]
        assert gateway.generals == ["Subsystem"] and gateway.bases == {}
        assert uml.effective_bases("Gateway") == {"base_Class": "Class"}
        assert type_of(gateway.tags["rate"], uml.by_id) == "Real"
        assert default_of(gateway.tags["rate"], uml.by_id) == "1.5"
        assert bounds(gateway.tags["label"]) == (0, None)


def test_a_tag_of_an_unsupported_type_is_refused(tmp_path: Path) -> None:
    text = resources.profile_path().read_text(encoding="utf-8")
    changed = tmp_path / "earl.sysml"
    changed.write_text(
        text.replace("#Tag attribute declaredType : AgentType[0..1];", "#Tag attribute declaredType : Complex[0..1];"),
        encoding="utf-8",
    )
    with pytest.raises(ProfileExportError, match="Agent.declaredType"):
        profile_spec(load_profile(changed))


# ---------------------------------------------------------------- Papyrus


def test_the_sample_profile_is_up_to_date() -> None:
    ((file_name, data),) = export_profile("papyrus").items()
    assert file_name == SAMPLE_PROFILE.name
    assert SAMPLE_PROFILE.read_bytes() == data, (
        "samples/pick_and_place/EARL.profile.uml is out of date: "
        "run `earl-m2t profile --format papyrus -o samples/pick_and_place`"
    )


def _epackage(root: etree._Element) -> etree._Element:
    annotation = root.find("eAnnotations")
    assert annotation is not None and annotation.get("source") == UML2_ANNOTATION
    (package,) = [c for c in annotation.iterchildren("contents") if xmi_type(c) == "ecore:EPackage"]
    return package


def test_papyrus_profile_carries_its_ecore_definition(generated: dict[str, tuple[str, bytes]]) -> None:
    uml = read_profile(generated["papyrus"][1])
    root = uml.root
    assert etree.QName(root).localname == "Profile" and root.get(f"{{{XMI}}}version") == "20131001"
    assert root.get(XMI_ID) == EARL_PROFILE_ID
    package = _epackage(root)
    assert package.get(XMI_ID) == EARL_EPACKAGE_ID
    assert package.get("nsURI") == EARL_NS and package.get("nsPrefix") == "EARL"

    classes = {c.get("name"): c for c in package.iterchildren("eClassifiers") if xmi_type(c) == "ecore:EClass"}
    enums = {c.get("name"): c for c in package.iterchildren("eClassifiers") if xmi_type(c) == "ecore:EEnum"}
    assert set(classes) == set(uml.stereotypes)
    assert {e: [lit.get("name") for lit in c.iterchildren("eLiterals")] for e, c in enums.items()} == uml.enumerations
    for name, eclass in classes.items():
        stereotype = uml.stereotypes[name]
        (note,) = eclass.iterchildren("eAnnotations")
        assert note.get("source") == UML2_ANNOTATION and note.get("references") == stereotype.element.get(XMI_ID)
        assert (eclass.get("abstract") == "true") == stereotype.abstract
        supers = [uml.by_id[i].get("name") for i in (eclass.get("eSuperTypes") or "").split()]
        assert supers == stereotype.generals
        features = {f.get("name"): f for f in eclass.iterchildren("eStructuralFeatures")}
        assert set(features) == set(stereotype.bases) | set(stereotype.tags)
        for base, metaclass in stereotype.bases.items():
            etype = features[base].find("eType")
            assert xmi_type(features[base]) == "ecore:EReference" and features[base].get("lowerBound") == "1"
            assert etype is not None and etype.get("href") == f"http://www.eclipse.org/uml2/5.0.0/UML#//{metaclass}"
    priority = {f.get("name"): f for f in classes["FsmTransition"].iterchildren("eStructuralFeatures")}["priority"]
    assert priority.get("defaultValueLiteral") == "0" and priority.get("lowerBound") == "1"
    declared = {f.get("name"): f for f in classes["Agent"].iterchildren("eStructuralFeatures")}["declaredType"]
    assert declared.get("eType") == enums["AgentType"].get(XMI_ID) and declared.get("lowerBound") is None
    # the metaclasses are imported as Papyrus does (metaclassReference)
    imported = [uml.by_id[i] for i in (root.get("metaclassReference") or "").split()]
    assert sorted(i.get("alias") or "" for i in imported) == sorted({m for s in uml.stereotypes.values()
                                                                      for m in s.bases.values()})


def test_the_sample_applies_the_generated_papyrus_profile(generated: dict[str, tuple[str, bytes]]) -> None:
    """(a) The sample's EARL namespace, schemaLocation and profile application point into the
    generated profile, and every application in it is a stereotype of that profile."""
    uml = read_profile(generated["papyrus"][1])
    ns_uri = _epackage(uml.root).get("nsURI") or ""
    sample = etree.parse(str(SAMPLE)).getroot()
    assert sample.nsmap["EARL"] == ns_uri
    assert dialect_table().is_earl(ns_uri)
    locations = (sample.get("{http://www.w3.org/2001/XMLSchema-instance}schemaLocation") or "").split()
    assert locations[locations.index(ns_uri) + 1] == f"EARL.profile.uml#{EARL_EPACKAGE_ID}"
    hrefs = [el.get("href") or "" for el in sample.iter() if (el.get("href") or "").startswith("EARL.profile.uml#")]
    assert len(hrefs) == 2
    for href in hrefs:
        assert href.partition("#")[2] in uml.by_id, href
    assert uml.by_id[EARL_PROFILE_ID] is uml.element

    applications = [el for el in sample if etree.QName(el).namespace == ns_uri]
    assert len(applications) > 100
    for application in applications:
        name = etree.QName(application).localname
        assert name in uml.stereotypes and not uml.stereotypes[name].abstract, name
        bases = uml.effective_bases(name)
        tags = uml.effective_tags(name)
        for attribute, value in application.attrib.items():
            if attribute == XMI_ID:
                continue
            if attribute.startswith("base_"):
                assert attribute in bases, f"{name}@{attribute}"
            else:
                assert attribute in tags, f"{name}@{attribute}"
                tag_type = type_of(tags[attribute], uml.by_id)
                if tag_type in uml.enumerations:
                    assert value in uml.enumerations[tag_type]
                elif tag_type == "Integer":
                    int(value)

    raw = load_raw_model(SAMPLE)
    families = {app.family for apps in raw.stereotypes.values() for app in apps if app.profile_uri == ns_uri}
    assert families == {"earl"}


# ---------------------------------------------------------------- Cameo


def _cameo_model(profile_uri: str) -> str:
    """A small model as Cameo saves it, applying the generated profile at root level."""
    return f"""<?xml version='1.0' encoding='UTF-8'?>
<xmi:XMI xmlns:uml='http://www.omg.org/spec/UML/20131001' xmlns:xmi='http://www.omg.org/spec/XMI/20131001' xmlns:sysml='http://www.omg.org/spec/SysML/20181001/SysML' xmlns:EARL='{profile_uri}'>
	<xmi:Documentation>
		<xmi:exporter>MagicDraw UML</xmi:exporter>
		<xmi:exporterVersion>2022x v7</xmi:exporterVersion>
	</xmi:Documentation>
	<uml:Model xmi:type='uml:Model' xmi:id='eee_1045467100313_135436_1' name='Model'>
		<packagedElement xmi:type='uml:Class' xmi:id='_cell' name='Cell'>
			<ownedAttribute xmi:type='uml:Property' xmi:id='_cell_arm' name='arm' aggregation='composite' type='_arm'/>
		</packagedElement>
		<packagedElement xmi:type='uml:Class' xmi:id='_arm' name='Arm'>
			<ownedAttribute xmi:type='uml:Property' xmi:id='_arm_control' name='control' aggregation='composite' type='_control'/>
		</packagedElement>
		<packagedElement xmi:type='uml:Class' xmi:id='_control' name='ArmControl'/>
	</uml:Model>
	<sysml:Block xmi:id='_cell_application' base_Class='_cell'/>
	<EARL:System xmi:id='_cell_application1' base_Class='_cell'/>
	<sysml:Block xmi:id='_arm_application' base_Class='_arm'/>
	<EARL:Agent xmi:id='_arm_application1' base_Class='_arm' declaredType='C'/>
	<sysml:Block xmi:id='_control_application' base_Class='_control'/>
	<EARL:ControlSubsystem xmi:id='_control_application1' base_Class='_control'/>
</xmi:XMI>
"""


def test_cameo_profile_uri_is_an_earl_namespace(generated: dict[str, tuple[str, bytes]]) -> None:
    uml = read_profile(generated["cameo"][1])
    uri = uml.element.get("URI") or ""
    assert uri == "http://www.magicdraw.com/schemas/EARL.xmi"
    assert uml.element.get("name") == "EARL"
    assert dialect_table().is_earl(uri)
    model = etree.fromstring(_cameo_model(uri).encode("utf-8"))
    for application in (el for el in model if etree.QName(el).namespace == uri):
        name = etree.QName(application).localname
        assert name in uml.stereotypes and not uml.stereotypes[name].abstract
        assert {a for a in application.attrib if a.startswith("base_")} <= set(uml.effective_bases(name))
    # Cameo types base_Class by the OMG UML metamodel
    base = uml.stereotypes["Agent"].element.find("ownedAttribute[@name='base_Class']/type")
    assert base is not None and base.get("href") == "http://www.omg.org/spec/UML/20131001/UML.xmi#Class"


def test_the_reader_recognises_a_cameo_model_applying_the_profile(
    generated: dict[str, tuple[str, bytes]], tmp_path: Path
) -> None:
    """(b) Round trip through the reader; skipped while the reader does not read Cameo XMI."""
    from earl_m2t import load
    from earl_m2t.export import model_to_dict

    uri = read_profile(generated["cameo"][1]).element.get("URI") or ""
    model = tmp_path / "cell.xmi"
    model.write_text(_cameo_model(uri), encoding="utf-8")
    try:
        loaded = load(model)
    except ModelReadError as error:
        if "not supported" in str(error):
            pytest.skip(f"the reader does not read Cameo XMI in this version: {error}")
        raise
    document = model_to_dict(loaded.model)
    (system,) = document["systems"]
    assert system["recognised_by"] == "stereotype"
    (agent,) = system["agents"]
    assert (agent["recognised_by"], agent["declared_type"]) == ("stereotype", "C")
    (control,) = agent["subsystems"]
    assert (control["kind"], control["recognised_by"]) == ("cs", "stereotype")


# ---------------------------------------------------------------- Enterprise Architect


def _ea_application(uml: UmlProfile, concept: str, base_id: str, **tags: str) -> str:
    """A stereotype application as EA exports it: the element named after the stereotype (spaces
    as ``_``, the real name in ``__EAStereoName``), no ``xmi:id``, the base and the tags as attributes."""
    stereotype = uml.stereotypes[concept]
    assert not stereotype.abstract, concept
    (base,) = uml.effective_bases(concept)
    name = stereotype.name
    attributes = [(base, base_id), ("__EAStereoName", name if " " in name else ""), *tags.items()]
    rendered = "".join(f' {key}="{value}"' for key, value in attributes if value)
    return f"<EARL:{name.replace(' ', '_')}{rendered}/>"


def _ea_model(uml: UmlProfile) -> str:
    """A small model as Enterprise Architect 16 exports it ("XMI 2.1") with the generated profile
    applied: the exported package inside ``EA_Model``, the applications inside that uml:Model
    after it, ports as ``ownedPort``, an opaque behaviour's language only in its extension record.
    Nothing is named with the EARL suffixes: only the stereotypes say what the elements are."""
    uri = uml.element.get("URI") or ""
    apps = [
        _ea_application(uml, "System", "EAID_CELL"),
        _ea_application(uml, "Agent", "EAID_ARM", declaredType="C"),
        _ea_application(uml, "ControlSubsystem", "EAID_CTRL"),
        _ea_application(uml, "InputBuffer", "EAID_CMD"),
        _ea_application(uml, "OutputBuffer", "EAID_STATE"),
        _ea_application(uml, "PartialTransitionFunction", "EAID_MOVE"),
    ]
    applications = "\n".join(f"\t\t{app}" for app in apps)
    return f"""<?xml version="1.0" encoding="windows-1252"?>
<xmi:XMI xmi:version="2.1" xmlns:uml="http://schema.omg.org/spec/UML/2.1" xmlns:xmi="http://schema.omg.org/spec/XMI/2.1" \
xmlns:thecustomprofile="http://www.sparxsystems.com/profiles/thecustomprofile/1.0" xmlns:EARL="{uri}" \
xmlns:SysML1.4="http://www.sparxsystems.com/profiles/SysML1.4/1.4">
\t<xmi:Documentation exporter="Enterprise Architect" exporterVersion="6.5"/>
\t<uml:Model xmi:type="uml:Model" name="EA_Model" visibility="public">
\t\t<packagedElement xmi:type="uml:Package" xmi:id="EAPK_CELL" name="Cell" visibility="public">
\t\t\t<packagedElement xmi:type="uml:DataType" xmi:id="EAID_POSE" name="Pose" visibility="public"/>
\t\t\t<packagedElement xmi:type="uml:Class" xmi:id="EAID_CELL" name="Cell" visibility="public">
\t\t\t\t<ownedAttribute xmi:type="uml:Property" xmi:id="EAID_CELL_ARM" name="arm" visibility="public" aggregation="composite">
\t\t\t\t\t<type xmi:idref="EAID_ARM"/>
\t\t\t\t</ownedAttribute>
\t\t\t</packagedElement>
\t\t\t<packagedElement xmi:type="uml:Class" xmi:id="EAID_ARM" name="Arm" visibility="public">
\t\t\t\t<ownedAttribute xmi:type="uml:Property" xmi:id="EAID_ARM_CTRL" name="control" visibility="public" aggregation="composite">
\t\t\t\t\t<type xmi:idref="EAID_CTRL"/>
\t\t\t\t</ownedAttribute>
\t\t\t</packagedElement>
\t\t\t<packagedElement xmi:type="uml:Class" xmi:id="EAID_CTRL" name="ArmControl" visibility="public">
\t\t\t\t<ownedPort xmi:type="uml:Port" xmi:id="EAID_CMD" name="command" visibility="public" aggregation="composite" isService="true">
\t\t\t\t\t<type xmi:idref="EAID_POSE"/>
\t\t\t\t</ownedPort>
\t\t\t\t<ownedPort xmi:type="uml:Port" xmi:id="EAID_STATE" name="state" visibility="public" aggregation="composite" isService="true">
\t\t\t\t\t<type xmi:idref="EAID_POSE"/>
\t\t\t\t</ownedPort>
\t\t\t\t<ownedBehavior xmi:type="uml:OpaqueBehavior" xmi:id="EAID_MOVE" name="move" visibility="public" body="// follow the command">
\t\t\t\t\t<ownedParameter xmi:type="uml:Parameter" xmi:id="EAID_MOVE_IN" name="command" visibility="public" direction="in"/>
\t\t\t\t\t<ownedParameter xmi:type="uml:Parameter" xmi:id="EAID_MOVE_OUT" name="state" visibility="public" direction="out"/>
\t\t\t\t</ownedBehavior>
\t\t\t</packagedElement>
\t\t</packagedElement>
\t\t<SysML1.4:block base_Class="EAID_CELL"/>
\t\t<SysML1.4:block base_Class="EAID_ARM"/>
\t\t<SysML1.4:block base_Class="EAID_CTRL"/>
{applications}
\t</uml:Model>
\t<xmi:Extension extender="Enterprise Architect" extenderID="6.5">
\t\t<elements>
\t\t\t<element xmi:idref="EAID_MOVE" xmi:type="uml:OpaqueBehavior" name="move" scope="public">
\t\t\t\t<model package="EAPK_CELL" owner="EAID_CTRL" tpos="0" ea_localid="7" ea_eleType="element"/>
\t\t\t\t<properties isSpecification="false" sType="OpaqueBehavior" nType="0" scope="public" stereotype="{uml.stereotypes["PartialTransitionFunction"].name}"/>
\t\t\t\t<code gentype="C++"/>
\t\t\t</element>
\t\t</elements>
\t</xmi:Extension>
</xmi:XMI>
"""


def test_the_reader_recognises_an_ea_model_applying_the_profile(
    generated: dict[str, tuple[str, bytes]], tmp_path: Path
) -> None:
    """(c) Round trip through the reader: a model applying the generated EA profile, as EA exports
    it, is read with its System, Agent, ControlSubsystem and buffers recognised by stereotype."""
    from earl_m2t import load
    from earl_m2t.export import model_to_dict

    uml = read_profile(generated["ea"][1])
    uri = uml.element.get("URI") or ""
    assert uri == "http://www.sparxsystems.com/profiles/EARL/1.0"
    assert uml.root.nsmap["EARL"] == uri and uml.element.get("nsPrefix") == "EARL"
    assert dialect_table().is_earl(uri)
    comment = uml.element.find("ownedComment/body")
    assert comment is not None and (comment.text or "").startswith("EARL Version:1.0")

    text = _ea_model(uml)
    model = etree.fromstring(text.encode("cp1252"))
    (ea_model,) = [el for el in model if etree.QName(el).localname == "Model"]
    applications = [el for el in ea_model if etree.QName(el).namespace == uri]
    assert len(applications) == 6 and not any(app.get(XMI_ID) for app in applications)
    for application in applications:  # every application is a stereotype of the generated profile
        name = application.get("__EAStereoName") or etree.QName(application).localname
        assert name in uml.stereotypes and not uml.stereotypes[name].abstract
        assert {a for a in application.attrib if a.startswith("base_")} <= set(uml.effective_bases(name))

    path = tmp_path / "cell.xml"
    path.write_bytes(text.encode("cp1252"))
    loaded = load(path)
    document = model_to_dict(loaded.model)
    assert document["dialect"] == "enterprise-architect" and document["model"] == "Cell"
    (system,) = document["systems"]
    assert (system["name"], system["recognised_by"]) == ("Cell", "stereotype")
    (agent,) = system["agents"]
    assert (agent["recognised_by"], agent["declared_type"]) == ("stereotype", "C")
    (control,) = agent["subsystems"]
    assert (control["kind"], control["recognised_by"]) == ("cs", "stereotype")
    assert [b["name"] for b in control["inputs"]] == ["command"]
    assert [b["name"] for b in control["outputs"]] == ["state"]
    (move,) = control["functions"]
    assert (move["name"], move["language"]) == ("move", "C++")  # the element's Language in EA


def test_profile_rejects_unknown_format_in_the_api() -> None:
    with pytest.raises(ProfileExportError, match="unknown profile format"):
        export_profile("rhapsody")
