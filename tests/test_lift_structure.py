"""Structure lifting beyond the sample: replicated robots, implicit systems, links between them."""

from __future__ import annotations

from pathlib import Path

from earl_m2t import check, load
from tests.support.papyrus_builder import REAL, End, ModelBuilder

ROOT = Path(__file__).resolve().parents[1]


def _cell_model(tmp_path: Path, robots: int, stereotypes: bool = True) -> Path:
    """A system with ``cell/r [robots]``, each robot holding one ``arm/a`` (cs, ve, re), and a
    ``plan/a`` outside the robots commanding every arm's cs."""
    mb = ModelBuilder("Cells", stereotypes=stereotypes)
    types = mb.package("DataTypes")
    message = types.data_type("Message")
    message.field("value", REAL)
    pkg = mb.package("SystemInstance")
    system = pkg.block("CellSystem", "System")
    robot = pkg.block("Cell", "Robot")

    def subsystem(name: str, stereotype: str, ins: list[str], outs: list[str]):
        block = pkg.block(name, stereotype)
        reads = [block.input_buffer(f"{n}/ib", message) for n in ins]
        writes = [block.output_buffer(f"{n}/ob", message) for n in outs]
        pf = block.partial_transition_function("step/pf", reads=reads, writes=writes)
        block.state_machine().state("run", initial=True).do_activity().stages([[pf]])
        return block

    arm_cs = subsystem("ArmControl", "ControlSubsystem", ["goal", "state"], ["command", "status"])
    drive_ve = subsystem("Drive", "VirtualEffector", ["command", "encoder"], ["state", "current"])
    motor_re = subsystem("Motor", "RealEffector", ["current"], ["encoder"])
    plan_cs = subsystem("PlanControl", "ControlSubsystem", ["status"], ["goal"])
    arm = pkg.block("Arm", "Agent")
    cs = arm.part("cs", arm_cs)
    ve = arm.part("drive/ve", drive_ve)
    re = arm.part("motor/re", motor_re)

    def port(block, name):
        return next(p for p in block.attributes if p.name == name)

    arm.connector("cs,drive/ve", End.at(port(arm_cs, "command/ob"), cs), End.at(port(drive_ve, "command/ib"), ve))
    arm.connector("drive/ve,cs", End.at(port(drive_ve, "state/ob"), ve), End.at(port(arm_cs, "state/ib"), cs))
    arm.connector("drive/ve,motor/re", End.at(port(drive_ve, "current/ob"), ve),
                  End.at(port(motor_re, "current/ib"), re))
    arm.connector("motor/re,drive/ve", End.at(port(motor_re, "encoder/ob"), re),
                  End.at(port(drive_ve, "encoder/ib"), ve))
    arm_part = robot.part("arm/a", arm)
    plan = pkg.block("Planner", "Agent")
    plan_cs_part = plan.part("cs", plan_cs)
    robot_part = system.part("cell/r", robot, robots if robots > 1 else None)
    plan_part = system.part("plan/a", plan)
    system.connector("plan/a,arm/a", End.at(port(plan_cs, "goal/ob"), plan_part, plan_cs_part),
                     End.at(port(arm_cs, "goal/ib"), robot_part, arm_part, cs))
    system.connector("arm/a,plan/a", End.at(port(arm_cs, "status/ob"), robot_part, arm_part, cs),
                     End.at(port(plan_cs, "status/ib"), plan_part, plan_cs_part))
    path = tmp_path / "cells.uml"
    path.write_bytes(mb.to_bytes())
    return path


def test_agents_of_replicated_robots_are_told_apart_by_their_robot(tmp_path: Path) -> None:
    model = load(_cell_model(tmp_path, robots=2)).model
    assert [r.name for r in model.robots] == ["cell1/r", "cell2/r"]
    assert [r.agents for r in model.robots] == [("cell1/r.arm/a",), ("cell2/r.arm/a",)]
    assert sorted(a.path for a in model.agents) == ["cell1/r.arm/a", "cell2/r.arm/a", "plan/a"]
    assert all(a.computed_type == "CET" for a in model.agents if a.name == "arm/a")


def test_an_inter_agent_link_fans_out_to_every_replicated_robot(tmp_path: Path) -> None:
    model = load(_cell_model(tmp_path, robots=2)).model
    (system,) = model.systems
    targets = sorted(link.target for link in system.links if link.source.startswith("plan/a"))
    assert targets == ["cell1/r.arm/a.cs.goal/ib", "cell2/r.arm/a.cs.goal/ib"]


def test_a_single_robot_model_checks_clean_with_and_without_stereotypes(tmp_path: Path) -> None:
    for stereotypes in (True, False):
        path = _cell_model(tmp_path, robots=1, stereotypes=stereotypes)
        findings = [f"{d.code} {d.message}" for d in check(path) if d.code != "C008"]
        assert findings == []
        model = load(path).model
        assert {a.name: a.computed_type for a in model.agents} == {"arm/a": "CET", "plan/a": "CT"}


def test_without_a_system_stereotype_the_top_level_block_with_robot_parts_is_the_system(tmp_path: Path) -> None:
    model = load(_cell_model(tmp_path, robots=1, stereotypes=False)).model
    (system,) = model.systems
    assert system.name == "CellSystem" and system.recognised_by == "structure"
