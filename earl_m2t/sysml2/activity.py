"""An action body as the activity of a transition function (paper Fig. 15).

SysML v2 successions become control flows: ``first start;`` sets where what follows starts,
``then X;`` is a flow from the previous action or control node to X, ``then fork;`` /
``then action a : 'p/pf';`` declare that node on the spot and flow into it, ``first A then
B;`` is a flow from A to B, ``start`` and ``done`` are the initial and final nodes. Each action
typed by a partial transition function of the subsystem is a call of it; the lift computes
the stages from the flows. ``constraint tc { … }`` and ``constraint ec { … }`` are the
behaviour's terminal and error conditions.
"""

from __future__ import annotations

from typing import Any

from earl_m2t.read.xmi import Element
from earl_m2t.sysml2.parser import identification, location, rule, simple_name
from earl_m2t.sysml2.scope import Scope
from earl_m2t.sysml2.texts import body_condition, chain_name
from earl_m2t.sysml2.uml import ID, Block, UmlWriter, set_line

CONDITION_ROLES = ("tc", "ec")
START, DONE = "start", "done"
CONTROL_NODES = {"fork": "ForkNode", "join": "JoinNode"}

Ref = Element | str | None  # a node, a name to look up once all are declared, or nothing


class ActivityWriter:
    def __init__(self, uml: UmlWriter, scope: Scope, block: Block, activity: Element) -> None:
        self.uml = uml
        self.scope = scope
        self.block = block
        self.activity = activity
        self.nodes: dict[str, Element] = {}
        self.ends: dict[str, Element] = {}
        self.edges: list[tuple[Ref, Ref, int]] = []

    def write(self, body: list[Any]) -> None:
        previous: Ref = None
        for member in body:
            kind = rule(member)
            line = location(member)[0]
            if kind == "FirstSuccession":
                source = self.reference(member.source)
                if member.target:
                    self.edges.append((source, self.reference(member.target), line))
                else:
                    previous = source
            elif kind == "TargetSuccession":
                declared = member.node if member.node is not None else member.usage
                if declared is not None:
                    created = self.declare(declared)
                    self.edges.append((previous, created, line))
                    previous = created
                else:
                    self.edges.append((previous, self.reference(member.target), line))
            elif kind == "ControlNode" or (kind == "Usage" and member.kind == "action"):
                previous = self.declare(member)
            elif kind == "Usage" and member.kind == "constraint":
                self.condition(member)
        self.flows()

    def reference(self, chain: str) -> Ref:
        name = chain_name(chain)
        if name in (START, DONE) and name not in self.nodes:
            if name not in self.ends:
                kind = "InitialNode" if name == START else "ActivityFinalNode"
                self.ends[name] = self.uml.child(self.activity, "node", kind, None, name)
            return self.ends[name]
        return name

    def declare(self, node: Any) -> Element:
        name = identification(node)[1] or ""
        if rule(node) == "ControlNode":
            created = self.uml.child(self.activity, "node", CONTROL_NODES[node.kind], node, name)
        else:
            created = self.uml.child(self.activity, "node", "CallBehaviorAction", node, name)
            target = self.scope.typing(node)
            called = ""
            if target is not None:
                called = identification(target.node)[1] or "" if target.node is not None else simple_name(target.text)
            behaviour = self.block.behaviours.get(called)
            if behaviour:
                created.set("behavior", behaviour)
        if name:
            self.nodes[name] = created
        return created

    def condition(self, member: Any) -> None:
        role = (identification(member)[1] or "").strip().lower()
        condition = body_condition(member)
        if role in CONDITION_ROLES and condition is not None:
            self.uml.constraint(self.activity, role, condition, member)

    def flows(self) -> None:
        """The control flows; an end that names no node is left out (rule T005 reports it)."""
        for source, target, line in self.edges:
            edge = self.uml.child(self.activity, "edge", "ControlFlow", None)
            set_line(edge, line)
            for end, value in (("source", source), ("target", target)):
                found = self.nodes.get(value) if isinstance(value, str) else value
                if found is not None:
                    edge.set(end, found.get(ID) or "")
