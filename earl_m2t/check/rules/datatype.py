"""D rules: dataTypes and the names generators turn into identifiers and files."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING

from earl_m2t.check.rule import Finding, rule
from earl_m2t.model.elements import Buffer, EarlModel, Memory, PartialFunction, PrimitivePredicate
from earl_m2t.model.graph import datatype_graph
from earl_m2t.model.location import Location
from earl_m2t.model.naming import (
    collision_key,
    field_name,
    host_problem,
    host_ros_name,
    identifier_problem,
    length_problem,
    message_name,
    windows_reserved,
)
from earl_m2t.shorten import shortened

if TYPE_CHECKING:
    from earl_m2t.gen.views.msg import NameProblem


@rule("D001")
def unresolved_type(model: EarlModel) -> Iterator[Finding]:
    for sub in model.definitions():
        typed: list[Buffer | Memory] = [*sub.buffers, *sub.memory]
        for item in typed:
            if item.type_ref and not item.datatype:
                yield Finding(f"{item.path} is typed by '{item.type_ref}', which cannot be resolved",
                              item.location, item.path)
    for datatype in model.datatypes.values():
        for field in datatype.fields:
            if field.type_ref and not field.type:
                yield Finding(f"field {datatype.qualified_name}.{field.name} is typed by '{field.type_ref}', "
                              "which cannot be resolved", field.location, f"{datatype.qualified_name}.{field.name}")
            elif not field.type and not field.type_ref:
                yield Finding(f"field {datatype.qualified_name}.{field.name} has no type", field.location,
                              f"{datatype.qualified_name}.{field.name}")


@rule("D002")
def recursive_datatype(model: EarlModel) -> Iterator[Finding]:
    import networkx as nx

    graph = datatype_graph(model)
    for cycle in sorted(nx.simple_cycles(graph), key=lambda c: sorted(c)):
        start = min(cycle)
        at = cycle.index(start)
        ordered = cycle[at:] + cycle[:at]
        datatype = model.datatypes[start]
        shown = " → ".join(ordered + [start])
        yield Finding(f"dataType {start} contains itself by value ({shown})", datatype.location, start)


def _named(model: EarlModel) -> Iterator[tuple[str, str, Location, str, str]]:
    """(name, path, location, scope, ROS naming) of every element whose name a generator uses.
    The ROS naming is how the ROS targets spell it: "snake" (namespaces, nodes, topics,
    fields), "message" (message types) or "" (no ROS name)."""
    for agent in model.agents:
        yield agent.name, agent.path, agent.location, "agents", "snake"
        for sub in agent.subsystems:
            yield sub.name, sub.path, sub.location, f"{agent.path} subsystems", "snake"
    for sub in model.definitions():
        scope = f"{sub.path} members"
        for buffer in sub.buffers:
            yield buffer.name, buffer.path, buffer.location, scope, "snake"
        others: list[Memory | PartialFunction | PrimitivePredicate] = [*sub.memory, *sub.functions, *sub.predicates]
        for item in others:
            yield item.name, item.path, item.location, scope, ""
        for bb in sub.behaviours:
            yield bb.name, bb.path, bb.location, f"{sub.path} behaviours", ""
        if sub.fsm is not None:
            for state in sub.fsm.states:
                yield state.name, state.path, state.location, f"{sub.fsm.path} states", ""
    for key, datatype in model.datatypes.items():
        if datatype.location.file == "<builtin>":
            continue
        yield datatype.name, key, datatype.location, "dataTypes", "message"
        for field in datatype.fields:
            yield field.name, f"{key}.{field.name}", field.location, f"{key} fields", "snake"


_ROS_KEYS: dict[str, Callable[[str], str]] = {"snake": field_name, "message": lambda name: message_name(name).lower()}


def _message_problems(model: EarlModel, rule_code: str) -> Iterator[NameProblem]:
    """The names the ROS messages (``gen --target msg``, which ``ros`` and ``orocos`` include)
    refuse, as their view finds them: the model's name, reserved message and field names,
    enumeration literals, names that collide."""
    from earl_m2t.gen.views.msg import refused_names  # docs/layers.toml: the one upward import

    yield from (problem for problem in refused_names(model) if problem.rule == rule_code)


@rule("D003")
def name_not_identifier(model: EarlModel) -> Iterator[Finding]:
    reported: set[str] = set()
    for name, path, location, _, _ in _named(model):
        problem = identifier_problem(name)
        if problem:
            reported.add(path)
            yield Finding(f"{path}: the name cannot become a C++ / ROS identifier: {problem}", location, path)
    for message_problem in _message_problems(model, "D003"):
        if message_problem.path not in reported:
            reported.add(message_problem.path)
            yield Finding(message_problem.text, message_problem.location, shortened(message_problem.path))


def _one_namespace(model: EarlModel, scope: str, items: list[tuple[str, str, Location]]) -> bool:
    """Whether elements of one name are in one namespace, where S012 reports them: always, but
    for dataTypes of several packages."""
    if scope != "dataTypes":
        return True
    package_of = {location: n for n, namesake in enumerate(model.datatype_namesakes)
                  for location in namesake.locations}
    return len({package_of.get(location, location) for _, _, location in items}) == 1


@rule("D004")
def identifier_collision(model: EarlModel) -> Iterator[Finding]:
    by_scope: dict[tuple[str, str], list[tuple[str, str, Location]]] = {}
    by_ros_name: dict[tuple[str, str], list[tuple[str, str, Location]]] = {}
    for name, path, location, scope, ros in _named(model):
        by_scope.setdefault((scope, collision_key(name)), []).append((name, path, location))
        if ros:
            by_ros_name.setdefault((scope, _ROS_KEYS[ros](name)), []).append((name, path, location))
    reported: set[str] = set()
    involved: set[str] = set()  # every path of a collision reported
    for (scope, key), items in by_scope.items():
        if len(items) == 1:
            continue  # nearly every name: nothing to compare it with
        names = list(dict.fromkeys(name for name, _, _ in items))
        _, path, location = items[-1]
        if len(names) > 1:
            reported.add(path)
            involved.update(p for _, p, _ in items)
            yield Finding(f"{path}: {' and '.join(repr(n) for n in names)} map to the same identifier or file "
                          f"name '{key}'", location, path)
        elif _one_namespace(model, scope, items):
            involved.update(p for _, p, _ in items)  # S012 reports the name given twice
        else:  # one name in two packages
            reported.add(path)
            involved.update(p for _, p, _ in items)
            yield Finding(f"{path}: {len(items)} elements are named '{names[0]}'", location, path)
    for (_, key), items in by_ros_name.items():
        if len(items) == 1:
            continue
        names = list(dict.fromkeys(name for name, _, _ in items))
        _, path, location = items[-1]
        if len(names) > 1 and path not in reported:
            involved.update(p for _, p, _ in items)
            yield Finding(f"{path}: {' and '.join(repr(n) for n in names)} map to the same ROS name '{key}'",
                          location, path)
    for message_problem in _message_problems(model, "D004"):
        if message_problem.path not in involved:
            involved.add(message_problem.path)
            yield Finding(message_problem.text, message_problem.location, shortened(message_problem.path))


def _named_with_model(model: EarlModel) -> Iterator[tuple[str, str, Location]]:
    """(name, path, location) of every name a generator uses, the model's and the systems' included."""
    if model.name:
        system = model.system
        yield model.name, "model", system.location if system is not None else Location(model.file, 0, 0)
    for system in model.systems:
        yield system.name, system.path, system.location
    for name, path, location, _, _ in _named(model):
        yield name, path, location


@rule("D005")
def name_too_long(model: EarlModel) -> Iterator[Finding]:
    for name, path, location in _named_with_model(model):
        problem = length_problem(name)
        if problem:
            yield Finding(f"{shortened(path)}: the name is too long for generated files: {problem}", location,
                          shortened(path))


@rule("D006")
def windows_reserved_name(model: EarlModel) -> Iterator[Finding]:
    for name, path, location in _named_with_model(model):
        device = windows_reserved(name)
        if device:
            yield Finding(f"{shortened(path)}: the name gives files named '{device}', a device name Windows "
                          f"reserves (such files cannot be created there)", location, shortened(path))


@rule("D007")
def host_name_invalid(model: EarlModel) -> Iterator[Finding]:
    first_of: dict[str, str] = {}  # a host's ROS name -> the first host written so
    for agent in model.agents:
        problem = host_problem(agent.host) if agent.host else ""
        if problem:
            yield Finding(f"agent {agent.path} has host '{shortened(agent.host)}', which cannot name a file and a "
                          f"ROS node: {problem}", agent.location, agent.path)
            continue
        if not agent.host:
            continue
        other = first_of.setdefault(host_ros_name(agent.host), agent.host)
        if other != agent.host:
            yield Finding(f"agent {agent.path} has host '{agent.host}', and another agent '{other}': the two are one "
                          f"name to ROS ('{host_ros_name(agent.host)}'), which names a host's lifecycle manager",
                          agent.location, agent.path)
