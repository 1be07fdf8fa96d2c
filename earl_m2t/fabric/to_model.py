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
from earl_m2t.fabric.fsm import FsmBuilder
from earl_m2t.fabric.package import FabricPackage, Where
from earl_m2t.lift.conditions import resolve_subsystem
from earl_m2t.lift.structure import computed_agent_type
from earl_m2t.model.datatypes import DataType
from earl_m2t.model.elements import (
    Agent,
    Buffer,
    BufferGroup,
    EarlModel,
    Link,
    PartialFunction,
    PrimitivePredicate,
    Robot,
    Simulation,
    Subsystem,
    System,
)
from earl_m2t.model.kinds import SUBSYSTEM_KINDS, DataTypeKind, Direction, LinkScope, SubsystemKind
from earl_m2t.model.location import Location

DIALECT = "fabric"
RECOGNISED = "suffix"
CODE = "C++"


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
    placed: list[tuple[Subsystem, tuple[tuple[str, str], ...]]] = []
    for package in packages:
        instances, instance_notes = instances_of(package, named[package.name])
        notes += instance_notes
        for names, channels in instances:
            subsystem = _subsystem(package, names, datatypes, types, channels if len(instances) == 1 else ())
            if any(s.name == names.part for s in agents.get(names.agent, [])):
                raise ModelReadError(package.spec_file, f"a second subsystem {names.agent}.{names.part} "
                                     f"(package {package.name}) among the imported packages")
            agents.setdefault(names.agent, []).append(subsystem)
            placed.append((subsystem, channels))
    first = _location(packages[0].where) if packages else Location("<fabric>")
    links = _links(placed)
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


def instances_of(package: FabricPackage, names: _Names) -> tuple[list[tuple[_Names, tuple[tuple[str, str], ...]]],
                                                                list[str]]:
    """The subsystem instances of a package, each with the channels of its buffers: one, or, when
    its configurations give its buffers other channels, one per configuration (FABRIC's deployer
    runs a subsystem per configuration file), each the control subsystem of an agent named after
    the configuration; and notes on what was decided."""
    aliases = {b.alias for b in package.buffers}
    distinct: list[tuple[str, tuple[tuple[str, str], ...]]] = []
    notes: list[str] = []
    for configuration in package.configurations:
        channels = tuple((alias, channel) for alias, channel in configuration.channels if alias in aliases)
        same = next((name for name, earlier in distinct if set(earlier) == set(channels)), None)
        if not channels:
            continue
        if same is not None:
            notes.append(f"{package.name}: configuration {configuration.name} gives the buffers the channels "
                         f"configuration {same} gives them: one subsystem for both")
            continue
        distinct.append((configuration.name, channels))
    if len(distinct) <= 1:
        return [(names, distinct[0][1] if distinct else ())], notes
    notes.append(f"{package.name}: configurations {', '.join(n for n, _ in distinct)} give its buffers other "
                 "channels: a subsystem of its definition for each, the control subsystem of an agent named "
                 "after the configuration")
    return [(_Names(_identifier(name), SubsystemKind.CS, "cs"), channels) for name, channels in distinct], notes


def _identifier(name: str) -> str:
    """A configuration's file name as an agent's name (``velma_core_re (kopia)`` → ``velma_core_re__kopia_``)."""
    text = re.sub(r"[^A-Za-z0-9_]", "_", name)
    return text if re.match(r"[A-Za-z]", text) else f"c_{text}"


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
               message_types: dict[str, str], channels: tuple[tuple[str, str], ...]) -> Subsystem:
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
                              recognised_by=RECOGNISED, side=buf.side, converter=buf.converter,
                              channel=dict(reversed(channels)).get(buf.alias, "")))
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

    fsm, behaviours = FsmBuilder(package, path, predicate_names).build()
    return resolve_subsystem(Subsystem(
        name=names.part, path=path, kind=names.kind, agent=names.agent, block=package.name,
        block_id=package.name, template=names.part, index=0,
        inputs=tuple(b for b in buffers if b.direction == "in"),
        outputs=tuple(b for b in buffers if b.direction == "out"), memory=(), fsm=fsm, behaviours=behaviours,
        functions=functions, predicates=predicates, exclusions=(), fsm_count=1, location=_location(package.where),
        recognised_by="stereotype", buffer_groups=groups,
        simulation=(Simulation(package.simulation.use_ros_sim_clock, package.simulation.use_sim_clock,
                               package.simulation.trigger_gazebo) if package.simulation else None)), datatypes)


def _links(placed: list[tuple[Subsystem, tuple[tuple[str, str], ...]]]) -> list[Link]:
    """A link from every output to every input of another subsystem on the same IPC channel."""
    writers: dict[str, list[tuple[Subsystem, Buffer]]] = {}
    readers: dict[str, list[tuple[Subsystem, Buffer]]] = {}
    for sub, channels in placed:
        by_alias = {(b.name.partition("/")[0], b.direction): b for b in sub.buffers}
        for alias, channel in channels:
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
