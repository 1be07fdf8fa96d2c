"""The behaviours a subsystem's ``part def`` owns: ``action def`` (a partial transition
function, or a shared basic behaviour ``/bb``), ``calc def`` / ``constraint def`` (a primitive
predicate), ``metadata … : Exclusive about …`` (exclusive predicates), ``metadata name :
Group { obligatory = …; optional = …; }`` (a buffer group), ``metadata name : Structure { … }``
(a configuration, in a system) and ``metadata name : Ltl { formula
= "…"; }`` (an LTL property for ``earl-m2t verify``)."""

from __future__ import annotations

from typing import Any

from earl_m2t.sysml2.fsm import Later, activity_step
from earl_m2t.sysml2.parser import identification, location, members, rule, simple_name
from earl_m2t.sysml2.scope import Resolved, Scope
from earl_m2t.sysml2.texts import PREDICATE_LANGUAGE, metadata_tags, representation, result_expression
from earl_m2t.sysml2.uml import ID, Block, UmlWriter

BASIC_BEHAVIOUR = "BasicBehaviour"
EXCLUSION = "Exclusion"
BUFFER_GROUP = "BufferGroup"
LTL_PROPERTY = "LtlProperty"
CONFIGURATION = "Configuration"
TAGGED_CONSTRAINTS = frozenset({BUFFER_GROUP, CONFIGURATION})
LTL_LANGUAGE = "LTL"


class BehaviourWriter:
    def __init__(self, uml: UmlWriter, scope: Scope, later: Later) -> None:
        self.uml = uml
        self.scope = scope
        self.later = later

    def action_definition(self, block: Block, node: Any) -> None:
        name = identification(node)[1] or ""
        concept = self.scope.concept_of(node)
        if concept == BASIC_BEHAVIOUR or (not concept and name.endswith("/bb")):
            activity = self.uml.child(block.element, "ownedBehavior", "Activity", node, name)
            if concept:
                self.uml.apply(activity, concept, {}, location(node)[0])
            block.behaviours[name] = activity.get(ID) or ""
            self.later.insert(0, activity_step(self.uml, self.scope, block, activity, list(members(node))))
            return
        behaviour = self.uml.child(block.element, "ownedBehavior", "OpaqueBehavior", node, name)
        if concept:
            self.uml.apply(behaviour, concept, {}, location(node)[0])
        block.behaviours[name] = behaviour.get(ID) or ""
        for member in members(node):
            if rule(member) == "Usage" and member.direction:
                parameter = self.uml.child(behaviour, "ownedParameter", "Parameter", member,
                                           identification(member)[1] or "")
                parameter.set("direction", member.direction)
                self.uml.set_type(parameter, self.scope.typing(member))
        written = representation(node)
        if written is not None:
            self.uml.body(behaviour, *written)

    def predicate(self, block: Block, node: Any) -> None:
        name = identification(node)[1] or ""
        behaviour = self.uml.child(block.element, "ownedBehavior", "FunctionBehavior", node, name)
        concept = self.scope.concept_of(node)
        if concept:
            self.uml.apply(behaviour, concept, {}, location(node)[0])
        block.behaviours[name] = behaviour.get(ID) or ""
        result = self.uml.child(behaviour, "ownedParameter", "Parameter", None, "return")
        result.set("direction", "return")
        self.uml.set_type(result, Resolved(primitive="Boolean"))
        written = representation(node)
        if written is not None:
            self.uml.body(behaviour, *written)
            return
        found = result_expression(node)
        if found is not None:
            self.uml.body(behaviour, PREDICATE_LANGUAGE, *found)

    def exclusion(self, block: Block, node: Any) -> None:
        if self.scope.metadata_concept(node.type) != EXCLUSION:
            return
        constraint = self.uml.child(block.element, "ownedRule", "Constraint", node, identification(node)[1] or "")
        self.uml.apply(constraint, EXCLUSION, {}, location(node)[0])

        def constrain() -> None:
            targets = [block.behaviours.get(simple_name(a), "") for a in node.about]
            constraint.set("constrainedElement", " ".join(t for t in targets if t))

        self.later.append(constrain)

    def tagged_constraint(self, block: Block, node: Any) -> None:
        """``metadata command : Group { obligatory = "a/ib"; optional = "b/ib"; }`` in a subsystem,
        ``metadata useA : Structure { agents = "…"; links = "…"; }`` in a system: a Constraint of
        the block stereotyped «BufferGroup» or «Configuration» with those tags."""
        concept = self.scope.metadata_concept(node.type)
        if concept not in TAGGED_CONSTRAINTS:
            return
        constraint = self.uml.child(block.element, "ownedRule", "Constraint", node, identification(node)[1] or "")
        self.uml.apply(constraint, concept, metadata_tags(node), location(node)[0])

    def ltl_property(self, block: Block, node: Any) -> None:
        """``metadata name : Ltl { formula = "…"; }``: a Constraint of the block stereotyped
        «LtlProperty» whose specification is the formula (language LTL)."""
        if self.scope.metadata_concept(node.type) != LTL_PROPERTY:
            return
        formula = metadata_tags(node).get("formula", "")
        line = next((location(item)[0] for item in getattr(node.body, "items", None) or []
                     if rule(item) == "MetadataBodyUsage" and simple_name(item.feature) == "formula"), 0)
        constraint = self.uml.constraint(block.element, identification(node)[1] or "", (LTL_LANGUAGE, formula, line),
                                         node)
        self.uml.apply(constraint, LTL_PROPERTY, {}, location(node)[0])
