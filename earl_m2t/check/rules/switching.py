"""X rules about a switch at run time: inputs left without a link, queued values a leaving agent
cannot drain, switch timeouts shorter than the drain, and sends on links a configuration closes."""

from __future__ import annotations

import math
from collections.abc import Iterator

from earl_m2t.analysis.receiving import receives
from earl_m2t.analysis.switching import (
    configurations_while,
    drain_bound,
    fed_inputs,
    leaving_agents,
    obligatory_inputs,
    queued_inputs,
    reachable_states,
    waits_without_bound,
)
from earl_m2t.check.rule import Finding, rule
from earl_m2t.model.elements import EarlModel
from earl_m2t.model.variability import coordinator, present


@rule("X007")
def obligatory_input_without_link(model: EarlModel) -> Iterator[Finding]:
    fed = fed_inputs(model)
    for system, sub in ((s, sub) for s in model.systems if s.configurations for a in s.agents for sub in a.subsystems):
        for state in reachable_states(sub):
            if not waits_without_bound(state):
                continue
            for buffer in obligatory_inputs(sub, state):
                links = fed.get(buffer.path, ())
                closed = [c.name for c in configurations_while(model, system, sub, state)
                          if links and not any(present(system, c).has_link(link) for link in links)]
                if closed:
                    yield Finding(f"state {state.path} waits for its obligatory input {buffer.path} without a "
                                  f"timeout, but no link into it is open in configuration {', '.join(closed)}, "
                                  "which can hold while the state is current: it would wait forever",
                                  state.location, state.path)


@rule("X008")
def leaving_queue_not_drained(model: EarlModel) -> Iterator[Finding]:
    for system in model.systems:
        for agent in leaving_agents(system):
            for sub, buffer in queued_inputs(model, agent):
                states = reachable_states(sub)
                if not any(s.quiescent for s in states):
                    continue  # no quiescent state declared: every iteration boundary is quiescent (X013)
                for state in states:
                    if not state.quiescent and not receives(sub, state, buffer):
                        yield Finding(f"state {state.path} of agent {agent.path}, which a switch can remove, is "
                                      f"not quiescent and does not receive its queued input {buffer.path}: values "
                                      "queued there wait until the switch timeout and are then dropped",
                                      state.location, state.path)


@rule("X009")
def switch_timeout_below_drain_bound(model: EarlModel) -> Iterator[Finding]:
    for system in model.systems:
        removable = leaving_agents(system)
        for cfg in system.configurations:
            timeout = cfg.switch_timeout
            if timeout is None or not math.isfinite(timeout) or timeout <= 0:
                continue
            structure = present(system, cfg)
            for agent in (a for a in removable if not structure.has_agent(a.path)):
                for sub, buffer in queued_inputs(model, agent):
                    bound = drain_bound(model, sub, buffer)
                    if bound is None or timeout >= bound.seconds:
                        continue
                    yield Finding(f"switchTimeout {timeout:g} s of configuration {cfg.path} is below the time a "
                                  f"switch into it may need to drain {buffer.path} of the leaving agent "
                                  f"{agent.path}: {bound.queue_size} values × {bound.receiver_period:g} s + "
                                  f"{bound.coordinator_period:g} s (a coordinator period) = {bound.seconds:g} s",
                                  cfg.location, cfg.path)


@rule("X014")
def write_on_closed_links(model: EarlModel) -> Iterator[Finding]:
    links_from: dict[str, list[str]] = {}
    for link in model.links:
        if link.source:
            links_from.setdefault(link.source, []).append(link.path)
    boss = coordinator(model)  # its states name configurations; another agent's sends are not tied to one
    if boss is None:
        return
    for system in (s for s in model.systems if s.configurations):
        for sub in (sub for agent in system.agents for sub in agent.subsystems if sub.path == boss.path):
            outputs = {b.path: b for b in sub.outputs if links_from.get(b.path)}
            for state in reachable_states(sub):
                behaviour = sub.behaviour(state.behaviours[0]) if len(state.behaviours) == 1 else None
                if behaviour is None:
                    continue
                written = [outputs[path] for name in behaviour.functions if (pf := sub.function(name)) is not None
                           for path in pf.writes if path in outputs]
                for buffer in dict.fromkeys(written):
                    closing = [c.name for c in configurations_while(model, system, sub, state)
                               if not any(present(system, c).has_link(path) for path in links_from[buffer.path])]
                    if closing:
                        yield Finding(f"state {state.path} writes Output Buffer {buffer.path}, but configuration "
                                      f"{', '.join(closing)}, which can hold while the state is current, closes "
                                      "every link from it: what the state sends there goes nowhere",
                                      state.location, state.path)

