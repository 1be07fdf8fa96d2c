"""The Papyrus XMI builder and the reference sample it writes."""

from __future__ import annotations

import importlib.util
import re
from collections import Counter
from pathlib import Path
from types import ModuleType

import pytest
from lxml import etree

from tests.support.papyrus_builder import (
    BOOLEAN,
    EARL_NS,
    EARL_STEREOTYPES,
    INTEGER,
    REAL,
    End,
    ModelBuilder,
    Multiplicity,
    Param,
)

ROOT = Path(__file__).resolve().parents[2]

SAMPLE = ROOT / "samples" / "pick_and_place" / "pick_and_place.uml"

XMI = "http://www.omg.org/spec/XMI/20131001"
UML = "http://www.eclipse.org/uml2/5.0.0/UML"
BLOCKS = "http://www.eclipse.org/papyrus/sysml/1.6/SysML/Blocks"
XMI_ID = f"{{{XMI}}}id"
XMI_TYPE = f"{{{XMI}}}type"

# Attributes holding one id (IDREF) or several (IDREFS) in the files the builder writes.
IDREF_ATTRS = {
    "type", "general", "classifierBehavior", "guard", "source", "target", "partWithPort",
    "role", "behavior", "annotatedElement", "constrainedElement", "incoming", "outgoing",
    "node", "propertyPath",
}  # fmt: skip


def _load_make_sample() -> ModuleType:
    spec = importlib.util.spec_from_file_location("make_sample", ROOT / "scripts" / "make_sample.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def make_sample() -> ModuleType:
    return _load_make_sample()


@pytest.fixture(scope="module")
def tree() -> etree._ElementTree:
    return etree.parse(str(SAMPLE), etree.XMLParser(resolve_entities=False, no_network=True))


@pytest.fixture(scope="module")
def by_id(tree: etree._ElementTree) -> dict[str, etree._Element]:
    return {el.get(XMI_ID): el for el in tree.iter() if el.get(XMI_ID)}


def _typed(tree: etree._ElementTree, xmi_type: str) -> list[etree._Element]:
    return [el for el in tree.iter() if el.get(XMI_TYPE) == xmi_type]


def _named(tree: etree._ElementTree, xmi_type: str, name: str) -> etree._Element:
    found = [el for el in _typed(tree, xmi_type) if el.get("name") == name]
    assert len(found) == 1, f"{xmi_type} {name!r}: {len(found)} found"
    return found[0]


def _applications(tree: etree._ElementTree) -> list[etree._Element]:
    return list(tree.getroot())[1:]


def _earl(tree: etree._ElementTree, name: str) -> list[etree._Element]:
    return [el for el in _applications(tree) if el.tag == f"{{{EARL_NS}}}{name}"]


def _names(elements: list[etree._Element]) -> list[str]:
    return [el.get("name") for el in elements]


# ---- determinism and the committed file ---------------------------------------------


def test_two_builds_are_byte_identical(make_sample: ModuleType) -> None:
    assert make_sample.build() == make_sample.build()


def test_committed_sample_matches_the_script(make_sample: ModuleType) -> None:
    assert SAMPLE.read_bytes() == make_sample.build(), "run: python scripts/make_sample.py"


def test_ids_do_not_depend_on_unrelated_elements() -> None:
    def build(extra: bool) -> str:
        mb = ModelBuilder("M")
        pkg = mb.package("P")
        if extra:
            pkg.data_type("Extra")
        return pkg.block("B").id

    assert build(False) == build(True)


# ---- Papyrus dialect -------------------------------------------------------------------


def test_header_namespaces_and_root(tree: etree._ElementTree) -> None:
    data = SAMPLE.read_bytes()
    assert data.startswith(b'<?xml version="1.0" encoding="UTF-8"?>\n<xmi:XMI xmi:version="20131001" ')
    root = tree.getroot()
    assert root.tag == f"{{{XMI}}}XMI"
    assert root.nsmap == {
        "xmi": XMI,
        "xsi": "http://www.w3.org/2001/XMLSchema-instance",
        "Blocks": BLOCKS,
        "EARL": EARL_NS,
        "ecore": "http://www.eclipse.org/emf/2002/Ecore",
        "uml": UML,
    }
    assert re.fullmatch(r"http:///schemas/EARL/_[A-Za-z0-9_-]{22}/0", EARL_NS)
    location = root.get("{http://www.w3.org/2001/XMLSchema-instance}schemaLocation").split()
    assert location[2] == EARL_NS and location[3].startswith("EARL.profile.uml#_")
    model = root[0]
    assert model.tag == f"{{{UML}}}Model" and model.get("name") == "PickAndPlace"
    assert model.get(XMI_TYPE) is None
    assert all(el.tag.startswith("{" + BLOCKS) or el.tag.startswith("{" + EARL_NS) for el in root[1:])


def test_layout_is_two_space_indented_utf8() -> None:
    text = SAMPLE.read_bytes().decode("utf-8")
    assert "\t" not in text and "\r" not in text
    for line in text.splitlines()[1:]:
        indent = len(line) - len(line.lstrip(" "))
        assert indent % 2 == 0, line
    assert "¬emergencyStop/pp.fun" in text  # raw UTF-8, not character references


def test_attribute_order_and_omitted_defaults(tree: etree._ElementTree) -> None:
    text = SAMPLE.read_text(encoding="utf-8")
    for tag in re.findall(r"<[A-Za-z]+ xmi:type=[^>]*>", text):
        attrs = re.findall(r' ([\w:]+)="', tag)
        assert attrs[:2] == ["xmi:type", "xmi:id"] or attrs[:1] == ["xmi:type"], tag
        if "name" in attrs and "xmi:id" in attrs:
            assert attrs.index("name") == 2, tag
    assert 'kind="initial"' not in text
    assert 'direction="in"' not in text
    assert 'aggregation="none"' not in text
    for el in tree.iter():
        children = [etree.QName(c).localname for c in el]
        if "language" in children:
            assert children.index("language") < children.index("body")


def test_every_id_is_unique_and_emf_shaped(tree: etree._ElementTree) -> None:
    ids = [el.get(XMI_ID) for el in tree.iter() if el.get(XMI_ID)]
    assert len(ids) == len(set(ids))
    assert all(re.fullmatch(r"_[A-Za-z0-9_-]{22}", i) for i in ids)


def test_every_idref_resolves(tree: etree._ElementTree, by_id: dict[str, etree._Element]) -> None:
    checked = 0
    for el in tree.iter():
        for attr, value in el.attrib.items():
            if attr in IDREF_ATTRS or attr.startswith("base_"):
                if attr == "source" and etree.QName(el).localname == "eAnnotations":
                    continue
                for ref in value.split():
                    assert ref in by_id, f"{attr}={ref} on {el.get(XMI_ID)}"
                    checked += 1
    assert checked > 600


def test_external_references_are_pathmaps_or_the_profile(tree: etree._ElementTree) -> None:
    hrefs = {el.get("href").split("#")[0] for el in tree.iter() if el.get("href")}
    assert hrefs == {
        "pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml",
        "pathmap://SysML16_PROFILES/SysML.profile.uml",
        "http://www.eclipse.org/papyrus/sysml/1.6/SysML",
        "EARL.profile.uml",
    }


# ---- stereotype applications -----------------------------------------------------------


def test_stereotype_applications_point_at_the_right_metaclass(
    tree: etree._ElementTree, by_id: dict[str, etree._Element]
) -> None:
    behaviours = {"uml:OpaqueBehavior", "uml:FunctionBehavior", "uml:Activity", "uml:StateMachine"}
    for app in _applications(tree):
        bases = [(k, v) for k, v in app.attrib.items() if k.startswith("base_")]
        assert len(bases) == 1
        attr, target = bases[0]
        metaclass = attr.removeprefix("base_")
        target_type = by_id[target].get(XMI_TYPE)
        if metaclass == "Behavior":
            assert target_type in behaviours
        else:
            assert target_type == f"uml:{metaclass}", (app.tag, target_type)
        if app.tag.startswith("{" + EARL_NS):
            assert EARL_STEREOTYPES[etree.QName(app).localname] == metaclass


def test_stereotype_counts(tree: etree._ElementTree) -> None:
    counts = Counter(etree.QName(app).localname for app in _applications(tree))
    assert counts == {
        "Block": 12, "NestedConnectorEnd": 8,
        "System": 1, "Robot": 1, "Agent": 3, "ControlSubsystem": 3,
        "VirtualEffector": 2, "RealEffector": 2,
        "InputBuffer": 12, "OutputBuffer": 12, "InternalMemory": 11,
        "InterSubsystemLink": 8, "InterAgentLink": 4,
        "FSM": 7, "FsmState": 11, "FsmTransition": 10, "BasicBehaviour": 11,
        "PartialTransitionFunction": 14, "PrimitivePredicate": 6,
        "Predicate": 32, "Exclusion": 1, "BufferGroup": 1, "LtlProperty": 1,
    }  # fmt: skip


def test_agent_types_and_transition_priorities(tree: etree._ElementTree, by_id: dict[str, etree._Element]) -> None:
    declared = {by_id[a.get("base_Class")].get("name"): a.get("declaredType") for a in _earl(tree, "Agent")}
    assert declared == {"TaskAgent": "CT", "ManipulatorAgent": "CET", "GripperAgent": "CET"}
    priorities = {
        by_id[t.get("base_Transition")].get("name"): t.get("priority") for t in _earl(tree, "FsmTransition")
    }
    assert priorities == {
        "supervise,abort/t": None,
        "idle,jointMove/t": None,
        "jointMove,jointMove/t": "1",
        "idle,operationalMove/t": None,
        "operationalMove,operationalMove/t": "1",
        "jointMove,idle/t": None,
        "operationalMove,idle/t": None,
        "idle,emergencyStop/t": "2",
        "jointMove,emergencyStop/t": "2",
        "operationalMove,emergencyStop/t": "2",
    }


# ---- structure -------------------------------------------------------------------------


def test_element_counts(tree: etree._ElementTree) -> None:
    assert len(_typed(tree, "uml:DataType")) == 12
    assert len(_typed(tree, "uml:Class")) == 12
    assert len(_typed(tree, "uml:Port")) == 24
    assert len(_typed(tree, "uml:Connector")) == 12
    assert len(_typed(tree, "uml:StateMachine")) == 7
    assert len(_typed(tree, "uml:State")) == 11
    assert len(_typed(tree, "uml:Transition")) == 17  # 10 FSM transitions + 7 from initial pseudostates
    assert len(_typed(tree, "uml:Pseudostate")) == 7
    assert len(_typed(tree, "uml:Activity")) == 11
    assert len(_typed(tree, "uml:OpaqueBehavior")) == 14
    assert len(_typed(tree, "uml:FunctionBehavior")) == 6


def test_system_robot_and_agents(tree: etree._ElementTree, by_id: dict[str, etree._Element]) -> None:
    def parts(block: str) -> dict[str, str]:
        cls = _named(tree, "uml:Class", block)
        return {
            p.get("name"): by_id[p.get("type")].get("name")
            for p in cls.findall("ownedAttribute")
            if p.get(XMI_TYPE) == "uml:Property" and p.get("aggregation") == "composite"
        }

    assert parts("PickAndPlaceSystem") == {"pickAndPlace/r": "PickAndPlaceRobot", "task/a": "TaskAgent"}
    assert parts("PickAndPlaceRobot") == {"manip/a": "ManipulatorAgent", "grip/a": "GripperAgent"}
    assert parts("TaskAgent") == {"cs": "TaskControl"}
    assert parts("ManipulatorAgent") == {
        "cs": "ManipulatorControl",
        "motorControllerK/ve": "MotorController",
        "motorK/re": "Motor",
    }
    assert parts("GripperAgent") == {
        "cs": "GripperControl",
        "fingerController/ve": "FingerController",
        "fingerMotor/re": "FingerMotor",
    }
    ve = _named(tree, "uml:Property", "motorControllerK/ve")
    assert ve.find("lowerValue").get("value") == "6" and ve.find("upperValue").get("value") == "6"


def test_links_go_from_output_to_input_buffers(tree: etree._ElementTree, by_id: dict[str, etree._Element]) -> None:
    names = []
    for conn in _typed(tree, "uml:Connector"):
        src, dst = conn.findall("end")
        assert by_id[src.get("role")].get("name").endswith("/ob")
        assert by_id[dst.get("role")].get("name").endswith("/ib")
        assert by_id[src.get("partWithPort")].get(XMI_TYPE) == "uml:Property"
        names.append(conn.get("name"))
    assert names[:4] == ["task/a,manip/a", "manip/a,task/a", "task/a,grip/a", "grip/a,task/a"]
    assert "cs,motorControllerK/ve" in names and "motorK/re,motorControllerK/ve" in names


def test_nested_connector_ends_follow_the_part_path(
    tree: etree._ElementTree, by_id: dict[str, etree._Element]
) -> None:
    nested = {
        n.get("base_ConnectorEnd"): n.get("propertyPath").split()
        for n in _applications(tree)
        if "propertyPath" in n.attrib
    }
    system = _named(tree, "uml:Class", "PickAndPlaceSystem")
    paths = set()
    for conn in system.findall("ownedConnector"):
        for end in conn.findall("end"):
            path = nested[end.get(XMI_ID)]
            assert path[-1] == end.get("partWithPort")
            paths.add(tuple(by_id[p].get("name") for p in path))
    assert paths == {("task/a", "cs"), ("pickAndPlace/r", "manip/a", "cs"), ("pickAndPlace/r", "grip/a", "cs")}


def test_data_types_and_multiplicities(tree: etree._ElementTree) -> None:
    q = _named(tree, "uml:DataType", "JointPosition").find("ownedAttribute")
    assert q.get("name") == "q" and q.find("type").get("href").endswith("#Real")
    assert (q.find("lowerValue").get("value"), q.find("upperValue").get("value")) == ("6", "6")
    setpoint = _named(tree, "uml:DataType", "ManipulatorCommand").find("ownedAttribute")
    assert setpoint.get("name") == "jointPosSetpoint"
    assert setpoint.find("lowerValue").get("value") is None  # 0 is the default and is omitted
    assert setpoint.find("upperValue").get("value") == "1"


# ---- manip/a.cs, paper Tables 4-7 ----------------------------------------------------


def test_manipulator_control_buffers_and_memory(tree: etree._ElementTree) -> None:
    cs = _named(tree, "uml:Class", "ManipulatorControl")
    attrs = cs.findall("ownedAttribute")
    assert _names([a for a in attrs if a.get(XMI_TYPE) == "uml:Port"]) == [
        "manipulatorCommand/ib", "manipulatorState/ob", "motorControllerStateK/ib", "motorControllerCommandK/ob",
    ]  # fmt: skip
    assert _names([a for a in attrs if a.get(XMI_TYPE) == "uml:Property"]) == [
        "motionFinished/m", "currentOperationalPos/m", "currentJointPos/m",
        "emergencyStopCommandK/m", "windingCurrentK/m",
    ]  # fmt: skip


def test_manipulator_control_predicates_and_exclusion(
    tree: etree._ElementTree, by_id: dict[str, etree._Element]
) -> None:
    cs = _named(tree, "uml:Class", "ManipulatorControl")
    pps = {b.get("name"): b for b in cs.findall("ownedBehavior") if b.get(XMI_TYPE) == "uml:FunctionBehavior"}
    assert list(pps) == ["emergencyStop/pp", "motionFinished/pp", "newJointPos/pp", "newOperationalPos/pp", "false/pp"]
    for pp in pps.values():
        assert pp.findtext("language") == "EARL"
        ret = pp.find("ownedParameter")
        assert (ret.get("name"), ret.get("direction")) == ("return", "return")
        assert ret.find("type").get("href").endswith("#Boolean")
    assert pps["newJointPos/pp"].findtext("body") == "newData(manipulatorCommand/ib.msg.jointPosSetpoint)"
    assert "∨ … ∨ motorControllerStateN/ib.msg.emergencyStopCommand" in pps["emergencyStop/pp"].findtext("body")
    rule = cs.find("ownedRule")
    assert rule.get("name") == "jointOrOperational"
    assert [by_id[i].get("name") for i in rule.get("constrainedElement").split()] == [
        "newJointPos/pp",
        "newOperationalPos/pp",
    ]
    assert rule.find("specification").findtext("body") == "exclusive(newJointPos/pp, newOperationalPos/pp)"
    assert [by_id[e.get("base_Constraint")] for e in _earl(tree, "Exclusion")] == [rule]


def test_manipulator_control_fsm(tree: etree._ElementTree, by_id: dict[str, etree._Element]) -> None:
    cs = _named(tree, "uml:Class", "ManipulatorControl")
    fsm = by_id[cs.get("classifierBehavior")]
    assert fsm.get(XMI_TYPE) == "uml:StateMachine"
    (region,) = fsm.findall("region")
    assert _names([v for v in region.findall("subvertex") if v.get(XMI_TYPE) == "uml:State"]) == [
        "idle", "jointMove", "operationalMove", "emergencyStop",
    ]  # fmt: skip
    initial = region.find("subvertex")
    assert initial.get(XMI_TYPE) == "uml:Pseudostate" and initial.get("kind") is None
    first = region.find("transition")
    assert first.get("source") == initial.get(XMI_ID) and by_id[first.get("target")].get("name") == "idle"
    guards = {}
    for tr in region.findall("transition")[1:]:
        guard = tr.find("ownedRule")
        assert tr.get("guard") == guard.get(XMI_ID)
        spec = guard.find("specification")
        assert spec.get(XMI_TYPE) == "uml:OpaqueExpression" and spec.findtext("language") == "EARL"
        guards[tr.get("name")] = spec.findtext("body")
    assert guards == {
        "idle,jointMove/t": "newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun",
        "jointMove,jointMove/t": "newJointPos/pp.fun ∧ ¬emergencyStop/pp.fun",
        "idle,operationalMove/t": "newOperationalPos/pp.fun ∧ ¬emergencyStop/pp.fun",
        "operationalMove,operationalMove/t": "newOperationalPos/pp.fun ∧ ¬emergencyStop/pp.fun",
        "jointMove,idle/t": "¬emergencyStop/pp.fun",
        "operationalMove,idle/t": "¬emergencyStop/pp.fun",
        "idle,emergencyStop/t": "emergencyStop/pp.fun ∨ inError()",
        "jointMove,emergencyStop/t": "emergencyStop/pp.fun ∨ inError()",
        "operationalMove,emergencyStop/t": "emergencyStop/pp.fun ∨ inError()",
    }


def test_manipulator_control_pf_parameters(tree: etree._ElementTree) -> None:
    cs = _named(tree, "uml:Class", "ManipulatorControl")
    pfs = {
        b.get("name"): [(p.get("name"), p.get("direction") or "in") for p in b.findall("ownedParameter")]
        for b in cs.findall("ownedBehavior")
        if b.get(XMI_TYPE) == "uml:OpaqueBehavior"
    }
    assert pfs["calculatePosition/pf"] == [
        ("motorControllerStateK/ib", "in"), ("currentJointPos/mo", "out"), ("currentOperationalPos/mo", "out"),
    ]  # fmt: skip
    assert pfs["jointMove/pf"] == [
        ("manipulatorCommand/ib", "in"), ("motorControllerStateK/ib", "in"),
        ("motionFinished/mo", "out"), ("windingCurrentK/mo", "out"),
    ]  # fmt: skip
    assert pfs["outputMotorCon/pf"] == [
        ("windingCurrentK/mi", "in"), ("emergencyStopCommandK/mi", "in"), ("motorControllerCommandK/ob", "out"),
    ]  # fmt: skip
    assert len(pfs) == 7
    for b in cs.findall("ownedBehavior"):
        if b.get(XMI_TYPE) == "uml:OpaqueBehavior":
            assert b.findtext("language") == "C++" and b.findtext("body").startswith("//")


def test_basic_behaviours_run_two_parallel_stages(tree: etree._ElementTree, by_id: dict[str, etree._Element]) -> None:
    cs = _named(tree, "uml:Class", "ManipulatorControl")
    expected_tc = {
        "idle/bb": "newJointPos/pp.fun ∨ newOperationalPos/pp.fun ∨ emergencyStop/pp.fun",
        "jointMove/bb": "motionFinished/pp.fun ∨ emergencyStop/pp.fun",
        "operationalMove/bb": "motionFinished/pp.fun ∨ emergencyStop/pp.fun",
        "emergencyStop/bb": "false/pp.fun",
    }
    own_pf = {
        "idle/bb": "passiveRegulation/pf",
        "jointMove/bb": "jointMove/pf",
        "operationalMove/bb": "operationalMove/pf",
        "emergencyStop/bb": "emergencyStop/pf",
    }
    activities = [s.find("doActivity") for s in cs.iter("subvertex") if s.get(XMI_TYPE) == "uml:State"]
    assert _names(activities) == list(expected_tc)
    for act in activities:
        rules = {r.get("name"): r.find("specification").findtext("body") for r in act.findall("ownedRule")}
        # a failing pf ends every behaviour but the error state's own (no way out of it)
        ec = "FALSE" if act.get("name") == "emergencyStop/bb" else "¬behaviourOk()"
        assert rules == {"tc": expected_tc[act.get("name")], "ec": ec}
        nodes = {n.get(XMI_ID): n for n in act.findall("node")}
        assert act.get("node").split() == list(nodes)
        edges = act.findall("edge")
        for n in nodes.values():
            into = [e.get(XMI_ID) for e in edges if e.get("target") == n.get(XMI_ID)]
            out_of = [e.get(XMI_ID) for e in edges if e.get("source") == n.get(XMI_ID)]
            assert (n.get("incoming") or "").split() == into
            assert (n.get("outgoing") or "").split() == out_of
        # Walk the flow: initial -> fork -> 2 calls -> join -> fork -> 2 calls -> join -> final.
        succ = {e.get("source"): [] for e in edges}
        for e in edges:
            succ[e.get("source")].append(e.get("target"))
        (start,) = [i for i, n in nodes.items() if n.get(XMI_TYPE) == "uml:InitialNode"]
        stages, current = [], start
        while nodes[current].get(XMI_TYPE) != "uml:ActivityFinalNode":
            (nxt,) = succ[current]
            if nodes[nxt].get(XMI_TYPE) == "uml:ForkNode":
                calls = succ[nxt]
                stages.append({by_id[nodes[c].get("behavior")].get("name") for c in calls})
                (join,) = {succ[c][0] for c in calls}
                assert nodes[join].get(XMI_TYPE) == "uml:JoinNode"
                current = join
            else:
                current = nxt
        assert stages == [
            {"calculatePosition/pf", own_pf[act.get("name")]},
            {"outputManipState/pf", "outputMotorCon/pf"},
        ]


# ---- builder options -------------------------------------------------------------------


def _small(**options: bool) -> bytes:
    mb = ModelBuilder("Small", **options)
    types = mb.package("DataTypes")
    cmd = types.data_type("Command")
    cmd.field("values", REAL, "*")
    cmd.field("count", INTEGER, "0..1")
    inst = mb.package("SystemInstance")
    model = mb.earl_model()
    cs = inst.block("Control", "ControlSubsystem")
    cs.specialize(model["ControlSubsystem"])
    ve = inst.block("Drive", "VirtualEffector")
    out = cs.output_buffer("command/ob", cmd)
    inp = ve.input_buffer("command/ib", cmd)
    flag = cs.memory("busy/m", BOOLEAN)
    pf = cs.opaque_behavior("send/pf", [Param("command/ob", cmd, "out"), Param("busy/m", BOOLEAN, "inout")])
    fsm = cs.state_machine()
    run = fsm.state("run", initial=True)
    run.do_activity(ec=None).stages([[pf]])
    agent = inst.block("Agent1", "Agent", {"declaredType": "CE"})
    cs_part = agent.part("cs", cs)
    ve_part = agent.part("drive/ve", ve)
    agent.connector("cs,drive/ve", End.at(out, cs_part), End.at(inp, ve_part), "InterSubsystemLink")
    assert flag.name == "busy/m"
    return mb.to_bytes()


def test_builder_without_stereotypes_writes_no_earl() -> None:
    plain = _small(stereotypes=False).decode("utf-8")
    assert "EARL:" not in plain and "schemas/EARL" not in plain and "EARL.profile" not in plain
    assert "<language>EARL</language>" in plain  # conditions stay in the EARL language
    root = etree.fromstring(plain.encode("utf-8"))
    assert {etree.QName(a).localname for a in root[1:]} == {"Block"}
    generals = root.findall(".//generalization")
    assert len(generals) == 1
    assert 'name="ControlSubsystem"' in plain and "uml:Generalization" in plain


def test_builder_small_model_encodings() -> None:
    data = _small()
    assert data == _small()
    root = etree.fromstring(data)
    values = root.find(".//ownedAttribute[@name='values']")
    assert values.find("lowerValue").get("value") is None and values.find("upperValue").get("value") == "*"
    pf = root.find(".//ownedBehavior[@name='send/pf']")
    assert [p.get("direction") for p in pf.findall("ownedParameter")] == ["out", "inout"]
    act = root.find(".//doActivity")
    assert [r.get("name") for r in act.findall("ownedRule")] == ["tc"]
    assert act.find("node[@name='send/pf']").get(XMI_TYPE) == "uml:CallBehaviorAction"
    assert len(act.findall("node")) == 3 and len(act.findall("edge")) == 2


def test_nested_path_option_drops_the_part_with_port() -> None:
    def system(include: bool) -> list[str]:
        mb = ModelBuilder("N", nested_path_includes_part_with_port=include)
        pkg = mb.package("P")
        cs = pkg.block("CS", "ControlSubsystem")
        port = cs.output_buffer("x/ob", REAL)
        agent = pkg.block("A", "Agent")
        cs_part = agent.part("cs", cs)
        sys_block = pkg.block("S", "System")
        agent_part = sys_block.part("a/a", agent)
        other = sys_block.part("b/a", agent)
        sys_block.connector("a/a,b/a", End.at(port, agent_part, cs_part), End.at(port, other, cs_part))
        root = etree.fromstring(mb.to_bytes())
        return [n.get("propertyPath") for n in root if etree.QName(n).localname == "NestedConnectorEnd"]

    with_part, without_part = system(True), system(False)
    assert [len(p.split()) for p in with_part] == [2, 2]
    assert [len(p.split()) for p in without_part] == [1, 1]


def test_multiplicity_specs() -> None:
    assert Multiplicity.of(6) == Multiplicity(6, 6)
    assert Multiplicity.of("0..1") == Multiplicity(0, 1)
    assert Multiplicity.of("*") == Multiplicity(0, None)
    assert Multiplicity.of("1..*") == Multiplicity(1, None)
    assert Multiplicity.of(None) is None


def test_duplicate_paths_and_unknown_stereotypes_are_refused() -> None:
    mb = ModelBuilder("D")
    pkg = mb.package("P")
    pkg.block("B")
    with pytest.raises(ValueError, match="qualified path"):
        pkg.block("B")
    with pytest.raises(ValueError, match="unknown EARL stereotype"):
        pkg.block("C", "Gadget")
