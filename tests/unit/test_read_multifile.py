"""Models kept in several files: relative hrefs are read, libraries are known by name, and what
cannot be resolved is one R004 warning per resource (or per missing id), never a crash."""

from __future__ import annotations

import zipfile
from pathlib import Path

import pytest

import earl_m2t.read.resources as resources
from earl_m2t import Diagnostic, check, load
from earl_m2t.lift.datatypes import DataTypeLifter
from earl_m2t.read.loader import load_raw_model
from earl_m2t.read.xmi import ExternalRef, RawModel

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
CORPUS = ROOT.parent / "shared" / "corpus"
UML_TYPES = "pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml"
EARL_NS = "http:///schemas/EARL/_profile/1"


def papyrus(body: str, applications: str = "", name: str = "M", *, xmi: str = "http://www.omg.org/spec/XMI/20131001",
            uml: str = "http://www.eclipse.org/uml2/5.0.0/UML") -> str:
    """A Papyrus file: one uml:Model holding ``body``, then the stereotype applications."""
    return (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        f'<xmi:XMI xmi:version="20131001" xmlns:xmi="{xmi}" xmlns:uml="{uml}" xmlns:EARL="{EARL_NS}">\n'
        f'  <uml:Model xmi:id="_model" name="{name}">\n{body}  </uml:Model>\n{applications}</xmi:XMI>\n'
    )


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    return path


def codes(findings: list[Diagnostic], *wanted: str) -> list[str]:
    return [d.code for d in findings if d.code in wanted]


def unresolved(findings: list[Diagnostic]) -> list[Diagnostic]:
    return [d for d in findings if d.code == "R004"]


# -- a model in three files --------------------------------------------------------------------------------
#
#   model/model.uml      the system and the robot; the robot's agents are typed by blocks of agents.uml
#   model/agents.uml     Arm «Agent» (stereotyped there) and Gripper :> EARL-model.uml#_agent, their
#                        subsystems; buffers typed by ../lib/types.uml, memory by a UML primitive type
#   model/EARL-model.uml the EARL Model blocks (package EARL::Model), specialised by Gripper
#   lib/types.uml        the dataTypes, in an older Eclipse UML2 generation (XMI 2.0 namespace)

MODEL = papyrus("""\
    <packageImport xmi:id="_import">
      <importedPackage xmi:type="uml:Package" href="../lib/types.uml#_types"/>
    </packageImport>
    <packagedElement xmi:type="uml:Class" xmi:id="_system" name="CellSystem">
      <ownedAttribute xmi:id="_robotPart" name="cell/r" type="_robot" aggregation="composite"/>
    </packagedElement>
    <packagedElement xmi:type="uml:Class" xmi:id="_robot" name="Cell">
      <ownedAttribute xmi:id="_armPart" name="arm" aggregation="composite">
        <type xmi:type="uml:Class" href="agents.uml#_arm"/>
      </ownedAttribute>
      <ownedAttribute xmi:id="_gripPart" name="grip" aggregation="composite">
        <type xmi:type="uml:Class" href="./agents.uml#_gripper"/>
      </ownedAttribute>
    </packagedElement>
    <packagedElement xmi:type="uml:DataType" xmi:id="_shared" name="Unrelated"/>
    <profileApplication xmi:id="_pa">
      <eAnnotations xmi:id="_ea" source="http://www.eclipse.org/uml2/2.0.0/UML">
        <references href="EARL.profile.uml#_epackage"/>
      </eAnnotations>
      <appliedProfile href="EARL.profile.uml#_profile"/>
    </profileApplication>
""", """\
  <EARL:System xmi:id="_s1" base_Class="_system"/>
  <EARL:Robot xmi:id="_s2" base_Class="_robot"/>
""", "Cell")

AGENTS = papyrus(f"""\
    <packagedElement xmi:type="uml:Class" xmi:id="_arm" name="Arm">
      <ownedAttribute xmi:id="_armCs" name="cs" type="_armControl" aggregation="composite"/>
    </packagedElement>
    <packagedElement xmi:type="uml:Class" xmi:id="_armControl" name="ArmControl">
      <ownedAttribute xmi:type="uml:Port" xmi:id="_goal" name="goal/ib">
        <type xmi:type="uml:DataType" href="../lib/types.uml#_pose"/>
      </ownedAttribute>
      <ownedAttribute xmi:id="_steps" name="steps/m">
        <type xmi:type="uml:PrimitiveType" href="{UML_TYPES}#Integer"/>
      </ownedAttribute>
    </packagedElement>
    <packagedElement xmi:type="uml:Class" xmi:id="_gripper" name="Gripper">
      <generalization xmi:id="_gen">
        <general xmi:type="uml:Class" href="EARL-model.uml#_agent"/>
      </generalization>
      <ownedAttribute xmi:id="_gripCs" name="cs" type="_gripControl" aggregation="composite"/>
    </packagedElement>
    <packagedElement xmi:type="uml:Class" xmi:id="_gripControl" name="GripControl">
      <ownedAttribute xmi:type="uml:Port" xmi:id="_width" name="width/ob">
        <type xmi:type="uml:DataType" href="../lib/types.uml#_shared"/>
      </ownedAttribute>
    </packagedElement>
""", """\
  <EARL:Agent xmi:id="_s3" base_Class="_arm"/>
  <EARL:ControlSubsystem xmi:id="_s4" base_Class="_armControl"/>
""", "Agents")

EARL_MODEL = papyrus("""\
    <packagedElement xmi:type="uml:Package" xmi:id="_earl" name="EARL">
      <packagedElement xmi:type="uml:Package" xmi:id="_earlModel" name="Model">
        <packagedElement xmi:type="uml:Class" xmi:id="_agent" name="Agent"/>
      </packagedElement>
    </packagedElement>
""", name="EARLModel")

TYPES = papyrus(f"""\
    <packagedElement xmi:type="uml:Package" xmi:id="_types" name="DataTypes">
      <packagedElement xmi:type="uml:DataType" xmi:id="_pose" name="Pose">
        <ownedAttribute xmi:id="_x" name="x">
          <type xmi:type="uml:PrimitiveType" href="{UML_TYPES}#Real"/>
        </ownedAttribute>
        <ownedAttribute xmi:id="_frame" name="frame" type="_frameKind"/>
      </packagedElement>
      <packagedElement xmi:type="uml:Enumeration" xmi:id="_frameKind" name="Frame">
        <ownedLiteral xmi:id="_world" name="world"/>
        <ownedLiteral xmi:id="_tool" name="tool"/>
      </packagedElement>
      <packagedElement xmi:type="uml:DataType" xmi:id="_shared" name="Width">
        <ownedAttribute xmi:id="_mm" name="mm" type="_mmType"/>
      </packagedElement>
      <packagedElement xmi:type="uml:PrimitiveType" xmi:id="_mmType" name="Real"/>
    </packagedElement>
""", name="Types", xmi="http://www.omg.org/XMI", uml="http://www.eclipse.org/uml2/3.0.0/UML")


@pytest.fixture
def split(tmp_path: Path) -> Path:
    (tmp_path / ".git").mkdir()  # a repository: model/ may use ../lib/ (files outside it are not read)
    write(tmp_path / "model" / "agents.uml", AGENTS)
    write(tmp_path / "model" / "EARL-model.uml", EARL_MODEL)
    write(tmp_path / "lib" / "types.uml", TYPES)
    return write(tmp_path / "model" / "model.uml", MODEL)


def test_a_model_split_over_several_files_lifts_as_one_model(split: Path) -> None:
    model = load(split).model
    (system,) = model.systems
    assert system.name == "CellSystem"
    assert [r.agents for r in model.robots] == [("arm", "grip")]
    arm = next(a for a in model.agents if a.path == "arm")
    (cs,) = arm.subsystems
    assert [(b.name, b.datatype) for b in cs.buffers] == [("goal/ib", "DataTypes::Pose")]
    assert [(m.name, m.datatype) for m in cs.memory] == [("steps/m", "Integer")]
    pose = model.datatypes["DataTypes::Pose"]
    assert pose.kind == "struct" and [(f.name, f.type) for f in pose.fields] == [
        ("x", "Real"), ("frame", "DataTypes::Frame")]
    assert model.datatypes["DataTypes::Frame"].literals == ("world", "tool")


def test_a_split_model_has_no_unresolved_reference_or_type(split: Path) -> None:
    assert codes(check(split), "R004", "D001") == []


def test_elements_of_a_referenced_file_keep_their_file_and_line(split: Path) -> None:
    model = load(split).model
    types_file = str(split.parent.parent / "lib" / "types.uml")
    agents_file = str(split.parent / "agents.uml")
    assert model.file == str(split) and model.systems[0].location.file == str(split)
    pose = model.datatypes["DataTypes::Pose"]
    assert (pose.location.file, pose.location.line, pose.location.xmi_id) == (types_file, 5, "_pose")
    arm = next(a for a in model.agents if a.path == "arm")
    assert arm.subsystems[0].location.file == agents_file
    assert arm.subsystems[0].buffers[0].location.file == agents_file


def test_a_block_defined_and_stereotyped_in_another_file_is_recognised_by_its_stereotype(split: Path) -> None:
    model = load(split).model
    arm = next(a for a in model.agents if a.path == "arm")
    assert arm.recognised_by == "stereotype"
    assert arm.subsystems[0].kind == "cs" and arm.subsystems[0].recognised_by == "stereotype"


def test_a_generalisation_of_the_earl_model_block_in_another_file_recognises_an_agent(split: Path) -> None:
    model = load(split).model
    grip = next(a for a in model.agents if a.path == "grip")
    assert grip.recognised_by == "generalisation"


def test_references_resolve_among_the_ids_of_the_file_that_holds_them(split: Path) -> None:
    raw = load_raw_model(split)
    width_port = _element(raw, "agents.uml", "_width")
    width = raw.ref(width_port, "type")
    assert not isinstance(width, ExternalRef) and raw.name(width) == "Width"  # not model.uml's _shared
    assert raw.name(raw.by_id["_shared"]) == "Unrelated"
    mm = raw.ref(raw.children(width, "ownedAttribute")[0], "type")
    assert not isinstance(mm, ExternalRef) and raw.uml_type(mm) == "PrimitiveType"  # the XMI 2.0 file's own type
    assert raw.xmi_id(width) == "_shared" and raw.uml_type(width) == "DataType"
    assert raw.location(width).file.endswith(str(Path("lib") / "types.uml"))


def test_two_files_that_reference_each_other_are_read_once_each(tmp_path: Path,
                                                               monkeypatch: pytest.MonkeyPatch) -> None:
    a = write(tmp_path / "a.uml", papyrus("""\
    <packagedElement xmi:type="uml:Class" xmi:id="_a" name="A">
      <ownedAttribute xmi:id="_toB" name="b"><type xmi:type="uml:Class" href="b.uml#_b"/></ownedAttribute>
    </packagedElement>
    <packagedElement xmi:type="uml:DataType" xmi:id="_vec" name="Vector"/>
"""))
    write(tmp_path / "b.uml", papyrus(f"""\
    <packagedElement xmi:type="uml:Class" xmi:id="_b" name="B">
      <ownedAttribute xmi:id="_toA" name="a"><type xmi:type="uml:Class" href="a.uml#_a"/></ownedAttribute>
      <ownedAttribute xmi:id="_v" name="v"><type xmi:type="uml:DataType" href="./a.uml#_vec"/></ownedAttribute>
      <ownedAttribute xmi:id="_w" name="w">
        <type xmi:type="uml:DataType" href="../{tmp_path.name}/b.uml#_b"/>
      </ownedAttribute>
    </packagedElement>
"""))
    reads: list[str] = []
    original = resources.read_raw_model

    def counting(path: Path, dialect: str | None = None) -> RawModel:
        reads.append(path.name)
        return original(path, dialect)

    monkeypatch.setattr(resources, "read_raw_model", counting)
    raw = load_raw_model(a)
    assert reads == ["b.uml"]  # a.uml is the model itself; b.uml once, however it is spelled
    b = raw.ref(raw.by_id["_toB"], "type")
    assert not isinstance(b, ExternalRef)
    to_a, to_vec, to_b = (raw.ref(p, "type") for p in raw.children(b, "ownedAttribute"))
    assert to_a is raw.by_id["_a"] and to_vec is raw.by_id["_vec"] and to_b is b
    assert unresolved(raw.diagnostics) == []


def test_a_missing_file_gives_one_r004_naming_the_uri_the_referring_element_and_the_count(tmp_path: Path) -> None:
    path = write(tmp_path / "model.uml", papyrus(f"""\
    <packagedElement xmi:type="uml:DataType" xmi:id="_pose" name="Pose">
      <ownedAttribute xmi:id="_x" name="x"><type xmi:type="uml:DataType" href="units.uml#_meter"/></ownedAttribute>
      <ownedAttribute xmi:id="_y" name="y"><type xmi:type="uml:DataType" href="units.uml#_meter"/></ownedAttribute>
      <ownedAttribute xmi:id="_z" name="z"><type xmi:type="uml:DataType" href="units.uml#_second"/></ownedAttribute>
      <ownedAttribute xmi:id="_t" name="t"><type href="{UML_TYPES}#Real"/></ownedAttribute>
    </packagedElement>
"""))
    raw = load_raw_model(path)
    (finding,) = unresolved(raw.diagnostics)
    assert finding.severity.value == "warning"
    assert (finding.location.file, finding.location.line, finding.location.xmi_id) == (str(path), 5, "_x")
    assert finding.message == (f"unresolved reference units.uml#_meter (type of Property 'x'): cannot read "
                               f"{tmp_path / 'units.uml'}: no such file (3 references to this resource)")
    assert finding.element == "x"
    assert [(f.name, f.type, f.type_ref) for f in _fields(raw)] == [
        ("x", "", "units.uml#_meter"), ("y", "", "units.uml#_meter"), ("z", "", "units.uml#_second"),
        ("t", "Real", "")]


def test_types_from_a_missing_file_are_d001_each_and_the_file_one_r004(split: Path) -> None:
    (split.parent.parent / "lib" / "types.uml").unlink()
    findings = [d for d in check(split) if d.code in ("R004", "D001")]
    assert [(d.code, Path(d.location.file).name, d.location.line) for d in findings] == [
        ("D001", "agents.uml", 8), ("D001", "agents.uml", 22), ("R004", "model.uml", 5)]
    assert [d.element for d in findings[:2]] == ["arm.cs.goal/ib", "grip.cs.width/ob"]
    assert "'../lib/types.uml#_pose'" in findings[0].message
    r004 = findings[2]  # at the first reference, the import, counting those of agents.uml too
    assert r004.message == (f"unresolved reference ../lib/types.uml#_types (importedPackage of PackageImport "
                            f"'_import'): cannot read {split.parent.parent / 'lib' / 'types.uml'}: no such file "
                            "(3 references to this resource)")


def test_an_id_that_a_referenced_file_does_not_hold_gives_one_r004_per_href(split: Path) -> None:
    agents = split.parent / "agents.uml"
    agents.write_text(AGENTS.replace("types.uml#_pose", "types.uml#_gone"), encoding="utf-8")
    model = split.read_text(encoding="utf-8").replace("agents.uml#_gripper", "agents.uml#_gone")
    split.write_text(model, encoding="utf-8")
    found = unresolved(check(split))
    assert [(Path(d.location.file).name, d.location.xmi_id) for d in found] == [
        ("agents.uml", "_goal"), ("model.uml", "_gripPart")]
    assert found[0].message.endswith(f"{Path('lib') / 'types.uml'} has no element with xmi:id '_gone'")
    assert "./agents.uml#_gone (type of Property 'grip')" in found[1].message


@pytest.mark.parametrize(("content", "reason"), [
    ('<?xml version="1.0"?>\n<xmi:XMI xmlns:xmi="http://www.omg.org/spec/XMI/20131001">\n  <broken\n',
     "not well-formed XML"),
    ("<notes>no model here</notes>", "not an XMI file"),
    ('<?xml version="1.0"?>\n<!DOCTYPE x [<!ENTITY e "boom">]>\n<x>&e;</x>', "document type declarations"),
    ("", "not well-formed XML"),
])
def test_a_malformed_referenced_file_gives_r004_with_the_reason_not_a_crash(tmp_path: Path, content: str,
                                                                            reason: str) -> None:
    write(tmp_path / "types.uml", content)
    path = write(tmp_path / "model.uml", papyrus("""\
    <packagedElement xmi:type="uml:DataType" xmi:id="_pose" name="Pose">
      <ownedAttribute xmi:id="_x" name="x"><type xmi:type="uml:DataType" href="types.uml#_meter"/></ownedAttribute>
    </packagedElement>
"""))
    (finding,) = unresolved(load_raw_model(path).diagnostics)
    assert f"cannot read {tmp_path / 'types.uml'}: {reason}" in finding.message
    assert finding.location.line == 5


def test_a_referenced_directory_gives_r004(tmp_path: Path) -> None:
    (tmp_path / "types.uml").mkdir()
    path = write(tmp_path / "model.uml", papyrus("""\
    <packagedElement xmi:type="uml:Class" xmi:id="_c" name="C">
      <generalization xmi:id="_g"><general href="types.uml#_base"/></generalization>
    </packagedElement>
"""))
    (finding,) = unresolved(load_raw_model(path).diagnostics)
    assert "(general of Generalization '_g')" in finding.message and "is a directory" in finding.message


@pytest.mark.parametrize("href", [
    f"{UML_TYPES}#Real",
    "pathmap://UML_LIBRARIES/EcorePrimitiveTypes.library.uml#EDouble",
    "pathmap://UML_LIBRARIES/JavaPrimitiveTypes.library.uml#double",
    "pathmap://SysML16_LIBRARIES/SysML-Standard-Library.uml#SysML.package_packagedElement_Libraries."
    "package_packagedElement_PrimitiveValueTypes.dataType_packagedElement_Real",
    "pathmap://SysML14_LIBRARIES/SysML-Standard-Library.uml#SysML.package_packagedElement_Libraries."
    "package_packagedElement_PrimitiveValueTypes.dataType_packagedElement_Real",
    "http://www.omg.org/spec/UML/20131001/PrimitiveTypes.xmi#Real",
    "https://www.omg.org/spec/UML/20161101/PrimitiveTypes.xmi#Real",
    "http://www.omg.org/spec/SysML/20181001/SysML.xmi#SysML_dataType.Real",
    "http://www.omg.org/spec/SysML/20150709/SysML.xmi#_SysML_Libraries_PackageableElement-PrimitiveValueTypes_"
    "PackageableElement-Real_PackageableElement",
    "http://www.eclipse.org/emf/2002/Ecore#//EDouble",
    "#EAJava_double",
])
def test_a_library_type_resolves_by_name_and_is_no_finding(tmp_path: Path, href: str) -> None:
    path = write(tmp_path / "model.uml", papyrus(f"""\
    <packagedElement xmi:type="uml:DataType" xmi:id="_pose" name="Pose">
      <ownedAttribute xmi:id="_x" name="x"><type href="{href}"/></ownedAttribute>
    </packagedElement>
"""))
    raw = load_raw_model(path)
    assert unresolved(raw.diagnostics) == []
    (field,) = _fields(raw)
    assert (field.type, field.type_ref) == ("Real", "")


def test_a_known_library_element_that_is_no_primitive_type_is_d001_not_r004(tmp_path: Path) -> None:
    path = write(tmp_path / "model.uml", papyrus("""\
    <packagedElement xmi:type="uml:DataType" xmi:id="_pose" name="Pose">
      <ownedAttribute xmi:id="_c" name="c"><type href="pathmap://SysML16_LIBRARIES/SysML-Standard-Library.uml#SysML.\
package_packagedElement_Libraries.package_packagedElement_PrimitiveValueTypes.dataType_packagedElement_Complex"/>
      </ownedAttribute>
    </packagedElement>
"""))
    raw = load_raw_model(path)
    assert unresolved(raw.diagnostics) == []
    (field,) = _fields(raw)
    assert field.type == "" and field.type_ref.endswith("dataType_packagedElement_Complex")


ECLIPSE = "is a file of an Eclipse workspace or plug-in, which is never opened"


@pytest.mark.parametrize(("href", "reason"), [
    ("pathmap://ROBOT_LIBRARIES/Units.library.uml#Real", "is a pathmap earl-m2t does not know"),
    ("platform:/resource/Robot/types.uml#_pose", ECLIPSE),
    ("platform:/plugin/org.robot/types.uml#_pose", ECLIPSE),
    ("http://example.org/robot/types.uml#_pose", "is a URL, which is never fetched"),
    ("file:///opt/robot/types.uml#_pose", "is a file: URI, which is never opened"),
])
def test_uris_that_are_never_opened_give_r004(tmp_path: Path, href: str, reason: str) -> None:
    path = write(tmp_path / "model.uml", papyrus(f"""\
    <packagedElement xmi:type="uml:DataType" xmi:id="_pose" name="Pose">
      <ownedAttribute xmi:id="_x" name="x"><type href="{href}"/></ownedAttribute>
      <ownedAttribute xmi:id="_y" name="y"><type href="{href}"/></ownedAttribute>
    </packagedElement>
"""))
    raw = load_raw_model(path)
    (finding,) = unresolved(raw.diagnostics)
    resource = href.partition("#")[0]
    assert finding.message.startswith(f"unresolved reference {href} (type of Property 'x'): {resource} {reason}")
    assert finding.message.endswith("(2 references to this resource)")
    assert [f.type for f in _fields(raw)] == ["", ""]  # not by name: D001 where it matters


def test_a_platform_resource_is_not_opened_even_where_a_file_of_that_path_exists(tmp_path: Path) -> None:
    write(tmp_path / "resource" / "Robot" / "types.uml", TYPES)
    write(tmp_path / "Robot" / "types.uml", TYPES)
    path = write(tmp_path / "model.uml", papyrus("""\
    <packagedElement xmi:type="uml:DataType" xmi:id="_p" name="P">
      <ownedAttribute xmi:id="_x" name="x"><type href="platform:/resource/Robot/types.uml#_pose"/></ownedAttribute>
    </packagedElement>
"""))
    raw = load_raw_model(path)
    assert len(unresolved(raw.diagnostics)) == 1
    assert isinstance(raw.ref(raw.by_id["_x"], "type"), ExternalRef)


def test_an_absolute_path_is_never_opened(split: Path) -> None:
    absolute = (split.parent.parent / "lib" / "types.uml").resolve().as_posix()
    path = write(split.parent / "absolute.uml", papyrus(f"""\
    <packagedElement xmi:type="uml:DataType" xmi:id="_p" name="P">
      <ownedAttribute xmi:id="_x" name="x"><type href="{absolute}#_pose"/></ownedAttribute>
    </packagedElement>
"""))
    raw = load_raw_model(path)
    (finding,) = unresolved(raw.diagnostics)
    assert "is an absolute path, which is never opened" in finding.message
    assert isinstance(raw.ref(raw.by_id["_x"], "type"), ExternalRef)


def test_profile_applications_and_annotations_are_not_followed(tmp_path: Path) -> None:
    path = write(tmp_path / "model.uml", papyrus("""\
    <packagedElement xmi:type="uml:Class" xmi:id="_c" name="C"/>
    <profileApplication xmi:id="_pa">
      <eAnnotations xmi:id="_ea" source="http://www.eclipse.org/uml2/2.0.0/UML">
        <references href="missing/EARL.profile.uml#_epackage"/>
      </eAnnotations>
      <appliedProfile href="missing/EARL.profile.uml#_profile"/>
    </profileApplication>
""", '  <EARL:Agent xmi:id="_s" base_Class="_c"/>\n'))
    raw = load_raw_model(path)
    assert unresolved(raw.diagnostics) == []
    assert [a.family for a in raw.applied(raw.by_id["_c"])] == ["earl"]


def test_a_used_project_beside_a_magicdraw_model_is_read_from_its_archive(tmp_path: Path) -> None:
    header = ("<?xml version='1.0' encoding='UTF-8'?>\n<xmi:XMI xmlns:uml='http://www.omg.org/spec/UML/20131001' "
              "xmlns:xmi='http://www.omg.org/spec/XMI/20131001'>\n<xmi:Documentation><xmi:exporter>MagicDraw UML"
              "</xmi:exporter></xmi:Documentation>\n")
    library = header + """<uml:Model xmi:type='uml:Model' xmi:id='_lib' name='Units'>
<packagedElement xmi:type='uml:DataType' xmi:id='_19_0_meter' name='Meter'/>
</uml:Model>
</xmi:XMI>
"""
    with zipfile.ZipFile(tmp_path / "Robot Units.mdzip", "w") as archive:
        archive.writestr("com.nomagic.magicdraw.uml_model.model", library)
    path = write(tmp_path / "model.xmi", header + """<uml:Model xmi:type='uml:Model' xmi:id='_m' name='Cell'>
<packagedElement xmi:type='uml:DataType' xmi:id='_pose' name='Pose'>
<ownedAttribute xmi:type='uml:Property' xmi:id='_x' name='x'><type href='Robot%20Units.mdzip#_19_0_meter'/>
</ownedAttribute>
<ownedAttribute xmi:type='uml:Property' xmi:id='_y' name='y'><type href='Sensors.mdzip#_19_0_tick'/></ownedAttribute>
</packagedElement>
</uml:Model>
</xmi:XMI>
""")
    raw = load_raw_model(path)
    meter = raw.ref(raw.by_id["_x"], "type")
    assert not isinstance(meter, ExternalRef) and raw.name(meter) == "Meter"
    assert raw.location(meter).file == f"{tmp_path / 'Robot Units.mdzip'}!com.nomagic.magicdraw.uml_model.model"
    (finding,) = unresolved(raw.diagnostics)
    assert "Sensors.mdzip#_19_0_tick" in finding.message and "no such file" in finding.message
    assert "a used project is read from beside the model only" in finding.message


def test_the_reference_sample_has_no_unresolved_reference() -> None:
    assert unresolved(load_raw_model(SAMPLE).diagnostics) == []


@pytest.mark.skipif(not CORPUS.is_dir(), reason="shared corpus not beside the checkout")
def test_the_platform_resource_import_of_the_arrowhead_corpus_model_is_r004() -> None:
    path = CORPUS / "papyrus" / "arrowhead-principles-sysml16.uml"
    (finding,) = unresolved(check(path))
    assert (finding.location.file, finding.location.line) == (str(path), 11)
    assert finding.message.startswith(
        "unresolved reference platform:/resource/EclipseArrowhead/EclipseArrowhead_v6.uml#_GJjFMDdfEe6h28lXN9kaaA "
        "(importedPackage of PackageImport '_YUyBQH_GEe6Xb_ifwf_2_Q'): platform:/resource/EclipseArrowhead/"
        "EclipseArrowhead_v6.uml is a file of an Eclipse workspace or plug-in, which is never opened")
    assert finding.message.endswith("(7 references to this resource)")


def _fields(raw: RawModel) -> tuple:
    """The fields of the dataType Pose, lifted."""
    types = DataTypeLifter(raw)
    return types.datatypes[types.lift(raw.by_id["_pose"])].fields


def _element(raw: RawModel, file: str, xmi_id: str):
    """An element of a referenced file, found through the references that lead to it."""
    for el in raw.root.iter():
        for feature in ("type", "general", "importedPackage"):
            for target in raw.refs(el, feature) if isinstance(el.tag, str) else ():
                if not isinstance(target, ExternalRef) and raw.file_of(target).endswith(file):
                    found = target.getroottree().getroot().xpath(f"//*[@*[local-name()='id']='{xmi_id}']")
                    if found:
                        return found[0]
    raise AssertionError(f"{xmi_id} of {file} not reached")


def test_the_json_of_show_names_the_file_of_elements_read_from_another_file(split: Path) -> None:
    from earl_m2t.export import model_to_dict

    data = model_to_dict(load(split).model)

    def located(node: object) -> list[dict]:
        if isinstance(node, dict):
            return ([node] if "xmi_id" in node else []) + [d for v in node.values() for d in located(v)]
        return [d for v in node for d in located(v)] if isinstance(node, list) else []

    files = {d["xmi_id"]: d.get("file") for d in located(data)}
    assert files["_system"] is None and files["_armPart"] is None  # the model file's own: no key
    assert files["_pose"] == str(split.parent.parent / "lib" / "types.uml")
    assert files["_armCs"] == files["_goal"] == str(split.parent / "agents.uml")


def test_a_referenced_file_of_an_unknown_tool_is_read_as_the_dialect_named_for_the_model(tmp_path: Path) -> None:
    omg = ('<?xml version="1.0"?>\n<xmi:XMI xmlns:xmi="http://www.omg.org/spec/XMI/20131001" '
           'xmlns:uml="http://www.omg.org/spec/UML/20131001">\n')
    write(tmp_path / "types.xmi", omg + """<uml:Model xmi:type="uml:Model" xmi:id="_t" name="Types">
<packagedElement xmi:type="uml:DataType" xmi:id="_meter" name="Meter"/>
</uml:Model>
</xmi:XMI>
""")
    path = write(tmp_path / "model.xmi", omg + """<uml:Model xmi:type="uml:Model" xmi:id="_m" name="M">
<packagedElement xmi:type="uml:DataType" xmi:id="_pose" name="Pose">
<ownedAttribute xmi:type="uml:Property" xmi:id="_x" name="x"><type href="types.xmi#_meter"/></ownedAttribute>
</packagedElement>
</uml:Model>
</xmi:XMI>
""")
    raw = load_raw_model(path, "cameo-clean")
    assert unresolved(raw.diagnostics) == []
    meter = raw.ref(raw.by_id["_x"], "type")
    assert not isinstance(meter, ExternalRef) and raw.name(meter) == "Meter"
    main = write(tmp_path / "main.uml", papyrus("""\
    <packagedElement xmi:type="uml:DataType" xmi:id="_pose" name="Pose">
      <ownedAttribute xmi:id="_x" name="x"><type href="types.xmi#_meter"/></ownedAttribute>
    </packagedElement>
"""))
    (finding,) = unresolved(load_raw_model(main).diagnostics)  # detected, and no dialect named
    assert "XMI with OMG UML namespaces from an unknown tool is not supported" in finding.message


def test_a_datatype_of_another_file_with_a_name_already_used_is_qualified_by_its_model(split: Path) -> None:
    model_text = split.read_text(encoding="utf-8").replace(
        '<packagedElement xmi:type="uml:DataType" xmi:id="_shared" name="Unrelated"/>',
        '<packagedElement xmi:type="uml:Package" xmi:id="_own" name="DataTypes">'
        '<packagedElement xmi:type="uml:DataType" xmi:id="_ownPose" name="Pose"/></packagedElement>')
    split.write_text(model_text, encoding="utf-8")
    raw = load_raw_model(split)
    types = DataTypeLifter(raw)
    own = types.lift(raw.by_id["_ownPose"])
    other = types.type_of(_element(raw, "agents.uml", "_goal"))[0]
    assert (own, other) == ("DataTypes::Pose", "Types::DataTypes::Pose")
    assert types.datatypes[other].location.file.endswith("types.uml")
