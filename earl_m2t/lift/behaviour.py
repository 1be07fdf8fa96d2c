"""Lifting a subsystem block's behaviour: FSM (stm), basic behaviours and their stages (act),
partial transition functions, primitive predicates and exclusions."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from earl_m2t.lift.activation import activation_of
from earl_m2t.lift.recognise import Recogniser, suffix_of
from earl_m2t.lift.tags import flag, names, tag
from earl_m2t.model.conditions import Condition, ConditionRole
from earl_m2t.model.elements import (
    Access,
    ActivityProblem,
    BasicBehaviour,
    Buffer,
    Exclusion,
    Fsm,
    Memory,
    PartialFunction,
    PrimitivePredicate,
    State,
    Transition,
)
from earl_m2t.model.kinds import AccessMode
from earl_m2t.model.location import Location
from earl_m2t.model.naming import stem, suffix
from earl_m2t.read.xmi import Element, ExternalRef, RawModel

PREDICATE_LANGUAGES = frozenset({"", "earl", "earl-predicate", "predicate"})
CONTROL_NODES = frozenset(
    {"InitialNode", "ActivityFinalNode", "FlowFinalNode", "ForkNode", "JoinNode", "MergeNode", "DecisionNode"}
)
ACTION_TYPES = frozenset({"CallBehaviorAction", "OpaqueAction", "CallOperationAction"})
PIN_FEATURES = frozenset({"argument", "result", "inputValue", "outputValue"})
MEMORY_ACCESS_SUFFIXES: dict[str, AccessMode | None] = {"m": None, "mi": AccessMode.READ, "mo": AccessMode.WRITE}
PARAMETER_ACCESS = {"in": AccessMode.READ, "out": AccessMode.WRITE, "inout": AccessMode.READWRITE}
CONDITION_FEATURES = ("ownedRule", "postcondition", "precondition")  # where tc and ec are looked for, in order
CONDITION_NAMES = {"tc": "tc", "terminalcondition": "tc", "ec": "ec", "errorcondition": "ec"}


@dataclass
class BehaviourContext:
    """What the behaviour lifter needs of the subsystem instance it works for."""

    raw: RawModel
    recogniser: Recogniser
    path: str  # the subsystem instance path
    inputs: tuple[Buffer, ...]
    outputs: tuple[Buffer, ...]
    memory: tuple[Memory, ...]
    # makes a condition of the FSM or a basic behaviour (text, language, location, owner, role),
    # resolved in the subsystem
    make_condition: ConditionMaker = Condition


ConditionMaker = Callable[[str, str, Location, str, ConditionRole], Condition]


def condition_of(raw: RawModel, constraint: Element | None, owner: str, role: ConditionRole,
                 make: ConditionMaker = Condition) -> Condition | None:
    """The predicate text of a Constraint (or an expression / opaque behaviour) in the EARL
    language, made a condition by ``make``."""
    if constraint is None:
        return None
    spec = constraint
    if raw.uml_type(constraint) == "Constraint":
        specs = raw.children(constraint, "specification")
        if not specs:
            ref = raw.ref(constraint, "specification")
            specs = [ref] if ref is not None and not isinstance(ref, ExternalRef) else []
        if not specs:
            return make("", "", raw.location(constraint), owner, role)
        spec = specs[0]
    bodies = raw.opaque_bodies(spec)
    if not bodies and spec.get("value") is not None:  # a LiteralBoolean / LiteralString guard
        bodies = [("", spec.get("value") or "")]
    if not bodies:
        return make("", "", raw.location(spec), owner, role)
    language, body = next(((lang, b) for lang, b in bodies if lang.strip().lower() in PREDICATE_LANGUAGES), bodies[0])
    return make(body.strip(), language, raw.body_location(spec), owner, role)


class BehaviourLifter:
    def __init__(self, ctx: BehaviourContext) -> None:
        self.ctx = ctx
        self.raw = ctx.raw
        self._owned: dict[int, list[tuple[Element, str]]] = {}
        self._storage: dict[str, tuple[str, ...]] = {}  # resolve_storage's answers: pfs name the same buffers

    # -- owned behaviours of the block -------------------------------------------------------
    def owned_behaviours(self, block: Element) -> list[tuple[Element, str]]:
        """(behaviour, concept) for every owned behaviour, concept "" when not an EARL one."""
        found = self._owned.get(id(block))
        if found is None:
            recognise = self.ctx.recogniser.recognise
            found = [(beh, recognise(beh).concept) for beh in self.raw.children(block, "ownedBehavior")]
            self._owned[id(block)] = found
        return found

    def functions(self, block: Element) -> tuple[PartialFunction, ...]:
        result = []
        for beh, concept in self.owned_behaviours(block):
            if concept != "PartialTransitionFunction":
                continue
            name = self.raw.name(beh)
            bodies = self.raw.opaque_bodies(beh)
            language, body = bodies[0] if bodies else ("", "")
            accesses = tuple(self._access(p) for p in self.raw.children(beh, "ownedParameter")
                             if p.get("direction") != "return")
            result.append(
                PartialFunction(name, f"{self.ctx.path}.{name}", accesses, language, body,
                                self.raw.location(beh), self.ctx.recogniser.recognise(beh).route)
            )
        return tuple(result)

    def _access(self, param: Element) -> Access:
        direction = param.get("direction") or "in"
        name = self.raw.name(param).strip()
        # the paper's mi / mo names say the access themselves; otherwise the direction does
        mode = MEMORY_ACCESS_SUFFIXES.get(suffix(name)) or PARAMETER_ACCESS.get(direction, AccessMode.READ)
        foreign = ""
        local = name
        if "." in name:
            qualifier, _, local = name.rpartition(".")
            if qualifier not in ("", "self") and qualifier != self.ctx.path.rpartition(".")[2]:
                foreign = qualifier
        targets = () if foreign else self.resolve_storage(local)
        return Access(name, mode, targets, foreign, self.raw.location(param))

    def resolve_storage(self, name: str) -> tuple[str, ...]:
        """Paths of the buffers or memory a pf parameter or predicate names (templates name all instances)."""
        found = self._storage.get(name)
        if found is None:
            found = self._storage[name] = self._resolve_storage(name)
        return found

    def _resolve_storage(self, name: str) -> tuple[str, ...]:
        descriptive, abbr = stem(name), suffix(name)
        buffers = self.ctx.inputs + self.ctx.outputs
        if abbr in ("ib", "ob", ""):
            hits = tuple(b.path for b in buffers if name in (b.name, b.template)
                         or (not abbr and descriptive in (stem(b.name), stem(b.template))))
            if hits:
                return hits
        if abbr in MEMORY_ACCESS_SUFFIXES or not abbr:
            return tuple(m.path for m in self.ctx.memory
                         if descriptive in (stem(m.name), stem(m.template)) or name in (m.name, m.template))
        return ()

    def predicates(self, block: Element) -> tuple[PrimitivePredicate, ...]:
        result = []
        candidates = list(self.owned_behaviours(block))
        candidates += [(r, self.ctx.recogniser.recognise(r).concept) for r in self.raw.children(block, "ownedRule")]
        for el, concept in candidates:
            if concept != "PrimitivePredicate":
                continue
            name = self.raw.name(el)
            path = f"{self.ctx.path}.{name}"
            if self.raw.uml_type(el) == "Constraint":
                fun = condition_of(self.raw, el, path, ConditionRole.FUN)
                language, body = (fun.language, fun.text) if fun else ("", "")
            else:
                bodies = self.raw.opaque_bodies(el)
                language, body = next(
                    ((lang, b) for lang, b in bodies if lang.strip().lower() in PREDICATE_LANGUAGES),
                    bodies[0] if bodies else ("", ""),
                )
                fun = Condition(body.strip(), language, self.raw.body_location(el), path, ConditionRole.FUN)
            if fun is not None and language.strip().lower() not in PREDICATE_LANGUAGES:
                fun = None  # user code in another language (C++): generated as a stub to implement
            result.append(
                PrimitivePredicate(name, path, fun, language, body, self.raw.location(el),
                                   self.ctx.recogniser.recognise(el).route)
            )
        return tuple(result)

    def exclusions(self, block: Element) -> tuple[Exclusion, ...]:
        result = []
        for rule in self.raw.children(block, "ownedRule"):
            concept = self.ctx.recogniser.recognise(rule).concept
            names: list[str] = []
            if concept == "Exclusion":
                names = [self.raw.name(t) for t in self.raw.refs(rule, "constrainedElement")
                         if not isinstance(t, ExternalRef)]
            if not names:
                cond = condition_of(self.raw, rule, self.ctx.path, ConditionRole.EXCLUSION)
                names = parse_exclusive(cond.text) if cond is not None else []
            if len(names) >= 2:
                result.append(Exclusion(self.raw.name(rule), tuple(names), self.raw.location(rule)))
        return tuple(result)

    # -- the state machine -----------------------------------------------------------------
    def state_machines(self, block: Element) -> list[Element]:
        machines = [b for b in self.raw.children(block, "ownedBehavior") if self.raw.uml_type(b) == "StateMachine"]
        preferred = self.raw.ref(block, "classifierBehavior")
        if isinstance(preferred, ExternalRef) or preferred is None or preferred not in machines:
            return machines
        return [preferred] + [m for m in machines if m is not preferred]

    def fsm(self, machine: Element) -> tuple[Fsm, list[BasicBehaviour]]:
        raw = self.raw
        fsm_path = f"{self.ctx.path}.fsm"
        regions = raw.children(machine, "region")
        vertices: dict[int, tuple[str, Element]] = {}
        initial_pseudostates: list[Element] = []
        for region in regions:
            for vertex in raw.children(region, "subvertex"):
                vtype = raw.uml_type(vertex)
                if vtype == "Pseudostate" and (vertex.get("kind") or "initial") == "initial":
                    initial_pseudostates.append(vertex)
                elif vtype in ("State", ""):
                    vertices[id(vertex)] = (raw.name(vertex), vertex)
        states = []
        behaviours: list[BasicBehaviour] = []
        for name, vertex in vertices.values():
            bbs = self._state_behaviours(vertex, name)
            behaviours.extend(bbs)
            tags = self.ctx.recogniser.tags(vertex)
            states.append(State(name, f"{fsm_path}.{name}", tuple(b.name for b in bbs), raw.location(vertex),
                                activation_of(tags), tag(tags, "configuration") or "", flag(tag(tags, "quiescent")),
                                names(raw, tag(tags, "behaviours")), flag(tag(tags, "exclusiveGuards"))))
        initial_ids = {id(p) for p in initial_pseudostates}
        initial_states: list[str] = []
        left_initials: set[int] = set()
        transitions = []
        order = 0
        for region in regions:
            for tr in raw.in_connector_order(raw.children(region, "transition")):
                source = raw.ref(tr, "source")
                target = raw.ref(tr, "target")
                if source is not None and not isinstance(source, ExternalRef) and id(source) in initial_ids:
                    left_initials.add(id(source))
                    if target is not None and not isinstance(target, ExternalRef) and id(target) in vertices:
                        initial_states.append(vertices[id(target)][0])
                    else:
                        initial_states.append("")
                    continue
                transitions.append(self._transition(tr, source, target, vertices, fsm_path, order))
                order += 1
        # an initial pseudostate that leads nowhere still counts as a (broken) initial state
        initial_states.extend("" for p in initial_pseudostates if id(p) not in left_initials)
        fsm = Fsm(raw.name(machine) or "fsm", fsm_path, tuple(states), tuple(transitions),
                  tuple(initial_states), raw.location(machine))
        return fsm, behaviours

    def _transition(self, tr: Element, source, target, vertices, fsm_path: str, order: int) -> Transition:
        raw = self.raw

        def end(vertex) -> tuple[str, bool]:
            if vertex is None or isinstance(vertex, ExternalRef):
                return "", True
            if id(vertex) in vertices:
                return vertices[id(vertex)][0], False
            return raw.name(vertex), True

        src, src_foreign = end(source)
        dst, dst_foreign = end(target)
        name = raw.name(tr) or f"{src},{dst}/t"
        path = f"{fsm_path}.{name}"
        guard = raw.ref(tr, "guard")
        if guard is None or isinstance(guard, ExternalRef):
            inline = raw.children(tr, "guard")
            guard = inline[0] if inline else None
        condition = condition_of(raw, guard, path, ConditionRole.IC, self.ctx.make_condition)
        priority = 0
        tags = self.ctx.recogniser.tags(tr)
        if "priority" in tags:
            try:
                priority = int(tags["priority"])
            except ValueError:
                priority = 0
        return Transition(name, path, src, dst, src_foreign, dst_foreign, condition, priority, order, raw.location(tr),
                          bool(raw.name(tr)))

    def _state_behaviours(self, state: Element, state_name: str) -> list[BasicBehaviour]:
        found = []
        for activity in self.raw.children(state, "doActivity"):
            called = self._called_basic_behaviour(activity)
            found.append(self.basic_behaviour(called if called is not None else activity, state_name))
        return found

    def _called_basic_behaviour(self, activity: Element) -> Element | None:
        """A doActivity that only calls a shared basic-behaviour activity owned by the block."""
        actions = [n for n in self.raw.children(activity, "node") if self.raw.uml_type(n) in ACTION_TYPES]
        if len(actions) != 1:
            return None
        called = self.raw.ref(actions[0], "behavior")
        if called is None or isinstance(called, ExternalRef):
            return None
        if self.ctx.recogniser.recognise(called).concept == "BasicBehaviour":
            return called
        return None

    # -- basic behaviour and transition-function stages ----------------------------------------
    def basic_behaviour(self, activity: Element, state_name: str) -> BasicBehaviour:
        raw = self.raw
        name = raw.name(activity) or f"{state_name}/bb"
        path = f"{self.ctx.path}.{name}"
        by_feature: dict[str, list[Element]] = {feature: [] for feature in CONDITION_FEATURES}
        for owned in activity:  # one pass over the children for the three features
            features = by_feature.get(owned.tag)
            if features is not None:
                features.append(owned)
        rules: dict[str, Element] = {}
        for owned in (el for feature in CONDITION_FEATURES for el in by_feature[feature]):
            role = CONDITION_NAMES.get(raw.name(owned).strip().lower().replace(" ", ""))
            if role and role not in rules:
                rules[role] = owned
        tc = condition_of(raw, rules.get("tc"), path, ConditionRole.TC, self.ctx.make_condition)
        ec = condition_of(raw, rules.get("ec"), path, ConditionRole.EC, self.ctx.make_condition)
        stages, problems = self.stages(activity)
        return BasicBehaviour(name, path, tc, ec, stages, tuple(problems), raw.location(activity),
                              self.ctx.recogniser.recognise(activity).route or "position")

    def stages(self, activity: Element) -> tuple[tuple[tuple[str, ...], ...], list[ActivityProblem]]:
        """Split the pf calls of a tf activity into stages: an action's stage is its depth in the flow."""
        raw = self.raw
        problems: list[ActivityProblem] = []
        nodes = list(raw.children(activity, "node"))
        if not nodes:
            return (), problems
        successors: dict[int, list[int]] = {id(n): [] for n in nodes}
        indegree: dict[int, int] = dict.fromkeys(successors, 0)
        kinds: dict[int, str] = {id(node): raw.uml_type(node) for node in nodes}

        def action_of(end: Element) -> Element:
            """A flow that ends at a pin ends at the pin's action."""
            if id(end) not in kinds and end.tag in PIN_FEATURES:
                parent = end.getparent()
                if parent is not None and id(parent) in kinds:
                    return parent
            return end

        for edge in raw.children(activity, "edge"):
            source, target = raw.ref(edge, "source"), raw.ref(edge, "target")
            if source is None or target is None or isinstance(source, ExternalRef) or isinstance(target, ExternalRef):
                problems.append(ActivityProblem("a flow without a source or a target", raw.location(edge)))
                continue
            source = action_of(source)
            target = action_of(target)
            if id(source) in kinds and id(target) in kinds:
                successors[id(source)].append(id(target))
                indegree[id(target)] += 1
        forks = sum(1 for k in kinds.values() if k == "ForkNode")
        joins = sum(1 for k in kinds.values() if k == "JoinNode")
        if forks != joins:
            problems.append(ActivityProblem(f"unbalanced fork/join ({forks} fork, {joins} join)",
                                            raw.location(activity)))
        actions: dict[int, str] = {}
        for node in nodes:
            if kinds[id(node)] not in ACTION_TYPES:
                if kinds[id(node)] not in CONTROL_NODES:
                    problems.append(ActivityProblem(f"unsupported activity node {kinds[id(node)] or node.tag}",
                                                    raw.location(node)))
                continue
            pf = self._called_function(node)
            if pf is None:
                problems.append(ActivityProblem(
                    f"action '{raw.name(node)}' calls no partial transition function of this subsystem",
                    raw.location(node)))
                continue
            actions[id(node)] = pf
        # longest path in pf calls (Kahn's order): an action's depth is its stage
        depth = dict.fromkeys(successors, 0)
        ready = [n for n, d in indegree.items() if d == 0]
        remaining = dict(indegree)
        ordered = 0
        while ready:
            current = ready.pop()
            ordered += 1
            step = depth[current] + (1 if current in actions else 0)
            for nxt in successors[current]:
                depth[nxt] = max(depth[nxt], step)
                remaining[nxt] -= 1
                if remaining[nxt] == 0:
                    ready.append(nxt)
        if ordered != len(successors):
            problems.append(ActivityProblem("the control flow has a cycle", raw.location(activity)))
            return (), problems
        initials = [n for n, k in kinds.items() if k == "InitialNode"]
        if actions and len(initials) != 1:
            problems.append(ActivityProblem(f"expected one initial node, found {len(initials)}",
                                            raw.location(activity)))
        elif initials:
            reachable = _reachable(initials[0], successors)
            for node in nodes:
                if id(node) in actions and id(node) not in reachable:
                    problems.append(ActivityProblem(
                        f"action '{raw.name(node)}' is not reachable from the initial node", raw.location(node)))
        by_stage: dict[int, list[str]] = {}
        for node in nodes:  # model order inside a stage
            if id(node) in actions:
                by_stage.setdefault(depth[id(node)], []).append(actions[id(node)])
        return tuple(tuple(by_stage[d]) for d in sorted(by_stage)), problems

    def _called_function(self, action: Element) -> str | None:
        called = self.raw.ref(action, "behavior")
        if called is not None and not isinstance(called, ExternalRef):
            name = self.raw.name(called)
            if self.ctx.recogniser.recognise(called).concept == "PartialTransitionFunction" or suffix_of(name) == "pf":
                return name
            return None
        name = self.raw.name(action)
        return name if suffix_of(name) == "pf" else None


def _reachable(start: int, successors: dict[int, list[int]]) -> set[int]:
    seen = {start}
    stack = [start]
    while stack:
        for nxt in successors[stack.pop()]:
            if nxt not in seen:
                seen.add(nxt)
                stack.append(nxt)
    return seen


def parse_exclusive(text: str) -> list[str]:
    """``exclusive(a/pp, b/pp)`` → ``['a/pp', 'b/pp']``; anything else → ``[]``."""
    text = text.strip()
    if not (text.lower().startswith("exclusive(") and text.endswith(")")):
        return []
    inner = text[len("exclusive(") : -1]
    return [part.strip().removesuffix(".fun") for part in inner.split(",") if part.strip()]


__all__ = ["BehaviourContext", "BehaviourLifter", "condition_of", "parse_exclusive"]
