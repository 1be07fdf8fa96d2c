"""Agent Groups (GpAgents) and Subsystem Groups (GpSubsys): lifted, shown, checked.

``tests/fixtures/groups/heating.sysml`` gathers two room agents in the Agent Group ``rooms/ga``
of the robot ``house/r``, each room's drivers in the Subsystem Group ``drivers/gs``; links reach
through the groups. A group only structures the model: its Agents are the robot's Agents, its
Subsystems the Agent's. The rule triggers (S010, S011) are rows of tests/rules/test_rule_triggers.py.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from earl_m2t.api import check, load
from earl_m2t.convert import to_sysml
from earl_m2t.export import model_to_dict
from earl_m2t.profile import load_profile
from tests.test_sample_dialects_equal import without_location

ROOT = Path(__file__).resolve().parents[1]
HEATING = ROOT / "tests" / "fixtures" / "groups" / "heating.sysml"
GUIDE_GROUPS = ROOT / "tests" / "fixtures" / "guide" / "groups.uml"  # Papyrus XMI


def test_the_groups_are_concepts_of_the_profile_named_as_the_authors_do() -> None:
    profile = load_profile()
    assert profile.concepts["AgentGroup"].abbreviation == "ga"
    assert profile.concepts["SubsystemGroup"].abbreviation == "gs"
    assert profile.concepts["AgentGroup"].metaclass == profile.concepts["SubsystemGroup"].metaclass == "Class"


def test_an_agent_group_contributes_its_agents_to_its_robot() -> None:
    (system,) = load(HEATING).model.systems
    (robot,) = system.robots
    assert robot.agents == ("kitchen/a", "hall/a")
    assert [a.path for a in system.agents] == ["supervisor/a", "kitchen/a", "hall/a"]
    (group,) = system.groups
    assert (group.name, group.kind, group.block, group.owner, group.members) == (
        "rooms/ga", "ga", "Rooms", "house/r", ("kitchen/a", "hall/a"))
    assert [link.name for link in system.links] == ["supervisor/a,kitchen/a", "kitchen/a,hall/a"]
    kitchen = next(a for a in system.agents if a.path == "kitchen/a")
    assert kitchen.computed_type == "CET"


def test_a_subsystem_group_contributes_its_subsystems_to_its_agent() -> None:
    (system,) = load(HEATING).model.systems
    for agent in system.agents[1:]:
        assert [(s.kind, s.path) for s in agent.subsystems] == [
            ("cs", f"{agent.path}.cs"), ("ve", f"{agent.path}.heaterDriver/ve"), ("re", f"{agent.path}.heater/re")]
        (group,) = agent.groups
        assert (group.path, group.kind, group.members) == (
            f"{agent.path}.drivers/gs", "gs", (f"{agent.path}.heaterDriver/ve", f"{agent.path}.heater/re"))
        assert [(link.source, link.target) for link in agent.links] == [
            (f"{agent.path}.cs.heaterCommand/ob", f"{agent.path}.heaterDriver/ve.command/ib"),
            (f"{agent.path}.heaterDriver/ve.power/ob", f"{agent.path}.heater/re.power/ib"),
        ]


def test_the_grouped_model_checks_clean() -> None:
    assert [str(d) for d in check(HEATING)] == []


def test_show_prints_the_groups_in_text_and_json() -> None:
    def show(*options: str) -> str:
        run = subprocess.run([sys.executable, "-m", "earl_m2t", "show", str(HEATING), *options],
                             capture_output=True, text=True, check=True)
        return run.stdout

    text = show()
    assert "  group ga rooms/ga [Rooms] in house/r: kitchen/a, hall/a\n" in text
    assert "    group gs drivers/gs [HeaterDrivers] in hall/a: heaterDriver/ve, heater/re\n" in text
    (system,) = json.loads(show("--format", "json"))["systems"]
    (group,) = system["groups"]
    assert {k: group[k] for k in ("name", "kind", "owner", "members")} == {
        "name": "rooms/ga", "kind": "ga", "owner": "house/r", "members": ["kitchen/a", "hall/a"]}
    assert system["agents"][1]["groups"][0]["members"] == ["kitchen/a.heaterDriver/ve", "kitchen/a.heater/re"]


def test_the_diagrams_and_the_report_show_the_groups(tmp_path: Path) -> None:
    for command in (["gen", str(HEATING), "--target", "diagrams", "-o", str(tmp_path / "d")],
                    ["report", str(HEATING), "-o", str(tmp_path / "r")]):
        subprocess.run([sys.executable, "-m", "earl_m2t", *command], capture_output=True, text=True, check=True)
    system = (tmp_path / "d" / "system.dot").read_text(encoding="utf-8")
    robot = system.index("subgraph cluster_r0")
    group = system.index("subgraph cluster_g0", robot)
    assert "label=<agent group <b>rooms/ga</b>>" in system[group:]
    assert system[group:].split("}")[0].split(";")[-3:-1] == ["\n      a1", "\n      a2"]
    agent = (tmp_path / "d" / "agent-kitchen-a.dot").read_text(encoding="utf-8")
    assert agent.count("subsystem group drivers/gs") == 2
    assert (tmp_path / "d" / "system.svg").read_text(encoding="utf-8").count("rooms/ga") == 1
    report = (tmp_path / "r" / "index.html").read_text(encoding="utf-8")
    assert ("<tr><td><code>rooms/ga</code></td><td>agent group</td><td>Rooms</td><td><code>house/r</code></td>"
            "<td><code>kitchen/a</code>, <code>hall/a</code></td></tr>") in report
    assert report.count("<td>subsystem group</td>") == 2


def test_the_guide_example_has_the_groups_in_papyrus_xmi() -> None:
    """tests/fixtures/guide/groups.uml: the same constructs as Papyrus writes them, the links
    through the groups with SysML NestedConnectorEnds."""
    example = ROOT / "tests" / "fixtures" / "guide" / "groups.uml"
    (system,) = load(example).model.systems
    assert [(g.path, g.kind, g.owner, g.members) for g in system.groups] == [
        ("rooms/ga", "ga", "house/r", ("kitchen/a",))]
    kitchen = next(a for a in system.agents if a.path == "kitchen/a")
    assert [(g.path, g.members) for g in kitchen.groups] == [
        ("kitchen/a.drivers/gs", ("kitchen/a.heaterDriver/ve", "kitchen/a.heater/re"))]
    assert [link.name for link in kitchen.links] == ["cs,heaterDriver/ve", "heaterDriver/ve,heater/re"]
    assert [(link.source, link.target) for link in system.links] == [
        ("supervisor/a.cs.command/ob", "kitchen/a.cs.command/ib")]
    assert check(example) == []


def _in_the_system(tmp_path: Path) -> Path:
    """heating.sysml with its Agent Group directly in the System (no robot: S001)."""
    text = HEATING.read_text(encoding="utf-8")
    text = text.replace("part 'house/r' : HouseHeating;", "part 'rooms/ga' : Rooms;")
    text = text.replace("'house/r'.'rooms/ga'", "'rooms/ga'")
    robot = "        part def HouseHeating :> Robot {\n            part 'rooms/ga' : Rooms;\n        }\n"
    assert robot in text
    path = tmp_path / "in_the_system.sysml"
    path.write_text(text.replace(robot, ""), encoding="utf-8")
    return path


@pytest.mark.parametrize("source", [HEATING, GUIDE_GROUPS, None], ids=["heating.sysml", "groups.uml", "in-the-system"])
def test_convert_writes_the_groups_and_reads_back_as_the_same_model(source: Path | None, tmp_path: Path) -> None:
    """Agent and Subsystem Groups are written as groups (``part def Rooms :> AgentGroup``), and
    links reach through them: the converted text lifts to the same model, groups included."""
    source = source or _in_the_system(tmp_path)
    original = load(source).model
    (system,) = original.systems
    assert system.groups and any(a.groups for a in system.agents)  # both kinds of group to write
    converted = tmp_path / "converted.sysml"
    converted.write_text(to_sysml(original), encoding="utf-8")
    text = converted.read_text(encoding="utf-8")
    for group in system.groups:
        assert f"part def {group.block} :> AgentGroup {{" in text
        owner = system.name if group.owner == system.name else next(r.block for r in system.robots
                                                                     if r.path == group.owner)
        owner_body = text.split(f"part def {owner} :> ")[1].split("\n        }")[0]
        assert f"part '{group.name}' : {group.block};" in owner_body
    for group in (g for a in system.agents for g in a.groups):
        assert f"part def {group.block} :> SubsystemGroup {{" in text
    assert without_location(model_to_dict(load(converted).model)) == without_location(model_to_dict(original))
    assert [(d.code, d.message) for d in check(converted)] == [(d.code, d.message) for d in check(source)]
    assert to_sysml(load(converted).model) == text
