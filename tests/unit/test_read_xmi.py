"""The XMI reader: one pass, ids indexed, the four reference encodings, stereotypes by namespace."""

from __future__ import annotations

from pathlib import Path

import pytest

from earl_m2t.diagnostics import ModelReadError
from earl_m2t.read.dialects import normalise_uri
from earl_m2t.read.loader import load_raw_model
from earl_m2t.read.xmi import ExternalRef

HEADER = (
    '<?xml version="1.0" encoding="UTF-8"?>\n'
    '<xmi:XMI xmi:version="20131001" xmlns:xmi="http://www.omg.org/spec/XMI/20131001" '
    'xmlns:uml="http://www.eclipse.org/uml2/5.0.0/UML" '
    'xmlns:Blocks="http://www.eclipse.org/papyrus/sysml/1.6/SysML/Blocks" '
    'xmlns:EARL="http:///schemas/EARL/_abc/3">\n'
)

MODEL = HEADER + """  <uml:Model xmi:id="m" name="M">
    <packagedElement xmi:type="uml:Class" xmi:id="A" name="Agent1">
      <ownedAttribute xmi:id="p1" name="cs" type="B" aggregation="composite"/>
      <ownedAttribute xmi:type="uml:Property" xmi:id="p2" name="x">
        <type xmi:type="uml:PrimitiveType" href="pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml#Boolean"/>
      </ownedAttribute>
      <ownedAttribute xmi:type="uml:Property" xmi:id="p3" name="y">
        <type xmi:idref="B"/>
      </ownedAttribute>
      <xmi:Extension extender="tool"><copy xmi:id="A"/></xmi:Extension>
    </packagedElement>
    <packagedElement xmi:type="uml:Class" xmi:id="B" name="Control"/>
    <packagedElement xmi:type="uml:Association" xmi:id="as" memberEnd="p1 p3 missing"/>
  </uml:Model>
  <Blocks:Block xmi:id="s1" base_Class="A"/>
  <EARL:Agent xmi:id="s2" base_Class="A" declaredType="CT"/>
  <EARL:ControlSubsystem xmi:id="s3"><base_Class xmi:idref="B"/></EARL:ControlSubsystem>
</xmi:XMI>
"""


@pytest.fixture
def raw(tmp_path: Path):
    path = tmp_path / "m.uml"
    path.write_text(MODEL, encoding="utf-8")
    return load_raw_model(path)


def test_every_element_with_an_id_is_indexed_once_and_extensions_are_skipped(raw) -> None:
    assert set(raw.by_id) == {"m", "A", "p1", "p2", "p3", "B", "as"}
    assert raw.by_id["A"].get("name") == "Agent1"  # not the extension's copy
    assert raw.diagnostics == []


def test_the_dialect_of_an_eclipse_uml2_file_without_tool_markers_is_papyrus(raw) -> None:
    assert raw.dialect == "papyrus"


def test_elements_keep_their_file_and_line(raw) -> None:
    location = raw.location(raw.by_id["p2"])
    assert location.file.endswith("m.uml") and location.line == 6 and location.xmi_id == "p2"


def test_the_uml_type_comes_from_xmi_type_or_from_the_feature_when_left_out(raw) -> None:
    assert raw.uml_type(raw.by_id["A"]) == "Class"
    assert raw.uml_type(raw.by_id["p1"]) == "Property"  # EMF leaves xmi:type out
    assert raw.uml_type(raw.by_id["m"]) == "Model"


def test_references_resolve_in_all_four_encodings(raw) -> None:
    assert raw.ref(raw.by_id["p1"], "type") is raw.by_id["B"]  # IDREF attribute
    assert raw.ref(raw.by_id["p3"], "type") is raw.by_id["B"]  # child with xmi:idref
    external = raw.ref(raw.by_id["p2"], "type")  # child with href
    assert isinstance(external, ExternalRef) and external.fragment == "Boolean"
    ends = raw.refs(raw.by_id["as"], "memberEnd")  # IDREFS list, one dangling
    assert ends[:2] == [raw.by_id["p1"], raw.by_id["p3"]]
    assert isinstance(ends[2], ExternalRef) and ends[2].fragment == "missing"


def test_stereotype_applications_are_indexed_by_the_extended_element(raw) -> None:
    applied = {(a.name, raw.table.is_earl(a.profile_uri), raw.table.is_sysml(a.profile_uri))
               for a in raw.applied(raw.by_id["A"])}
    assert applied == {("Block", False, True), ("Agent", True, False)}
    (agent,) = [a for a in raw.applied(raw.by_id["A"]) if a.name == "Agent"]
    assert agent.tags == {"declaredType": "CT"}
    assert [a.name for a in raw.applied(raw.by_id["B"])] == ["ControlSubsystem"]  # base_Class as a child


def test_duplicate_ids_are_reported_not_fatal(tmp_path: Path) -> None:
    path = tmp_path / "dup.uml"
    path.write_text(MODEL.replace('xmi:id="B"', 'xmi:id="A"'), encoding="utf-8")
    raw = load_raw_model(path)
    assert [d.code for d in raw.diagnostics] == ["R002"]
    assert raw.diagnostics[0].location.line > 0


def test_namespace_uris_are_compared_without_scheme_and_trailing_slash() -> None:
    assert normalise_uri("https://www.omg.org/spec/XMI/20131001/") == "http://www.omg.org/spec/XMI/20131001"


def test_a_single_root_uml_model_without_xmi_wrapper_is_read(tmp_path: Path) -> None:
    path = tmp_path / "single.uml"
    path.write_text(
        '<?xml version="1.0"?>\n<uml:Model xmi:version="20131001" xmlns:xmi="http://www.omg.org/spec/XMI/20131001" '
        'xmlns:uml="http://www.eclipse.org/uml2/5.0.0/UML" xmi:id="m" name="M">\n'
        '  <packagedElement xmi:type="uml:Class" xmi:id="c" name="C"/>\n</uml:Model>\n', encoding="utf-8")
    raw = load_raw_model(path)
    assert set(raw.by_id) == {"m", "c"}


def test_a_declared_windows_1252_encoding_is_honoured(tmp_path: Path) -> None:
    path = tmp_path / "w.uml"
    text = MODEL.replace('encoding="UTF-8"', 'encoding="windows-1252"').replace("Control", "Contr\u00f4le")
    path.write_bytes(text.encode("cp1252"))
    raw = load_raw_model(path)
    assert raw.by_id["B"].get("name") == "Contr\u00f4le"


def test_a_zip_archive_without_a_magicdraw_model_member_is_reported_in_one_line(tmp_path: Path) -> None:
    import zipfile

    path = tmp_path / "project.zip"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("model.uml", MODEL)
    with pytest.raises(ModelReadError) as info:
        load_raw_model(path)
    assert "ZIP archive without a MagicDraw model member" in info.value.one_line()
    assert "\n" not in info.value.one_line()


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (b"<a><b></a>", "not well-formed"),
        (b"<project/>", "not an XMI file"),
    ],
)
def test_unreadable_files_raise_one_clear_error(tmp_path: Path, content: bytes, message: str) -> None:
    path = tmp_path / "x.uml"
    path.write_bytes(content)
    with pytest.raises(ModelReadError) as info:
        load_raw_model(path)
    assert message in info.value.one_line() and "\n" not in info.value.one_line()
