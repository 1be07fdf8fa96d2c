"""A FABRIC package's behaviours and states as an EARL subsystem's basic behaviours and FSM.

A state running several behaviours gets one basic behaviour composing them (EARL's state has
one): FABRIC ends the state when one's err_cond holds, else when one's stop_cond holds, and runs
the components of all (master_component.cpp, updateHook), so the composition's tc and ec are the
disjunctions and its one stage runs every component. The state keeps FABRIC's behaviours (tag
``behaviours``) for gen --target orocos. FABRIC stops with an error when the init_cond of two
next states hold (calculateNextState() returns -1), so the guards are written back as they are
(tag ``exclusiveGuards``).
"""

from __future__ import annotations

import re

from earl_m2t.diagnostics import ModelReadError
from earl_m2t.fabric.conditions import ConditionError, parse_fabric_condition
from earl_m2t.fabric.package import FabricBehaviour, FabricPackage, FabricState, Where
from earl_m2t.model.conditions import Condition, ConditionRole
from earl_m2t.model.elements import Activation, BasicBehaviour, Fsm, State, Transition
from earl_m2t.model.location import Location
from earl_m2t.predicate import format_predicate

PREDICATE_CALL = re.compile(r"([A-Za-z_][A-Za-z0-9_]*/pp)\b")
LANGUAGE = "EARL"
RECOGNISED = "suffix"
COMPOSED = "__"  # joins the names of the behaviours a state runs side by side


class FsmBuilder:
    """The basic behaviours and the FSM of one package's subsystem at ``path``."""

    def __init__(self, package: FabricPackage, path: str, predicates: dict[str, str]) -> None:
        self.package = package
        self.path = path
        self.predicates = predicates  # FABRIC name -> EARL primitive predicate name
        self.by_name = {b.name: b for b in package.behaviours}

    def build(self) -> tuple[Fsm, tuple[BasicBehaviour, ...]]:
        behaviours = [self.behaviour(b.name, b.stop_cond, b.err_cond, b.running, b.where, f"behavior '{b.name}'")
                      for b in self.package.behaviours]
        fsm_path = f"{self.path}.fsm"
        states = tuple(self.state(s, fsm_path, behaviours) for s in self.package.states)
        transitions: list[Transition] = []
        for s in self.package.states:
            for target, text, where in s.next_states:
                name = f"{s.name},{target}/t"
                transitions.append(Transition(
                    name=name, path=f"{fsm_path}.{name}", source=s.name, target=target, source_foreign=False,
                    target_foreign=False,
                    condition=self.condition(text, where, f"{fsm_path}.{name}", ConditionRole.IC,
                                             f"state '{s.name}' next_state '{target}'"),
                    priority=0, order=len(transitions), location=_location(where)))
        fsm = Fsm(name="fsm", path=fsm_path, states=states, transitions=tuple(transitions),
                  initial_states=(self.package.initial,), location=_location(self.package.where))
        return fsm, tuple(behaviours)

    def condition(self, text: str, where: Where, owner: str, role: ConditionRole, what: str) -> Condition:
        try:
            expr = parse_fabric_condition(text, self.predicates)
        except ConditionError as exc:
            raise ModelReadError(where.file, f"{what}: {exc}", where.line) from None
        # the paper's form, x/pp.fun, which SysML v2 text writes as a call: 'x/pp'()
        text = PREDICATE_CALL.sub(r"\1.fun", format_predicate(expr))
        return Condition(text, LANGUAGE, _location(where), owner, role)

    def behaviour(self, name: str, stop_cond: str, err_cond: str, running: tuple[str, ...], where: Where,
                  what: str) -> BasicBehaviour:
        bb_path = f"{self.path}.{name}/bb"
        return BasicBehaviour(
            name=f"{name}/bb", path=bb_path,
            tc=self.condition(stop_cond, where, bb_path, ConditionRole.TC, f"{what} stop_cond"),
            ec=self.condition(err_cond, where, bb_path, ConditionRole.EC, f"{what} err_cond"),
            stages=((tuple(f"{r}/pf" for r in running),) if running else ()), activity_problems=(),
            location=_location(where), recognised_by=RECOGNISED)

    def state(self, s: FabricState, fsm_path: str, behaviours: list[BasicBehaviour]) -> State:
        """The state; the composition of its behaviours is added to ``behaviours`` when new."""
        composes: tuple[str, ...] = ()
        own = tuple(f"{b}/bb" for b in s.behaviours)
        if len(s.behaviours) > 1:
            composes, name = own, self.composed_name(s.behaviours)
            if all(b.name != f"{name}/bb" for b in behaviours):
                parts: list[FabricBehaviour] = [self.by_name[b] for b in s.behaviours]
                behaviours.append(self.behaviour(
                    name, " or ".join(f"({p.stop_cond})" for p in parts),
                    " or ".join(f"({p.err_cond})" for p in parts),
                    tuple(dict.fromkeys(r for p in parts for r in p.running)), s.where,
                    f"state '{s.name}' behaviors"))
            own = (f"{name}/bb",)
        group = s.group
        return State(name=s.name, path=f"{fsm_path}.{s.name}", behaviours=own, location=_location(s.where),
                     activation=Activation(group=group.name, min_period=group.min_period,
                                           first_timeout=group.first_timeout, next_timeout=group.next_timeout,
                                           min_period_sim=group.min_period_sim,
                                           first_timeout_sim=group.first_timeout_sim, used_time=group.used_time),
                     composes=composes, exclusive_guards=len(s.next_states) > 1)

    def composed_name(self, parts: tuple[str, ...]) -> str:
        """The name of the basic behaviour composing FABRIC's behaviours ``parts``: their names
        joined (an identifier, as generated code needs), distinct from FABRIC's own behaviours."""
        name = COMPOSED.join(parts)
        candidate, n = name, 1
        while candidate in self.by_name:
            n += 1
            candidate = f"{name}_{n}"
        return candidate


def _location(where: Where) -> Location:
    return Location(where.file, where.line)
