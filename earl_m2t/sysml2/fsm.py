"""A ``state`` usage (or definition) of a subsystem as its state machine.

``entry; then S;`` makes S the initial state; ``state S { do action 'S/bb' { … } }`` gives S
its basic behaviour, inline or by reference (``do 'shared/bb';``, ``do action : 'shared/bb';``)
to an ``action def`` of the subsystem; ``transition name first S if guard then T { … }``
is a transition, its guard the initial condition, ``@Priority { priority = n; }`` in its
body its priority; ``@Activation { bufferGroup = …; }`` in a state's body its activation.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from earl_m2t.read.xmi import Element
from earl_m2t.sysml2.activity import ActivityWriter
from earl_m2t.sysml2.parser import identification, location, members, rule
from earl_m2t.sysml2.scope import Scope
from earl_m2t.sysml2.texts import chain_name, guard
from earl_m2t.sysml2.uml import ID, Block, UmlWriter, set_line

Later = list[Callable[[], None]]  # steps that need every block's behaviours first


class FsmWriter:
    def __init__(self, uml: UmlWriter, scope: Scope, later: Later) -> None:
        self.uml = uml
        self.scope = scope
        self.later = later

    def state_machine(self, block: Block, node: Any, name: str) -> None:
        machine = self.uml.child(block.element, "ownedBehavior", "StateMachine", node, name)
        if not block.element.get("classifierBehavior"):
            block.element.set("classifierBehavior", machine.get(ID) or "")
            block.element.set("isActive", "true")  # a block running its own state machine is active (UML)
        self.uml.annotations(machine, node)
        region = self.uml.child(machine, "region", "Region", None)
        body: list[Any] = []
        target = self.scope.typing(node)
        if target is not None and target.node is not None and target.node.kind == "state":
            body.extend(members(target.node))
        body.extend(members(node))
        states: dict[str, Element] = {}  # by name: the first state of a name (rule S012 reports a second)
        vertices: dict[int, Element] = {}  # by state usage
        for member in body:
            name_of_state = identification(member)[1] if rule(member) == "Usage" and member.kind == "state" else None
            if name_of_state:
                vertex = vertices[id(member)] = self.uml.child(region, "subvertex", "State", member, name_of_state)
                states.setdefault(name_of_state, vertex)
        after_entry = False
        for member in body:
            kind = rule(member)
            if kind == "TargetSuccession" and after_entry and member.target:
                self.initial(region, member, states)
            elif kind == "TransitionUsage":
                self.transition(region, member, states)
            elif kind == "Usage" and member.kind == "state":
                self.state_behaviour(block, vertices.get(id(member)), member)
                self.state_activation(vertices.get(id(member)), member)
            after_entry = kind == "EntryAction"

    def initial(self, region: Element, member: Any, states: dict[str, Element]) -> None:
        initial = self.uml.child(region, "subvertex", "Pseudostate", member)
        initial.set("kind", "initial")
        transition = self.uml.child(region, "transition", "Transition", None)
        set_line(transition, location(member)[0])
        transition.set("source", initial.get(ID) or "")
        found = states.get(chain_name(member.target))
        if found is not None:
            transition.set("target", found.get(ID) or "")

    def transition(self, region: Element, node: Any, states: dict[str, Element]) -> None:
        transition = self.uml.child(region, "transition", "Transition", node, identification(node)[1] or "")
        for end, chain in (("source", node.source), ("target", node.target)):
            state = states.get(chain_name(chain))
            if state is not None:
                transition.set(end, state.get(ID) or "")
        condition = guard(node.guard, node)
        if condition is not None:
            constraint = self.uml.constraint(transition, "ic", condition, node)
            transition.set("guard", constraint.get(ID) or "")
        self.uml.annotations(transition, node)

    def state_activation(self, state: Element | None, node: Any) -> None:
        """``@Activation { bufferGroup = "command"; minPeriod = 0.001; … }`` in a state's body."""
        if state is None:
            return
        for member in members(node):
            if rule(member) == "MetadataUsage" and not member.about:
                self.uml.metadata(state, member)

    def state_behaviour(self, block: Block, state: Element | None, node: Any) -> None:
        if state is None:
            return
        for member in members(node):
            if rule(member) != "DoAction":
                continue
            declaration = member.declaration
            name = identification(declaration)[1] if declaration is not None else None
            activity = self.uml.child(state, "doActivity", "Activity", member, name or "")
            typing = self.scope.typing(member) if declaration is not None else None
            called = chain_name(member.reference) if member.reference else (
                identification(typing.node)[1] or "" if typing is not None and typing.node is not None else "")
            own = list(members(member))
            if called and not own:
                action = self.uml.child(activity, "node", "CallBehaviorAction", None, called)
                self.later.append(call(block, action, called))
            else:
                self.later.insert(0, activity_step(self.uml, self.scope, block, activity, own))


def call(block: Block, action: Element, called: str) -> Callable[[], None]:
    """Point a call action at a behaviour of the block, once all are written."""
    def step() -> None:
        behaviour = block.behaviours.get(called)
        if behaviour:
            action.set("behavior", behaviour)
    return step


def activity_step(uml: UmlWriter, scope: Scope, block: Block, activity: Element, body: list[Any]) -> Callable[[], None]:
    return lambda: ActivityWriter(uml, scope, block, activity).write(body)
