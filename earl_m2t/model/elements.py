"""The typed, immutable EARL model that every stage after lifting works on.

Elements refer to each other by *element path* (``manip/a.cs.manipulatorCommand/ib``), the
same string diagnostics and ``show`` print, so the model stays a tree of frozen values;
:class:`EarlModel` resolves paths.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from functools import cached_property

from earl_m2t.model.activation import Activation, BufferGroup, Simulation
from earl_m2t.model.conditions import Condition
from earl_m2t.model.configuration import Configuration
from earl_m2t.model.datatypes import DataType, DataTypeNamesake
from earl_m2t.model.directives import LtlProperty, Suppression
from earl_m2t.model.kinds import (
    AccessMode,
    Direction,
    GroupKind,
    LinkScope,
    Reactivation,
    ReceiveMode,
    Reliability,
    SubsystemKind,
)
from earl_m2t.model.location import Location
from earl_m2t.model.scope import Scope


@dataclass(frozen=True, slots=True)
class Buffer:
    name: str
    path: str
    direction: Direction
    datatype: str  # key into EarlModel.datatypes, "" when untyped or unresolved
    template: str  # name before replicated expansion (``motorControllerStateK/ib``)
    index: int  # 1..N for replicated instances, 0 otherwise
    location: Location
    recognised_by: str
    type_ref: str = ""  # the type reference as written when it did not resolve (rule D001)
    # how an Input Buffer receives: a ReceiveMode (a queue holds up to queue_size values), or the
    # tag's value as written, which B011 reports
    receive: str = ReceiveMode.LATEST
    queue_size: int = 0
    # FABRIC's <in/out side converter> (tags side, converter): "" when not given
    side: str = ""
    converter: str = ""
    channel: str = ""  # FABRIC's IPC channel of the buffer (<io_buffer name>, tag channel)
    # whether its link may drop values: a Reliability, or the tag's value as written (B011); C010
    # reports links whose two ends disagree
    reliability: str = Reliability.RELIABLE

    @property
    def abbreviation(self) -> str:
        return "ib" if self.direction == Direction.IN else "ob"


@dataclass(frozen=True, slots=True)
class Memory:
    name: str
    path: str
    datatype: str
    template: str
    index: int
    location: Location
    recognised_by: str
    type_ref: str = ""


@dataclass(frozen=True, slots=True)
class PrimitivePredicate:
    name: str
    path: str
    fun: Condition | None  # None when the body is user code in another language
    language: str
    body: str
    location: Location
    recognised_by: str


@dataclass(frozen=True, slots=True)
class Exclusion:
    """Primitive predicates the model declares mutually exclusive (paper Table 6 note)."""

    name: str
    predicates: tuple[str, ...]  # names of primitive predicates
    location: Location


@dataclass(frozen=True, slots=True)
class Access:
    """A pf's declared access to a buffer or memory: the parameter as written, and what it resolved to."""

    name: str
    mode: AccessMode
    targets: tuple[str, ...]  # paths of buffers/memory of its subsystem
    foreign: str  # path of a subsystem it names that is not its own, else ""
    location: Location


@dataclass(frozen=True, slots=True)
class PartialFunction:
    name: str
    path: str
    accesses: tuple[Access, ...]
    language: str
    body: str
    location: Location
    recognised_by: str

    @property
    def reads(self) -> tuple[str, ...]:
        return tuple(t for a in self.accesses if a.mode != AccessMode.WRITE for t in a.targets)

    @property
    def writes(self) -> tuple[str, ...]:
        return tuple(t for a in self.accesses if a.mode != AccessMode.READ for t in a.targets)


@dataclass(frozen=True, slots=True)
class ActivityProblem:
    """Why a transition function's activity could not be staged (rule T005)."""

    message: str
    location: Location


@dataclass(frozen=True, slots=True)
class BasicBehaviour:
    name: str
    path: str
    tc: Condition | None
    ec: Condition | None
    stages: tuple[tuple[str, ...], ...]  # pf names per stage, stage 1 first
    activity_problems: tuple[ActivityProblem, ...]
    location: Location
    recognised_by: str

    @property
    def functions(self) -> tuple[str, ...]:
        return tuple(pf for stage in self.stages for pf in stage)


@dataclass(frozen=True, slots=True)
class State:
    name: str
    path: str
    behaviours: tuple[str, ...]  # bb names; exactly one is expected (B002)
    location: Location
    activation: Activation = Activation()
    configuration: str = ""  # the configuration it names (a coordinator's state), "" for none
    quiescent: bool = False  # its agent may be stopped by a switch while it is current
    # FABRIC's behaviours of a state that runs several side by side (tag behaviours): its one
    # basic behaviour composes them; () for a state of one behaviour
    composes: tuple[str, ...] = ()
    # its guards exclude each other by design (tag exclusiveGuards): FABRIC gets them as written
    exclusive_guards: bool = False


@dataclass(frozen=True, slots=True)
class Transition:
    name: str
    path: str
    source: str  # state name, or "" when not a state of this FSM
    target: str
    source_foreign: bool  # source/target lie outside this FSM (B003)
    target_foreign: bool
    condition: Condition | None
    priority: int
    order: int  # position in the model, which breaks priority ties
    location: Location
    # False when the model leaves it unnamed: it is then called ``source,target/t``, which two
    # unnamed transitions between the same states share (rule S012 compares named ones only)
    named: bool = True


@dataclass(frozen=True, slots=True)
class Fsm:
    name: str
    path: str
    states: tuple[State, ...]
    transitions: tuple[Transition, ...]
    initial_states: tuple[str, ...]  # targets of the initial pseudostates
    location: Location

    @property
    def initial(self) -> str | None:
        return self.initial_states[0] if len(self.initial_states) == 1 else None

    def state(self, name: str) -> State | None:
        return next((s for s in self.states if s.name == name), None)


@dataclass(frozen=True, slots=True)
class Subsystem:
    name: str
    path: str
    kind: SubsystemKind
    agent: str
    block: str  # name of the block that defines it
    block_id: str
    template: str
    index: int
    inputs: tuple[Buffer, ...]
    outputs: tuple[Buffer, ...]
    memory: tuple[Memory, ...]
    fsm: Fsm | None
    behaviours: tuple[BasicBehaviour, ...]
    functions: tuple[PartialFunction, ...]
    predicates: tuple[PrimitivePredicate, ...]
    exclusions: tuple[Exclusion, ...]
    fsm_count: int
    location: Location
    recognised_by: str
    buffer_groups: tuple[BufferGroup, ...] = ()
    scope: Scope | None = None  # what the names in its conditions stand for; set by the lift
    simulation: Simulation | None = None  # FABRIC's <simulation> (tags useRosSimClock, ...)

    @property
    def buffers(self) -> tuple[Buffer, ...]:
        return self.inputs + self.outputs

    def conditions(self) -> Iterator[Condition]:
        """Every condition it holds: guards, tc/ec, primitive predicate bodies."""
        if self.fsm is not None:
            for tr in self.fsm.transitions:
                if tr.condition is not None:
                    yield tr.condition
        for bb in self.behaviours:
            for cond in (bb.tc, bb.ec):
                if cond is not None:
                    yield cond
        for pp in self.predicates:
            if pp.fun is not None:
                yield pp.fun

    def behaviour(self, name: str) -> BasicBehaviour | None:
        return next((b for b in self.behaviours if b.name == name), None)

    def function(self, name: str) -> PartialFunction | None:
        return next((f for f in self.functions if f.name == name), None)

    def predicate(self, name: str) -> PrimitivePredicate | None:
        return next((p for p in self.predicates if p.name == name), None)

    # the paper's part names, for the rule language (``self.ib``, ``self.ob``, ``self.m``)
    @property
    def ib(self) -> tuple[Buffer, ...]:
        return self.inputs

    @property
    def ob(self) -> tuple[Buffer, ...]:
        return self.outputs

    @property
    def m(self) -> tuple[Memory, ...]:
        return self.memory


@dataclass(frozen=True, slots=True)
class Link:
    """A communication link from an Output Buffer to an Input Buffer."""

    name: str
    path: str
    ends: tuple[str, str]  # buffer paths in model order ("" for an end that is not a buffer)
    source: str  # the Output Buffer end, "" when none or both
    target: str  # the Input Buffer end, "" when none or both
    scope: LinkScope
    owner: str  # agent path for inter-subsystem links, system name otherwise
    template: str
    location: Location


@dataclass(frozen=True, slots=True)
class GroupMember:
    """A part of a group's block: its name, the EARL concept it was recognised as ("" for none)
    and where it is."""

    name: str
    concept: str
    location: Location


@dataclass(frozen=True, slots=True)
class Group:
    """An Agent Group (``kind`` ``ga``, the authors' GpAgents; in the System or a Robot) or a
    Subsystem Group (``gs``, GpSubsys; in an Agent): a part whose block gathers Agents or
    Subsystems. The group only structures the model: ``members`` are the paths of the Agents or
    Subsystems it contributes to its ``owner`` (a system, robot or agent path); ``parts`` are
    all parts of its block, those it may not hold included (rules S010, S011)."""

    name: str
    path: str
    kind: GroupKind
    block: str
    owner: str
    members: tuple[str, ...]
    parts: tuple[GroupMember, ...]
    location: Location
    recognised_by: str


@dataclass(frozen=True, slots=True)
class Agent:
    name: str
    path: str
    block: str
    robot: str  # robot path, "" for agents directly in the system
    subsystems: tuple[Subsystem, ...]
    links: tuple[Link, ...]  # inter-subsystem links
    declared_type: str
    computed_type: str
    location: Location
    recognised_by: str
    groups: tuple[Group, ...] = ()  # Subsystem Groups
    optional: bool = False  # its part's multiplicity is [0..1]: the general model may leave it out
    # how a switch brings it back: a Reactivation, or the tag's value as written (a rule reports it)
    reactivation: str = Reactivation.RESTART
    host: str = ""  # the tag host: the computer its nodes run on, "" for the default host (rule D007)

    def of_kind(self, kind: SubsystemKind) -> tuple[Subsystem, ...]:
        return tuple(s for s in self.subsystems if s.kind == kind)

    @property
    def cs(self) -> tuple[Subsystem, ...]:
        return self.of_kind(SubsystemKind.CS)

    @property
    def ve(self) -> tuple[Subsystem, ...]:
        return self.of_kind(SubsystemKind.VE)

    @property
    def re(self) -> tuple[Subsystem, ...]:
        return self.of_kind(SubsystemKind.RE)

    @property
    def vr(self) -> tuple[Subsystem, ...]:
        return self.of_kind(SubsystemKind.VR)

    @property
    def rr(self) -> tuple[Subsystem, ...]:
        return self.of_kind(SubsystemKind.RR)


@dataclass(frozen=True, slots=True)
class Robot:
    name: str
    path: str
    block: str
    agents: tuple[str, ...]  # agent paths
    location: Location
    recognised_by: str


@dataclass(frozen=True, slots=True)
class System:
    name: str
    path: str
    robots: tuple[Robot, ...]
    agents: tuple[Agent, ...]  # every agent, inside robots or not
    links: tuple[Link, ...]  # inter-agent links
    location: Location
    recognised_by: str
    groups: tuple[Group, ...] = ()  # Agent Groups, in the system or in its robots
    configurations: tuple[Configuration, ...] = ()  # its «Configuration» constraints, in model order

    def configuration(self, name: str) -> Configuration | None:
        return next((c for c in self.configurations if c.name == name), None)


@dataclass(frozen=True)
class EarlModel:
    """The lifted model of one file."""

    file: str
    dialect: str
    name: str
    systems: tuple[System, ...]
    datatypes: Mapping[str, DataType]  # by qualified name, read-only
    has_earl_content: bool = True  # False when nothing in the file was recognised as EARL
    suppressions: tuple[Suppression, ...] = ()  # its ``earl-m2t: ignore[…]`` comments
    properties: tuple[LtlProperty, ...] = ()  # its «LtlProperty» constraints and ``earl-m2t: ltl`` comments
    # the names a package gives to several of its dataTypes (rule S012): ``datatypes`` holds one
    # dataType per qualified name, of those the model uses
    datatype_namesakes: tuple[DataTypeNamesake, ...] = ()

    @property
    def system(self) -> System | None:
        return self.systems[0] if self.systems else None

    @property
    def agents(self) -> tuple[Agent, ...]:
        return tuple(a for s in self.systems for a in s.agents)

    @property
    def robots(self) -> tuple[Robot, ...]:
        return tuple(r for s in self.systems for r in s.robots)

    @property
    def subsystems(self) -> tuple[Subsystem, ...]:
        return tuple(sub for a in self.agents for sub in a.subsystems)

    @property
    def links(self) -> tuple[Link, ...]:
        return tuple(link for a in self.agents for link in a.links) + tuple(
            link for s in self.systems for link in s.links
        )

    @cached_property
    def _buffers(self) -> dict[str, Buffer]:
        return {b.path: b for s in self.subsystems for b in s.buffers}

    @cached_property
    def _subsystems(self) -> dict[str, Subsystem]:
        return {s.path: s for s in self.subsystems}

    def buffer(self, path: str) -> Buffer | None:
        return self._buffers.get(path)

    def subsystem(self, path: str) -> Subsystem | None:
        return self._subsystems.get(path)

    def subsystem_of(self, buffer_path: str) -> Subsystem | None:
        buf = self._buffers.get(buffer_path)
        if buf is None:
            return None
        return self._subsystems.get(buf.path.rpartition(".")[0]) or next(
            (s for s in self.subsystems if buf in s.buffers), None
        )

    def definitions(self) -> Iterator[Subsystem]:
        """One subsystem per defining block: replicated instances share their behaviour."""
        seen: set[str] = set()
        for sub in self.subsystems:
            if sub.block_id not in seen:
                seen.add(sub.block_id)
                yield sub
