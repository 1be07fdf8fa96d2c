"""The example models of ``docs/modelling-guide.md``: each construct of the guide is lifted as the guide says.

The models live in ``tests/fixtures/guide/`` and are written by
``tests/fixtures/guide/make_examples.py``; every one of them except the deliberately broken
ones checks without errors.
"""

from __future__ import annotations

import importlib.util
import re
from functools import cache
from pathlib import Path
from types import ModuleType

import pytest

from earl_m2t import Loaded, Severity, check, load
from earl_m2t.model.elements import EarlModel, Subsystem
from earl_m2t.predicate import (
    And,
    BuiltIn,
    BuiltInPredicate,
    Const,
    Not,
    Or,
    PredicateRef,
    Replicated,
    parse_predicate,
    walk,
)

ROOT = Path(__file__).resolve().parents[1]
GUIDE = ROOT / "docs" / "modelling-guide.md"
EXAMPLES = ROOT / "tests" / "fixtures" / "guide"

ROUTES = ("stereotype", "generalisation", "suffix")

# Every `## ` / `### ` section of the guide and the example models that show its constructs.
SECTIONS: dict[str, tuple[str, ...]] = {
    '1. Three ways to say "this is an EARL concept"': (
        "route-stereotype.uml", "route-generalisation.uml", "route-suffix.uml", "route-mixed.uml",
        "route-conflict.uml",
    ),
    "2. Structure (bdd, ibd)": ("route-stereotype.uml", "inter-agent-links.uml", "datatypes.uml", "agent-type.uml"),
    "Replicated instances (`motorControllerK/ve` with multiplicity N)": ("replication.uml",),
    "3. Behaviour (stm, act)": (
        "fsm.uml", "shared-basic-behaviour.uml", "shared-basic-behaviour-empty.uml", "pf-accesses.uml",
        "primitive-predicates.uml", "exclusions.uml", "agent-type.uml", "agent-type-mismatch.uml",
    ),
    "Transition-function stages": ("stages.uml", "stages-conflict.uml"),
    "Activation: buffer groups, timeouts and receive modes": ("activation.uml",),
    "Properties the whole system must keep (`earl-m2t verify`)": ("ltl-property.uml",),
    "When a pf fails: `behaviourOk()` and `inError()`": ("pf-health.uml",),
    "Variable structure: configurations, the coordinator, quiescent states": ("variable-structure.uml",),
    "4. Conditions: the predicate language": (
        "primitive-predicates.uml", "fsm.uml", "replication.uml", "predicate-errors.uml",
    ),
    "Groups of agents and of subsystems (`/ga`, `/gs`)": ("groups.uml",),
    # the profile's stereotypes, as applied in the Papyrus examples (the EA files are samples/…/variants)
    "5. Enterprise Architect with the EARL MDG": ("route-stereotype.uml",),
    # every example's blocks with a state machine are isActive, as the section asks
    "6. Checking the Papyrus files with Eclipse UML2": ("fsm.uml",),
    "7. The three routes side by side": ("route-stereotype.uml", "route-generalisation.uml", "route-suffix.uml"),
}  # fmt: skip

# Every row of the guide's tables (first cell as written) and the example model that shows it.
TABLE_ROWS: dict[str, str] = {
    # section 2
    "System": "route-stereotype.uml",
    "Robot `/r`": "route-stereotype.uml",
    "Agent `/a`": "inter-agent-links.uml",
    "Subsystem `cs ve re vr rr`": "agent-type.uml",
    "Input / Output Buffer `/ib` `/ob`": "route-stereotype.uml",
    "Internal Memory `/m`": "route-stereotype.uml",
    "inter-subsystem Link": "route-stereotype.uml",
    "inter-agent Link `/aa`": "inter-agent-links.uml",
    "dataType": "datatypes.uml",
    # section 2, groups
    "Agent Group `/ga` (`«AgentGroup»`, the authors' `«GpAgents»`)": "groups.uml",
    "Subsystem Group `/gs` (`«SubsystemGroup»`, the authors' `«GpSubsys»`)": "groups.uml",
    # section 3
    "FSM `fsm`": "fsm.uml",
    "FSM State `s`": "fsm.uml",
    "initial FSM State `ifs`": "fsm.uml",
    "FSM Transition `t`": "fsm.uml",
    "initial condition `ic`": "fsm.uml",
    "transition `priority`": "fsm.uml",
    "Basic Behaviour `bb`": "shared-basic-behaviour.uml",
    "terminal condition `tc`, error condition `ec`": "fsm.uml",
    "Transition Function `tf`": "stages.uml",
    "Partial Transition Function `pf`": "stages.uml",
    "what a pf reads and writes": "pf-accesses.uml",
    "Primitive Predicate `pp`": "primitive-predicates.uml",
    "mutually exclusive predicates": "exclusions.uml",
    "declared agent type": "agent-type.uml",
    # section 3, activation
    "buffer group": "activation.uml",
    "state activation": "activation.uml",
    "receive mode": "activation.uml",
    # section 3, properties for verify
    "LTL property (earl-m2t)": "ltl-property.uml",
    # section 3, variable structure
    "general model": "variable-structure.uml",
    "configuration": "variable-structure.uml",
    "coordinator": "variable-structure.uml",
    "quiescent state": "variable-structure.uml",
    "`behaviourOk()`": "pf-health.uml",
    "`inError()`": "pf-health.uml",
    "`leaving()`": "variable-structure.uml",
    "reactivation": "variable-structure.uml",
    "host": "inter-agent-links.uml",
    "reliability": "inter-agent-links.uml",
    "switch timeout": "variable-structure.uml",
    "variable agent": "variable-structure.uml",
    "coordinator state": "variable-structure.uml",
    # section 4
    "primitive predicate": "primitive-predicates.uml",
    "and, or, not": "fsm.uml",
    "constants": "primitive-predicates.uml",
    "buffer and memory fields": "primitive-predicates.uml",
    "new data": "primitive-predicates.uml",
    "comparison": "primitive-predicates.uml",
    "built-in predicates": "variable-structure.uml",
    "replicated instances": "replication.uml",
}

# the deliberately broken examples and the error codes each must report
BROKEN = {
    "stages-conflict.uml": {"T001", "T002"},
    "predicate-errors.uml": {"B008", "B005"},
    "agent-type-mismatch.uml": {"S007"},
}
CLEAN = sorted(p.name for p in EXAMPLES.glob("*.uml") if p.name not in BROKEN)

# ---------------------------------------------------------------------------- helpers


@cache
def loaded(name: str) -> Loaded:
    return load(EXAMPLES / name)


def lifted(name: str) -> EarlModel:
    return loaded(name).model


def subsystem(name: str, path: str) -> Subsystem:
    found = lifted(name).subsystem(path)
    assert found is not None, f"{name}: no subsystem {path}"
    return found


def codes(name: str, severity: Severity | None = None) -> set[str]:
    return {d.code for d in check(EXAMPLES / name) if severity is None or d.severity is severity}


def _make_examples() -> ModuleType:
    spec = importlib.util.spec_from_file_location("make_examples", EXAMPLES / "make_examples.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _guide_sections() -> dict[str, list[str]]:
    """Each `## ` / `### ` heading of the guide with the lines under it (code blocks skipped)."""
    sections: dict[str, list[str]] = {}
    current: list[str] = []
    fenced = False
    for line in GUIDE.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            fenced = not fenced
            continue
        if fenced:
            continue
        heading = re.match(r"#{2,3} (.+)", line)
        if heading:
            current = sections.setdefault(heading.group(1).strip(), [])
        else:
            current.append(line)
    return sections


def _table_rows(lines: list[str]) -> list[str]:
    """The first cells of the body rows of the markdown tables in ``lines``."""
    rows = []
    for i, line in enumerate(lines):
        if not line.startswith("|") or re.match(r"\|[-| :]+\|$", line.strip()):
            continue
        if i + 1 < len(lines) and re.match(r"\|[-| :]+\|$", lines[i + 1].strip()):
            continue  # a header row
        rows.append(line.strip("|").split(" | ")[0].strip())
    return rows


# ---------------------------------------------------------------------------- coverage of the guide


def test_every_construct_section_of_the_guide_has_an_example_model() -> None:
    assert set(_guide_sections()) == set(SECTIONS)
    for section, files in SECTIONS.items():
        for file in files:
            assert (EXAMPLES / file).is_file(), f"{section}: missing example {file}"


def test_every_row_of_the_guide_tables_has_an_example_model() -> None:
    rows = [row for lines in _guide_sections().values() for row in _table_rows(lines)]
    assert rows, "the guide has tables"
    assert set(rows) == set(TABLE_ROWS)
    for row, file in TABLE_ROWS.items():
        assert (EXAMPLES / file).is_file(), f"{row}: missing example {file}"


def test_every_example_model_is_named_in_the_section_table() -> None:
    named = {file for files in SECTIONS.values() for file in files}
    assert named == {p.name for p in EXAMPLES.glob("*.uml")}


def test_the_example_models_are_exactly_what_make_examples_writes() -> None:
    built = _make_examples().build_all()
    assert set(built) == {p.name for p in EXAMPLES.glob("*.uml")}
    for name, data in built.items():
        assert (EXAMPLES / name).read_bytes() == data, f"{name} is stale: run tests/fixtures/guide/make_examples.py"


@pytest.mark.parametrize("name", CLEAN)
def test_every_example_except_the_broken_ones_checks_without_errors(name: str) -> None:
    errors = [f"{d.code} {d.message}" for d in check(EXAMPLES / name) if d.severity is Severity.ERROR]
    assert errors == []
    assert lifted(name).agents, "the example holds an EARL system"


@pytest.mark.parametrize("name", sorted(BROKEN))
def test_each_broken_example_reports_exactly_the_errors_it_shows(name: str) -> None:
    assert codes(name, Severity.ERROR) == BROKEN[name]


# ---------------------------------------------------------------------------- 1. three routes


def _shape(model: EarlModel) -> dict[str, object]:
    """What a model says, whatever the names and the route that recognised it."""

    def kinds(link_end: str) -> str:
        sub = model.subsystem_of(link_end)
        return sub.kind if sub is not None else "?"

    return {
        "systems": len(model.systems),
        "robots": len(model.robots),
        "agents": [(a.computed_type, len(a.subsystems)) for a in model.agents],
        "subsystems": [
            (s.kind, len(s.inputs), len(s.outputs), len(s.memory), len(s.functions)) for s in model.subsystems
        ],
        "links": sorted((kinds(link.source), kinds(link.target)) for link in model.links),
        "stages": [[len(bb.stages) for bb in s.behaviours] for s in model.subsystems],
    }


def test_the_three_routes_give_the_same_subsystem_kinds_buffers_and_links() -> None:
    shapes = {route: _shape(lifted(f"route-{route}.uml")) for route in ROUTES}
    assert shapes["stereotype"] == {
        "systems": 1,
        "robots": 1,
        "agents": [("CE", 3)],
        "subsystems": [("cs", 1, 1, 1, 1), ("ve", 1, 2, 0, 1), ("re", 1, 0, 0, 1)],
        "links": [("cs", "ve"), ("ve", "cs"), ("ve", "re")],
        "stages": [[1], [1], [1]],
    }
    assert shapes["generalisation"] == shapes["stereotype"]
    assert shapes["suffix"] == shapes["stereotype"]


@pytest.mark.parametrize("route", ROUTES)
def test_each_element_records_the_route_that_recognised_it(route: str) -> None:
    model = lifted(f"route-{route}.uml")
    (system,) = model.systems
    assert system.recognised_by == {"suffix": "structure"}.get(route, route)  # a System has no suffix
    assert [r.recognised_by for r in system.robots] == [route]
    assert [a.recognised_by for a in system.agents] == [route]
    assert [s.recognised_by for s in model.subsystems] == [route] * 3
    element_route = "stereotype" if route == "stereotype" else "suffix"  # ports and values cannot specialise
    assert {b.recognised_by for s in model.subsystems for b in (*s.buffers, *s.memory)} == {element_route}
    assert {pf.recognised_by for s in model.subsystems for pf in s.functions} == {element_route}


def test_the_stereotype_route_needs_no_suffix_in_any_name() -> None:
    model = lifted("route-stereotype.uml")
    assert [a.path for a in model.agents] == ["manip"]
    assert [s.path for s in model.subsystems] == ["manip.control", "manip.motorController", "manip.motor"]
    control = subsystem("route-stereotype.uml", "manip.control")
    assert [b.name for b in control.buffers] + [m.name for m in control.memory] == ["feedback", "command", "setpoint"]
    assert [pf.name for pf in control.functions] == ["plan"]
    assert [bb.name for bb in control.behaviours] == ["planning"]


def test_blocks_specialise_the_model_package_blocks_directly_or_through_an_intermediate_block() -> None:
    model = lifted("route-generalisation.uml")
    motor = subsystem("route-generalisation.uml", "manip.motor")
    assert motor.block == "Motor"  # Motor specialises Drive, which specialises Model::RealEffector
    assert (motor.kind, motor.recognised_by) == ("re", "generalisation")
    # the blocks of the Model package are the concepts, not part of the system
    assert {s.block for s in model.subsystems} == {"ManipulatorControl", "MotorController", "Motor"}
    assert [a.block for a in model.agents] == ["ManipulatorAgent"]


def test_a_suffix_may_be_carried_by_the_part_name_or_the_block_name() -> None:
    model = lifted("route-suffix.uml")
    assert [r.name for r in model.robots] == ["arm/r"]
    assert [a.name for a in model.agents] == ["manip/a"]
    kinds = {s.name: (s.kind, s.block) for s in model.subsystems}
    assert kinds == {
        "cs": ("cs", "ManipulatorControl"),  # the bare abbreviation as part name
        "motorController/ve": ("ve", "MotorController"),  # the part name
        "motor": ("re", "Motor/re"),  # the block name
    }


def test_a_model_may_mix_the_three_routes() -> None:
    model = lifted("route-mixed.uml")
    (system,) = model.systems
    assert (system.name, system.recognised_by) == ("CellSystem", "stereotype")
    assert [(r.name, r.recognised_by) for r in system.robots] == [("arm", "generalisation")]  # EARL::Robot
    assert [(a.name, a.recognised_by) for a in system.agents] == [("manip/a", "suffix")]
    assert [(s.name, s.kind, s.recognised_by) for s in model.subsystems] == [
        ("cs", "cs", "suffix"),
        ("motorController", "ve", "stereotype"),
        ("motor", "re", "generalisation"),
    ]
    cs = subsystem("route-mixed.uml", "manip/a.cs")
    assert [(b.name, b.direction, b.recognised_by) for b in cs.buffers] == [("command", "out", "stereotype")]
    assert [(m.name, m.recognised_by) for m in cs.memory] == [("setpoint/m", "suffix")]
    assert model.agents[0].computed_type == "CE"


def test_disagreeing_routes_are_reported_and_the_stereotype_wins() -> None:
    ve = subsystem("route-conflict.uml", "manip.motorController")
    assert ve.block == "MotorController/re"  # stereotyped «VirtualEffector»
    assert (ve.kind, ve.recognised_by) == ("ve", "stereotype")
    found = [d for d in check(EXAMPLES / "route-conflict.uml") if d.code == "R001"]
    assert len(found) == 1
    assert "VirtualEffector" in found[0].message and "RealEffector" in found[0].message
    assert found[0].severity is Severity.WARNING
    assert _shape(lifted("route-conflict.uml")) == _shape(lifted("route-stereotype.uml"))


# ---------------------------------------------------------------------------- 2. structure


def test_buffers_are_ports_typed_by_datatypes_and_memory_is_a_value_property() -> None:
    control = subsystem("route-generalisation.uml", "manip.control")
    assert [(b.name, b.direction, b.datatype) for b in control.buffers] == [
        ("feedback/ib", "in", "DataTypes::Feedback"),
        ("command/ob", "out", "DataTypes::Command"),
    ]
    assert [(m.name, m.datatype) for m in control.memory] == [("setpoint/m", "Real")]


@pytest.mark.parametrize("route", ROUTES)
def test_a_link_goes_from_the_output_buffer_to_the_input_buffer_whatever_the_order_of_its_ends(route: str) -> None:
    model = lifted(f"route-{route}.uml")
    (back,) = [link for link in model.links if link.name.endswith(("control", "cs"))]
    assert back.scope == "agent"
    # the connector lists the cs Input Buffer first
    assert model.buffer(back.ends[0]).direction == "in"  # type: ignore[union-attr]
    assert model.buffer(back.source).direction == "out"  # type: ignore[union-attr]
    assert model.subsystem_of(back.source).kind == "ve"  # type: ignore[union-attr]
    assert model.subsystem_of(back.target).kind == "cs"  # type: ignore[union-attr]


def test_agents_sit_in_a_robot_or_directly_in_the_system() -> None:
    model = lifted("inter-agent-links.uml")
    (system,) = model.systems
    assert [(r.name, r.agents) for r in system.robots] == [("arm/r", ("manip/a",))]
    assert {a.name: a.robot for a in system.agents} == {"manip/a": "arm/r", "task/a": ""}


def test_inter_agent_links_join_control_subsystems_through_nested_connector_ends() -> None:
    model = lifted("inter-agent-links.uml")
    (system,) = model.systems
    links = {link.name: link for link in system.links}
    assert set(links) == {"task/a,manip/a", "manip/a,task/a", "status"}
    assert all(link.scope == "system" and link.owner == "CellSystem" for link in system.links)
    forward = links["task/a,manip/a"]
    assert (forward.source, forward.target) == ("task/a.cs.manipulatorCommand/ob", "manip/a.cs.manipulatorCommand/ib")
    back = links["manip/a,task/a"]  # written with the Input Buffer end first
    assert back.ends == ("task/a.cs.manipulatorState/ib", "manip/a.cs.manipulatorState/ob")
    assert (back.source, back.target) == ("manip/a.cs.manipulatorState/ob", "task/a.cs.manipulatorState/ib")
    assert {a.name: a.computed_type for a in model.agents} == {"manip/a": "CT", "task/a": "CT"}


def test_a_link_may_drop_values_where_both_its_buffers_are_best_effort() -> None:
    model = lifted("inter-agent-links.uml")
    dropping = {b.path: b.reliability for sub in model.subsystems for b in sub.inputs + sub.outputs
                if b.reliability != "reliable"}
    assert dropping == {"manip/a.cs.status/ob": "best_effort", "task/a.cs.status/ib": "best_effort"}


def test_a_link_named_off_the_convention_is_reported_as_information_only() -> None:
    found = [d for d in check(EXAMPLES / "inter-agent-links.uml") if d.code == "C008"]
    assert [(d.severity, d.element) for d in found] == [(Severity.INFO, "status")]
    assert "manip/a,task/a" in found[0].message


def _trajectory_field(name: str):
    trajectory = lifted("datatypes.uml").datatypes["DataTypes::Trajectory"]
    field = trajectory.field_named(name)
    assert field is not None, name
    return field


def test_datatype_fields_may_be_datatypes_again() -> None:
    model = lifted("datatypes.uml")
    cs = subsystem("datatypes.uml", "manip/a.cs")
    assert [b.datatype for b in cs.buffers] == ["DataTypes::Trajectory"] * 2
    assert _trajectory_field("points").type == "DataTypes::JointPosition"
    assert _trajectory_field("goal").type == "DataTypes::Pose"
    joint_position = model.datatypes["DataTypes::JointPosition"]
    assert joint_position.kind == "struct" and [f.name for f in joint_position.fields] == ["q"]


def test_a_fixed_multiplicity_is_a_fixed_array_and_a_star_or_zero_to_n_a_variable_one() -> None:
    q = lifted("datatypes.uml").datatypes["DataTypes::JointPosition"].field_named("q")
    assert q is not None and (q.lower, q.upper, q.is_fixed_array, q.type) == (6, 6, True, "Real")
    points = _trajectory_field("points")  # [*]
    assert (points.lower, points.upper, points.is_array, points.is_fixed_array) == (0, None, True, False)
    via = _trajectory_field("via")  # [0..4]
    assert (via.lower, via.upper, via.is_array, via.is_fixed_array) == (0, 4, True, False)
    goal = _trajectory_field("goal")  # [0..1]
    assert (goal.lower, goal.upper, goal.is_fixed_array) == (0, 1, False)
    label = _trajectory_field("label")  # no multiplicity: one value
    assert (label.lower, label.upper, label.is_array) == (1, 1, False)


def test_primitive_types_are_recognised_by_their_uml_ecore_and_java_names() -> None:
    model = lifted("datatypes.uml")
    types = {name: _trajectory_field(name).type for name in (
        "label", "valid", "count", "segments", "period",
        "ecorePeriod", "ecoreValid", "ecoreCount", "ecoreLabel", "javaSpeed",
    )}  # fmt: skip
    assert types == {
        "label": "String", "valid": "Boolean", "count": "Integer", "segments": "Integer", "period": "Real",
        "ecorePeriod": "Real", "ecoreValid": "Boolean", "ecoreCount": "Integer", "ecoreLabel": "String",
        "javaSpeed": "Real",
    }  # fmt: skip
    for name, kind in (("Boolean", "boolean"), ("Integer", "integer"), ("Real", "real"), ("String", "string")):
        assert (model.datatypes[name].kind, model.datatypes[name].primitive) == ("primitive", kind)
    number = model.datatypes[_trajectory_field("gain").type]  # a uml:PrimitiveType of the model
    assert (number.name, number.kind, number.primitive) == ("Number", "primitive", "real")


def test_an_enumeration_is_a_datatype_with_its_literals() -> None:
    mode = lifted("datatypes.uml").datatypes[_trajectory_field("mode").type]
    assert (mode.qualified_name, mode.kind) == ("DataTypes::Mode", "enumeration")
    assert mode.literals == ("HOLD", "MOVE", "STOP")


def test_a_value_type_with_owned_attributes_is_a_composite_datatype() -> None:
    pose = lifted("datatypes.uml").datatypes["DataTypes::Pose"]
    assert pose.kind == "struct"
    assert [(f.name, f.type) for f in pose.fields] == [("x", "Real"), ("y", "Real"), ("theta", "Real")]
    memory = subsystem("datatypes.uml", "manip/a.cs").memory
    assert [(m.name, m.datatype) for m in memory] == [("lastPose/m", "DataTypes::Pose")]


# ---------------------------------------------------------------------------- replicated instances


def test_a_replicated_part_with_k_becomes_n_instances() -> None:
    (agent,) = lifted("replication.uml").agents
    assert [(s.name, s.template, s.index) for s in agent.ve] == [
        (f"motorController{k}/ve", "motorControllerK/ve", k) for k in (1, 2, 3)
    ]
    assert len({s.block_id for s in agent.ve}) == 1  # the instances share their definition


def test_a_replicated_part_without_k_gets_the_index_before_the_suffix() -> None:
    (agent,) = lifted("replication.uml").agents
    assert [(s.name, s.template, s.index) for s in agent.re] == [(f"motor{k}/re", "motor/re", k) for k in (1, 2, 3)]


def test_replicated_ports_and_memory_become_n_instances() -> None:
    cs = subsystem("replication.uml", "manip/a.cs")
    assert [b.name for b in cs.inputs] == [f"motorControllerState{k}/ib" for k in (1, 2, 3)]
    assert [b.name for b in cs.outputs] == [f"motorControllerCommand{k}/ob" for k in (1, 2, 3)] + ["mode/ob"]
    assert [(m.name, m.template, m.index) for m in cs.memory] == [
        (f"windingCurrent{k}/m", "windingCurrentK/m", k) for k in (1, 2, 3)
    ]
    assert [b.index for b in cs.outputs] == [1, 2, 3, 0]


def test_a_connector_between_two_replicated_ends_connects_instance_k_to_instance_k() -> None:
    model = lifted("replication.uml")
    (agent,) = model.agents
    commands = [link for link in agent.links if link.template == "cs,motorControllerK/ve"]
    assert [(link.name, link.source, link.target) for link in commands] == [
        (f"cs,motorController{k}/ve", f"manip/a.cs.motorControllerCommand{k}/ob",
         f"manip/a.motorController{k}/ve.motorControllerCommand/ib")
        for k in (1, 2, 3)
    ]
    states = [(link.source, link.target) for link in agent.links if link.template == "motorControllerK/ve,cs"]
    assert states == [(f"manip/a.motorController{k}/ve.motorControllerState/ob",
                       f"manip/a.cs.motorControllerState{k}/ib") for k in (1, 2, 3)]
    # two replicated parts: motorControllerK/ve [3] and motor/re [3]
    currents = [(link.source, link.target) for link in agent.links if link.template == "motorControllerK/ve,motor/re"]
    assert currents == [(f"manip/a.motorController{k}/ve.desiredCurrent/ob",
                         f"manip/a.motor{k}/re.desiredCurrent/ib") for k in (1, 2, 3)]


def test_an_end_with_one_instance_fans_out_to_every_instance_of_the_other_end() -> None:
    (agent,) = lifted("replication.uml").agents
    fan_out = [(link.source, link.target) for link in agent.links if link.template == "mode"]
    assert fan_out == [("manip/a.cs.mode/ob", f"manip/a.motorController{k}/ve.mode/ib") for k in (1, 2, 3)]


def test_replicated_predicate_forms_range_over_every_instance() -> None:
    cs = subsystem("replication.uml", "manip/a.cs")
    assert cs.scope is not None
    for name, op in (("anyStop/pp", "or"), ("eachStop/pp", "or"), ("allStopped/pp", "and")):
        pp = cs.predicate(name)
        assert pp is not None and pp.fun is not None
        expr = parse_predicate(pp.fun.text)
        replicated = [n for n in walk(expr) if isinstance(n, Replicated)]
        assert [(r.op, cs.scope.replication_count(r)) for r in replicated] == [(op, 3)], name
    assert parse_predicate(cs.predicate("anyStop/pp").fun.text) == parse_predicate(  # type: ignore[union-attr]
        cs.predicate("eachStop/pp").fun.text  # type: ignore[union-attr]
    )


# ---------------------------------------------------------------------------- 3. behaviour: FSM


def test_the_initial_state_is_the_target_of_the_transition_from_the_initial_pseudostate() -> None:
    fsm = subsystem("fsm.uml", "manip/a.cs").fsm
    assert fsm is not None
    assert fsm.path == "manip/a.cs.fsm"
    assert [s.name for s in fsm.states] == ["idle", "move", "stop"]
    assert fsm.initial_states == ("idle",) and fsm.initial == "idle"


def test_transitions_are_named_source_destination_and_guarded_by_their_initial_condition() -> None:
    fsm = subsystem("fsm.uml", "manip/a.cs").fsm
    assert fsm is not None
    assert [(t.name, t.source, t.target) for t in fsm.transitions] == [
        ("idle,move/t", "idle", "move"),
        ("move,move/t", "move", "move"),
        ("move,idle/t", "move", "idle"),
        ("idle,stop/t", "idle", "stop"),
        ("move,stop/t", "move", "stop"),
        ("stop,idle/t", "stop", "idle"),
    ]
    first = fsm.transitions[0].condition
    assert first is not None
    assert (first.text, first.language, first.role, first.owner) == (
        "newTarget/pp ∧ ¬stop/pp", "EARL", "ic", "manip/a.cs.fsm.idle,move/t")


def test_guards_in_unicode_word_and_c_notation_mean_the_same() -> None:
    fsm = subsystem("fsm.uml", "manip/a.cs").fsm
    assert fsm is not None
    guards = {t.name: parse_predicate(t.condition.text) for t in fsm.transitions}  # type: ignore[union-attr]
    expected = And((PredicateRef("newTarget/pp"), Not(PredicateRef("stop/pp"))))
    assert guards["idle,move/t"] == expected  # ∧ ¬
    assert guards["move,move/t"] == expected  # and not
    assert guards["move,idle/t"] == And((PredicateRef("finished/pp"), Not(PredicateRef("stop/pp"))))  # && !
    assert guards["move,stop/t"] == guards["idle,stop/t"] == PredicateRef("stop/pp")  # x/pp.fun is x/pp


def test_transition_priorities_default_to_zero_and_model_order_breaks_ties() -> None:
    fsm = subsystem("fsm.uml", "manip/a.cs").fsm
    assert fsm is not None
    assert {t.name: t.priority for t in fsm.transitions} == {
        "idle,move/t": 0, "move,move/t": 1, "move,idle/t": 0, "idle,stop/t": 2, "move,stop/t": 2, "stop,idle/t": 0,
    }  # fmt: skip
    assert [t.order for t in fsm.transitions] == list(range(6))
    from_move = sorted((t for t in fsm.transitions if t.source == "move"), key=lambda t: (-t.priority, t.order))
    assert [t.name for t in from_move] == ["move,stop/t", "move,move/t", "move,idle/t"]


def test_each_state_runs_its_basic_behaviour_with_tc_and_ec_and_a_missing_condition_is_false() -> None:
    cs = subsystem("fsm.uml", "manip/a.cs")
    assert cs.fsm is not None
    assert {s.name: s.behaviours for s in cs.fsm.states} == {
        "idle": ("idle/bb",), "move": ("move/bb",), "stop": ("stop/bb",),
    }
    move = cs.behaviour("move/bb")
    assert move is not None and move.tc is not None
    assert (move.tc.text, move.tc.role, move.tc.language) == ("finished/pp ∨ stop/pp ∨ newTarget/pp", "tc", "EARL")
    assert move.ec is None  # not modelled: FALSE
    idle = cs.behaviour("idle/bb")
    assert idle is not None and idle.ec is not None and (idle.ec.text, idle.ec.role) == ("FALSE", "ec")
    assert "B002" not in codes("fsm.uml")


def test_states_sharing_a_basic_behaviour_owned_by_the_block_run_it() -> None:
    cs = subsystem("shared-basic-behaviour.uml", "manip/a.cs")
    assert cs.fsm is not None
    assert {s.name: s.behaviours for s in cs.fsm.states} == {
        "idle": ("idle/bb",), "jointMove": ("move/bb",), "operationalMove": ("move/bb",),
    }
    assert [bb.name for bb in cs.behaviours] == ["idle/bb", "move/bb"]
    move = cs.behaviour("move/bb")
    assert move is not None and move.path == "manip/a.cs.move/bb"
    assert move.stages == (("move/pf",),)
    assert move.tc is not None and move.tc.text == "finished/pp"


def test_states_sharing_an_empty_basic_behaviour_run_it() -> None:
    cs = subsystem("shared-basic-behaviour-empty.uml", "manip/a.cs")
    assert cs.fsm is not None
    assert {s.name: s.behaviours for s in cs.fsm.states} == {"ready": ("wait/bb",), "paused": ("wait/bb",)}
    assert [bb.name for bb in cs.behaviours] == ["wait/bb"]


# ---------------------------------------------------------------------------- stages


def test_the_calls_between_a_fork_and_a_join_are_one_stage() -> None:
    move = subsystem("stages.uml", "manip/a.cs").behaviour("move/bb")
    assert move is not None and move.activity_problems == ()
    assert move.stages == (
        ("calculatePosition/pf", "jointMove/pf"),
        ("outputManipState/pf", "outputMotorCon/pf"),
    )


def test_a_plain_sequence_of_calls_is_one_stage_per_call() -> None:
    hold = subsystem("stages.uml", "manip/a.cs").behaviour("hold/bb")
    assert hold is not None and hold.activity_problems == ()
    assert hold.stages == (("calculatePosition/pf",), ("outputManipState/pf",), ("trace/pf",))


def test_a_partial_transition_function_may_be_an_opaque_behaviour_or_an_activity() -> None:
    cs = subsystem("stages.uml", "manip/a.cs")
    assert [(pf.name, pf.language) for pf in cs.functions] == [
        ("calculatePosition/pf", "C++"), ("jointMove/pf", "C++"), ("outputManipState/pf", "C++"),
        ("outputMotorCon/pf", "C++"), ("trace/pf", ""),
    ]  # fmt: skip
    assert cs.function("trace/pf").path == "manip/a.cs.trace/pf"  # type: ignore[union-attr]


def test_two_pf_of_one_stage_writing_the_same_memory_or_output_buffer_are_reported() -> None:
    found = {d.code: d for d in check(EXAMPLES / "stages-conflict.uml") if d.code in ("T001", "T002")}
    assert set(found) == {"T001", "T002"}
    assert "jointPos/m" in found["T001"].message and "manipState/ob" in found["T002"].message
    assert found["T001"].element == "manip/a.cs.move/bb"


# ---------------------------------------------------------------------------- what a pf reads and writes


def test_pf_parameters_in_read_out_write_and_inout_both() -> None:
    pf = subsystem("pf-accesses.uml", "manip/a.cs").function("integrate/pf")
    assert pf is not None
    assert [(a.name, a.mode) for a in pf.accesses] == [
        ("command/ib", "read"), ("position/m", "readwrite"), ("velocity/mo", "write"), ("state/ob", "write"),
    ]  # fmt: skip
    assert pf.reads == ("manip/a.cs.command/ib", "manip/a.cs.position/m")
    assert pf.writes == ("manip/a.cs.position/m", "manip/a.cs.velocity/m", "manip/a.cs.state/ob")
    assert all(a.foreign == "" for a in pf.accesses)


def test_memory_parameters_named_m_mi_or_mo_name_the_same_memory() -> None:
    cs = subsystem("pf-accesses.uml", "manip/a.cs")
    targets = {a.name: a.targets for pf in cs.functions for a in pf.accesses}
    assert targets["position/m"] == targets["position/mi"] == ("manip/a.cs.position/m",)
    assert targets["velocity/mo"] == targets["velocity/mi"] == ("manip/a.cs.velocity/m",)
    regulate = cs.function("regulate/pf")
    assert regulate is not None and regulate.reads == ("manip/a.cs.position/m", "manip/a.cs.velocity/m")
    assert "T003" not in codes("pf-accesses.uml")


def test_a_replicated_memory_named_by_its_k_name_is_every_instance() -> None:
    regulate = subsystem("pf-accesses.uml", "manip/a.cs").function("regulate/pf")
    assert regulate is not None
    assert regulate.writes == tuple(f"manip/a.cs.windingCurrent{k}/m" for k in (1, 2, 3))


def test_a_memory_parameter_named_mo_is_a_write_even_with_the_default_direction() -> None:
    keep = subsystem("pf-accesses.uml", "manip/a.cs").function("keepTarget/pf")
    assert keep is not None
    assert keep.reads == ("manip/a.cs.command/ib",)
    assert keep.writes == ("manip/a.cs.target/m",)


# ---------------------------------------------------------------------------- primitive predicates


def test_a_primitive_predicate_with_an_earl_body_has_it_as_its_fun() -> None:
    cs = subsystem("primitive-predicates.uml", "manip/a.cs")
    stop = cs.predicate("stop/pp")
    assert stop is not None and stop.fun is not None
    assert (stop.path, stop.language, stop.recognised_by) == ("manip/a.cs.stop/pp", "EARL", "stereotype")
    assert (stop.fun.text, stop.fun.role, stop.fun.owner) == ("command/ib.msg.stop", "fun", "manip/a.cs.stop/pp")


def test_a_primitive_predicate_in_another_language_is_user_code_without_fun() -> None:
    collision = subsystem("primitive-predicates.uml", "manip/a.cs").predicate("collision/pp")
    assert collision is not None
    assert collision.fun is None
    assert (collision.language, collision.body) == ("C++", "return gripper_.collision();")


def test_a_constraint_with_an_earl_specification_is_a_primitive_predicate() -> None:
    ready = subsystem("primitive-predicates.uml", "manip/a.cs").predicate("ready/pp")
    assert ready is not None and ready.fun is not None
    assert (ready.fun.text, ready.language, ready.recognised_by) == (
        "not stop and (finished/pp.fun or FALSE)", "EARL", "suffix")
    assert parse_predicate(ready.fun.text) == And((
        Not(PredicateRef("stop")), Or((PredicateRef("finished/pp"), Const(False)))))


def test_an_opaque_behaviour_may_be_a_primitive_predicate() -> None:
    idle = subsystem("primitive-predicates.uml", "manip/a.cs").predicate("idle/pp")
    assert idle is not None and idle.fun is not None
    assert parse_predicate(idle.fun.text) == Or((
        Not(PredicateRef("newTarget/pp")), And((PredicateRef("stop/pp"), Const(True)))))


@pytest.mark.parametrize("name", ["primitive-predicates.uml", "fsm.uml", "replication.uml", "exclusions.uml"])
def test_every_condition_of_the_examples_parses_and_names_known_elements(name: str) -> None:
    model = lifted(name)
    for sub in model.definitions():
        for condition in sub.conditions():
            assert condition.expr is not None and condition.problems == (), condition
    assert codes(name) & {"B005", "B008"} == set()


def test_syntax_errors_are_b008_with_the_column_and_unknown_names_are_b005() -> None:
    found = {d.code: d for d in check(EXAMPLES / "predicate-errors.uml") if d.code in ("B005", "B008")}
    assert found["B008"].element == "manip/a.cs.fsm.run,halt/t"
    assert found["B008"].location.column == len("stop/pp ∧ ∧")  # the second ∧
    assert found["B005"].element == "manip/a.cs.halt/bb"
    assert "unknown/pp" in found["B005"].message


def test_mutually_exclusive_predicates_are_read_from_both_forms() -> None:
    cs = subsystem("exclusions.uml", "manip/a.cs")
    assert [(e.name, e.predicates) for e in cs.exclusions] == [
        ("jointOrOperational", ("newJointPos/pp", "newOperationalPos/pp")),  # «Exclusion», constrainedElement
        ("openOrClose", ("open/pp", "close/pp")),  # exclusive(...) specification, .fun dropped
    ]
    assert [pp.name for pp in cs.predicates] == ["newJointPos/pp", "newOperationalPos/pp", "open/pp", "close/pp"]


# ---------------------------------------------------------------------------- agent types


def test_the_declared_agent_type_is_kept_next_to_the_computed_one() -> None:
    agents = {a.name: (a.declared_type, a.computed_type) for a in lifted("agent-type.uml").agents}
    assert agents == {"manip/a": ("CET", "CET"), "task/a": ("CT", "CT"), "monitor/a": ("", "CR")}
    kinds = {s.path: s.kind for s in lifted("agent-type.uml").subsystems}
    assert kinds["monitor/a.filter/vr"] == "vr" and kinds["monitor/a.sensor/rr"] == "rr"
    assert "S007" not in codes("agent-type.uml")


def test_a_declared_type_that_differs_from_the_computed_one_is_reported_by_s007() -> None:
    agents = {a.name: (a.declared_type, a.computed_type) for a in lifted("agent-type-mismatch.uml").agents}
    assert agents["manip/a"] == ("CERT", "CET")
    found = [d for d in check(EXAMPLES / "agent-type-mismatch.uml") if d.code == "S007"]
    assert [(d.severity, d.element) for d in found] == [(Severity.ERROR, "manip/a")]


def test_activation_example_lifts_its_group_state_activation_and_queue() -> None:
    cs = subsystem("activation.uml", "manip/a.cs")
    (group,) = cs.buffer_groups
    assert (group.name, group.obligatory, group.optional) == ("drive", ("feedback/ib",), ("command/ib",))
    command = next(b for b in cs.inputs if b.name == "command/ib")
    assert (command.receive, command.queue_size) == ("queue", 4)
    assert cs.fsm is not None
    for state in cs.fsm.states:
        activation = state.activation
        assert (activation.group, activation.min_period, activation.first_timeout, activation.next_timeout) == (
            "drive", 0.001, 0.1, 0.01)


def test_ltl_property_example_holds_two_properties_that_verify_proves(capsys: pytest.CaptureFixture[str]) -> None:
    import json

    from earl_m2t.cli.app import main

    loaded = load(EXAMPLES / "ltl-property.uml")
    assert [(p.label, p.text) for p in loaded.properties] == [
        ("stopLatches", "[] (manip/a.cs@stopped -> [] manip/a.cs@stopped)"),
        ("stopIsHeeded", "[] (manip/a.cs.stop/pp -> manip/a.cs@stopped)"),
    ]
    assert main(["verify", str(EXAMPLES / "ltl-property.uml"), "--format", "json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert [line for line in result["proven"] if line.endswith(" holds")] == [
        "[] (manip/a.cs@stopped -> [] manip/a.cs@stopped) holds",
        "[] (manip/a.cs.stop/pp -> manip/a.cs@stopped) holds",
    ]


# ---------------------------------------------------------------------------- 3. variable structure


def test_configurations_name_variable_agents_and_links_and_the_coordinator_switches_them() -> None:
    model = lifted("variable-structure.uml")
    (system,) = model.systems
    assert [(c.name, c.agents, c.links, c.switch_timeout) for c in system.configurations] == [
        ("useA", ("manipA/a",), ("task/a,manipA/a", "manipA/a,task/a"), 0.05),
        ("useB", ("manipB/a",), ("task/a,manipB/a", "manipB/a,task/a"), 0.05),
    ]
    assert {a.path: (a.optional, a.reactivation) for a in system.agents} == {
        "manipA/a": (True, "resume"), "manipB/a": (True, "resume"), "task/a": (False, "restart")}
    task = subsystem("variable-structure.uml", "task/a.cs")
    assert task.fsm is not None and [(s.name, s.configuration) for s in task.fsm.states] == [
        ("withA", "useA"), ("withB", "useB")]
    manip = subsystem("variable-structure.uml", "manipA/a.cs")
    assert manip.fsm is not None and [(s.name, s.quiescent) for s in manip.fsm.states] == [
        ("idle", True), ("moving", False)]
    assert codes("variable-structure.uml") == set()


def test_a_behaviour_ends_on_a_failed_pf_and_a_transition_is_taken_on_the_error() -> None:
    model = lifted("pf-health.uml")
    [sub] = model.subsystems
    assert sub.fsm is not None
    [transition] = sub.fsm.transitions
    assert transition.condition is not None and transition.condition.expr == BuiltIn(BuiltInPredicate.IN_ERROR)
    driving = sub.behaviour(sub.fsm.states[0].behaviours[0])
    assert driving is not None and driving.ec is not None
    assert driving.ec.expr == Not(BuiltIn(BuiltInPredicate.BEHAVIOUR_OK))
