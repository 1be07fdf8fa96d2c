"""FABRIC packages → one lifted EARL model (a system of agents of subsystems).

Names follow FABRIC's own convention for packages, ``<agent>_<kind>_<name>``
(``velma_core_ve_body``: agent ``velma_core``, virtual effector ``ve_body``); a package name
without a kind is the control subsystem ``cs`` of an agent of that name, and so is every
package whose agent the imported packages do not complete (one cs, ve with re, vr with rr),
with a note. Every element keeps
FABRIC's name with the EARL suffix (``hi_cmd/ib``, ``recvStatus/pp``, ``safe/bb``, ``safe/pf``),
so gen --target orocos writes FABRIC's names back. Running components become partial
transition functions (one stage: FABRIC runs them side by side), their code stays the
component (its type from the configuration, as a comment). Each package's buffers are linked
to another imported package's buffers that use the same IPC channel (``<io_buffer name>``).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

from earl_m2t.diagnostics import ModelReadError
from earl_m2t.fabric.conditions import ConditionError, parse_fabric_condition
from earl_m2t.fabric.package import FabricPackage, Where
from earl_m2t.lift.conditions import resolve_subsystem
from earl_m2t.lift.structure import computed_agent_type
from earl_m2t.model.conditions import Condition, ConditionRole
from earl_m2t.model.datatypes import DataType
from earl_m2t.model.elements import (
    Activation,
    Agent,
    BasicBehaviour,
    Buffer,
    BufferGroup,
    EarlModel,
    Fsm,
    Link,
    PartialFunction,
    PrimitivePredicate,
    Robot,
    Simulation,
    State,
    Subsystem,
    System,
    Transition,
)
from earl_m2t.model.kinds import SUBSYSTEM_KINDS, DataTypeKind, Direction, LinkScope, SubsystemKind
from earl_m2t.model.location import Location
from earl_m2t.predicate import format_predicate

PREDICATE_CALL = re.compile(r"([A-Za-z_][A-Za-z0-9_]*/pp)\b")
DIALECT = "fabric"
RECOGNISED = "suffix"
LANGUAGE = "EARL"
CODE = "C++"
COMPOSED = "__"  # joins the names of the behaviours a state runs side by side


@dataclass(frozen=True)
class _Names:
    agent: str
    kind: SubsystemKind
    part: str  # the subsystem's part name in its agent


def package_names(package: str) -> _Names:
    for kind in SUBSYSTEM_KINDS:
        marker = f"_{kind}_"
        if marker in package:
            agent, _, rest = package.partition(marker)
            if agent and rest:
                return _Names(agent, kind, f"{kind}_{rest}")
    return _Names(package, SubsystemKind.CS, "cs")


def _complete(kinds: list[SubsystemKind]) -> bool:
    """The subsystems FABRIC's naming gives an agent make an EARL agent (rules S003-S005)."""
    return (kinds.count(SubsystemKind.CS) == 1 and (SubsystemKind.VE in kinds) == (SubsystemKind.RE in kinds)
            and (SubsystemKind.VR in kinds) == (SubsystemKind.RR in kinds))


def agent_names(packages: Sequence[FabricPackage]) -> tuple[dict[str, _Names], list[str]]:
    """Agent, kind and part name of every package, and notes on the packages whose agent is
    not complete among the imported ones: each becomes the control subsystem of an agent of its
    own name (FABRIC itself does not tell kinds apart)."""
    named = {p.name: package_names(p.name) for p in packages}
    kinds: dict[str, list[SubsystemKind]] = {}
    for names in named.values():
        kinds.setdefault(names.agent, []).append(names.kind)
    notes: list[str] = []
    for package, names in named.items():
        if not _complete(kinds[names.agent]):
            notes.append(f"{package}: the packages of agent {names.agent} imported do not make an EARL agent "
                         f"(one cs, ve with re, vr with rr); imported as the control subsystem of agent {package}")
            named[package] = _Names(package, SubsystemKind.CS, "cs")
    return named, notes


def _location(where: Where) -> Location:
    return Location(where.file, where.line)


def packages_to_model(packages: Sequence[FabricPackage], name: str) -> tuple[EarlModel, list[str]]:
    """One EARL model holding every package as a subsystem, and notes on how packages were
    placed; raises ModelReadError (file, line)."""
    datatypes: dict[str, DataType] = {}
    agents: dict[str, list[Subsystem]] = {}
    named, notes = agent_names(packages)
    types = message_types(packages)
    for package in packages:
        names = named[package.name]
        subsystem = _subsystem(package, names, datatypes, types)
        if any(s.name == names.part for s in agents.get(names.agent, [])):
            raise ModelReadError(package.spec_file, f"a second subsystem {names.agent}.{names.part} "
                                 f"(package {package.name}) among the imported packages")
        agents.setdefault(names.agent, []).append(subsystem)
    first = _location(packages[0].where) if packages else Location("<fabric>")
    links = _links(packages, agents)
    built: list[Agent] = []
    built_paths: list[str] = []
    for agent_name, subsystems in agents.items():
        own = tuple(link for link in links if link.scope == "agent" and link.owner == agent_name)
        kinds = {s.kind for s in subsystems}
        linked = any(link.scope == "system" and agent_name in (link.ends[0].split(".")[0], link.ends[1].split(".")[0])
                     for link in links)
        built_paths.append(agent_name)
        built.append(Agent(name=agent_name, path=agent_name, block=f"{agent_name}_agent", robot=f"{name}_robot",
                           subsystems=tuple(subsystems), links=own, declared_type="",
                           computed_type=computed_agent_type(bool(kinds & {"ve", "re"}), bool(kinds & {"vr", "rr"}),
                                                             linked),
                           location=subsystems[0].location, recognised_by="stereotype"))
    robot = Robot(name=f"{name}_robot", path=f"{name}_robot", block=f"{name}_robot", agents=tuple(built_paths),
                  location=first, recognised_by="stereotype")
    system = System(name=f"{name}_system", path=f"{name}_system", robots=(robot,), agents=tuple(built),
                    links=tuple(link for link in links if link.scope == "system"), location=first,
                    recognised_by="stereotype")
    return EarlModel(file=first.file, dialect=DIALECT, name=name, systems=(system,), datatypes=datatypes), notes


def message_types(packages: Sequence[FabricPackage]) -> dict[str, str]:
    """The dataType key of every ROS message type the packages name: ``pkg::Msg``, or, when
    another package has a message of that name too, ``pkg::pkg_Msg`` (generated code holds
    every dataType in one scope; the orocos target names the message ``pkg::Msg`` again)."""
    types = sorted({b.type for p in packages for b in p.buffers})
    count: dict[str, int] = {}
    for kind in types:
        count[kind.split("::")[1]] = count.get(kind.split("::")[1], 0) + 1
    keys: dict[str, str] = {}
    for kind in types:
        ros_package, message = kind.split("::")
        keys[kind] = kind if count[message] == 1 else f"{ros_package}::{ros_package}_{message}"
    return keys


def _subsystem(package: FabricPackage, names: _Names, datatypes: dict[str, DataType],
               message_types: dict[str, str]) -> Subsystem:
    path = f"{names.agent}.{names.part}"
    buffers: list[Buffer] = []
    for buf in package.buffers:
        key = message_types[buf.type]
        if key not in datatypes:
            name = key.split("::")[1]
            datatypes[key] = DataType(name, key, DataTypeKind.STRUCT, location=_location(buf.where))
        suffix = "ib" if buf.direction == "in" else "ob"
        buffer_name = f"{buf.alias}/{suffix}"
        buffers.append(Buffer(name=buffer_name, path=f"{path}.{buffer_name}", direction=Direction(buf.direction),
                              datatype=key, template=buffer_name, index=0, location=_location(buf.where),
                              recognised_by=RECOGNISED, side=buf.side, converter=buf.converter))
    inputs = {b.name.partition("/")[0]: b for b in buffers if b.direction == "in"}
    groups = tuple(BufferGroup(name=g.name, path=f"{path}.{g.name}",
                               obligatory=tuple(inputs[a].name for a in g.obligatory),
                               optional=tuple(inputs[a].name for a in g.optional), location=_location(g.where))
                   for g in package.groups)
    predicate_names = {p: f"{p}/pp" for p, _ in package.predicates}
    predicates = tuple(PrimitivePredicate(name=f"{p}/pp", path=f"{path}.{p}/pp", fun=None, language=CODE,
                                          body=f"// computed by the master of FABRIC package {package.name}",
                                          location=_location(where), recognised_by=RECOGNISED)
                       for p, where in package.predicates)
    component_types = {c.name: c.type for c in package.components}
    running = list(dict.fromkeys(r for b in package.behaviours for r in b.running))
    functions = tuple(PartialFunction(
        name=f"{r}/pf", path=f"{path}.{r}/pf", accesses=(), language=CODE,
        body=(f"// FABRIC component {r} of type {component_types[r]}" if component_types.get(r)
              else f"// FABRIC component {r}, created by FABRIC's deployer"),
        location=_location(next(b.where for b in package.behaviours if r in b.running)),
        recognised_by=RECOGNISED) for r in running)

    def condition(text: str, where: Where, owner: str, role: ConditionRole, what: str) -> Condition:
        try:
            expr = parse_fabric_condition(text, predicate_names)
        except ConditionError as exc:
            raise ModelReadError(where.file, f"{what}: {exc}", where.line) from None
        # the paper's form, x/pp.fun, which SysML v2 text writes as a call: 'x/pp'()
        text = PREDICATE_CALL.sub(r"\1.fun", format_predicate(expr))
        return Condition(text, LANGUAGE, _location(where), owner, role)

    def behaviour(name: str, stop_cond: str, err_cond: str, running: tuple[str, ...], where: Where,
                  what: str) -> BasicBehaviour:
        bb_path = f"{path}.{name}/bb"
        return BasicBehaviour(
            name=f"{name}/bb", path=bb_path,
            tc=condition(stop_cond, where, bb_path, ConditionRole.TC, f"{what} stop_cond"),
            ec=condition(err_cond, where, bb_path, ConditionRole.EC, f"{what} err_cond"),
            stages=((tuple(f"{r}/pf" for r in running),) if running else ()), activity_problems=(),
            location=_location(where), recognised_by=RECOGNISED)

    behaviours = [behaviour(b.name, b.stop_cond, b.err_cond, b.running, b.where, f"behavior '{b.name}'")
                  for b in package.behaviours]
    by_name = {b.name: b for b in package.behaviours}
    fsm_path = f"{path}.fsm"
    states: list[State] = []
    for s in package.states:
        composes: tuple[str, ...] = ()
        own = tuple(f"{b}/bb" for b in s.behaviours)
        if len(s.behaviours) > 1:
            # FABRIC runs them side by side: the state ends when one's err_cond (else one's
            # stop_cond) holds, the components of all run (master_component.cpp, updateHook)
            composes, name = own, _composed_name(s.behaviours, set(by_name))
            if all(b.name != f"{name}/bb" for b in behaviours):
                parts = [by_name[b] for b in s.behaviours]
                behaviours.append(behaviour(
                    name, " or ".join(f"({p.stop_cond})" for p in parts),
                    " or ".join(f"({p.err_cond})" for p in parts),
                    tuple(dict.fromkeys(r for p in parts for r in p.running)), s.where,
                    f"state '{s.name}' behaviors"))
            own = (f"{name}/bb",)
        states.append(State(name=s.name, path=f"{fsm_path}.{s.name}", behaviours=own, location=_location(s.where),
                            activation=Activation(group=s.group.name, min_period=s.group.min_period,
                                                  first_timeout=s.group.first_timeout,
                                                  next_timeout=s.group.next_timeout,
                                                  min_period_sim=s.group.min_period_sim,
                                                  first_timeout_sim=s.group.first_timeout_sim,
                                                  used_time=s.group.used_time),
                            composes=composes, exclusive_guards=len(s.next_states) > 1))
    transitions: list[Transition] = []
    for s in package.states:
        for target, text, where in s.next_states:
            name = f"{s.name},{target}/t"
            transitions.append(Transition(
                name=name, path=f"{fsm_path}.{name}", source=s.name, target=target, source_foreign=False,
                target_foreign=False,
                condition=condition(text, where, f"{fsm_path}.{name}", ConditionRole.IC,
                                    f"state '{s.name}' next_state '{target}'"),
                priority=0, order=len(transitions), location=_location(where)))
    fsm = Fsm(name="fsm", path=fsm_path, states=tuple(states), transitions=tuple(transitions),
              initial_states=(package.initial,), location=_location(package.where))
    return resolve_subsystem(Subsystem(
        name=names.part, path=path, kind=names.kind, agent=names.agent, block=package.name,
        block_id=package.name, template=names.part, index=0,
        inputs=tuple(b for b in buffers if b.direction == "in"),
        outputs=tuple(b for b in buffers if b.direction == "out"), memory=(), fsm=fsm, behaviours=tuple(behaviours),
        functions=functions, predicates=predicates, exclusions=(), fsm_count=1, location=_location(package.where),
        recognised_by="stereotype", buffer_groups=groups,
        simulation=(Simulation(package.simulation.use_ros_sim_clock, package.simulation.use_sim_clock,
                               package.simulation.trigger_gazebo) if package.simulation else None)), datatypes)


def _composed_name(parts: tuple[str, ...], taken: set[str]) -> str:
    """The name of the basic behaviour composing FABRIC's behaviours ``parts``: their names
    joined (an identifier, as generated code needs), distinct from FABRIC's own behaviours."""
    name = COMPOSED.join(parts)
    candidate, n = name, 1
    while candidate in taken:
        n += 1
        candidate = f"{name}_{n}"
    return candidate


def _links(packages: Sequence[FabricPackage], agents: dict[str, list[Subsystem]]) -> list[Link]:
    """A link from every output to every input of another package on the same IPC channel."""
    subsystems = {s.block: s for subs in agents.values() for s in subs}
    writers: dict[str, list[tuple[Subsystem, Buffer]]] = {}
    readers: dict[str, list[tuple[Subsystem, Buffer]]] = {}
    for package in packages:
        sub = subsystems[package.name]
        by_alias = {(b.name.partition("/")[0], b.direction): b for b in sub.buffers}
        for alias, channel in package.channels:
            for direction, table in ((Direction.OUT, writers), (Direction.IN, readers)):
                buf = by_alias.get((alias, direction))
                if buf is not None:
                    table.setdefault(channel, []).append((sub, buf))
    links: list[Link] = []
    for channel in sorted(set(writers) & set(readers)):
        for writer, source in writers[channel]:
            for reader, target in readers[channel]:
                if writer is reader:
                    continue
                same_agent = writer.agent == reader.agent
                name = f"{channel}/l"
                links.append(Link(name=name, path=f"{writer.agent if same_agent else ''}.{name}".lstrip("."),
                                  ends=(source.path, target.path), source=source.path, target=target.path,
                                  scope=LinkScope.AGENT if same_agent else LinkScope.SYSTEM,
                                  owner=writer.agent if same_agent else "", template=name,
                                  location=source.location))
    return links
