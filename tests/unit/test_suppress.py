"""Suppression comments: the tools' spellings of a comment, and matching by element path."""

from __future__ import annotations

from pathlib import Path

from lxml import etree

from earl_m2t import Diagnostic, Severity, check, load
from earl_m2t.check.engine import CheckOptions
from earl_m2t.check.suppress import apply_suppressions
from earl_m2t.model.location import Location

ROOT = Path(__file__).resolve().parents[2]
SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"
XMI = "http://www.omg.org/spec/XMI/20131001"


def _variant(tmp_path: Path, comment_xml: str) -> tuple[Path, str]:
    """The sample with link task/a,grip/a renamed (a C008 finding) and a comment put into the link."""
    root = etree.fromstring(SAMPLE.read_bytes())
    (link,) = root.xpath('//ownedConnector[@name="task/a,grip/a"]')
    link.set("name", "gripperCommand")
    link_id = link.get(f"{{{XMI}}}id")
    comment = etree.fromstring(comment_xml.replace("LINK", link_id))
    link.insert(0, comment)
    path = tmp_path / "variant.uml"
    path.write_bytes(etree.tostring(root))
    return path, link_id


def test_cameo_comment_with_body_attribute_and_idref_children(tmp_path: Path) -> None:
    xml = (f'<ownedComment xmlns:xmi="{XMI}" xmi:id="_c1" body="earl-m2t: ignore[C008] vendor names">'
           '<annotatedElement xmi:idref="LINK"/></ownedComment>')
    path, _ = _variant(tmp_path, xml)
    assert check(path) == []


def test_html_comment_body_and_several_codes(tmp_path: Path) -> None:
    body = ("&lt;html&gt;&lt;body&gt;&lt;p&gt;earl-m2t: ignore[C008, S001] vendor names&lt;/p&gt;"
            "&lt;/body&gt;&lt;/html&gt;")
    xml = f'<ownedComment xmlns:xmi="{XMI}" xmi:id="_c1" body="{body}" annotatedElement="LINK"/>'
    path, _ = _variant(tmp_path, xml)
    findings = check(path)
    assert [d.code for d in findings] == ["R005"]  # C008 silenced; S001 silences nothing
    assert "S001" in findings[0].message and "C008" not in findings[0].message


def test_a_comment_without_annotated_element_applies_to_its_owner(tmp_path: Path) -> None:
    xml = (f'<ownedComment xmlns:xmi="{XMI}" xmi:id="_c1">'
           '<body>earl-m2t: ignore[C008] vendor names</body></ownedComment>')
    path, _ = _variant(tmp_path, xml)
    assert check(path) == []


def test_a_finding_is_matched_by_the_path_of_the_annotated_element(tmp_path: Path) -> None:
    xml = (f'<ownedComment xmlns:xmi="{XMI}" xmi:id="_c1" annotatedElement="LINK">'
           '<body>earl-m2t: ignore[C006] ok</body></ownedComment>')
    path, link_id = _variant(tmp_path, xml)
    loaded = load(path)
    (link,) = [link for link in loaded.model.links if link.location.xmi_id == link_id]
    elsewhere = Diagnostic("C006", Severity.ERROR, "a finding located elsewhere", Location(str(path), 3, 0, "_x"),
                           link.path)
    other = Diagnostic("C006", Severity.ERROR, "another element", Location(str(path), 3, 0, "_x"), "task/a")
    kept = apply_suppressions([elsewhere, other], loaded.model, CheckOptions())
    assert kept == [other]
