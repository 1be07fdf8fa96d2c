"""``earl-m2t profile --format ea-mdg``: the EARL profile as an Enterprise Architect MDG Technology.

The file holds one ``<UMLProfile profiletype="uml2">`` in the shape of the profiles EA users
exchange (``../shared/profiles/spsysml-spsys-profile.xml``, written by EA): every EARL
stereotype with the metaclasses it applies to, its more general stereotypes and its tags.
earl-m2t reads it back as a profile file (``--profile``), as it reads SPSysML's.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from lxml import etree

from earl_m2t.profile import load_profile
from earl_m2t.profile_export.render import export_profile
from earl_m2t.stereotypes.ea_profile import read_profile_file
from earl_m2t.stereotypes.vocabulary import Vocabulary

ROOT = Path(__file__).resolve().parents[1]
SPSYS_PROFILE = ROOT.parent / "shared" / "profiles" / "spsysml-spsys-profile.xml"


@pytest.fixture(scope="module")
def mdg() -> etree._Element:
    ((name, data),) = export_profile("ea-mdg").items()
    assert name == "EARL.mdg.xml"
    return etree.fromstring(data)


def stereotypes(root: etree._Element) -> dict[str, etree._Element]:
    return {s.get("name"): s for s in root.iter("Stereotype")}


def test_the_technology_holds_one_uml2_profile_named_earl(mdg: etree._Element) -> None:
    assert mdg.tag == "MDG.Technology" and mdg.find("Documentation").get("name") == "EARL"
    (profile,) = mdg.findall("UMLProfiles/UMLProfile")
    assert profile.get("profiletype") == "uml2"
    assert profile.find("Documentation").get("name") == "EARL"
    assert [child.tag for child in profile.find("Content")] == [
        "Stereotypes", "TaggedValueTypes", "ViewDefinitions", "Metamodel"]


def test_every_concept_is_a_stereotype_with_its_metaclass_and_generals(mdg: etree._Element) -> None:
    profile = load_profile()
    found = stereotypes(mdg)
    assert list(found) == [c.name for c in profile.concepts.values() if c.metaclass]
    for concept in profile.concepts.values():
        stereotype = found[concept.name]
        assert (stereotype.get("isAbstract") == "true") == concept.abstract, concept.name
        assert (stereotype.get("generalizes") or "") == ",".join(concept.supertypes), concept.name
        assert stereotype.get("baseStereotypes") == stereotype.get("generalizes"), concept.name
        applies = [a.get("type") for a in stereotype.findall("AppliesTo/Apply")]
        assert applies == [concept.metaclass], concept.name
        assert stereotype.get("notes") == concept.doc


def test_the_tags_carry_their_types_literals_and_defaults(mdg: etree._Element) -> None:
    profile = load_profile()
    found = stereotypes(mdg)
    for concept in profile.concepts.values():
        declared = {f.name for f in concept.features if f.tag}
        tags = {t.get("name"): t for t in found[concept.name].findall("TaggedValues/Tag")}
        assert set(tags) == declared, concept.name
    declared_type = stereotypes(mdg)["Agent"].find("TaggedValues/Tag")
    assert declared_type.get("type") == "enumeration"
    assert declared_type.get("values") == ",".join(profile.enums["AgentType"])
    receive = {t.get("name"): t for t in found["InputBuffer"].iter("Tag")}
    assert (receive["receive"].get("values"), receive["receive"].get("default")) == ("latest,queue", "latest")
    assert (receive["queueSize"].get("type"), receive["queueSize"].get("default")) == ("int", "0")
    for concept in ("InputBuffer", "OutputBuffer"):
        reliability = {t.get("name"): t for t in found[concept].iter("Tag")}["reliability"]
        assert (reliability.get("values"), reliability.get("default")) == ("reliable,best_effort", "reliable")
    priority = found["FsmTransition"].find("TaggedValues/Tag")
    assert (priority.get("name"), priority.get("type"), priority.get("default")) == ("priority", "int", "0")


@pytest.mark.skipif(not SPSYS_PROFILE.is_file(), reason="SPSysML profile not beside the checkout")
def test_the_stereotypes_have_the_shape_of_an_ea_profile(mdg: etree._Element) -> None:
    """Every attribute and child EA wrote on SPSysML's stereotypes is on ours (and no other)."""
    theirs = etree.parse(str(SPSYS_PROFILE)).getroot()
    their_attributes = set().union(*(s.attrib.keys() for s in theirs.iter("Stereotype")))
    for stereotype in mdg.iter("Stereotype"):
        assert {"name", "notes", "cx", "cy", "bgcolor", "fontcolor", "bordercolor", "borderwidth",
                "hideicon"} <= set(stereotype.attrib)
        assert set(stereotype.attrib) <= their_attributes
    class_apply = next(a for a in mdg.iter("Apply") if a.get("type") == "Class")
    their_class_apply = next(a for a in theirs.iter("Apply") if a.get("type") == "Class")
    assert [(p.get("name"), p.get("value")) for p in class_apply] == [
        (p.get("name"), p.get("value")) for p in their_class_apply]


def test_the_command_writes_a_file_earl_m2t_reads_back_as_a_profile(tmp_path: Path) -> None:
    run = subprocess.run([sys.executable, "-m", "earl_m2t", "profile", "--format", "ea-mdg", "-o", str(tmp_path)],
                         capture_output=True, text=True, check=False)
    assert run.returncode == 0 and run.stdout == f"wrote {tmp_path / 'EARL.mdg.xml'}\n"
    base = Vocabulary(tuple(load_profile().concepts))
    (profile,) = read_profile_file(tmp_path / "EARL.mdg.xml", base.earl_concept)
    assert profile.name == "EARL"
    assert profile.concept("ControlSubsystem") == "ControlSubsystem"
    assert profile.concept("InterAgentLink") == "InterAgentLink"
