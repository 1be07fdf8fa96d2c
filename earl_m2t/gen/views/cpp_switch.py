"""The variable-structure part of the C++ view: for a system with configurations, the tables
the generated ``System`` hands to ``earl::Switch`` (per configuration, which variable agents and
which variable links it holds, and its switch timeout), the coordinator's map from its states
to configurations, and the slot of each variable agent. ``None`` for a system without
configurations, whose output stays what it was.
"""

from __future__ import annotations

import math
from typing import Any

from earl_m2t.gen.errors import GenError
from earl_m2t.gen.names import Scope, cpp_comment, cpp_string
from earl_m2t.model import variability
from earl_m2t.model.elements import EarlModel, System
from earl_m2t.model.kinds import REACTIVATIONS, Reactivation
from earl_m2t.model.limits import MAX_SECONDS

Data = dict[str, Any]


def has_configurations(model: EarlModel) -> bool:
    return variability.is_variable(model)


def switching_view(model: EarlModel, agents: list[Data], links: dict[str, Data], subsystems: dict[str, str],
                   members: Scope, default_timeout: float) -> Data | None:
    """The tables of ``model``'s system, or None when it has no configurations.

    ``agents``: the system's agent rows (``path``, ``member``); ``links``: every link's row by
    link path (``member``, the C++ expression of its channel from the system); ``subsystems``:
    subsystem path -> its member in its agent; ``members``: the system class's scope."""
    system = model.system
    if system is None or not has_configurations(model):
        return None
    coordinator = variability.coordinator(model)
    if coordinator is None or coordinator.fsm is None:
        raise GenError(f"{system.path}: configurations, but no coordinator names them (rule X003)")
    agent_paths, link_paths = variable_paths(system)
    by_agent = {a["path"]: a for a in agents}
    slots = {path: members.take(f"slot {by_agent[path]['member']}") for path in agent_paths}
    agent_of = {sub.path: a.path for a in system.agents for sub in a.subsystems}
    agent_rows = [{"path": path, "member": by_agent[path]["member"], "slot": slots[path], "name": cpp_string(path),
                   "reactivation": _reactivation(system, path)} for path in agent_paths]
    link_rows = []
    by_link = {link.path: link for link in variability.system_links(system)}
    for path in link_paths:
        if path not in links or path not in by_link:
            raise GenError(f"{path}: a configuration names a link the system does not have (rule X001)")
        row = links[path]
        receiver = agent_of.get(row["receiver_subsystem"], "")
        sender_agent, receiver_agent = variability.link_agents(system, by_link[path])
        link_rows.append({"name": cpp_string(path), "member": row["expression"],
                          "receiver": f"&{slots[receiver]}" if receiver in slots else "nullptr",
                          "sender_index": _agent_index(agent_paths, sender_agent),
                          "receiver_index": _agent_index(agent_paths, receiver_agent)})
    index: dict[str, int] = {}
    for i, c in enumerate(system.configurations):
        if index.setdefault(c.name, i) != i:  # a state naming it would get the other one's structure
            raise GenError(f"{c.path}: two configurations have this name (rule S012)")
    configurations = []
    for configuration in system.configurations:
        structure = variability.present(system, configuration)
        configurations.append({
            "name": cpp_string(configuration.name), "comment": cpp_comment(configuration.name),
            "agents": _mask([structure.has_agent(p) for p in agent_paths]),
            "links": _mask([structure.has_link(p) for p in link_paths]),
            "timeout": _nanoseconds(configuration.switch_timeout, default_timeout),
        })
    states = []
    for state in coordinator.fsm.states:
        named = state.configuration
        if named and named not in index:
            raise GenError(f"{state.path}: names the unknown configuration {named} (rule X004)")
        states.append(index[named] if named else -1)
    initial = coordinator.fsm.state(coordinator.fsm.initial or "")
    if initial is None or not initial.configuration:
        raise GenError(f"{coordinator.path}: the initial state names no configuration (rule X004)")
    coordinator_agent = by_agent[coordinator.agent]["member"]
    return {
        "configurations": configurations, "agents": agent_rows, "links": link_rows, "states": states,
        "agents_comment": cpp_comment(" ".join(agent_paths)) or "none",
        "links_comment": cpp_comment(" ".join(link_paths)) or "none",
        "slot_pointers": ", ".join(f"&{row['slot']}" for row in agent_rows),
        "coordinator": f"{coordinator_agent}.{subsystems[coordinator.path]}",
        "coordinator_comment": cpp_comment(coordinator.path),
        "initial": index[initial.configuration], "initial_comment": cpp_comment(initial.configuration),
        "agent_names": ", ".join(row["name"] for row in agent_rows) or "nullptr",
        "reactivations": ", ".join(f"earl::Reactivation::{row['reactivation']}" for row in agent_rows)
        or "earl::Reactivation::restart",
        "link_names": ", ".join(row["name"] for row in link_rows) or "nullptr",
        "link_senders": ", ".join(str(row["sender_index"]) for row in link_rows) or "-1",
        "link_receivers": ", ".join(str(row["receiver_index"]) for row in link_rows) or "-1",
    }


def variable_paths(system: System) -> tuple[list[str], list[str]]:
    """The variable agents and links, in model order."""
    agents = set(variability.variable_agents(system))
    links = set(variability.variable_links(system))
    every_link = [link.path for link in system.links] + [link.path for a in system.agents for link in a.links]
    ordered_links = [path for path in dict.fromkeys(every_link) if path in links]
    ordered_links += sorted(links - set(ordered_links))
    return [a.path for a in system.agents if a.path in agents], ordered_links


def _reactivation(system: System, path: str) -> str:
    agent = variability.agent_of(system, path)
    reactivation = str(agent.reactivation) if agent is not None else Reactivation.RESTART
    if reactivation not in REACTIVATIONS:
        raise GenError(f"{path}: reactivation is {reactivation}, not restart or resume")
    return reactivation


def _agent_index(agent_paths: list[str], path: str) -> int:
    """The index of a variable agent in the tables, -1 for an agent of every configuration."""
    return agent_paths.index(path) if path in agent_paths else -1


def _mask(flags: list[bool]) -> str:
    return ", ".join("true" if flag else "false" for flag in flags) or "false"


def _nanoseconds(seconds: float | None, default: float) -> int:
    value = default if seconds is None or not math.isfinite(seconds) or not 0 < seconds <= MAX_SECONDS else seconds
    return round(value * 1e9)
