"""Every catalogue rule has a broken model that triggers exactly that rule.

Each row of ``VARIANTS`` is a small, named mutation of the reference sample
(``samples/pick_and_place/pick_and_place.uml``), applied to its XML with lxml by element
name and structure, or - where a mutation of the sample would drag in other rules - a small
model written with the Papyrus builder. The test writes the variant, checks it and asserts
that

- the set of codes reported is exactly ``{CODE}`` (the row id up to the first ``-``), with
  at least one finding;
- one of those findings points at the broken element (its xmi:id or its line) and its
  message names that element.

A rule with several distinct triggers has one row per trigger (``B001-two-initial``).
``test_every_catalogue_rule_has_a_variant`` fails when a rule is added without a row.
"""

from __future__ import annotations

import copy
import tomllib
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from lxml import etree

from earl_m2t import Diagnostic, check
from earl_m2t.check.registry import catalogue
from tests.rules.test_variability_triggers import VARIABILITY_VARIANTS
from tests.support.papyrus_builder import REAL, Block, End, ModelBuilder, Property

ROOT = Path(__file__).resolve().parents[2]

XMI = "http://www.omg.org/spec/XMI/20131001"
UML = "http://www.eclipse.org/uml2/5.0.0/UML"
XMI_ID = f"{{{XMI}}}id"
XMI_TYPE = f"{{{XMI}}}type"
NS = {"xmi": XMI, "uml": UML}


# ---- what a variant promises ------------------------------------------------------------


@dataclass(frozen=True)
class Expect:
    """Where a finding of the variant must point, and what its message must name.

    ``xmi_id`` is the broken element as the rule reports it: the changed element itself, or
    the one the change breaks (the link whose end was retyped, the basic behaviour whose
    stage now conflicts, the agent whose structure changed). A finding matches by that id or
    by the element's line in the written variant; ``line`` replaces both for file-level
    findings. ``name`` must occur in the message; ``{file}`` stands for the variant's path.
    """

    xmi_id: str = ""
    name: str = ""
    line: int = 0


# ---- the sample as an lxml tree ---------------------------------------------------------


class Sample:
    """The model under mutation: look-ups by element name and structure, edits that keep
    the stereotype applications consistent."""

    def __init__(self, data: bytes) -> None:
        self.root = etree.fromstring(data)
        self._counter = 0

    def replace(self, data: bytes) -> None:
        """Use another model (one written with the builder) instead of the sample."""
        self.root = etree.fromstring(data)

    def to_bytes(self) -> bytes:
        return etree.tostring(self.root, xml_declaration=True, encoding="UTF-8")

    # -- ids --------------------------------------------------------------------------------
    @staticmethod
    def id(el: etree._Element) -> str:
        return el.get(XMI_ID) or ""

    def new_id(self) -> str:
        self._counter += 1
        return f"_variantElement{self._counter:03d}"

    # -- look-ups ---------------------------------------------------------------------------
    @staticmethod
    def _one(found: list, what: str) -> etree._Element:
        assert len(found) == 1, f"{what}: {len(found)} matches in the sample"
        return found[0]

    def _find(self, context: etree._Element, path: str, what: str, **names: str) -> etree._Element:
        return self._one(context.xpath(path, namespaces=NS, **names), what)

    def block(self, name: str) -> etree._Element:
        return self._find(self.root, '//packagedElement[@xmi:type="uml:Class"][@name=$n]', f"block {name}", n=name)

    def datatype(self, name: str) -> etree._Element:
        return self._find(self.root, '//packagedElement[@xmi:type="uml:DataType"][@name=$n]', f"dataType {name}",
                          n=name)

    def attribute(self, owner: str, name: str) -> etree._Element:
        """A part, port or value property of block ``owner`` (or a field of a dataType)."""
        found = self.root.xpath('//packagedElement[@name=$o]/ownedAttribute[@name=$n]', namespaces=NS, o=owner, n=name)
        return self._one(found, f"{owner}.{name}")

    def behavior(self, block: str, name: str) -> etree._Element:
        return self._find(self.block(block), "ownedBehavior[@name=$n]", f"{block}.{name}", n=name)

    def parameter(self, block: str, behavior: str, name: str) -> etree._Element:
        return self._find(self.behavior(block, behavior), "ownedParameter[@name=$n]", f"{behavior}({name})", n=name)

    def connector(self, block: str, name: str) -> etree._Element:
        return self._find(self.block(block), "ownedConnector[@name=$n]", f"{block} connector {name}", n=name)

    def state_machine(self, block: str) -> etree._Element:
        return self._find(self.block(block), 'ownedBehavior[@xmi:type="uml:StateMachine"]', f"{block} FSM")

    def region(self, block: str) -> etree._Element:
        return self._find(self.state_machine(block), "region", f"{block} FSM region")

    def state(self, block: str, name: str) -> etree._Element:
        return self._find(self.region(block), 'subvertex[@xmi:type="uml:State"][@name=$n]', f"{block} state {name}",
                          n=name)

    def initial_pseudostate(self, block: str) -> etree._Element:
        return self._find(self.region(block), 'subvertex[@xmi:type="uml:Pseudostate"]', f"{block} initial pseudostate")

    def transition(self, block: str, name: str) -> etree._Element:
        return self._find(self.region(block), "transition[@name=$n]", f"{block} transition {name}", n=name)

    def transition_from(self, block: str, source: etree._Element) -> etree._Element:
        return self._find(self.region(block), "transition[@source=$s]", f"{block} transition from {self.id(source)}",
                          s=self.id(source))

    def activity(self, block: str, state: str) -> etree._Element:
        """The basic behaviour (doActivity) of a state."""
        return self._find(self.state(block, state), "doActivity", f"{block} {state}/bb")

    def node(self, activity: etree._Element, name: str) -> etree._Element:
        return self._find(activity, "node[@name=$n]", f"activity node {name}", n=name)

    def guard_body(self, block: str, transition: str) -> etree._Element:
        return self._find(self.transition(block, transition), "ownedRule/specification/body", f"guard of {transition}")

    def stereotype_applications(self, name: str | None = None) -> list[etree._Element]:
        """Stereotype applications (children of the root outside the UML namespace)."""
        apps = []
        for child in self.root:
            if not isinstance(child.tag, str) or child.tag.startswith(f"{{{UML}}}"):
                continue
            if name is None or etree.QName(child).localname == name:
                apps.append(child)
        return apps

    def application(self, name: str, base: etree._Element) -> etree._Element:
        base_id = self.id(base)
        found = [a for a in self.stereotype_applications(name) if base_id in _base_ids(a)]
        return self._one(found, f"«{name}» of {base_id}")

    # -- edits ------------------------------------------------------------------------------
    def remove(self, el: etree._Element) -> None:
        """Delete an element, everything it contains and the stereotypes applied to them."""
        ids = {self.id(e) for e in el.iter() if self.id(e)}
        el.getparent().remove(el)
        for app in self.stereotype_applications():
            if _base_ids(app) & ids:
                self.root.remove(app)

    def add(self, parent: etree._Element, tag: str, xmi_type: str, after: etree._Element | None = None,
            **attrs: str) -> etree._Element:
        """A new element with a fresh xmi:id, appended to ``parent`` or put right after ``after``."""
        el = etree.Element(tag, {XMI_TYPE: xmi_type, XMI_ID: self.new_id()})
        for key, value in attrs.items():
            el.set(key, value)
        if after is not None:
            after.addnext(el)
        else:
            parent.append(el)
        return el

    def apply(self, stereotype: str, metaclass: str, base: etree._Element, **tags: str) -> etree._Element:
        """Apply an EARL stereotype to ``base``, as Papyrus does (an element after the model)."""
        earl = self.root.nsmap["EARL"]
        app = etree.SubElement(self.root, f"{{{earl}}}{stereotype}",
                               {XMI_ID: self.new_id(), f"base_{metaclass}": self.id(base)})
        for key, value in tags.items():
            app.set(key, value)
        return app

    def connect(self, block: str, name: str, *ends: tuple[etree._Element, etree._Element],
                stereotype: str = "InterSubsystemLink") -> etree._Element:
        """A connector of ``block`` between (part, port) ends, stereotyped like the sample's links."""
        owner = self.block(block)
        connectors = owner.xpath("ownedConnector")
        connector = self.add(owner, "ownedConnector", "uml:Connector", after=connectors[-1] if connectors else None,
                             name=name)
        for part, port in ends:
            self.add(connector, "end", "uml:ConnectorEnd", partWithPort=self.id(part), role=self.id(port))
        self.apply(stereotype, "Connector", connector)
        return connector

    def flow(self, activity: etree._Element, source: etree._Element, target: etree._Element) -> etree._Element:
        """A control flow of ``activity``, with the nodes' redundant incoming/outgoing lists."""
        first_node = activity.xpath("node")[0]
        edge = etree.Element("edge", {XMI_TYPE: "uml:ControlFlow", XMI_ID: self.new_id(),
                                      "target": self.id(target), "source": self.id(source)})
        first_node.addprevious(edge)
        _append_ref(source, "outgoing", self.id(edge))
        _append_ref(target, "incoming", self.id(edge))
        return edge

    def multiplicity(self, el: etree._Element, value: int) -> None:
        self.add(el, "lowerValue", "uml:LiteralInteger", value=str(value))
        self.add(el, "upperValue", "uml:LiteralUnlimitedNatural", value=str(value))


def _base_ids(app: etree._Element) -> set[str]:
    return {v for k, v in app.attrib.items() if k.startswith("base_")}


def _append_ref(el: etree._Element, attr: str, ref: str) -> None:
    el.set(attr, " ".join([*(el.get(attr) or "").split(), ref]))


def _remove_ref(el: etree._Element, attr: str, ref: str) -> None:
    el.set(attr, " ".join(r for r in (el.get(attr) or "").split() if r != ref))


def _move_agents_to_system(s: Sample) -> etree._Element:
    """Move manip/a and grip/a from the robot block into the System block; returns the robot part."""
    robot_part = s.attribute("PickAndPlaceSystem", "pickAndPlace/r")
    for agent in ("manip/a", "grip/a"):
        part = s.attribute("PickAndPlaceRobot", agent)
        robot_part.getparent().xpath("ownedAttribute")[-1].addnext(part)
    # the inter-agent links now reach the agents' cs ports without going through the robot
    for app in s.stereotype_applications("NestedConnectorEnd"):
        app.set("propertyPath", " ".join(p for p in app.get("propertyPath", "").split() if p != s.id(robot_part)))
    return robot_part


# ---- small models written with the builder ----------------------------------------------

KIND_STEREOTYPES = {
    "cs": "ControlSubsystem",
    "ve": "VirtualEffector",
    "re": "RealEffector",
    "vr": "VirtualReceptor",
    "rr": "RealReceptor",
}


@dataclass
class MiniAgent:
    block: Block
    part: Property
    parts: dict[str, Property] = field(default_factory=dict)


class Mini:
    """A small system in the Papyrus dialect: robot ``mini/r`` holding ``task/a`` and
    ``peer/a``, whose control subsystems exchange ``command`` and ``status`` (both agents are
    of type CT and the model checks clean). Variants add subsystems and links to ``task/a``.

    Used where a mutation of the sample would drag in other rules: the sample has no
    receptors, every buffer of it is linked (C007), each agent declares its type (S007) and
    its dataTypes differ at every pair of subsystem kinds EARL does not permit (C006)."""

    def __init__(self) -> None:
        self.mb = ModelBuilder("Mini")
        types = self.mb.package("DataTypes")
        self.message = types.data_type("Message")
        self.message.field("value", REAL)
        self.pkg = self.mb.package("SystemInstance")
        self.system = self.pkg.block("MiniSystem", "System")
        self.robot = self.pkg.block("MiniRobot", "Robot")
        self.robot_part = self.system.part("mini/r", self.robot)
        self.agents: dict[str, MiniAgent] = {}

    def subsystem(self, block: str, kind: str, ins: tuple[str, ...] = (), outs: tuple[str, ...] = (),
                  memory: tuple[str, ...] = ()) -> Block:
        """A subsystem block with buffers ``x/ib``, ``x/ob``, memory ``x/m``, one pf reading the
        inputs and writing the rest, and an FSM of one state running it."""
        sub = self.pkg.block(block, KIND_STEREOTYPES[kind])
        reads = [sub.input_buffer(f"{n}/ib", self.message) for n in ins]
        writes = [sub.output_buffer(f"{n}/ob", self.message) for n in outs]
        writes += [sub.memory(f"{n}/m", REAL) for n in memory]
        pf = sub.partial_transition_function("step/pf", reads=reads, writes=writes)
        sub.state_machine().state("run", initial=True).do_activity().stages([[pf]])
        return sub

    def agent(self, name: str, block: str, subsystems: dict[str, Block]) -> MiniAgent:
        agent_block = self.pkg.block(block, "Agent")
        part = self.robot.part(name, agent_block)
        agent = MiniAgent(agent_block, part, {n: agent_block.part(n, t) for n, t in subsystems.items()})
        self.agents[name] = agent
        return agent

    @staticmethod
    def _end(part: Property, port: str, *path: Property) -> End:
        block = part.type
        assert isinstance(block, Block)
        return End.at(next(p for p in block.attributes if p.name == port), *path, part)

    def link(self, agent: MiniAgent, source: str, target: str, name: str | None = None):
        """A link of ``agent`` from ``part.port`` to ``part.port`` (``cs.raw/ob``)."""
        (src, src_port), (dst, dst_port) = source.split(".", 1), target.split(".", 1)
        return agent.block.connector(name or f"{src},{dst}", self._end(agent.parts[src], src_port),
                                     self._end(agent.parts[dst], dst_port), "InterSubsystemLink")

    def task(self, ins: tuple[str, ...] = (), outs: tuple[str, ...] = (),
             subsystems: dict[str, Block] | None = None) -> MiniAgent:
        """``task/a``, its cs (ports ``status/ib``, ``command/ob`` plus ``ins``/``outs``) and
        ``subsystems``; then ``peer/a`` and the two inter-agent links."""
        cs = self.subsystem("TaskControl", "cs", ("status", *ins), ("command", *outs))
        task = self.agent("task/a", "TaskAgent", {"cs": cs, **(subsystems or {})})
        self.agent("peer/a", "PeerAgent", {"cs": self.subsystem("PeerControl", "cs", ("command",), ("status",))})
        for source, target, message in (("task/a", "peer/a", "command"), ("peer/a", "task/a", "status")):
            src, dst = self.agents[source], self.agents[target]
            self.system.connector(
                f"{source},{target}",
                self._end(src.parts["cs"], f"{message}/ob", self.robot_part, src.part),
                self._end(dst.parts["cs"], f"{message}/ib", self.robot_part, dst.part),
                "InterAgentLink",
            )
        return task

    def to_bytes(self) -> bytes:
        return self.mb.to_bytes()


def mini_base() -> Mini:
    mini = Mini()
    mini.task()
    return mini


# ---- S: structure -----------------------------------------------------------------------


def system_without_robot(s: Sample) -> Expect:
    """S001: the System owns no Robot. manip/a and grip/a become parts of the System block
    PickAndPlaceSystem directly (the inter-agent links' nested ends follow them) and the
    robot part pickAndPlace/r is deleted together with its block PickAndPlaceRobot."""
    robot_part = _move_agents_to_system(s)
    s.remove(robot_part)
    s.remove(s.block("PickAndPlaceRobot"))
    system = s.block("PickAndPlaceSystem")
    return Expect(s.id(system), "PickAndPlaceSystem")


def robot_without_agent(s: Sample) -> Expect:
    """S002: the Robot pickAndPlace/r contains no Agent: its agent parts manip/a and grip/a
    move from the robot block to the System block, the robot part stays."""
    robot_part = _move_agents_to_system(s)
    return Expect(s.id(robot_part), "pickAndPlace/r")


def agent_with_two_control_subsystems(s: Sample) -> Expect:
    """S003: the Agent task/a has two Control Subsystems: its part ``cs`` gets the fixed
    multiplicity [2] (replicated instances cs1, cs2, both still linked to manip/a and grip/a)."""
    s.multiplicity(s.attribute("TaskAgent", "cs"), 2)
    return Expect(s.id(s.attribute("PickAndPlaceSystem", "task/a")), "task/a")


def virtual_receptor_without_real_receptor(s: Sample) -> Expect:
    """S004 (small model): task/a has a Virtual Receptor filter/vr, linked both ways to its
    cs, but no Real Receptor."""
    mini = Mini()
    vr = mini.subsystem("Filter", "vr", ("raw",), ("filtered",))
    task = mini.task(("filtered",), ("raw",), {"filter/vr": vr})
    mini.link(task, "cs.raw/ob", "filter/vr.raw/ib")
    mini.link(task, "filter/vr.filtered/ob", "cs.filtered/ib")
    s.replace(mini.to_bytes())
    return Expect(task.part.id, "task/a")


def virtual_effector_without_real_effector(s: Sample) -> Expect:
    """S005 (small model): task/a has a Virtual Effector driver/ve, linked both ways to its
    cs, but no Real Effector."""
    mini = Mini()
    ve = mini.subsystem("Driver", "ve", ("drive",), ("state",))
    task = mini.task(("state",), ("drive",), {"driver/ve": ve})
    mini.link(task, "cs.drive/ob", "driver/ve.drive/ib")
    mini.link(task, "driver/ve.state/ob", "cs.state/ib")
    s.replace(mini.to_bytes())
    return Expect(task.part.id, "task/a")


def zombie_agent(s: Sample) -> Expect:
    """S006 (small model): a third Agent spare/a whose cs only keeps a memory: no effectors,
    no receptors, no inter-agent link - a zombie (type C)."""
    mini = mini_base()
    spare = mini.agent("spare/a", "SpareAgent", {"cs": mini.subsystem("SpareControl", "cs", memory=("heartbeat",))})
    s.replace(mini.to_bytes())
    return Expect(spare.part.id, "spare/a")


def declared_type_mismatch(s: Sample) -> Expect:
    """S007: task/a's «Agent» declaredType says CET (teleoperated) but the agent has no
    effectors: its structure makes it CT."""
    task = s.block("TaskAgent")
    s.application("Agent", task).set("declaredType", "CET")
    return Expect(s.id(s.attribute("PickAndPlaceSystem", "task/a")), "task/a")


def virtual_effector_without_output(s: Sample) -> Expect:
    """S008 (small model): task/a drives motor/re through driver/ve, and also has a second
    Virtual Effector lamp/ve fed by the cs that has an Input Buffer but no Output Buffer."""
    mini = Mini()
    driver = mini.subsystem("Driver", "ve", ("drive",), ("current",))
    lamp = mini.subsystem("Lamp", "ve", ("lamp",))
    motor = mini.subsystem("Motor", "re", ("current",))
    task = mini.task((), ("drive", "lamp"), {"driver/ve": driver, "lamp/ve": lamp, "motor/re": motor})
    mini.link(task, "cs.drive/ob", "driver/ve.drive/ib")
    mini.link(task, "driver/ve.current/ob", "motor/re.current/ib")
    mini.link(task, "cs.lamp/ob", "lamp/ve.lamp/ib")
    s.replace(mini.to_bytes())
    return Expect(task.parts["lamp/ve"].id, "lamp/ve")


def untyped_memory(s: Sample) -> Expect:
    """S009: the Internal Memory currentJointPos/m of ManipulatorControl loses its type
    (the value property has no dataType)."""
    memory = s.attribute("ManipulatorControl", "currentJointPos/m")
    del memory.attrib["type"]
    return Expect(s.id(memory), "currentJointPos/m")


# ---- C: links ---------------------------------------------------------------------------


def link_between_two_outputs(s: Sample) -> Expect:
    """C001: a new link of GripperAgent joins two Output Buffers: cs.fingerCommand/ob and
    fingerController/ve.desiredCurrent/ob. It is unnamed (cs,fingerController/ve names a link
    of the sample, S012)."""
    cs, ve = s.attribute("GripperAgent", "cs"), s.attribute("GripperAgent", "fingerController/ve")
    connector = s.connect("GripperAgent", "",
                          (cs, s.attribute("GripperControl", "fingerCommand/ob")),
                          (ve, s.attribute("FingerController", "desiredCurrent/ob")))
    return Expect(s.id(connector), "grip/a.cs,fingerController/ve")


def link_between_two_inputs(s: Sample) -> Expect:
    """C001: a new, unnamed link of GripperAgent joins two Input Buffers: fingerController/ve's
    motorControllerCommand/ib and cs.fingerState/ib."""
    cs, ve = s.attribute("GripperAgent", "cs"), s.attribute("GripperAgent", "fingerController/ve")
    connector = s.connect("GripperAgent", "",
                          (ve, s.attribute("FingerController", "motorControllerCommand/ib")),
                          (cs, s.attribute("GripperControl", "fingerState/ib")))
    return Expect(s.id(connector), "grip/a.fingerController/ve,cs")


def link_to_a_memory(s: Sample) -> Expect:
    """C001: a new link of GripperAgent goes from cs.fingerCommand/ob to the Internal Memory
    integralError/m of fingerController/ve - a value property, not a buffer."""
    cs, ve = s.attribute("GripperAgent", "cs"), s.attribute("GripperAgent", "fingerController/ve")
    connector = s.connect("GripperAgent", "cs,fingerController/ve",
                          (cs, s.attribute("GripperControl", "fingerCommand/ob")),
                          (ve, s.attribute("FingerController", "integralError/m")))
    return Expect(s.id(connector), "cs,fingerController/ve")


def link_control_to_real_effector(s: Sample) -> Expect:
    """C002 (small model): besides the chain cs → driver/ve → motor/re, task/a links its cs
    straight to the Real Effector motor/re (cs → re is not a permitted link)."""
    mini = Mini()
    driver = mini.subsystem("Driver", "ve", ("drive",), ("current",))
    motor = mini.subsystem("Motor", "re", ("current",))
    task = mini.task((), ("drive", "direct"), {"driver/ve": driver, "motor/re": motor})
    mini.link(task, "cs.drive/ob", "driver/ve.drive/ib")
    mini.link(task, "driver/ve.current/ob", "motor/re.current/ib")
    direct = mini.link(task, "cs.direct/ob", "motor/re.current/ib")
    s.replace(mini.to_bytes())
    return Expect(direct.id, "task/a.cs,motor/re")


def inter_agent_link_inside_one_agent(s: Sample) -> Expect:
    """C003: an inter-agent link (a connector of the System block with nested ends) from
    manip/a's cs.motorControllerCommandK/ob to manip/a's motorControllerK/ve - both ends in
    one agent."""
    system = s.block("PickAndPlaceSystem")
    robot, manip = s.attribute("PickAndPlaceSystem", "pickAndPlace/r"), s.attribute("PickAndPlaceRobot", "manip/a")
    cs, ve = s.attribute("ManipulatorAgent", "cs"), s.attribute("ManipulatorAgent", "motorControllerK/ve")
    ends = ((cs, s.attribute("ManipulatorControl", "motorControllerCommandK/ob")),
            (ve, s.attribute("MotorController", "motorControllerCommand/ib")))
    connector = s.connect("PickAndPlaceSystem", "manip/a,manip/a", *ends, stereotype="InterAgentLink")
    blocks = s.root.nsmap["Blocks"]
    for end, (part, _) in zip(connector.xpath("end"), ends):
        etree.SubElement(s.root, f"{{{blocks}}}NestedConnectorEnd",
                         {XMI_ID: s.new_id(), "base_ConnectorEnd": s.id(end),
                          "propertyPath": " ".join(s.id(p) for p in (robot, manip, part))})
    assert connector.getparent() is system
    return Expect(s.id(connector), "manip/a,manip/a")


def real_effector_unreached(s: Sample) -> Expect:
    """C004: grip/a's cs no longer commands its virtual effector: the link
    cs,fingerController/ve is deleted with the ve's motorControllerCommand/ib and the
    regulateFinger/pf parameter reading it. fingerMotor/re is still fed by
    fingerController/ve, but no chain cs → ve → re reaches it."""
    s.remove(s.connector("GripperAgent", "cs,fingerController/ve"))
    s.remove(s.attribute("FingerController", "motorControllerCommand/ib"))
    s.remove(s.parameter("FingerController", "regulateFinger/pf", "motorControllerCommand/ib"))
    return Expect(s.id(s.attribute("GripperAgent", "fingerMotor/re")), "fingerMotor/re")


def real_receptor_unheard(s: Sample) -> Expect:
    """C005 (small model): task/a's Real Receptor camera/rr feeds the Virtual Receptor
    filter/vr, whose output reaches no control subsystem."""
    mini = Mini()
    vr = mini.subsystem("Filter", "vr", ("raw",), ("filtered",))
    rr = mini.subsystem("Camera", "rr", (), ("raw",))
    task = mini.task((), (), {"filter/vr": vr, "camera/rr": rr})
    mini.link(task, "camera/rr.raw/ob", "filter/vr.raw/ib")
    s.replace(mini.to_bytes())
    return Expect(task.parts["camera/rr"].id, "camera/rr")


def link_datatype_mismatch(s: Sample) -> Expect:
    """C006: motorControllerK/ve's Output Buffer desiredCurrent/ob is retyped to
    GripperStatus; the link motorControllerK/ve,motorK/re still ends in motorK/re's
    desiredCurrent/ib of type MotorCurrent. (The message names the link's first instance.)"""
    port = s.attribute("MotorController", "desiredCurrent/ob")
    port.set("type", s.id(s.datatype("GripperStatus")))
    connector = s.connector("ManipulatorAgent", "motorControllerK/ve,motorK/re")
    return Expect(s.id(connector), "motorController1/ve,motor1/re")


def input_buffer_unfed(s: Sample) -> Expect:
    """C007: TaskControl gets a new Input Buffer operatorCommand/ib (a «InputBuffer» port
    typed by ManipulatorCommand) that no link feeds."""
    last_port = s.attribute("TaskControl", "gripperStatus/ib")
    port = s.add(s.block("TaskControl"), "ownedAttribute", "uml:Port", after=last_port, name="operatorCommand/ib",
                 type=s.id(s.datatype("ManipulatorCommand")), aggregation="composite")
    s.apply("InputBuffer", "Port", port)
    return Expect(s.id(port), "operatorCommand/ib")


def link_name_convention(s: Sample) -> Expect:
    """C008: the inter-agent link task/a,grip/a is renamed gripperCommand instead of the
    paper's ``source,destination`` form."""
    connector = s.connector("PickAndPlaceSystem", "task/a,grip/a")
    connector.set("name", "gripperCommand")
    return Expect(s.id(connector), "gripperCommand")


def best_effort_into_reliable(s: Sample) -> Expect:
    """C010: FingerMotor's encoder/ob is best_effort; the link fingerMotor/re,fingerController/ve
    ends in FingerController's reliable encoder/ib, a pair DDS never matches."""
    s.application("OutputBuffer", s.attribute("FingerMotor", "encoder/ob")).set("reliability", "best_effort")
    connector = s.connector("GripperAgent", "fingerMotor/re,fingerController/ve")
    return Expect(s.id(connector), "grip/a.fingerMotor/re.encoder/ob → grip/a.fingerController/ve.encoder/ib")


def queue_best_effort(s: Sample) -> Expect:
    """C010: ManipulatorControl's queued manipulatorCommand/ib is best_effort, which a queue
    that loses no value silently cannot be."""
    s.application("InputBuffer", s.attribute("ManipulatorControl", "manipulatorCommand/ib")).set(
        "reliability", "best_effort")
    connector = s.connector("PickAndPlaceSystem", "task/a,manip/a")
    return Expect(s.id(connector), "manip/a.cs.manipulatorCommand/ib")


# ---- B: FSMs and conditions -------------------------------------------------------------


def fsm_without_initial_state(s: Sample) -> Expect:
    """B001: ManipulatorControl's state machine loses its initial pseudostate and the
    transition leaving it: the FSM has no initial state."""
    pseudostate = s.initial_pseudostate("ManipulatorControl")
    s.remove(s.transition_from("ManipulatorControl", pseudostate))
    s.remove(pseudostate)
    return Expect(s.id(s.state_machine("ManipulatorControl")), "manip/a.cs.fsm")


def initial_pseudostate_leads_nowhere(s: Sample) -> Expect:
    """B001: ManipulatorControl's initial pseudostate stays but the transition leaving it
    (to idle) is deleted: the initial state is nowhere."""
    s.remove(s.transition_from("ManipulatorControl", s.initial_pseudostate("ManipulatorControl")))
    return Expect(s.id(s.state_machine("ManipulatorControl")), "manip/a.cs.fsm")


def fsm_with_two_initial_states(s: Sample) -> Expect:
    """B001: ManipulatorControl's region gets a second initial pseudostate whose transition
    leads to emergencyStop: two initial states (idle, emergencyStop)."""
    region = s.region("ManipulatorControl")
    first = s.initial_pseudostate("ManipulatorControl")
    pseudostate = s.add(region, "subvertex", "uml:Pseudostate", after=first)
    s.add(region, "transition", "uml:Transition", after=s.transition_from("ManipulatorControl", first),
          source=s.id(pseudostate), target=s.id(s.state("ManipulatorControl", "emergencyStop")))
    return Expect(s.id(s.state_machine("ManipulatorControl")), "manip/a.cs.fsm")


def subsystem_without_fsm(s: Sample) -> Expect:
    """B001: FingerMotor (grip/a's Real Effector fingerMotor/re) loses its state machine
    (the classifier behaviour, with its states and basic behaviours)."""
    block = s.block("FingerMotor")
    s.remove(s.state_machine("FingerMotor"))
    del block.attrib["classifierBehavior"]
    return Expect(s.id(s.attribute("GripperAgent", "fingerMotor/re")), "fingerMotor/re")


def subsystem_with_two_fsms(s: Sample) -> Expect:
    """B001: FingerMotor owns a second, empty state machine fsm2 next to its FSM."""
    fsm = s.state_machine("FingerMotor")
    extra = s.add(s.block("FingerMotor"), "ownedBehavior", "uml:StateMachine", after=fsm, name="fsm2")
    s.add(extra, "region", "uml:Region", name="Region1")
    return Expect(s.id(fsm), "grip/a.fingerMotor/re")


def state_without_basic_behaviour(s: Sample) -> Expect:
    """B002: TaskControl's state abort loses its doActivity (its basic behaviour abort/bb)."""
    s.remove(s.activity("TaskControl", "abort"))
    return Expect(s.id(s.state("TaskControl", "abort")), "abort")


def transition_to_another_fsm(s: Sample) -> Expect:
    """B003: TaskControl's FSM gets a transition abort,idle/t whose destination is the state
    idle of ManipulatorControl's FSM."""
    region = s.region("TaskControl")
    last = region.xpath("transition")[-1]
    transition = s.add(region, "transition", "uml:Transition", after=last, name="abort,idle/t",
                       source=s.id(s.state("TaskControl", "abort")),
                       target=s.id(s.state("ManipulatorControl", "idle")))
    return Expect(s.id(transition), "abort,idle/t")


def unreachable_state(s: Sample) -> Expect:
    """B004: the transition idle,operationalMove/t of ManipulatorControl is deleted, so no
    transition leads to the state operationalMove any more. (idle/bb's terminal condition
    drops newOperationalPos with it, else idle could end with no transition enabled: B007.)"""
    s.remove(s.transition("ManipulatorControl", "idle,operationalMove/t"))
    tc = s._find(s.activity("ManipulatorControl", "idle"), 'ownedRule[@name="tc"]/specification/body', "tc")
    tc.text = "newJointPos/pp.fun ∨ emergencyStop/pp.fun"
    return Expect(s.id(s.state("ManipulatorControl", "operationalMove")), "operationalMove")


def guard_names_unknown_predicate(s: Sample) -> Expect:
    """B005: the initial condition of idle,jointMove/t names newJointPosition/pp, which is no
    primitive predicate of ManipulatorControl (it has newJointPos/pp)."""
    body = s.guard_body("ManipulatorControl", "idle,jointMove/t")
    body.text = "newJointPosition/pp.fun ∧ ¬emergencyStop/pp.fun"
    return Expect(s.id(body.getparent()), "idle,jointMove/t")


def predicate_names_unknown_field(s: Sample) -> Expect:
    """B005: the body of the primitive predicate newJointPos/pp reads a field jointSetpoint
    that ManipulatorCommand does not have (it has jointPosSetpoint)."""
    pp = s.behavior("ManipulatorControl", "newJointPos/pp")
    pp.find("body").text = "newData(manipulatorCommand/ib.msg.jointSetpoint)"
    return Expect(s.id(pp), "newJointPos/pp")


def guard_indexes_a_boolean(s: Sample) -> Expect:
    """B005: the guard of idle,jointMove/t indexes emergencyStopCommand, a single Boolean of
    ManipulatorCommand (generated C++ would not compile)."""
    body = s.guard_body("ManipulatorControl", "idle,jointMove/t")
    body.text = "manipulatorCommand/ib.msg.emergencyStopCommand[2]"
    return Expect(s.id(body.getparent()), "'emergencyStopCommand' is not an array")


def guard_index_out_of_range(s: Sample) -> Expect:
    """B005: the guard of idle,jointMove/t reads q[6] of JointPosition's q [6], one past its
    last element q[5] (generated C++ would read out of bounds)."""
    body = s.guard_body("ManipulatorControl", "idle,jointMove/t")
    body.text = "currentJointPos/m.data.q[6] > 0.5 ∧ ¬emergencyStop/pp.fun"
    return Expect(s.id(body.getparent()), "index 6 is out of range: 'q' has 6 elements")


def guard_is_a_composite(s: Sample) -> Expect:
    """B005: the guard of idle,jointMove/t is the optional jointPosSetpoint of the command, a
    composite value rather than a boolean or a number."""
    body = s.guard_body("ManipulatorControl", "idle,jointMove/t")
    body.text = "manipulatorCommand/ib.msg.jointPosSetpoint ∧ ¬emergencyStop/pp.fun"
    return Expect(s.id(body.getparent()), "is an optional value [0..1], not a boolean or a number")


def guard_names_a_seventh_motor(s: Sample) -> Expect:
    """B005: the guard of idle,jointMove/t reads motorControllerState7/ib, but ManipulatorControl
    has six instances of motorControllerStateK/ib."""
    body = s.guard_body("ManipulatorControl", "idle,jointMove/t")
    body.text = "motorControllerState7/ib.msg.motorPos > 0.5 ∧ ¬emergencyStop/pp.fun"
    return Expect(s.id(body.getparent()), "its instances are numbered 1 to 6")


def guard_names_the_template(s: Sample) -> Expect:
    """B005: the guard of idle,jointMove/t reads windingCurrentK/m, the name of all six instances,
    outside a replication (any K: …)."""
    body = s.guard_body("ManipulatorControl", "idle,jointMove/t")
    body.text = "windingCurrentK/m > 2.5 ∧ ¬emergencyStop/pp.fun"
    return Expect(s.id(body.getparent()), "'windingCurrentK/m' stands for each of 6 instances")


def exclusion_removed(s: Sample) -> Expect:
    """B006: ManipulatorControl's «Exclusion» jointOrOperational (newJointPos/pp and
    newOperationalPos/pp never hold together) is deleted: idle,jointMove/t and
    idle,operationalMove/t, both of priority 0, can then be enabled together."""
    s.remove(s._find(s.block("ManipulatorControl"), 'ownedRule[@name="jointOrOperational"]', "exclusion"))
    return Expect(s.id(s.transition("ManipulatorControl", "idle,jointMove/t")),
                  "idle,jointMove/t and idle,operationalMove/t can both fire when newJointPos ∧ "
                  "newOperationalPos ∧ ¬emergencyStop")


def self_transition_priority_removed(s: Sample) -> Expect:
    """B006: jointMove,jointMove/t loses its priority 1 (its «FsmTransition» keeps the default
    0): it ties with jointMove,idle/t, and both hold when a new joint setpoint arrives as the
    motion finishes."""
    transition = s.transition("ManipulatorControl", "jointMove,jointMove/t")
    del s.application("FsmTransition", transition).attrib["priority"]
    return Expect(s.id(transition), "jointMove,jointMove/t and jointMove,idle/t can both fire when newJointPos ∧ "
                                    "motionFinished ∧ ¬emergencyStop")


def emergency_transition_removed(s: Sample) -> Expect:
    """B007: idle,emergencyStop/t is deleted: idle/bb still terminates on an emergency stop,
    but then neither idle,jointMove/t nor idle,operationalMove/t is enabled."""
    s.remove(s.transition("ManipulatorControl", "idle,emergencyStop/t"))
    return Expect(s.id(s.state("ManipulatorControl", "idle")), "idle/bb can terminate (tc holds, ec does not) when "
                                                                "emergencyStop")


def state_without_exit(s: Sample) -> Expect:
    """B007: TaskControl's abort/bb gets the terminal condition taskAborted/pp (it was FALSE),
    but no transition leaves abort."""
    tc = s._find(s.activity("TaskControl", "abort"), 'ownedRule[@name="tc"]/specification/body', "tc")
    tc.text = "taskAborted/pp"
    return Expect(s.id(s.state("TaskControl", "abort")), "when taskAborted, and then no transition leaves it")


def guard_syntax_error(s: Sample) -> Expect:
    """B008: the initial condition of idle,jointMove/t has a doubled operator
    (``newJointPos/pp.fun ∧ ∧ ¬emergencyStop/pp.fun``) and does not parse."""
    body = s.guard_body("ManipulatorControl", "idle,jointMove/t")
    body.text = "newJointPos/pp.fun ∧ ∧ ¬emergencyStop/pp.fun"
    return Expect(s.id(body.getparent()), "idle,jointMove/t")


def empty_terminal_condition(s: Sample) -> Expect:
    """B008: the terminal condition tc of TaskControl's supervise/bb has an empty body."""
    tc = s._find(s.activity("TaskControl", "supervise"), 'ownedRule[@name="tc"]/specification', "tc")
    tc.find("body").text = ""
    return Expect(s.id(tc), "supervise/bb")


# ---- activation: buffer groups, state activation, receive modes ------------------------------


def _buffer_group(s: Sample) -> etree._Element:
    """The constraint of ManipulatorControl stereotyped «BufferGroup» (the group ``commands``)."""
    return s._find(s.block("ManipulatorControl"), 'ownedRule[@name="commands"]', "buffer group commands")


def buffer_group_names_unknown_buffer(s: Sample) -> Expect:
    """B009: the group commands names the obligatory buffer manipulatorCmd/ib, which
    ManipulatorControl does not have (its Input Buffer is manipulatorCommand/ib)."""
    group = _buffer_group(s)
    s.application("BufferGroup", group).set("obligatory", "manipulatorCmd/ib")
    return Expect(s.id(group), "manipulatorCmd/ib")


def buffer_group_names_output_buffer(s: Sample) -> Expect:
    """B009: the group commands names the Output Buffer manipulatorState/ob as optional."""
    group = _buffer_group(s)
    s.application("BufferGroup", group).set("optional", "motorControllerStateK/ib manipulatorState/ob")
    return Expect(s.id(group), "manipulatorState/ob")


def state_without_buffer_group(s: Sample) -> Expect:
    """B010: the state operationalMove of ManipulatorControl loses its tag bufferGroup while the
    subsystem is activated by the group commands."""
    state = s.state("ManipulatorControl", "operationalMove")
    del s.application("FsmState", state).attrib["bufferGroup"]
    return Expect(s.id(state), "operationalMove")


def state_names_unknown_buffer_group(s: Sample) -> Expect:
    """B010: the state idle of ManipulatorControl names the buffer group 'command', a typo of commands."""
    state = s.state("ManipulatorControl", "idle")
    s.application("FsmState", state).set("bufferGroup", "command")
    return Expect(s.id(state), "'command'")


def queue_of_no_value(s: Sample) -> Expect:
    """B011: ManipulatorControl's manipulatorCommand/ib receives a queue of 0 values."""
    port = s.attribute("ManipulatorControl", "manipulatorCommand/ib")
    s.application("InputBuffer", port).set("queueSize", "0")
    return Expect(s.id(port), "manipulatorCommand/ib")


def negative_timeout(s: Sample) -> Expect:
    """B011: the state jointMove of ManipulatorControl waits -0.02 s for its obligatory inputs."""
    state = s.state("ManipulatorControl", "jointMove")
    s.application("FsmState", state).set("nextTimeout", "-0.02")
    return Expect(s.id(state), "nextTimeout")


def reliability_unknown(s: Sample) -> Expect:
    """B011: TaskControl's gripperCommand/ob has the reliability 'lossy', neither reliable nor best_effort."""
    port = s.attribute("TaskControl", "gripperCommand/ob")
    s.application("OutputBuffer", port).set("reliability", "lossy")
    return Expect(s.id(port), "'lossy'")


def error_condition_reads_in_error(s: Sample) -> Expect:
    """B012: jointMove/bb's error condition reads inError() (the previous iteration's value)."""
    ec = s._find(s.activity("ManipulatorControl", "jointMove"), 'ownedRule[@name="ec"]/specification/body', "ec")
    ec.text = "inError() ∨ ¬behaviourOk()"
    return Expect(s.id(ec.getparent()), "inError()")


def one_shot_command_into_latest_value(s: Sample) -> Expect:
    """C009: ManipulatorControl's manipulatorCommand/ib receives the latest value again (the
    sample's tags receive = queue removed) and no longer activates an iteration (the group waits
    for the motor controllers instead), while newJointPos/pp tests newData() on it."""
    port = s.attribute("ManipulatorControl", "manipulatorCommand/ib")
    app = s.application("InputBuffer", port)
    for tag in ("receive", "queueSize"):
        del app.attrib[tag]
    group = s.application("BufferGroup", _buffer_group(s))
    group.set("obligatory", "motorControllerStateK/ib")
    group.set("optional", "manipulatorCommand/ib")
    return Expect(s.id(port), "manipulatorCommand/ib")


# ---- T: transition functions ------------------------------------------------------------


def _add_parameter(s: Sample, pf: etree._Element, name: str, direction: str, like: etree._Element) -> etree._Element:
    """A new parameter ``name`` of ``pf``: a copy of the parameter ``like`` (its type and
    multiplicity) with fresh ids, put after the pf's last parameter."""
    param = copy.deepcopy(like)
    for el in param.iter():
        if el.get(XMI_ID):
            el.set(XMI_ID, s.new_id())
    param.set("name", name)
    if direction == "in":
        param.attrib.pop("direction", None)
    else:
        param.set("direction", direction)
    pf.xpath("ownedParameter")[-1].addnext(param)
    return param


def stage_memory_write_conflict(s: Sample) -> Expect:
    """T001: calculatePosition/pf also writes the memory motionFinished (new out parameter
    motionFinished/mo); in jointMove/bb it runs in stage 1 next to jointMove/pf, which
    writes motionFinished too."""
    _add_parameter(s, s.behavior("ManipulatorControl", "calculatePosition/pf"), "motionFinished/mo", "out",
                   like=s.parameter("ManipulatorControl", "jointMove/pf", "motionFinished/mo"))
    return Expect(s.id(s.activity("ManipulatorControl", "jointMove")), "jointMove/bb")


def stage_output_write_conflict(s: Sample) -> Expect:
    """T002: outputManipState/pf also writes the Output Buffer motorControllerCommandK/ob (a
    new out parameter); in every basic behaviour it runs in stage 2 next to outputMotorCon/pf,
    which writes it too."""
    _add_parameter(s, s.behavior("ManipulatorControl", "outputManipState/pf"), "motorControllerCommandK/ob", "out",
                   like=s.parameter("ManipulatorControl", "outputMotorCon/pf", "motorControllerCommandK/ob"))
    return Expect(s.id(s.activity("ManipulatorControl", "idle")), "idle/bb")


def pf_reads_foreign_buffer(s: Sample) -> Expect:
    """T003: calculatePosition/pf of manip/a's cs gets a parameter
    motorControllerK/ve.encoder/ib: it reads an Input Buffer of another subsystem."""
    pf = s.behavior("ManipulatorControl", "calculatePosition/pf")
    param = _add_parameter(s, pf, "motorControllerK/ve.encoder/ib", "in",
                           like=s.parameter("MotorController", "regulateMotor/pf", "encoder/ib"))
    return Expect(s.id(param), "calculatePosition/pf")


def pf_reads_unknown_storage(s: Sample) -> Expect:
    """T003: calculatePosition/pf gets a parameter motorPosition/ib, which names no buffer or
    memory of manip/a's cs."""
    pf = s.behavior("ManipulatorControl", "calculatePosition/pf")
    param = _add_parameter(s, pf, "motorPosition/ib", "in",
                           like=s.parameter("ManipulatorControl", "calculatePosition/pf", "motorControllerStateK/ib"))
    return Expect(s.id(param), "motorPosition/ib")


def stage_read_write_race(s: Sample) -> Expect:
    """T004: outputMotorCon/pf, in stage 2 next to outputManipState/pf, also writes the memory
    motionFinished/m (a new out parameter), which outputManipState/pf reads."""
    _add_parameter(s, s.behavior("ManipulatorControl", "outputMotorCon/pf"), "motionFinished/mo", "out",
                   like=s.parameter("ManipulatorControl", "jointMove/pf", "motionFinished/mo"))
    return Expect(s.id(s.activity("ManipulatorControl", "idle")), "outputManipState/pf reads memory motionFinished/m")


def output_buffer_not_written(s: Sample) -> Expect:
    """T006: holdCommands/pf, the only pf of TaskControl's abort/bb, loses its parameter
    gripperCommand/ob: in abort nothing writes that Output Buffer, and its last value is sent."""
    s.remove(s.parameter("TaskControl", "holdCommands/pf", "gripperCommand/ob"))
    return Expect(s.id(s.activity("TaskControl", "abort")), "gripperCommand/ob")


def tf_calls_unknown_pf(s: Sample) -> Expect:
    """T005: the call action of TaskControl's abort/bb calls regulateMotor/pf, a partial
    transition function of MotorController, not of task/a's cs."""
    activity = s.activity("TaskControl", "abort")
    s.node(activity, "holdCommands/pf").set("behavior", s.id(s.behavior("MotorController", "regulateMotor/pf")))
    return Expect(s.id(activity), "abort/bb")


def tf_unbalanced_fork_join(s: Sample) -> Expect:
    """T005: ManipulatorControl's idle/bb loses JoinNode2: both branches of the second
    parallel stage flow straight into the final node (two forks, one join)."""
    activity = s.activity("ManipulatorControl", "idle")
    join, final = s.node(activity, "JoinNode2"), s.node(activity, "ActivityFinalNode1")
    for edge in activity.xpath("edge[@target=$j]", j=s.id(join)):
        edge.set("target", s.id(final))
    s.remove(s._find(activity, "edge[@source=$j]", "join → final", j=s.id(join)))
    final.set("incoming", " ".join(e.get(XMI_ID) for e in activity.xpath("edge[@target=$f]", f=s.id(final))))
    _remove_ref(activity, "node", s.id(join))
    s.remove(join)
    return Expect(s.id(activity), "idle/bb")


def tf_cycle(s: Sample) -> Expect:
    """T005: ManipulatorControl's idle/bb gets a control flow from JoinNode2 back to
    ForkNode1: the transition function's flow has a cycle."""
    activity = s.activity("ManipulatorControl", "idle")
    s.flow(activity, s.node(activity, "JoinNode2"), s.node(activity, "ForkNode1"))
    return Expect(s.id(activity), "idle/bb")


# ---- D: dataTypes and names -------------------------------------------------------------


def memory_of_unknown_type(s: Sample) -> Expect:
    """D001: FingerController's memory desiredPosition/m is typed by Complex of the SysML
    standard library: a library known by name only, and Complex is no primitive type."""
    memory = s.attribute("FingerController", "desiredPosition/m")
    memory.find("type").set("href", "pathmap://SysML16_LIBRARIES/SysML-Standard-Library.uml#SysML.package_"
                            "packagedElement_Libraries.package_packagedElement_PrimitiveValueTypes."
                            "dataType_packagedElement_Complex")
    return Expect(s.id(memory), "desiredPosition/m")


def field_of_unknown_type(s: Sample) -> Expect:
    """D001: the field x of the dataType Vector3 refers to an element id the file does not hold."""
    x = s.attribute("Vector3", "x")
    x.remove(x.find("type"))
    x.set("type", "_deletedDataTypeId")
    return Expect(s.id(x), "Vector3.x")


def recursive_datatype(s: Sample) -> Expect:
    """D002: the dataType Vector3 gets a field origin of type Vector3 (contains itself by value)."""
    vector = s.datatype("Vector3")
    s.add(vector, "ownedAttribute", "uml:Property", name="origin", type=s.id(vector))
    return Expect(s.id(vector), "Vector3")


def name_not_identifier(s: Sample) -> Expect:
    """D003: FingerController's memory desiredPosition/m is renamed desired-position/m."""
    memory = s.attribute("FingerController", "desiredPosition/m")
    memory.set("name", "desired-position/m")
    return Expect(s.id(memory), "desired-position/m")


def model_name_not_ascii(s: Sample) -> Expect:
    """D003: the model is renamed Straße: the ROS targets cannot name their message package after
    it (reported at the System, which the package stands for)."""
    model = s._find(s.root, "uml:Model", "model")
    model.set("name", "Straße")
    system = next(el for el in s.root.iter() if isinstance(el.tag, str) and el.tag.endswith("}System"))
    return Expect(system.get("base_Class") or "", "model 'Straße': cannot become a ROS package name")


def field_named_like_a_python_keyword(s: Sample) -> Expect:
    """D003: the field x of Vector3 is renamed yield: a Python keyword, which the generated
    ROS message classes cannot take as a field name."""
    x = s.attribute("Vector3", "x")
    x.set("name", "yield")
    return Expect(s.id(x), "Vector3.yield")


def memory_names_differ_in_case(s: Sample) -> Expect:
    """D004: FingerController gets a memory IntegralError/m right after integralError/m;
    the two differ only in case and map to one identifier."""
    original = s.attribute("FingerController", "integralError/m")
    memory = copy.deepcopy(original)
    for el in memory.iter():
        if el.get(XMI_ID):
            el.set(XMI_ID, s.new_id())
    memory.set("name", "IntegralError/m")
    original.addnext(memory)
    s.apply("InternalMemory", "Property", memory)
    return Expect(s.id(memory), "IntegralError/m")


def datatype_names_differ_in_case(s: Sample) -> Expect:
    """D004: the dataType EncoderReading is renamed motorCurrent, next to MotorCurrent: the
    two generated message files differ only in case."""
    datatype = s.datatype("EncoderReading")
    datatype.set("name", "motorCurrent")
    return Expect(s.id(datatype), "motorCurrent")


def field_names_differ_in_ros_spelling(s: Sample) -> Expect:
    """D004: GripperStatus gets a field motion_finished next to motionFinished: distinct C++
    identifiers, but one snake_case ROS field name."""
    original = s.attribute("GripperStatus", "motionFinished")
    field = copy.deepcopy(original)
    for el in field.iter():
        if el.get(XMI_ID):
            el.set(XMI_ID, s.new_id())
    field.set("name", "motion_finished")
    original.addnext(field)
    return Expect(s.id(field), "motion_finished")


def name_too_long(s: Sample) -> Expect:
    """D005: the dataType EncoderReading gets a 65-character name, one more than every target's file names allow."""
    datatype = s.datatype("EncoderReading")
    datatype.set("name", "EncoderReading" + "X" * 51)
    return Expect(s.id(datatype), "DataTypes::EncoderReading" + "X" * 51)


def name_of_thousands_of_characters(s: Sample) -> Expect:
    """D005: the pf planTask/pf gets a 5,000-character name (the element path is shown shortened)."""
    pf = next(el for el in s.root.iter() if el.get("name") == "planTask/pf")
    pf.set("name", "p" * 5000 + "/pf")
    return Expect(s.id(pf), "task/a.cs." + "p" * 38 + "…" + "p" * 21 + "/pf (5013 characters)")


def windows_device_name(s: Sample) -> Expect:
    """D006: the dataType GripperStatus is renamed Aux: its message would be Aux.msg."""
    datatype = s.datatype("GripperStatus")
    datatype.set("name", "Aux")
    return Expect(s.id(datatype), "DataTypes::Aux")


def host_with_a_space(s: Sample) -> Expect:
    """D007: task/a's «Agent» has the tag host "cell 1", which cannot name a launch file and a ROS node."""
    task = s.block("TaskAgent")
    s.application("Agent", task).set("host", "cell 1")
    return Expect(s.id(s.attribute("PickAndPlaceSystem", "task/a")), "has host 'cell 1'")


def datatype_names_differ_in_ros_spelling(s: Sample) -> Expect:
    """D004: the dataType EncoderReading is renamed Motor_Current, next to MotorCurrent: both
    become the ROS message MotorCurrent."""
    datatype = s.datatype("EncoderReading")
    datatype.set("name", "Motor_Current")
    return Expect(s.id(datatype), "Motor_Current")


# ---- R: reading and recognition ---------------------------------------------------------


def part_name_contradicts_block(s: Sample) -> Expect:
    """R001: grip/a's part fingerMotor/re (typed by the «RealEffector» block FingerMotor) is
    renamed fingerMotor/ve, its two links renamed to match: the part's suffix says Virtual
    Effector, the block's stereotype Real Effector."""
    part = s.attribute("GripperAgent", "fingerMotor/re")
    part.set("name", "fingerMotor/ve")
    for connector in s.block("GripperAgent").xpath("ownedConnector"):
        connector.set("name", connector.get("name").replace("fingerMotor/re", "fingerMotor/ve"))
    return Expect(s.id(part), "FingerMotor")


def block_suffix_contradicts_stereotype(s: Sample) -> Expect:
    """R001: the «VirtualEffector» block FingerController is renamed FingerController/re,
    whose suffix says Real Effector (the modelling guide's own example)."""
    block = s.block("FingerController")
    block.set("name", "FingerController/re")
    return Expect(s.id(block), "FingerController/re")


def duplicate_xmi_id(s: Sample) -> Expect:
    """R002: a second comment of the model carries the xmi:id of the model's first comment."""
    model = s._find(s.root, "uml:Model", "model")
    comment = model.find("ownedComment")
    duplicate = copy.deepcopy(comment)
    duplicate.find("body").text = "A copy pasted from another model, id and all."
    model.xpath("packagedElement")[-1].addnext(duplicate)
    return Expect(s.id(duplicate), s.id(duplicate))


def import_from_a_missing_file(s: Sample) -> Expect:
    """R004: the model imports the package of a units library kept in another file, which is
    not beside the model (a relative href that cannot be resolved)."""
    model = s._find(s.root, "uml:Model", "model")
    package_import = s.add(model, "packageImport", "uml:PackageImport")
    imported = etree.SubElement(package_import, "importedPackage")
    imported.set(XMI_TYPE, "uml:Package")
    imported.set("href", "../libraries/robot-units.uml#_unitsPackage")
    model.insert(0, package_import)
    return Expect(s.id(package_import), "../libraries/robot-units.uml#_unitsPackage")


def replication_beyond_its_bound(s: Sample) -> Expect:
    """R008: the replicated Internal Memory emergencyStopCommandK/m of ManipulatorControl stands
    for 2,147,483,648 instances instead of six."""
    memory = s.attribute("ManipulatorControl", "emergencyStopCommandK/m")
    for bound in memory:
        if etree.QName(bound).localname in ("lowerValue", "upperValue"):
            bound.set("value", "2147483648")
    return Expect(s.id(memory), "2147483648 instances")


def no_earl_model(s: Sample) -> Expect:
    """R003: the SystemInstance package is deleted (with every EARL stereotype applied in it):
    the file is a library of dataTypes, no EARL model."""
    s.remove(s._find(s.root, '//packagedElement[@xmi:type="uml:Package"][@name="SystemInstance"]', "package"))
    assert not [a for a in s.stereotype_applications() if etree.QName(a).namespace == s.root.nsmap["EARL"]]
    return Expect(line=1, name="{file}")


def _suppress(s: Sample, element: etree._Element, text: str) -> etree._Element:
    """A Papyrus comment on ``element`` whose body is ``text``."""
    comment = s.add(element, "ownedComment", "uml:Comment", annotatedElement=s.id(element))
    etree.SubElement(comment, "body").text = text
    element.insert(0, comment)
    return comment


def unused_suppression(s: Sample) -> Expect:
    """R005: the link task/a,grip/a carries the comment ``earl-m2t: ignore[C008]`` with a
    reason, but its name follows the convention: the suppression silences nothing."""
    connector = s.connector("PickAndPlaceSystem", "task/a,grip/a")
    comment = _suppress(s, connector, "earl-m2t: ignore[C008] the gripper team names its links")
    return Expect(s.id(comment), "C008")


def suppression_without_reason(s: Sample) -> Expect:
    """R006: the link task/a,grip/a is renamed gripperCommand (C008) and carries the comment
    ``earl-m2t: ignore[C008]`` without a reason: C008 is silenced, the missing reason reported."""
    connector = s.connector("PickAndPlaceSystem", "task/a,grip/a")
    connector.set("name", "gripperCommand")
    comment = _suppress(s, connector, "earl-m2t: ignore[C008]")
    return Expect(s.id(comment), "no reason")


def construct_outside_the_subset(text: str) -> tuple[str, str]:
    """R007: the SysML v2 sample's control subsystem of task/a also performs an action, a
    construct outside the subset earl-m2t reads."""
    anchor = "        part def TaskControl :> ControlSubsystem {\n"
    assert anchor in text
    return text.replace(anchor, anchor + "            perform planTask;\n", 1), "perform"


# ---- the table --------------------------------------------------------------------------

# ---- S010, S011: groups ------------------------------------------------------------------


def _group(s: Sample, owner: str, part_name: str, block_name: str, stereotype: str,
           held: list[tuple[str, str]]) -> etree._Element:
    """A new group block ``block_name`` «stereotype» holding parts (name, block), and a part
    ``part_name`` of block ``owner`` typed by it; returns the group block."""
    anchor = s.block(owner)
    block = s.add(anchor.getparent(), "packagedElement", "uml:Class", after=anchor, name=block_name)
    for name, type_name in held:
        s.add(block, "ownedAttribute", "uml:Property", name=name, type=s.id(s.block(type_name)),
              aggregation="composite")
    s.apply(stereotype, "Class", block)
    s.add(anchor, "ownedAttribute", "uml:Property", after=anchor.xpath("ownedAttribute")[-1], name=part_name,
          type=s.id(block), aggregation="composite")
    return block


def agent_group_holds_a_subsystem(s: Sample) -> Expect:
    """S010: the System gets an Agent Group mirror/ga whose block holds motorController/ve, a
    Virtual Effector outside any Agent, and no Agent."""
    block = _group(s, "PickAndPlaceSystem", "mirror/ga", "Mirror", "AgentGroup",
                   [("motorController/ve", "MotorController")])
    return Expect(s.id(block.xpath("ownedAttribute")[0]), "motorController/ve")


def subsystem_group_holds_the_control_subsystem(s: Sample) -> Expect:
    """S011: GripperAgent gets a Subsystem Group spare/gs whose block holds a cs typed by
    GripperControl: the Control Subsystem belongs in the Agent itself."""
    block = _group(s, "GripperAgent", "spare/gs", "SpareDrivers", "SubsystemGroup", [("cs", "GripperControl")])
    return Expect(s.id(block.xpath("ownedAttribute")[0]), "ControlSubsystem")


# ---- S012: paths ---------------------------------------------------------------------------


def agent_named_twice(s: Sample) -> Expect:
    """S012: the System gets a second part task/a typed by TaskAgent, as a copy-paste in a
    modelling tool makes it: two Agents with one path."""
    first = s.attribute("PickAndPlaceSystem", "task/a")
    second = s.add(first.getparent(), "ownedAttribute", "uml:Property", after=first, name="task/a",
                   type=first.get("type") or "", aggregation="composite")
    return Expect(s.id(second), "task/a")


Mutation = Callable[[Sample], Expect]

VARIANTS: dict[str, Mutation] = {
    "S001": system_without_robot,
    "S002": robot_without_agent,
    "S003": agent_with_two_control_subsystems,
    "S004": virtual_receptor_without_real_receptor,
    "S005": virtual_effector_without_real_effector,
    "S006": zombie_agent,
    "S007": declared_type_mismatch,
    "S008": virtual_effector_without_output,
    "S009": untyped_memory,
    "S010": agent_group_holds_a_subsystem,
    "S011": subsystem_group_holds_the_control_subsystem,
    "S012": agent_named_twice,
    "C001": link_between_two_outputs,
    "C001-two-inputs": link_between_two_inputs,
    "C001-memory-end": link_to_a_memory,
    "C002": link_control_to_real_effector,
    "C003": inter_agent_link_inside_one_agent,
    "C004": real_effector_unreached,
    "C005": real_receptor_unheard,
    "C006": link_datatype_mismatch,
    "C007": input_buffer_unfed,
    "C008": link_name_convention,
    "C009": one_shot_command_into_latest_value,
    "C010": best_effort_into_reliable,
    "C010-queue": queue_best_effort,
    "B001": fsm_without_initial_state,
    "B001-initial-leads-nowhere": initial_pseudostate_leads_nowhere,
    "B001-two-initial": fsm_with_two_initial_states,
    "B001-no-fsm": subsystem_without_fsm,
    "B001-two-fsms": subsystem_with_two_fsms,
    "B002": state_without_basic_behaviour,
    "B003": transition_to_another_fsm,
    "B004": unreachable_state,
    "B005": guard_names_unknown_predicate,
    "B005-unknown-field": predicate_names_unknown_field,
    "B005-index-not-array": guard_indexes_a_boolean,
    "B005-index-out-of-range": guard_index_out_of_range,
    "B005-not-a-condition": guard_is_a_composite,
    "B005-instance-out-of-range": guard_names_a_seventh_motor,
    "B005-template-outside-replication": guard_names_the_template,
    "B006": exclusion_removed,
    "B006-priority": self_transition_priority_removed,
    "B007": emergency_transition_removed,
    "B007-no-exit": state_without_exit,
    "B008": guard_syntax_error,
    "B008-empty-tc": empty_terminal_condition,
    "B009": buffer_group_names_unknown_buffer,
    "B009-output": buffer_group_names_output_buffer,
    "B010": state_without_buffer_group,
    "B010-unknown-group": state_names_unknown_buffer_group,
    "B011": queue_of_no_value,
    "B011-negative-timeout": negative_timeout,
    "B011-reliability": reliability_unknown,
    "B012": error_condition_reads_in_error,
    "T001": stage_memory_write_conflict,
    "T002": stage_output_write_conflict,
    "T003": pf_reads_foreign_buffer,
    "T003-unknown-storage": pf_reads_unknown_storage,
    "T004": stage_read_write_race,
    "T005": tf_calls_unknown_pf,
    "T005-unbalanced": tf_unbalanced_fork_join,
    "T005-cycle": tf_cycle,
    "T006": output_buffer_not_written,
    "D001": memory_of_unknown_type,
    "D001-field": field_of_unknown_type,
    "D002": recursive_datatype,
    "D003": name_not_identifier,
    "D003-model-name": model_name_not_ascii,
    "D003-python-keyword": field_named_like_a_python_keyword,
    "D004": memory_names_differ_in_case,
    "D004-datatype-case": datatype_names_differ_in_case,
    "D004-ros-field": field_names_differ_in_ros_spelling,
    "D004-ros-message": datatype_names_differ_in_ros_spelling,
    "D005": name_too_long,
    "D005-thousands": name_of_thousands_of_characters,
    "D006": windows_device_name,
    "D007": host_with_a_space,
    "R001": part_name_contradicts_block,
    "R001-block-suffix": block_suffix_contradicts_stereotype,
    "R002": duplicate_xmi_id,
    "R003": no_earl_model,
    "R004": import_from_a_missing_file,
    "R005": unused_suppression,
    "R006": suppression_without_reason,
    "R008": replication_beyond_its_bound,
}

# Rows whose broken model is the SysML v2 text of the sample (samples/pick_and_place/pick_and_place.sysml):
# the mutation takes the text and gives the broken text and the construct the finding names.
SYSML_VARIANTS: dict[str, Callable[[str], tuple[str, str]]] = {
    "R007": construct_outside_the_subset,
}

# Rows that expose a defect of earl-m2t rather than of the variant.
KNOWN_BUGS: dict[str, str] = {
}


def _params() -> list:
    params = []
    for variant, mutation in VARIANTS.items():
        marks = [pytest.mark.xfail(strict=True, reason=KNOWN_BUGS[variant])] if variant in KNOWN_BUGS else []
        params.append(pytest.param(variant, mutation, id=variant, marks=marks))
    return params


def _code(variant: str) -> str:
    return variant.partition("-")[0]


def _describe(findings: list[Diagnostic]) -> str:
    return "\n".join(f"  {d.code} {d.location.line}:{d.location.xmi_id} {d.message}" for d in findings) or "  (none)"


def _line_of(path: Path, xmi_id: str) -> int:
    root = etree.parse(str(path)).getroot()
    found = root.xpath("//*[@xmi:id=$i]", namespaces=NS, i=xmi_id)
    assert found, f"{xmi_id} is not in the variant"
    return found[0].sourceline


# ---- tests ------------------------------------------------------------------------------


def test_every_catalogue_rule_has_a_variant() -> None:
    listed = tomllib.loads((ROOT / "metamodel" / "rules" / "catalogue.toml").read_text(encoding="utf-8"))
    # the verification rules (engine spin) have their variants in test_verify_rules.py
    codes = {code for code, row in listed["rules"].items() if row["engine"] != "spin"}
    codes |= {code for code, info in catalogue().items() if info.engine != "spin"}
    covered = {_code(v) for v in VARIANTS} | {_code(v) for v in SYSML_VARIANTS}
    covered |= {_code(v) for v in VARIABILITY_VARIANTS}  # variable structure: test_variability_triggers.py
    assert codes - covered == set(), "rules without a broken variant"
    assert covered - codes == set(), "variants of rules that are not in the catalogue"


def test_every_mutation_says_what_it_breaks() -> None:
    for variant, mutation in {**VARIANTS, **SYSML_VARIANTS}.items():
        doc = (mutation.__doc__ or "").strip()
        assert doc.startswith(_code(variant)), f"{mutation.__name__}: docstring must start with {_code(variant)}"


def test_small_model_base_is_clean(tmp_path: Path) -> None:
    path = tmp_path / "mini.uml"
    path.write_bytes(mini_base().to_bytes())
    findings = check(path)
    assert findings == [], _describe(findings)


@pytest.mark.parametrize(("variant", "mutation"), _params())
def test_variant_triggers_exactly_its_rule(variant: str, mutation: Mutation, sample_bytes: bytes,
                                           tmp_path: Path) -> None:
    code = _code(variant)
    sample = Sample(sample_bytes)
    expect = mutation(sample)
    path = tmp_path / "variant.uml"
    path.write_bytes(sample.to_bytes())

    findings = check(path)

    assert findings, f"{variant}: no finding"
    assert {d.code for d in findings} == {code}, f"{variant}: expected only {code}, got\n{_describe(findings)}"
    assert all(d.location.file == str(path) for d in findings)
    line = expect.line or _line_of(path, expect.xmi_id)
    pointing = [d for d in findings if d.location.line > 0
                and ((expect.xmi_id and d.location.xmi_id == expect.xmi_id) or d.location.line == line)]
    assert pointing, f"{variant}: no finding points at {expect.xmi_id or 'line'} (line {line}):\n{_describe(findings)}"
    name = expect.name.format(file=path)
    assert any(name in d.message for d in pointing), (
        f"{variant}: no finding at the element names {name!r}:\n{_describe(pointing)}"
    )


@pytest.mark.parametrize("variant", list(SYSML_VARIANTS))
def test_sysml_variant_triggers_exactly_its_rule(variant: str, tmp_path: Path) -> None:
    sample = (ROOT / "samples" / "pick_and_place" / "pick_and_place.sysml").read_text(encoding="utf-8")
    broken, construct = SYSML_VARIANTS[variant](sample)
    path = tmp_path / "variant.sysml"
    path.write_text(broken, encoding="utf-8")
    line = next(n for n, text in enumerate(broken.splitlines(), 1) if text.strip().startswith(construct))
    findings = check(path)
    assert {d.code for d in findings} == {_code(variant)}, _describe(findings)
    assert [(d.location.line, d.location.column) for d in findings] == [(line, 13)]
    assert f"'{construct}'" in findings[0].message
