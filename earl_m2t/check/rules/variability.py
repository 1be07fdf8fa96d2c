"""X rules: variable structure, the configurations of a System and the coordinator that switches
them (design: the general model, configurations, quiescent states, leaving(), reactivation)."""

from __future__ import annotations

import math
from collections.abc import Iterator

from earl_m2t.analysis.switching import leaving_agents, reachable_configurations, system_of
from earl_m2t.check.rule import Finding, rule
from earl_m2t.model.conditions import Condition
from earl_m2t.model.elements import EarlModel, Subsystem, System
from earl_m2t.model.kinds import REACTIVATIONS, SubsystemKind
from earl_m2t.model.limits import MAX_SECONDS
from earl_m2t.model.variability import coordinator, coordinators, present, system_links, variable_agents
from earl_m2t.predicate import BuiltIn, BuiltInPredicate
from earl_m2t.predicate.walk import walk


def _variable_systems(model: EarlModel) -> Iterator[System]:
    return (s for s in model.systems if s.configurations)


@rule("X001")
def configuration_unknown_element(model: EarlModel) -> Iterator[Finding]:
    for system in _variable_systems(model):
        for cfg in system.configurations:
            for what, name in [("agent", n) for n in cfg.unknown_agents] + [("link", n) for n in cfg.unknown_links]:
                if model.subsystem(name) is not None:
                    problem = (f"names subsystem {name}; a configuration names agents (a subsystem is present "
                               "with its agent) and links")
                else:
                    problem = f"names {what} '{name}', which is no {what} of system {system.name}"
                yield Finding(f"configuration {cfg.path} {problem}", cfg.location, cfg.path)


@rule("X002")
def configuration_dangling_link(model: EarlModel) -> Iterator[Finding]:
    for system in _variable_systems(model):
        links = {link.path: link for link in system_links(system)}
        for cfg in system.configurations:
            structure = present(system, cfg)
            for path in sorted(structure.links):
                link = links.get(path)
                if link is None:
                    continue
                for end in (link.source, link.target):
                    sub = model.subsystem_of(end)
                    if sub is not None and not structure.has_agent(sub.agent):
                        yield Finding(f"link {path} is present in configuration {cfg.path}, but its end {end} "
                                      f"belongs to agent {sub.agent}, which is absent there", cfg.location, cfg.path)


@rule("X003")
def coordinator_not_one_control_subsystem(model: EarlModel) -> Iterator[Finding]:
    found = coordinators(model)
    if len(found) > 1:
        shown = ", ".join(sub.path for sub in found)
        for sub in found:
            yield Finding(f"{len(found)} subsystems name configurations in their states ({shown}); one control "
                          "subsystem, the coordinator, switches configurations", sub.location, sub.path)
    elif found and found[0].kind != SubsystemKind.CS:
        sub = found[0]
        yield Finding(f"subsystem {sub.path} ({sub.kind}) names configurations in its states; the coordinator "
                      "that switches configurations is a control subsystem", sub.location, sub.path)
    elif not found:
        for system in _variable_systems(model):
            yield Finding(f"system {system.name} has configurations, but no state of a control subsystem names "
                          "one: nothing selects the configuration that holds", system.location, system.path)


def _coordinator_definitions(model: EarlModel) -> Iterator[Subsystem]:
    ids = {sub.block_id for sub in coordinators(model)}
    return (sub for sub in model.definitions() if sub.block_id in ids)


@rule("X004")
def coordinator_state_configuration(model: EarlModel) -> Iterator[Finding]:
    for sub in _coordinator_definitions(model):
        initial = sub.fsm.state(sub.fsm.initial or "") if sub.fsm is not None else None
        if initial is not None and not initial.configuration:
            yield Finding(f"the coordinator {sub.path} starts in state {initial.path}, which names no "
                          "configuration: none holds when the system starts", initial.location, initial.path)
    for sub in model.definitions():
        naming = [s for s in sub.fsm.states if s.configuration] if sub.fsm is not None else []
        system = system_of(model, sub) if naming else None
        for state in naming if system is not None else ():
            if system is not None and system.configuration(state.configuration) is None:
                known = ", ".join(c.name for c in system.configurations) or "none"
                yield Finding(f"state {state.path} names configuration '{state.configuration}', which system "
                              f"{system.name} does not have (its configurations: {known})", state.location,
                              state.path)


@rule("X005")
def coordinator_agent_absent(model: EarlModel) -> Iterator[Finding]:
    sub = coordinator(model)
    system = system_of(model, sub) if sub is not None else None
    if sub is not None and system is not None:
        for cfg in system.configurations:
            if not present(system, cfg).has_agent(sub.agent):
                yield Finding(f"agent {sub.agent} of the coordinator {sub.path} is absent in configuration "
                              f"{cfg.path}: switching to it would stop the coordinator", cfg.location, cfg.path)


@rule("X006")
def variable_agent_multiplicity(model: EarlModel) -> Iterator[Finding]:
    for system in _variable_systems(model):
        named = variable_agents(system)
        for agent in system.agents:
            if agent.path in named and not agent.optional:
                yield Finding(f"agent {agent.path} is present only where a configuration names it, but the "
                              "multiplicity of its part is not [0..1]", agent.location, agent.path)
            elif agent.path not in named and agent.optional:
                yield Finding(f"the part of agent {agent.path} has multiplicity [0..1], but no configuration "
                              "names it: it is always present", agent.location, agent.path)


@rule("X010")
def configuration_unreachable_or_duplicate(model: EarlModel) -> Iterator[Finding]:
    for system in _variable_systems(model):
        if coordinators(model):
            reached = {c.name for c in reachable_configurations(model, system)}
            for cfg in system.configurations:
                if cfg.name not in reached:
                    yield Finding(f"configuration {cfg.path} is named by no state the coordinator can reach: it "
                                  "never holds", cfg.location, cfg.path)
        seen: dict[tuple[frozenset[str], frozenset[str]], str] = {}
        for cfg in system.configurations:
            key = (frozenset(cfg.agents), frozenset(cfg.links))
            if key in seen:
                yield Finding(f"configuration {cfg.path} has the same agents and links as {seen[key]}",
                              cfg.location, cfg.path)
            else:
                seen[key] = cfg.path


class _LeavingUse:
    """Whether a condition uses leaving(), walked once per parsed expression: conditions with the
    same text share their expression, and a model without leaving() has thousands of them."""

    def __init__(self) -> None:
        self._known: dict[int, bool] = {}  # id of an expression the model holds -> the answer

    def __call__(self, condition: Condition) -> bool:
        expr = condition.expr
        if expr is None:
            return False
        found = self._known.get(id(expr))
        if found is None:
            found = self._known[id(expr)] = any(
                isinstance(node, BuiltIn) and node.name == BuiltInPredicate.LEAVING for node in walk(expr))
        return found


@rule("X011")
def leaving_outside_variable_agent(model: EarlModel) -> Iterator[Finding]:
    _uses_leaving = _LeavingUse()
    using = {sub.block_id for sub in model.definitions() if any(_uses_leaving(c) for c in sub.conditions())}
    removable = {a.path for s in model.systems for a in leaving_agents(s)} if using else set()
    for sub in model.subsystems:
        if sub.block_id not in using or sub.agent in removable:
            continue
        for condition in sub.conditions():
            if _uses_leaving(condition):
                yield Finding(f"{condition.owner} uses leaving(), which is always false in {sub.path}: no "
                              f"configuration removes agent {sub.agent}", condition.location, condition.owner)


@rule("X012")
def variability_value_invalid(model: EarlModel) -> Iterator[Finding]:
    for system in model.systems:
        for agent in system.agents:
            if agent.reactivation not in REACTIVATIONS:
                yield Finding(f"agent {agent.path} has reactivation '{agent.reactivation}'; the reactivations "
                              f"are {', '.join(REACTIVATIONS)}", agent.location, agent.path)
        for cfg in system.configurations:
            timeout = cfg.switch_timeout
            if timeout is not None and not (math.isfinite(timeout) and 0 < timeout <= MAX_SECONDS):
                yield Finding(f"configuration {cfg.path}: switchTimeout is not a number of seconds > 0 and at most "
                              f"{MAX_SECONDS:.0f} (a year)", cfg.location, cfg.path)


@rule("X013")
def quiescence_mismatch(model: EarlModel) -> Iterator[Finding]:
    for system in model.systems:
        removable = {a.path for a in leaving_agents(system)}
        for agent in system.agents:
            for sub in agent.subsystems:
                states = sub.fsm.states if sub.fsm is not None else ()
                if agent.path in removable:
                    if sub.kind == SubsystemKind.CS and states and not any(s.quiescent for s in states):
                        yield Finding(f"a switch can remove agent {agent.path}, but its control subsystem "
                                      f"{sub.path} has no quiescent state: a switch may stop it at any iteration "
                                      "boundary", sub.location, sub.path)
                    continue
                for state in states:
                    if state.quiescent:
                        yield Finding(f"state {state.path} is quiescent, but no configuration removes agent "
                                      f"{agent.path}: the tag has no effect", state.location, state.path)
