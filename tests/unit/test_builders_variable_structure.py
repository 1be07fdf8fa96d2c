"""The three sample builders write what a variable-structure model says: a «Configuration»
constraint of the System block with its tags, the «FsmState» tags ``configuration`` and
``quiescent``, the «Agent» tag ``reactivation`` and agent parts of multiplicity ``[0..1]``, each
the way its tool writes a stereotyped constraint, a tag and a multiplicity."""

from __future__ import annotations

from typing import Any

import pytest
from lxml import etree

from tests.support.sample_kit import DIALECTS

NAMESPACES = {
    "papyrus": "http://www.omg.org/spec/XMI/20131001",
    "cameo": "http://www.omg.org/spec/XMI/20131001",
    "ea": "http://schema.omg.org/spec/XMI/2.1",
}


def build(dialect: str) -> bytes:
    kit = DIALECTS[dialect]
    mb = kit.model_builder("Cell")
    types = mb.package("DataTypes")
    command = types.data_type("Command")
    command.field("seq", kit.integer)
    pkg = mb.package("SystemInstance")
    system = pkg.block("CellSystem", "System")
    robot = pkg.block("Cell", "Robot")
    arm = pkg.block("ArmAgent", "Agent", {"declaredType": "CT", "reactivation": "resume"})
    cs = pkg.block("ArmControl", "ControlSubsystem")
    cs.input_buffer("command/ib", command)
    fsm = cs.state_machine()
    idle = fsm.state("idle", initial=True)
    idle.do_activity()
    idle.stereotype("FsmState", {"configuration": "useA", "quiescent": True})
    system.part("cell/r", robot)
    robot.part("armA/a", arm, "0..1")
    arm.part("cs", cs)
    system.configuration("useA", agents=["armA/a"], links=["task/a,armA/a", "armA/a,task/a"], switch_timeout=0.05)
    return mb.to_bytes()


def applications(root: etree._Element, name: str) -> list[etree._Element]:
    return [el for el in root.iter() if isinstance(el.tag, str) and etree.QName(el).localname == name
            and any(key.startswith("base_") for key in el.attrib)]


def element(root: etree._Element, dialect: str, xmi_type: str, name: str) -> etree._Element:
    type_attr = f"{{{NAMESPACES[dialect]}}}type"
    (found,) = [el for el in root.iter() if el.get(type_attr) == xmi_type and el.get("name") == name
                and el.tag not in ("qualifier", "element")]  # not EA's copies of a part or record of an element
    return found


def the_id(el: etree._Element, dialect: str) -> Any:
    return el.get(f"{{{NAMESPACES[dialect]}}}id")


@pytest.fixture(scope="module", params=list(DIALECTS))
def written(request: pytest.FixtureRequest) -> tuple[str, etree._Element]:
    dialect: str = request.param
    return dialect, etree.fromstring(build(dialect), etree.XMLParser(resolve_entities=False, no_network=True))


def test_a_configuration_is_a_stereotyped_constraint_of_the_system_block(written: tuple[str, etree._Element]) -> None:
    dialect, root = written
    constraint = element(root, dialect, "uml:Constraint", "useA")
    assert constraint.getparent() is element(root, dialect, "uml:Class", "CellSystem")
    (app,) = applications(root, "Configuration")
    assert app.get("base_Constraint") == the_id(constraint, dialect)
    assert (app.get("agents"), app.get("links"), app.get("switchTimeout")) == (
        "armA/a", "task/a,armA/a armA/a,task/a", "0.05")


def test_the_new_state_and_agent_tags_are_written(written: tuple[str, etree._Element]) -> None:
    dialect, root = written
    (state,) = applications(root, "FsmState")
    assert (state.get("configuration"), state.get("quiescent")) == ("useA", "true")
    (agent,) = applications(root, "Agent")
    assert agent.get("reactivation") == "resume"


def test_a_variable_agent_part_has_multiplicity_zero_to_one(written: tuple[str, etree._Element]) -> None:
    dialect, root = written
    part = element(root, dialect, "uml:Property", "armA/a")
    lower, upper = part.find("lowerValue"), part.find("upperValue")
    assert lower is not None and upper is not None
    assert lower.get("value", "0") == "0" and upper.get("value") == "1"


def test_cameo_lists_the_tags_the_file_sets() -> None:
    root = etree.fromstring(build("cameo"))
    hrefs = next(el for el in root.iter("stereotypesHREFS"))
    tags = {el.get("name") for el in hrefs.iter("tag") if (el.get("name") or "").startswith("EARL:")}
    assert tags == {"EARL:Agent:declaredType", "EARL:Agent:reactivation", "EARL:FsmState:configuration",
                    "EARL:FsmState:quiescent", "EARL:Configuration:agents", "EARL:Configuration:links",
                    "EARL:Configuration:switchTimeout"}


def test_enterprise_architect_keeps_the_reactivation_values_in_the_block_record() -> None:
    data = build("ea").decode("cp1252")
    assert 'name="reactivation" value="resume#NOTES#Values: restart,resume&amp;#xA;"' in data
