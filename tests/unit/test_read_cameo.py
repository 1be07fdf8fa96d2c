"""Reading Cameo / MagicDraw XMI: native files, Clean XMI, the Eclipse UML2 export and .mdzip projects."""

from __future__ import annotations

import json
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from earl_m2t.diagnostics import ModelReadError
from earl_m2t.lift import lift
from earl_m2t.lift.recognise import Recogniser
from earl_m2t.profile import load_profile
from earl_m2t.read import mdzip
from earl_m2t.read.loader import load_raw_model
from earl_m2t.read.xmi import ExternalRef, RawModel

ROOT = Path(__file__).resolve().parents[2]
MODEL_MEMBER = "com.nomagic.magicdraw.uml_model.model"
SHARED_MEMBER = "com.nomagic.magicdraw.uml_model.shared_model"

# MagicDraw native XMI: single quotes, tabs, no xmi:version, stereotype applications at the
# root after the root-level xmi:Extension, application ids derived from the base id.
CAMEO = """<?xml version='1.0' encoding='UTF-8'?>
<xmi:XMI xmlns:uml='http://www.omg.org/spec/UML/20131001' xmlns:xmi='http://www.omg.org/spec/XMI/20131001' \
xmlns:sysml='http://www.omg.org/spec/SysML/20181001/SysML' \
xmlns:MD_Customization_for_SysML__additional_stereotypes='http://www.magicdraw.com/spec/Customization/180/SysML' \
xmlns:EARL='http://www.magicdraw.com/schemas/EARL.xmi' xmlns:Other='http://example.org/not-earl'>
	<xmi:Documentation>
		<xmi:exporter>MagicDraw UML</xmi:exporter>
		<xmi:exporterVersion>2022x v7</xmi:exporterVersion>
	</xmi:Documentation>
	<xmi:Extension extender='MagicDraw UML 2022x'>
		<plugin pluginName='SysML' pluginVersion='2022x'/>
		<copy xmi:id='_c1'/>
	</xmi:Extension>
	<uml:Model xmi:type='uml:Model' xmi:id='eee_1045467100313_135436_1' name='Model'>
		<ownedComment xmi:type='uml:Comment' xmi:id='_note' body='first&#10;second'>
			<annotatedElement xmi:idref='_c1'/>
		</ownedComment>
		<packagedElement xmi:type='uml:Class' xmi:id='_c1' name='Manipulator'>
			<xmi:Extension extender='MagicDraw UML 2022x'>
				<modelExtension><lowerValue xmi:type='uml:LiteralInteger' xmi:id='_p1' value='1'/></modelExtension>
			</xmi:Extension>
			<ownedAttribute xmi:type='uml:Property' xmi:id='_p1' name='cs' aggregation='composite' type='_c2' association='_as'/>
			<ownedAttribute xmi:type='uml:Property' xmi:id='_p2' name='flag'>
				<type href='UML_Standard_Profile.mdzip#eee_1045467100323_917313_65'>
					<xmi:Extension extender='MagicDraw UML 2022x'>
						<referenceExtension referentPath='UML Standard Profile::MagicDraw Profile::datatypes::boolean' referentType='DataType'/>
					</xmi:Extension>
				</type>
			</ownedAttribute>
			<ownedRule xmi:type='uml:Constraint' xmi:id='_r1' name='tc'>
				<constrainedElement xmi:idref='_c1'/>
				<specification xmi:type='uml:OpaqueExpression' xmi:id='_x1'>
					<body>a/pp ∧ b/pp</body>
					<body>a &amp;&amp; b</body>
					<language>EARL</language>
					<language>C</language>
				</specification>
			</ownedRule>
		</packagedElement>
		<packagedElement xmi:type='uml:Class' xmi:id='_c2' name='Control'/>
		<packagedElement xmi:type='uml:Class' xmi:id='_c3' name='Impostor'/>
		<packagedElement xmi:type='uml:Association' xmi:id='_as'>
			<memberEnd xmi:idref='_p1'/>
			<memberEnd xmi:idref='_e1'/>
			<ownedEnd xmi:type='uml:Property' xmi:id='_e1' type='_c1' association='_as'/>
		</packagedElement>
	</uml:Model>
	<xmi:Extension extender='MagicDraw UML 2022x'>
		<stereotypesHREFS><stereotype name='EARL:Agent' stereotypeHREF='EARL.mdzip#_st'/></stereotypesHREFS>
	</xmi:Extension>
	<sysml:Block xmi:id='_c1_application' base_Class='_c1'/>
	<EARL:Agent xmi:id='_c1application1' base_Class='_c1' declaredType='CE'/>
	<sysml:Block xmi:id='_c2_application' base_Class='_c2'/>
	<EARL:ControlSubsystem xmi:id='_c2application1' base_Class='_c2'/>
	<Other:Agent xmi:id='_c3_application' base_Class='_c3'/>
	<MD_Customization_for_SysML__additional_stereotypes:PartProperty xmi:id='_p1_application' base_Property='_p1'/>
</xmi:XMI>
"""


def write(tmp_path: Path, text: str, name: str = "model.xmi") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture
def raw(tmp_path: Path) -> RawModel:
    return load_raw_model(write(tmp_path, CAMEO))


def earl(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "earl_m2t", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=120)


# -- native XMI ------------------------------------------------------------------------------------

def test_a_magicdraw_export_with_single_quotes_is_read_as_the_cameo_dialect(raw: RawModel) -> None:
    assert raw.dialect == "cameo"
    assert raw.by_id["_c1"].get("name") == "Manipulator"


def test_root_level_and_nested_extensions_are_skipped_and_their_repeated_ids_ignored(raw: RawModel) -> None:
    assert raw.diagnostics == []
    assert raw.by_id["_p1"].get("name") == "cs"  # not the modelExtension's lowerValue copy
    assert raw.by_id["_c1"].tag == "packagedElement"  # not the root extension's copy


def test_child_idrefs_resolve_like_attributes(raw: RawModel) -> None:
    assert raw.refs(raw.by_id["_as"], "memberEnd") == [raw.by_id["_p1"], raw.by_id["_e1"]]
    assert raw.refs(raw.by_id["_note"], "annotatedElement") == [raw.by_id["_c1"]]
    assert raw.refs(raw.by_id["_r1"], "constrainedElement") == [raw.by_id["_c1"]]


def test_bodies_written_before_their_languages_are_paired_in_order(raw: RawModel) -> None:
    spec = raw.by_id["_x1"]
    assert raw.opaque_bodies(spec) == [("EARL", "a/pp ∧ b/pp"), ("C", "a && b")]
    assert raw.body_location(spec).line == spec[0].sourceline


def test_stereotypes_at_the_root_are_indexed_by_their_base_not_by_their_application_ids(raw: RawModel) -> None:
    names = sorted(app.name for app in raw.applied(raw.by_id["_c1"]))
    assert names == ["Agent", "Block"]
    assert not any(key.endswith(("_application", "application1")) for key in raw.stereotypes)
    assert "_c1_application" not in raw.by_id and "_c1application1" not in raw.by_id
    (part,) = raw.applied(raw.by_id["_p1"])
    assert part.name == "PartProperty" and part.family == "other"  # MagicDraw customization: a hint only


def test_an_earl_block_in_the_magicdraw_namespace_is_recognised_as_an_agent(raw: RawModel) -> None:
    recogniser = Recogniser(raw, load_profile())
    agent = recogniser.recognise(raw.by_id["_c1"])
    assert (agent.concept, agent.route) == ("Agent", "stereotype")
    assert recogniser.tags(raw.by_id["_c1"]) == {"declaredType": "CE"}
    assert recogniser.recognise(raw.by_id["_c2"]).concept == "ControlSubsystem"


def test_stereotypes_are_recognised_by_namespace_uri_never_by_prefix(tmp_path: Path) -> None:
    # the EARL profile under another prefix is still EARL; another profile's "Agent" is not
    swapped = CAMEO.replace("xmlns:EARL=", "xmlns:Earl2=").replace("<EARL:", "<Earl2:")
    raw = load_raw_model(write(tmp_path, swapped))
    recogniser = Recogniser(raw, load_profile())
    assert recogniser.recognise(raw.by_id["_c1"]).concept == "Agent"
    assert recogniser.recognise(raw.by_id["_c3"]).concept == ""


def test_a_magicdraw_datatype_known_only_by_its_referent_path_is_a_primitive(raw: RawModel) -> None:
    ref = raw.ref(raw.by_id["_p2"], "type")
    assert isinstance(ref, ExternalRef) and ref.name == "boolean"
    assert ref.path == "UML Standard Profile::MagicDraw Profile::datatypes::boolean"
    from earl_m2t.lift.datatypes import DataTypeLifter

    assert DataTypeLifter(raw).type_of(raw.by_id["_p2"]) == ("Boolean", "")


# -- the EARL profile under a URI of its own ---------------------------------------------------------

OWN_URI = "http://example.org/robotics/EARL"


def _with_profile(profile_xml: str, application_xml: str) -> str:
    return (
        CAMEO.replace("xmlns:EARL='http://www.magicdraw.com/schemas/EARL.xmi'", f"xmlns:EARL='{OWN_URI}'")
        .replace("\t</uml:Model>", profile_xml + application_xml + "\t</uml:Model>")
    )


def test_a_profile_named_earl_applied_from_another_project_gives_its_uri(tmp_path: Path) -> None:
    application = f"""		<profileApplication xmi:type='uml:ProfileApplication' xmi:id='_pa'>
			<appliedProfile href='{OWN_URI}.xmi#_prof'>
				<xmi:Extension extender='MagicDraw UML 2022x'>
					<referenceExtension referentPath='EARL' referentType='Profile'/>
				</xmi:Extension>
			</appliedProfile>
		</profileApplication>
"""
    raw = load_raw_model(write(tmp_path, _with_profile("", application)))
    assert OWN_URI in raw.earl_uris
    assert Recogniser(raw, load_profile()).recognise(raw.by_id["_c1"]).concept == "Agent"


def test_a_profile_named_earl_defined_in_the_project_gives_its_uri(tmp_path: Path) -> None:
    profile = f"""		<packagedElement xmi:type='uml:Profile' xmi:id='_prof' name='EARL' URI='{OWN_URI}'>
			<packagedElement xmi:type='uml:Stereotype' xmi:id='_st' name='Agent'/>
		</packagedElement>
"""
    application = """		<profileApplication xmi:type='uml:ProfileApplication' xmi:id='_pa'>
			<appliedProfile xmi:idref='_prof'/>
		</profileApplication>
"""
    raw = load_raw_model(write(tmp_path, _with_profile(profile, application)))
    assert OWN_URI in raw.earl_uris
    assert Recogniser(raw, load_profile()).recognise(raw.by_id["_c1"]).concept == "Agent"


def test_a_profile_with_another_name_does_not_make_its_stereotypes_earl(tmp_path: Path) -> None:
    profile = f"""		<packagedElement xmi:type='uml:Profile' xmi:id='_prof' name='Robotics' URI='{OWN_URI}'/>
"""
    raw = load_raw_model(write(tmp_path, _with_profile(profile, "")))
    assert raw.earl_uris == frozenset()
    assert Recogniser(raw, load_profile()).recognise(raw.by_id["_c1"]).concept == ""


def test_an_earl_model_block_in_a_used_project_is_found_by_its_referent_path(tmp_path: Path) -> None:
    specialised = """<packagedElement xmi:type='uml:Class' xmi:id='_c3' name='Impostor'>
			<generalization xmi:type='uml:Generalization' xmi:id='_g1'>
				<general href='EARL.mdzip#_2022x_ea10352_1727351790000_900003_1'>
					<xmi:Extension extender='MagicDraw UML 2022x'>
						<referenceExtension referentPath='EARL::Model::Agent' referentType='Class'/>
					</xmi:Extension>
				</general>
			</generalization>
		</packagedElement>"""
    text = CAMEO.replace("<packagedElement xmi:type='uml:Class' xmi:id='_c3' name='Impostor'/>", specialised)
    raw = load_raw_model(write(tmp_path, text))
    found = Recogniser(raw, load_profile()).recognise(raw.by_id["_c3"])
    assert (found.concept, found.route) == ("Agent", "generalisation")
    elsewhere = text.replace("EARL::Model::Agent", "Vendor::Parts::Agent")
    raw = load_raw_model(write(tmp_path, elsewhere, "other.xmi"))
    assert Recogniser(raw, load_profile()).recognise(raw.by_id["_c3"]).concept == ""


# -- other Cameo exports and other generations ----------------------------------------------------------

CLEAN = """<?xml version="1.0" encoding="UTF-8"?>
<xmi:XMI xmlns:xmi="http://www.omg.org/spec/XMI/20131001" xmlns:uml="http://www.omg.org/spec/UML/20131001"
         xmlns:sysml="http://www.omg.org/spec/SysML/20150709/SysML">
  <xmi:documentation xmi:type="xmi:Documentation">
    <xmi:exporter>MagicDraw Clean XMI Exporter</xmi:exporter><xmi:exporterVersion>19.0 v9</xmi:exporterVersion>
  </xmi:documentation>
  <uml:Model xmi:type="uml:Model" xmi:id="eee_1045467100313_135436_1" name="Model">
    <packagedElement xmi:type="uml:Class" xmi:id="_c1" name="B"/>
  </uml:Model>
  <sysml:Block xmi:id="_c1_application" base_Class="_c1"/>
</xmi:XMI>
"""

ECLIPSE_EXPORT = """<?xml version="1.0" encoding="UTF-8"?>
<xmi:XMI xmi:version="20131001" xmlns:xmi="http://www.omg.org/spec/XMI/20131001"
    xmlns:SysML.Blocks="http:///SysML/Blocks.ecore" xmlns:uml="http://www.eclipse.org/uml2/5.0.0/UML">
  <uml:Model xmi:id="eee_1045467100313_135436_1" name="Model">
    <packagedElement xmi:type="uml:Class" xmi:id="_19_0_4_2b4a0c1_1611929941338_712674_1" name="A">
      <ownedAttribute xmi:id="_19_0_4_2b4a0c1_1611929941338_712674_2" name="p"/>
      <ownedConnector xmi:id="_19_0_4_2b4a0c1_1611929941338_712674_3" name="k">
        <end xmi:id="_19_0_4_2b4a0c1_1611929941338_712674_4" role="_19_0_4_2b4a0c1_1611929941338_712674_2"/>
      </ownedConnector>
    </packagedElement>
    <packagedElement xmi:type="uml:Activity" xmi:id="_19_0_4_2b4a0c1_1611929941338_712674_5" name="act">
      <node xmi:type="uml:CallBehaviorAction" xmi:id="_19_0_4_2b4a0c1_1611929941338_712674_6" name="call">
        <argument xmi:id="_19_0_4_2b4a0c1_1611929941338_712674_7" name="in"/>
        <result xmi:id="_19_0_4_2b4a0c1_1611929941338_712674_8" name="out"/>
      </node>
    </packagedElement>
  </uml:Model>
  <SysML.Blocks:Block xmi:id="_blk" base_Class="_19_0_4_2b4a0c1_1611929941338_712674_1"/>
</xmi:XMI>
"""


def test_the_magicdraw_clean_xmi_export_is_its_own_dialect(tmp_path: Path) -> None:
    raw = load_raw_model(write(tmp_path, CLEAN))
    assert raw.dialect == "cameo-clean"
    assert raw.has_sysml(raw.by_id["_c1"], "Block")


def test_the_eclipse_uml2_export_of_cameo_is_told_from_papyrus_and_its_missing_types_filled_in(
    tmp_path: Path,
) -> None:
    raw = load_raw_model(write(tmp_path, ECLIPSE_EXPORT))
    assert raw.dialect == "cameo-eclipse-uml2"
    ids = {raw.name(el): el for el in raw.by_id.values()}
    assert raw.uml_type(ids["p"]) == "Property" and raw.uml_type(ids["k"]) == "Connector"
    assert raw.uml_type(ids["in"]) == "InputPin" and raw.uml_type(ids["out"]) == "OutputPin"
    assert raw.has_sysml(ids["A"], "Block")  # http:///SysML/Blocks.ecore is SysML


def test_the_eclipse_uml2_export_is_recognised_by_magicdraw_ids_alone(tmp_path: Path) -> None:
    text = ECLIPSE_EXPORT.replace('xmlns:SysML.Blocks="http:///SysML/Blocks.ecore"', 'xmlns:B="http://example.org/b"')
    text = text.replace("SysML.Blocks:Block", "B:Block")
    assert load_raw_model(write(tmp_path, text)).dialect == "cameo-eclipse-uml2"
    only_elements = text.replace("eee_1045467100313_135436_1", "_L6NhkFhUEeyvNLF48Hn8sw")
    assert load_raw_model(write(tmp_path, only_elements, "e.uml")).dialect == "cameo-eclipse-uml2"
    papyrus_ids = only_elements.replace("_19_0_4_2b4a0c1_1611929941338_712674_", "_b80QkFhUEeyvNLF48Hn8s")
    assert load_raw_model(write(tmp_path, papyrus_ids, "p.uml")).dialect == "papyrus"


def test_older_eclipse_uml2_generations_are_papyrus(tmp_path: Path) -> None:
    old = """<?xml version="1.0" encoding="UTF-8"?>
<xmi:XMI xmi:version="2.1" xmlns:xmi="http://schema.omg.org/spec/XMI/2.1" xmlns:uml="http://www.eclipse.org/uml2/3.0.0/UML"
    xmlns:Blocks="http://www.eclipse.org/papyrus/0.7.0/SysML/Blocks">
  <uml:Model xmi:id="_m" name="Old">
    <packagedElement xmi:type="uml:Class" xmi:id="_c" name="C"><ownedConnector xmi:id="_k"/></packagedElement>
  </uml:Model>
  <Blocks:Block xmi:id="_b" base_Class="_c"/>
</xmi:XMI>
"""
    raw = load_raw_model(write(tmp_path, old, "old.uml"))
    assert raw.dialect == "papyrus"
    assert raw.has_sysml(raw.by_id["_c"], "Block") and raw.uml_type(raw.by_id["_k"]) == "Connector"
    xmi20 = old.replace('xmi:version="2.1"', 'xmi:version="2.0"').replace(
        "http://schema.omg.org/spec/XMI/2.1", "http://www.omg.org/XMI").replace("uml2/3.0.0", "uml2/4.0.0")
    assert load_raw_model(write(tmp_path, xmi20, "old20.uml")).dialect == "papyrus"


def test_a_magicdraw_file_without_documentation_is_known_by_its_extension_extender(tmp_path: Path) -> None:
    text = (CAMEO.split("\t<xmi:Documentation>")[0] + "\t<xmi:Extension"
            + CAMEO.split("</xmi:Documentation>\n\t<xmi:Extension")[1])
    assert load_raw_model(write(tmp_path, text)).dialect == "cameo"


def test_an_exporter_named_enterprise_architect_is_not_taken_for_magicdraw(tmp_path: Path) -> None:
    text = CLEAN.replace("""<xmi:documentation xmi:type="xmi:Documentation">
    <xmi:exporter>MagicDraw Clean XMI Exporter</xmi:exporter><xmi:exporterVersion>19.0 v9</xmi:exporterVersion>
  </xmi:documentation>""", '<xmi:Documentation exporter="Enterprise Architect" exporterVersion="6.5"/>')
    assert load_raw_model(write(tmp_path, text)).dialect == "enterprise-architect"


# -- .mdzip ---------------------------------------------------------------------------------------------

SHARED = """<?xml version='1.0' encoding='UTF-8'?>
<xmi:XMI xmlns:uml='http://www.omg.org/spec/UML/20131001' xmlns:xmi='http://www.omg.org/spec/XMI/20131001'>
	<xmi:Documentation><xmi:exporter>MagicDraw UML</xmi:exporter></xmi:Documentation>
	<uml:Package xmi:type='uml:Package' xmi:id='_shared' name='Shared'>
		<packagedElement xmi:type='uml:DataType' xmi:id='_dt' name='Pose'/>
	</uml:Package>
</xmi:XMI>
"""


def make_mdzip(path: Path, model: str = CAMEO, shared: str | None = None) -> Path:
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        archive.writestr("proxy.local__PROJECT-1234_resource_com$dnomagic$dmagicdraw$duml_umodel$dmodel$dsnapshot",
                         "<xmi:XMI xmlns:xmi='http://www.omg.org/XMI'><broken")
        archive.writestr("BINARY-0a1b2c3d", b"\x89PNG\r\n\x1a\n\x00\x00")
        archive.writestr("Records.properties", "#Records\n")
        archive.writestr(MODEL_MEMBER, model)
        if shared is not None:
            archive.writestr(SHARED_MEMBER, shared)
    return path


def test_an_mdzip_is_read_from_its_model_member_and_locations_name_the_member(tmp_path: Path) -> None:
    path = make_mdzip(tmp_path / "project.mdzip")
    raw = load_raw_model(path)
    assert raw.dialect == "cameo"
    location = raw.location(raw.by_id["_c1"])
    assert location.file == f"{path}!{MODEL_MEMBER}"
    lines = CAMEO.splitlines()
    assert location.line == lines.index(next(line for line in lines if "'_c1' name=" in line)) + 1
    assert list(tmp_path.iterdir()) == [path]  # nothing extracted


def test_the_shared_model_member_is_read_too_and_references_into_it_resolve(tmp_path: Path) -> None:
    model = CAMEO.replace(
        "<type href='UML_Standard_Profile.mdzip#eee_1045467100323_917313_65'>",
        "<type href='local:/PROJECT-1234?resource=com.nomagic.magicdraw.uml_umodel.shared_model#_dt'>",
    )
    raw = load_raw_model(make_mdzip(tmp_path / "p.mdzip", model, SHARED))
    shared_type = raw.ref(raw.by_id["_p2"], "type")
    assert shared_type is raw.by_id["_dt"]
    assert raw.location(shared_type).file.endswith(f"p.mdzip!{SHARED_MEMBER}")
    assert raw.location(raw.by_id["_c1"]).file.endswith(f"p.mdzip!{MODEL_MEMBER}")
    assert raw.owner(raw.by_id["_shared"]) is None


def test_an_mdzip_lifts_like_the_plain_file(tmp_path: Path) -> None:
    fixture = (ROOT / "tests" / "fixtures" / "cameo" / "arm-cameo2022x.xmi").read_text(encoding="utf-8")
    zipped = lift(load_raw_model(make_mdzip(tmp_path / "arm.mdzip", fixture))).model
    plain = lift(load_raw_model(write(tmp_path, fixture, "arm.xmi"))).model
    assert [a.path for a in zipped.agents] == [a.path for a in plain.agents] == ["manip/a", "task/a"]
    assert zipped.system is not None and len(zipped.system.links) == 2


def test_a_zip_bomb_is_refused_in_one_line_without_extracting_it(tmp_path: Path) -> None:
    path = tmp_path / "bomb.mdzip"
    with zipfile.ZipFile(path, "w", compression=zipfile.ZIP_DEFLATED) as archive:
        archive.writestr(MODEL_MEMBER, b"<" + b" " * (40 << 20))
    assert path.stat().st_size < 1 << 20
    # named relative to its folder: a label over 120 characters (a deep temporary folder) is shortened
    result = subprocess.run([sys.executable, "-m", "earl_m2t", "check", path.name], cwd=tmp_path,
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and "ZIP bomb" in result.stderr
    assert result.stderr.startswith(f"{path.name}!{MODEL_MEMBER}: error: ")


def test_an_oversize_member_is_refused_in_one_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(mdzip, "MAX_MEMBER_BYTES", 1000)
    with pytest.raises(ModelReadError) as info:
        load_raw_model(make_mdzip(tmp_path / "big.mdzip"))
    assert "too large" in info.value.one_line() and "\n" not in info.value.one_line()


def test_a_member_whose_directory_entry_lies_about_its_size_is_refused_in_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = make_mdzip(tmp_path / "lying.mdzip")
    real_infolist = zipfile.ZipFile.infolist

    def lying_infolist(self: zipfile.ZipFile) -> list[zipfile.ZipInfo]:
        infos = real_infolist(self)
        for info in infos:
            info.file_size = min(info.file_size, 100)  # the directory claims a small member
        return infos

    monkeypatch.setattr(zipfile.ZipFile, "infolist", lying_infolist)
    with pytest.raises(ModelReadError) as info:
        load_raw_model(path)
    assert "\n" not in info.value.one_line() and str(path) in info.value.one_line()


def test_a_damaged_archive_is_reported_in_one_line(tmp_path: Path) -> None:
    path = make_mdzip(tmp_path / "cut.mdzip")
    data = path.read_bytes()
    start = data.index(MODEL_MEMBER.encode()) + len(MODEL_MEMBER)
    path.write_bytes(data[:start] + bytes(b ^ 0xFF for b in data[start:start + 64]) + data[start + 64:])
    result = earl("show", str(path))
    assert result.returncode == 2 and result.stderr.count("\n") == 1 and "Traceback" not in result.stderr


# -- --dialect ------------------------------------------------------------------------------------------

def test_the_dialect_option_overrides_detection(tmp_path: Path) -> None:
    path = write(tmp_path, CAMEO)
    assert load_raw_model(path, "cameo-clean").dialect == "cameo-clean"
    shown = earl("show", "--dialect", "cameo-clean", str(path))
    assert shown.returncode == 0 and shown.stdout.splitlines()[0].startswith("model Model  (cameo-clean) ")
    checked = earl("check", "--dialect", "papyrus", "--format", "json", str(path))
    assert checked.returncode == 1 and checked.stderr == ""  # read, then R003: agents without a system
    assert [d["code"] for d in json.loads(checked.stdout)["diagnostics"]] == ["R003"]


def test_the_dialect_option_reads_a_file_whose_tool_is_unknown(tmp_path: Path) -> None:
    unknown = CLEAN.replace("MagicDraw Clean XMI Exporter", "Some Modeller")
    path = write(tmp_path, unknown)
    refused = earl("show", str(path))
    assert refused.returncode == 2 and "--dialect" in refused.stderr and refused.stderr.count("\n") == 1
    assert earl("show", "--dialect", "cameo-clean", str(path)).returncode == 0


@pytest.mark.parametrize("command", ["check", "show"])
def test_an_unknown_dialect_is_a_one_line_usage_error(tmp_path: Path, command: str) -> None:
    result = earl(command, "--dialect", "rhapsody", str(write(tmp_path, CAMEO)))
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1 and "rhapsody" in result.stderr and "cameo" in result.stderr
    assert result.stdout == ""
