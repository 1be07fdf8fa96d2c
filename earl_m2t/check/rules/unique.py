"""One name per element in each namespace (S012): a name given twice makes two elements one to
every reader of the model (``show``, ``diff``, the rules that look an element up by its name)
and to the generated files, topics and components named after it.

The namespaces: the configurations, Agents, inter-agent links of a System; the Subsystems and
inter-subsystem links of an Agent; the buffers, memories, pfs and pps of a subsystem definition
(one namespace, as in its block), its basic behaviours, the states and the transitions of its
FSM; the dataTypes of a package (as the lift records them) and the fields of a dataType; the
model's LTL properties. An element without a name has no name to repeat: unnamed transitions
(called ``source,target/t``) and links (``source,target``) are not compared.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from earl_m2t.check.rule import Finding, rule
from earl_m2t.model.elements import Agent, EarlModel, Link, Subsystem, System
from earl_m2t.model.location import Location

PATHS = "every element needs a path of its own"


@dataclass(frozen=True, slots=True)
class Named:
    """An element as a namespace holds it: what it is, the name compared, its path."""

    kind: str
    name: str
    path: str
    location: Location


@dataclass(frozen=True, slots=True)
class Repeated:
    """A name given to ``count`` elements of one namespace: ``second`` is where it is given again."""

    second: Named
    first: Named
    count: int
    reason: str  # why the namespace needs names of their own


def _place(first: Location, second: Location) -> str:
    """Where the first element is, seen from the second: its line, and its file when another."""
    if first.file == second.file and first.line:
        return f"line {first.line}"
    return f"{first.file}:{first.line}" if first.line else first.file


def _repeated(elements: Iterable[Named], reason: str, one_element_per_place: bool = False) -> Iterator[Repeated]:
    """The names given twice or more, in the order their second element comes. With
    ``one_element_per_place``, elements at one place are one element (the links of one replicated
    connector)."""
    first: dict[str, Named] = {}
    later: dict[str, list[Named]] = {}
    for element in elements:
        if not element.name:
            continue
        seen = first.setdefault(element.name, element)
        if seen is element or (one_element_per_place and any(
                element.location == other.location for other in (seen, *later.get(element.name, ())))):
            continue
        later.setdefault(element.name, []).append(element)
    for name, repeats in later.items():
        yield Repeated(repeats[0], first[name], len(repeats) + 1, reason)


def _in(namespace: str) -> str:
    return f"every element needs a name of its own in {namespace}"


def _links(links: Iterable[Link], namespace: str, prefix: str = "") -> Iterator[Repeated]:
    """The named links of a namespace by the name of their connector (a replicated connector
    gives links of its own name, or of one name, at its one place)."""
    named = (Named("link", link.template, f"{prefix}{link.template}", link.location) for link in links)
    yield from _repeated(named, _in(namespace), one_element_per_place=True)


def _system(system: System) -> Iterator[Repeated]:
    yield from _repeated((Named("configuration", c.name, c.path, c.location) for c in system.configurations),
                         _in(f"system {system.name}"))
    yield from _repeated((Named("agent", a.path, a.path, a.location) for a in system.agents), PATHS)
    yield from _links(system.links, f"system {system.name}")
    for agent in system.agents:
        yield from _agent(agent)


def _agent(agent: Agent) -> Iterator[Repeated]:
    yield from _repeated((Named("subsystem", s.path, s.path, s.location) for s in agent.subsystems), PATHS)
    yield from _links(agent.links, f"agent {agent.path}", f"{agent.path}.")


def _definition(sub: Subsystem) -> Iterator[Repeated]:
    """The namespaces of a subsystem's block: its members, its basic behaviours, its FSM's
    states and transitions."""
    members = [
        *(Named("input buffer", b.name, b.path, b.location) for b in sub.inputs),
        *(Named("output buffer", b.name, b.path, b.location) for b in sub.outputs),
        *(Named("memory", m.name, m.path, m.location) for m in sub.memory),
        *(Named("pf", f.name, f.path, f.location) for f in sub.functions),
        *(Named("pp", p.name, p.path, p.location) for p in sub.predicates),
    ]
    members.sort(key=lambda named: (named.location.file, named.location.line))  # the order of the block
    yield from _repeated(members, _in(f"subsystem {sub.path}"))
    yield from _repeated((Named("basic behaviour", b.name, b.path, b.location) for b in sub.behaviours),
                         _in(f"subsystem {sub.path}"))
    if sub.fsm is not None:
        fsm = sub.fsm
        yield from _repeated((Named("state", s.name, s.path, s.location) for s in fsm.states), _in(f"FSM {fsm.path}"))
        yield from _repeated((Named("transition", t.name if t.named else "", t.path, t.location)
                              for t in fsm.transitions), _in(f"FSM {fsm.path}"))


def _datatypes(model: EarlModel) -> Iterator[Repeated]:
    for namesake in model.datatype_namesakes:
        package, _, _ = namesake.qualified_name.rpartition("::")
        first, second = (Named("dataType", namesake.qualified_name, namesake.qualified_name, location)
                         for location in namesake.locations[:2])
        yield Repeated(second, first, len(namesake.locations), _in(f"package {package}" if package else "the model"))
    for key, datatype in model.datatypes.items():
        yield from _repeated((Named("field", f.name, f"{key}.{f.name}", f.location) for f in datatype.fields),
                             _in(f"dataType {key}"))


def repetitions(model: EarlModel) -> Iterator[Repeated]:
    """Every name given twice or more in one namespace of the model."""
    for system in model.systems:
        yield from _system(system)
    for sub in model.definitions():
        yield from _definition(sub)
    yield from _datatypes(model)
    yield from _repeated((Named("LTL property", p.label, p.title, p.location) for p in model.properties),
                         _in("the model"))


@rule("S012")
def path_not_unique(model: EarlModel) -> Iterator[Finding]:
    reported: set[tuple[str, Location, Location]] = set()  # the agents of one block share their links
    for repeated in repetitions(model):
        second, first = repeated.second, repeated.first
        if second.kind == "link":
            if (second.name, second.location, first.location) in reported:
                continue
            reported.add((second.name, second.location, first.location))
        times = "twice" if repeated.count == 2 else f"{repeated.count} times"
        also = "" if first.kind == second.kind else f", {first.kind} {first.path}"
        yield Finding(f"{second.kind} {second.path} is named {times} (first at "
                      f"{_place(first.location, second.location)}{also}): {repeated.reason}",
                      second.location, second.path)
