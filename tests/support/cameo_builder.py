"""Write EARL models as Cameo Systems Modeler 2022x saves them (MagicDraw native project XMI).

The output is the ``com.nomagic.magicdraw.uml_model.model`` member of a ``.mdzip``: an
``xmi:XMI`` root without ``xmi:version`` (XMI 20131001, OMG UML 20131001, SysML 1.6 as
``sysml:`` = ``http://www.omg.org/spec/SysML/20181001/SysML``), single-quoted attributes,
tab indentation, the ``xmi:Documentation`` and plug-in ``xmi:Extension`` blocks before the
model, and after it a root ``xmi:Extension`` with the ``stereotypesHREFS`` map followed by
the stereotype applications (ids ``<base id>_application``, ``…_application1`` for a second
stereotype on the same element).

MagicDraw habits reproduced: attributes before references (``name visibility aggregation
type association``), ``visibility='public'`` on features, regions, vertices, transitions,
activity nodes and edges but not on packaged elements or behaviours; ``<body>`` before
``<language>``; ``<annotatedElement>`` / ``<constrainedElement>`` as ``xmi:idref`` children;
no ``incoming``/``outgoing`` on activity nodes; a ``weight`` literal on every edge; no
``kind`` on the initial pseudostate; SysML value types (``SysML_dataType.Real``) as hrefs
with a ``referenceExtension``; the customization stereotypes ``PartProperty`` and
``ValueProperty`` on part and value properties of blocks; ``sysml:NestedConnectorEnd`` with
the whole part path (down to and including ``partWithPort``). The EARL profile comes from a
used project: only SysML has a ``profileApplication``; EARL applications use the namespace
MagicDraw derives from the profile name, ``http://www.magicdraw.com/schemas/EARL.xmi``.

The module also holds the dialect-neutral model the Cameo and Enterprise Architect writers
share (``ea_builder`` imports it). Its API mirrors ``papyrus_builder``: ``ModelBuilder``,
``package``, ``data_type``/``field``, ``block`` with ``input_buffer``, ``output_buffer``,
``memory``, ``part``, ``connector``, ``state_machine``, ``partial_transition_function``,
``primitive_predicate``, ``exclusion``; ``StateMachine.state``/``transition``;
``State.do_activity(...).stages(...)``; ``End.at(port, *parts)``; ``to_bytes()``.

Ids are derived from each element's qualified path (owner chain, kind, name), so two builds
give byte-identical output and an element keeps its id when others are added.
"""

from __future__ import annotations

import hashlib
import uuid
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from enum import Enum
from pathlib import Path
from typing import TypeVar, Union

from tests.support.papyrus_builder import EARL_STEREOTYPES, Multiplicity, MultiplicitySpec

__all__ = [
    "BOOLEAN",
    "EARL_NS",
    "EARL_STEREOTYPES",
    "INTEGER",
    "REAL",
    "STRING",
    "Activity",
    "ActivityNode",
    "Applied",
    "BaseModelBuilder",
    "Block",
    "Comment",
    "Connector",
    "Constraint",
    "ControlFlow",
    "DataType",
    "Element",
    "End",
    "ModelBuilder",
    "Multiplicity",
    "OpaqueBehavior",
    "Package",
    "Param",
    "Parameter",
    "Primitive",
    "Property",
    "Pseudostate",
    "State",
    "StateMachine",
    "Transition",
    "XmlNode",
    "md_id",
]

# ---- the dialect-neutral model -------------------------------------------------------------


class Primitive(Enum):
    """A primitive type; each writer maps it to its tool's library type."""

    BOOLEAN = "Boolean"
    INTEGER = "Integer"
    REAL = "Real"
    STRING = "String"


BOOLEAN = Primitive.BOOLEAN
INTEGER = Primitive.INTEGER
REAL = Primitive.REAL
STRING = Primitive.STRING

TypeRef = Union[Primitive, "DataType", "Block"]
_E = TypeVar("_E", bound="Element")


@dataclass(frozen=True)
class Applied:
    """An EARL stereotype applied to an element, with its tags rendered as strings."""

    name: str
    tags: tuple[tuple[str, str], ...] = ()

    @property
    def metaclass(self) -> str:
        return EARL_STEREOTYPES[self.name]


class Element:
    """A model element: qualified key (the source of its ids), comments and EARL stereotypes."""

    kind = "Element"
    key: str

    def __init__(self, builder: BaseModelBuilder, owner: Element | None, name: str | None, key_name: str | None = None):
        self.builder = builder
        self.owner = owner
        self.name = name
        prefix = owner.key + "\n" if owner is not None else ""
        self.key = f"{prefix}{self.kind}\t{key_name if key_name is not None else name}"
        builder._register(self.key)
        self.comments: list[Comment] = []
        self.applied: list[Applied] = []

    def comment(self, body: str) -> Comment:
        """Attach a comment annotating this element."""
        note = Comment(self.builder, self, body, len(self.comments) + 1)
        self.comments.append(note)
        return note

    def stereotype(self, name: str, tags: Mapping[str, str | int | bool] | None = None) -> None:
        """Apply the EARL stereotype ``name`` (skipped when the builder writes no EARL stereotypes)."""
        self.builder.apply_earl(self, name, tags)

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.name!r}>"


class Comment(Element):
    """A comment whose annotated element is its owner."""

    kind = "Comment"

    def __init__(self, builder: BaseModelBuilder, owner: Element, body: str, index: int):
        super().__init__(builder, owner, None, key_name=str(index))
        self.body = body


class Package(Element):
    """A package holding packages, data types and blocks."""

    kind = "Package"

    def __init__(self, builder: BaseModelBuilder, owner: Element | None, name: str):
        super().__init__(builder, owner, name)
        self.members: list[Element] = []

    def package(self, name: str) -> Package:
        """Create a nested package."""
        return self._own(Package(self.builder, self, name))

    def data_type(self, name: str) -> DataType:
        """Create a data type; add its fields with :meth:`DataType.field`."""
        return self._own(DataType(self.builder, self, name))

    def block(
        self, name: str, stereotype: str | None = None, tags: Mapping[str, str | int | bool] | None = None
    ) -> Block:
        """Create a SysML block, optionally with an EARL stereotype."""
        block = self._own(Block(self.builder, self, name))
        if stereotype is not None:
            block.stereotype(stereotype, tags)
        return block

    def _own(self, element: _E) -> _E:
        self.members.append(element)
        return element


class Model(Package):
    """The root model."""

    kind = "Model"


class Property(Element):
    """A data type field, part, port (buffer) or value property (memory)."""

    kind = "Property"

    def __init__(
        self,
        builder: BaseModelBuilder,
        owner: Element,
        name: str,
        type_: TypeRef | None,
        multiplicity: MultiplicitySpec = None,
        *,
        port: bool = False,
        composite: bool = False,
    ):
        self.kind = "Port" if port else "Property"
        super().__init__(builder, owner, name)
        self.type = type_
        self.multiplicity = Multiplicity.of(multiplicity)
        self.is_port = port
        self.composite = composite

    @property
    def is_part(self) -> bool:
        return self.composite and isinstance(self.type, Block)

    @property
    def is_value(self) -> bool:
        """A value property of a block (an EARL memory), not a field of a data type."""
        return not self.is_port and not self.is_part and isinstance(self.owner, Block)


class DataType(Element):
    """A data type whose attributes are the fields of an EARL dataType."""

    kind = "DataType"

    def __init__(self, builder: BaseModelBuilder, owner: Element, name: str):
        super().__init__(builder, owner, name)
        self.fields: list[Property] = []

    def field(self, name: str, type_: TypeRef, multiplicity: MultiplicitySpec = None) -> Property:
        """Add a field; ``multiplicity`` 6 is a fixed array, ``"*"`` or ``"0..1"`` a variable one."""
        prop = Property(self.builder, self, name, type_, multiplicity)
        self.fields.append(prop)
        return prop


@dataclass(frozen=True)
class Param:
    """A behaviour parameter: ``direction`` is ``in``, ``out``, ``inout`` or ``return``."""

    name: str
    type: TypeRef | None = None
    direction: str = "in"
    multiplicity: MultiplicitySpec = None


class Parameter(Element):
    """An owned parameter of a behaviour."""

    kind = "Parameter"

    def __init__(self, builder: BaseModelBuilder, owner: Element, param: Param):
        if param.direction not in ("in", "out", "inout", "return"):
            raise ValueError(f"parameter {param.name!r}: unknown direction {param.direction!r}")
        super().__init__(builder, owner, param.name)
        self.param = param
        self.multiplicity = Multiplicity.of(param.multiplicity)


class OpaqueBehavior(Element):
    """An opaque behaviour (pf) or function behaviour (pp) with parameters, body and language."""

    kind = "Behavior"

    def __init__(
        self,
        builder: BaseModelBuilder,
        owner: Element,
        name: str,
        params: Sequence[Param],
        body: str,
        language: str,
        *,
        function: bool = False,
    ):
        super().__init__(builder, owner, name)
        self.function = function
        self.parameters = [Parameter(builder, self, p) for p in params]
        self.body = body
        self.language = language


class Constraint(Element):
    """A constraint (guard, ``tc``/``ec``, exclusion) with an optional opaque specification."""

    kind = "Constraint"

    def __init__(
        self,
        builder: BaseModelBuilder,
        owner: Element,
        name: str | None,
        body: str | None,
        language: str = "EARL",
        constrained: Sequence[Element] = (),
    ):
        super().__init__(builder, owner, name, key_name=name or "guard")
        self.body = body
        self.language = language
        self.constrained = list(constrained)


@dataclass(frozen=True)
class End:
    """A connector end: ``role`` (a port) reached through ``path``, the parts from the
    connector's owner down to the part whose type owns ``role`` (outer to inner)."""

    role: Property
    path: tuple[Property, ...] = ()

    @classmethod
    def at(cls, role: Property, *path: Property) -> End:
        """``End.at(port, robot_part, agent_part, cs_part)``."""
        return cls(role, tuple(path))

    @property
    def part_with_port(self) -> Property | None:
        return self.path[-1] if self.path else None


class ConnectorEnd(Element):
    """One end of a connector."""

    kind = "End"

    def __init__(self, builder: BaseModelBuilder, owner: Element, index: int, end: End):
        super().__init__(builder, owner, None, key_name=str(index))
        self.end = end


class Connector(Element):
    """A connector owned by a block, from ``source`` (output buffer) to ``target`` (input buffer)."""

    kind = "Connector"

    def __init__(self, builder: BaseModelBuilder, owner: Element, name: str, source: End, target: End):
        super().__init__(builder, owner, name)
        self.ends = [ConnectorEnd(builder, self, 1, source), ConnectorEnd(builder, self, 2, target)]


class Block(Element):
    """A SysML block: parts, ports (buffers), values (memory), connectors, FSM, pf, pp, exclusions."""

    kind = "Class"

    def __init__(self, builder: BaseModelBuilder, owner: Element, name: str):
        super().__init__(builder, owner, name)
        self.rules: list[Constraint] = []
        self.attributes: list[Property] = []
        self.connectors: list[Connector] = []
        self.behaviors: list[Element] = []
        self.classifier_behavior: Element | None = None

    # -- structure

    def part(self, name: str, type_: Block, multiplicity: MultiplicitySpec = None) -> Property:
        """Add a part property typed by a block."""
        return self._attr(Property(self.builder, self, name, type_, multiplicity, composite=True))

    def port(
        self, name: str, type_: TypeRef, multiplicity: MultiplicitySpec = None, stereotype: str | None = None
    ) -> Property:
        """Add a port, optionally stereotyped (``InputBuffer``, ``OutputBuffer``)."""
        prop = self._attr(Property(self.builder, self, name, type_, multiplicity, port=True, composite=True))
        if stereotype is not None:
            prop.stereotype(stereotype)
        return prop

    def input_buffer(self, name: str, type_: TypeRef, multiplicity: MultiplicitySpec = None) -> Property:
        """Add an Input Buffer: a port stereotyped ``«InputBuffer»``."""
        return self.port(name, type_, multiplicity, "InputBuffer")

    def output_buffer(self, name: str, type_: TypeRef, multiplicity: MultiplicitySpec = None) -> Property:
        """Add an Output Buffer: a port stereotyped ``«OutputBuffer»``."""
        return self.port(name, type_, multiplicity, "OutputBuffer")

    def value(
        self, name: str, type_: TypeRef, multiplicity: MultiplicitySpec = None, stereotype: str | None = None
    ) -> Property:
        """Add a value property (not a port), optionally stereotyped."""
        prop = self._attr(Property(self.builder, self, name, type_, multiplicity))
        if stereotype is not None:
            prop.stereotype(stereotype)
        return prop

    def memory(self, name: str, type_: TypeRef, multiplicity: MultiplicitySpec = None) -> Property:
        """Add an Internal Memory: a value property stereotyped ``«InternalMemory»``."""
        return self.value(name, type_, multiplicity, "InternalMemory")

    def connector(self, name: str, source: End, target: End, stereotype: str | None = None) -> Connector:
        """Add a connector from ``source`` (output buffer end) to ``target`` (input buffer end)."""
        conn = Connector(self.builder, self, name, source, target)
        self.connectors.append(conn)
        if stereotype is not None:
            conn.stereotype(stereotype)
        return conn

    def _attr(self, prop: Property) -> Property:
        self.attributes.append(prop)
        return prop

    # -- behaviour

    def state_machine(self, name: str = "fsm", stereotype: str | None = "FSM") -> StateMachine:
        """Add a state machine with one region; the first one becomes the classifier behaviour."""
        machine = StateMachine(self.builder, self, name)
        self.behaviors.append(machine)
        if self.classifier_behavior is None:
            self.classifier_behavior = machine
        if stereotype is not None:
            machine.stereotype(stereotype)
        return machine

    def opaque_behavior(
        self,
        name: str,
        params: Sequence[Param] = (),
        body: str = "",
        language: str = "C++",
        *,
        function: bool = False,
        stereotype: str | None = None,
    ) -> OpaqueBehavior:
        """Add an owned opaque behaviour (a function behaviour when ``function``)."""
        behavior = OpaqueBehavior(self.builder, self, name, params, body, language, function=function)
        self.behaviors.append(behavior)
        if stereotype is not None:
            behavior.stereotype(stereotype)
        return behavior

    def partial_transition_function(
        self,
        name: str,
        reads: Sequence[Property] = (),
        writes: Sequence[Property] = (),
        body: str = "",
        language: str = "C++",
    ) -> OpaqueBehavior:
        """Add a pf whose parameters are named after the buffers and memories it reads and writes
        (a read memory ``x/m`` becomes ``x/mi``, a written one ``x/mo``)."""
        params = [self._pf_param(p, "in") for p in reads] + [self._pf_param(p, "out") for p in writes]
        return self.opaque_behavior(name, params, body, language, stereotype="PartialTransitionFunction")

    @staticmethod
    def _pf_param(prop: Property, direction: str) -> Param:
        name = prop.name or ""
        if not prop.is_port and name.endswith("/m"):
            name += "i" if direction == "in" else "o"
        return Param(name, prop.type, direction, prop.multiplicity)

    def primitive_predicate(self, name: str, body: str, language: str = "EARL") -> OpaqueBehavior:
        """Add a pp: a function behaviour with a Boolean ``return`` parameter."""
        return self.opaque_behavior(
            name, [Param("return", BOOLEAN, "return")], body, language, function=True, stereotype="PrimitivePredicate"
        )

    def exclusion(
        self, name: str, predicates: Sequence[OpaqueBehavior] = (), body: str | None = None, stereotype: bool = True
    ) -> Constraint:
        """Declare primitive predicates mutually exclusive (constrained elements and/or an EARL body)."""
        rule = Constraint(self.builder, self, name, body, "EARL", predicates)
        self.rules.append(rule)
        if stereotype:
            rule.stereotype("Exclusion")
        return rule

    def ltl_property(self, name: str, formula: str) -> Constraint:
        """An «LtlProperty» constraint: ``earl-m2t verify`` checks the LTL formula of its
        specification (language LTL)."""
        rule = Constraint(self.builder, self, name, formula, "LTL")
        self.rules.append(rule)
        rule.stereotype("LtlProperty")
        return rule

    def buffer_group(self, name: str, obligatory: Sequence[Property] = (),
                     optional: Sequence[Property] = ()) -> Constraint:
        """A «BufferGroup» constraint whose tags name the obligatory and optional Input Buffers."""
        return self._tagged_rule(name, "BufferGroup", {"obligatory": " ".join(p.name or "" for p in obligatory),
                                                       "optional": " ".join(p.name or "" for p in optional)})

    def configuration(self, name: str, agents: Sequence[str] = (), links: Sequence[str] = (),
                      switch_timeout: float | str | None = None) -> Constraint:
        """A «Configuration» constraint of a System block whose tags name the variable agents and
        inter-agent links present in it (paths separated by spaces) and its ``switchTimeout`` (s)."""
        tags: dict[str, str] = {"agents": " ".join(agents), "links": " ".join(links)}
        if switch_timeout is not None:
            tags["switchTimeout"] = str(switch_timeout)
        return self._tagged_rule(name, "Configuration", tags)

    def _tagged_rule(self, name: str, stereotype: str, tags: Mapping[str, str]) -> Constraint:
        rule = Constraint(self.builder, self, name, None)
        self.rules.append(rule)
        rule.stereotype(stereotype, tags)
        return rule


class Pseudostate(Element):
    """The initial pseudostate of a region."""

    kind = "Pseudostate"


class State(Element):
    """A state; its basic behaviour is the ``doActivity`` made by :meth:`do_activity`."""

    kind = "State"

    def __init__(self, builder: BaseModelBuilder, owner: Element, name: str):
        super().__init__(builder, owner, name)
        self.do: Activity | None = None

    def do_activity(
        self,
        name: str | None = None,
        tc: str | None = "FALSE",
        ec: str | None = "FALSE",
        stereotype: str | None = "BasicBehaviour",
    ) -> Activity:
        """Create the state's ``doActivity`` (default name ``<state>/bb``) with ``tc``/``ec`` rules."""
        if self.do is not None:
            raise ValueError(f"state {self.name!r} already has a doActivity")
        act = Activity(self.builder, self, name or f"{self.name}/bb")
        if tc is not None:
            act.condition("tc", tc)
        if ec is not None:
            act.condition("ec", ec)
        if stereotype is not None:
            act.stereotype(stereotype)
        self.do = act
        return act


class Transition(Element):
    """A transition; the guard is a constraint with an EARL specification."""

    kind = "Transition"

    def __init__(
        self,
        builder: BaseModelBuilder,
        owner: Element,
        name: str | None,
        source: Element,
        target: Element,
        guard: str | None,
    ):
        super().__init__(builder, owner, name, key_name=name or f"{source.key}->{target.key}")
        self.source = source
        self.target = target
        self.guard = Constraint(builder, self, None, guard) if guard is not None else None


class StateMachine(Element):
    """A state machine with one region: an initial pseudostate, states and transitions."""

    kind = "StateMachine"

    def __init__(self, builder: BaseModelBuilder, owner: Element, name: str):
        super().__init__(builder, owner, name)
        self.region_key = self.key + "\nRegion\tRegion1"
        self.initial: Pseudostate | None = None
        self.states: list[State] = []
        self.transitions: list[Transition] = []

    def state(self, name: str, initial: bool = False, stereotype: str | None = "FsmState") -> State:
        """Add a state; ``initial=True`` also adds the initial pseudostate and its transition."""
        st = State(self.builder, self, name)
        self.states.append(st)
        if stereotype is not None:
            st.stereotype(stereotype)
        if initial:
            if self.initial is not None:
                raise ValueError(f"state machine {self.name!r} already has an initial state")
            self.initial = Pseudostate(self.builder, self, None, key_name="initial")
            self.transitions.insert(0, Transition(self.builder, self, None, self.initial, st, None))
        return st

    def transition(
        self,
        source: State,
        target: State,
        guard: str | None = None,
        name: str | None = None,
        priority: int = 0,
        stereotype: bool = True,
    ) -> Transition:
        """Add a transition named ``source,target/t`` by default; a non-zero ``priority`` is tagged."""
        tr = Transition(self.builder, self, name or f"{source.name},{target.name}/t", source, target, guard)
        self.transitions.append(tr)
        if stereotype:
            tr.stereotype("FsmTransition", {"priority": priority} if priority else None)
            if tr.guard is not None:
                tr.guard.stereotype("Predicate")
        return tr

    def vertices(self) -> list[Element]:
        """The initial pseudostate (if any), then the states."""
        return ([self.initial] if self.initial is not None else []) + list(self.states)


class ActivityNode(Element):
    """A control node (``InitialNode``, ``ForkNode``, ``JoinNode``, ``ActivityFinalNode``) or a
    ``CallBehaviorAction``; ``node_type`` is the UML metaclass name."""

    kind = "ActivityNode"

    def __init__(self, builder: BaseModelBuilder, owner: Activity, node_type: str, name: str, behavior: Element | None):
        super().__init__(builder, owner, name)
        self.node_type = node_type
        self.behavior = behavior
        self.incoming: list[ControlFlow] = []
        self.outgoing: list[ControlFlow] = []


class ControlFlow(Element):
    """A control flow between two activity nodes."""

    kind = "ControlFlow"

    def __init__(self, builder: BaseModelBuilder, owner: Activity, source: ActivityNode, target: ActivityNode):
        super().__init__(builder, owner, None, key_name=f"{source.name}->{target.name}")
        self.source = source
        self.target = target
        source.outgoing.append(self)
        target.incoming.append(self)


class Activity(Element):
    """An activity: a basic behaviour (``tc``/``ec`` rules) whose graph is the tf."""

    kind = "Activity"

    def __init__(self, builder: BaseModelBuilder, owner: Element, name: str):
        super().__init__(builder, owner, name)
        self.rules: list[Constraint] = []
        self.nodes: list[ActivityNode] = []
        self.edges: list[ControlFlow] = []
        self._counters: dict[str, int] = {}

    def condition(self, name: str, body: str, language: str = "EARL", stereotype: bool = True) -> Constraint:
        """Add an owned rule, e.g. ``tc`` or ``ec``, with an EARL specification."""
        rule = Constraint(self.builder, self, name, body, language)
        self.rules.append(rule)
        if stereotype:
            rule.stereotype("Predicate")
        return rule

    def _control(self, node_type: str) -> ActivityNode:
        count = self._counters.get(node_type, 0) + 1
        self._counters[node_type] = count
        node = ActivityNode(self.builder, self, node_type, f"{node_type}{count}", None)
        self.nodes.append(node)
        return node

    def initial(self) -> ActivityNode:
        """Add an ``InitialNode``."""
        return self._control("InitialNode")

    def fork(self) -> ActivityNode:
        """Add a ``ForkNode``."""
        return self._control("ForkNode")

    def join(self) -> ActivityNode:
        """Add a ``JoinNode``."""
        return self._control("JoinNode")

    def final(self) -> ActivityNode:
        """Add an ``ActivityFinalNode``."""
        return self._control("ActivityFinalNode")

    def call(self, behavior: Element, name: str | None = None) -> ActivityNode:
        """Add a ``CallBehaviorAction`` of ``behavior``, named after it by default."""
        node = ActivityNode(self.builder, self, "CallBehaviorAction", name or behavior.name or "", behavior)
        self.nodes.append(node)
        return node

    def flow(self, source: ActivityNode, target: ActivityNode) -> None:
        """Add a ``ControlFlow`` from ``source`` to ``target``."""
        self.edges.append(ControlFlow(self.builder, self, source, target))

    def stages(self, stages: Sequence[Sequence[Element]]) -> list[list[ActivityNode]]:
        """Build initial → stage 1 → stage 2 … → final, one call per behaviour; a stage of several
        behaviours sits between a fork and a join. Returns the call actions."""
        calls: list[list[ActivityNode]] = []
        last = self.initial()
        for stage in stages:
            if not stage:
                continue
            actions = [self.call(b) for b in stage]
            calls.append(actions)
            if len(actions) == 1:
                self.flow(last, actions[0])
                last = actions[0]
                continue
            fork = self.fork()
            self.flow(last, fork)
            for action in actions:
                self.flow(fork, action)
            join = self.join()
            for action in actions:
                self.flow(action, join)
            last = join
        self.flow(last, self.final())
        return calls


class BaseModelBuilder:
    """The dialect-neutral part of a builder: the element tree and the EARL stereotypes.

    ``stereotypes=False`` applies no EARL stereotype (the suffix-only variant); SysML's own
    stereotypes are always written.
    """

    def __init__(self, name: str, *, stereotypes: bool = True):
        self.stereotypes = stereotypes
        self._keys: set[str] = set()
        self.model = Model(self, None, name)

    def package(self, name: str) -> Package:
        """Create a top-level package of the model."""
        return self.model.package(name)

    def comment(self, body: str) -> Comment:
        """Attach a comment to the model."""
        return self.model.comment(body)

    def apply_earl(self, element: Element, stereotype: str, tags: Mapping[str, str | int | bool] | None = None) -> None:
        """Apply an EARL stereotype to ``element``; a no-op when ``stereotypes`` is off."""
        if stereotype not in EARL_STEREOTYPES:
            raise ValueError(f"unknown EARL stereotype {stereotype!r}")
        if not self.stereotypes:
            return
        rendered = tuple(
            (k, ("true" if v else "false") if isinstance(v, bool) else str(v)) for k, v in (tags or {}).items()
        )
        for i, applied in enumerate(element.applied):
            if applied.name == stereotype:  # applied already: add the tags
                element.applied[i] = Applied(stereotype, (*applied.tags, *rendered))
                return
        element.applied.append(Applied(stereotype, rendered))

    def to_bytes(self) -> bytes:  # pragma: no cover - every dialect overrides
        raise NotImplementedError

    def write(self, path: str | Path) -> None:
        """Write :meth:`to_bytes` to ``path``."""
        Path(path).write_bytes(self.to_bytes())

    def _register(self, key: str) -> None:
        if key in self._keys:
            raise ValueError("two elements share one qualified path: " + key.replace("\n", " :: "))
        self._keys.add(key)


# ---- XML writing (shared by the Cameo and EA writers) ------------------------------------------


class XmlNode:
    """One XML element: qualified tag, ordered attributes, children or text."""

    __slots__ = ("tag", "attrs", "children", "text")

    def __init__(self, tag: str, attrs: Iterable[tuple[str, str | None]] = (), text: str | None = None):
        self.tag = tag
        self.attrs = [(k, v) for k, v in attrs if v is not None]
        self.children: list[XmlNode] = []
        self.text = text

    def add(self, child: XmlNode | None) -> XmlNode | None:
        if child is not None:
            self.children.append(child)
        return child

    def sub(self, tag: str, attrs: Iterable[tuple[str, str | None]] = (), text: str | None = None) -> XmlNode:
        """Add and return a new child."""
        child = XmlNode(tag, attrs, text)
        self.children.append(child)
        return child

    def write(self, out: list[str], depth: int, style: XmlStyle) -> None:
        pad = "\t" * depth
        q = style.quote
        attrs = "".join(f" {k}={q}{style.attr(v)}{q}" for k, v in self.attrs)
        nl = style.newline
        if self.text is not None:
            out.append(f"{pad}<{self.tag}{attrs}>{style.text(self.text)}</{self.tag}>{nl}")
        elif not self.children:
            out.append(f"{pad}<{self.tag}{attrs}/>{nl}")
        else:
            out.append(f"{pad}<{self.tag}{attrs}>{nl}")
            for child in self.children:
                child.write(out, depth + 1, style)
            out.append(f"{pad}</{self.tag}>{nl}")


@dataclass(frozen=True)
class XmlStyle:
    """How a tool writes XML: quote character, line end and escaping."""

    quote: str
    newline: str
    attr_escapes: tuple[tuple[str, str], ...]
    text_escapes: tuple[tuple[str, str], ...]

    def attr(self, value: str) -> str:
        for old, new in self.attr_escapes:
            value = value.replace(old, new)
        return value

    def text(self, value: str) -> str:
        for old, new in self.text_escapes:
            value = value.replace(old, new)
        return value


# MagicDraw: single quotes, all five entities, newlines in attributes as &#10;.
MD_STYLE = XmlStyle(
    quote="'",
    newline="\n",
    attr_escapes=(
        ("&", "&amp;"), ("<", "&lt;"), (">", "&gt;"), ('"', "&quot;"), ("'", "&#39;"),
        ("\n", "&#10;"), ("\r", "&#13;"), ("\t", "&#9;"),
    ),
    text_escapes=(("&", "&amp;"), ("<", "&lt;"), (">", "&gt;"), ('"', "&quot;"), ("'", "&#39;")),
)  # fmt: skip


# ---- Cameo / MagicDraw ids and constants -----------------------------------------------------

XMI_NS = "http://www.omg.org/spec/XMI/20131001"
UML_NS = "http://www.omg.org/spec/UML/20131001"
SYSML_NS = "http://www.omg.org/spec/SysML/20181001/SysML"
MD_CUSTOM_NS = "http://www.magicdraw.com/spec/Customization/180/SysML"
MD_CUSTOM = "MD_Customization_for_SysML__additional_stereotypes"
EARL_NS = "http://www.magicdraw.com/schemas/EARL.xmi"
EXTENDER = "MagicDraw UML 2022x"
ROOT_MODEL_ID = "eee_1045467100313_135436_1"  # the id of every model made from MagicDraw's template
SYSML_XMI = "http://www.omg.org/spec/SysML/20181001/SysML.xmi"

# SysML 1.6 value types as Cameo 2022x references them: (fragment, originalID).
_VALUE_TYPES = {
    Primitive.BOOLEAN: ("SysML_dataType.Boolean", "_16_5_1_12c903cb_1245415335546_39033_4086"),
    Primitive.INTEGER: ("SysML_dataType.Integer", "_16_5_1_12c903cb_1245415335546_8641_4088"),
    Primitive.REAL: ("SysML_dataType.Real", "_11_5EAPbeta_be00301_1147431819399_50461_1671"),
    Primitive.STRING: ("SysML_dataType.String", "_16_5_1_12c903cb_1245415335546_479030_4092"),
}

# Used projects as MagicDraw 2022x names them in stereotypesHREFS.
_SHARED = "?resource=com.nomagic.magicdraw.uml_umodel.shared_umodel"
_SYSML_PROJECT = "local:/PROJECT-44892a3bf693c0a47eb2f3bf10930f" + _SHARED
_CUSTOM_PROJECT = "local:/PROJECT-9b4d2b1641e6203934d95e7bde5fe08" + _SHARED
_MD_PROFILE_PROJECT = "local:/PROJECT-877558e9224f114d50dea1f39a1c119" + _SHARED
_BASE_ELEMENT_TAG = ("base_Element", "_10_0EAPbeta_be00301_1123081772098_411862_275", _MD_PROFILE_PROJECT)

# (qualified stereotype, stereotype id in its project, project, tags as (name, id, project)).
_MD_STEREOTYPES: dict[str, tuple[str, str, tuple[tuple[str, str, str], ...]]] = {
    "sysml:Block": (
        "_11_5EAPbeta_be00301_1147424179914_458922_958",
        _SYSML_PROJECT,
        (("isEncapsulated", "_11_5EAPbeta_be00301_1147424201876_860708_1049", _SYSML_PROJECT),),
    ),
    "sysml:NestedConnectorEnd": (
        "_11_5EAPbeta_be00301_1147431307463_773225_1455",
        _SYSML_PROJECT,
        (
            _BASE_ELEMENT_TAG,
            ("base_Element", "_17_0_5beta_17530432_1382583873425_737094_11432", _SYSML_PROJECT),
            ("propertyPath", "_11_5EAPbeta_be00301_1147431377925_245593_1615", _SYSML_PROJECT),
        ),
    ),
    f"{MD_CUSTOM}:PartProperty": (
        "_15_0_be00301_1199377756297_348405_2678",
        _CUSTOM_PROJECT,
        (_BASE_ELEMENT_TAG, ("base_Property", "_11_5EAPbeta_be00301_1147424449672_715796_1055", _CUSTOM_PROJECT)),
    ),
    f"{MD_CUSTOM}:ValueProperty": ("_12_0_be00301_1164123483951_695645_2041", _CUSTOM_PROJECT, (_BASE_ELEMENT_TAG,)),
}

# The EARL profile, in a used project ("EARL Profile.mdzip").
_EARL_PROJECT_ID = str(uuid.UUID(hashlib.sha256(b"EARL Profile.mdzip").hexdigest()[:32], version=4))
_EARL_PROJECT = f"local:/PROJECT-{_EARL_PROJECT_ID}{_SHARED}"
# The tags of its stereotypes; the stereotypesHREFS map lists those an application of the file sets.
_EARL_TAGS = {"Agent": ("declaredType", "reactivation"), "FsmTransition": ("priority",),
              "InputBuffer": ("receive", "queueSize"),
              "FsmState": ("bufferGroup", "minPeriod", "firstTimeout", "nextTimeout", "configuration", "quiescent"),
              "BufferGroup": ("obligatory", "optional"), "Configuration": ("agents", "links", "switchTimeout")}

_USER = hashlib.sha256(b"earl-m2t sample").hexdigest()[:7]  # MagicDraw's per-installation id part
_EPOCH_MS = 1_717_200_000_000  # 2024-06-01: ids carry creation times after this


def md_id(key: str, user: str = _USER) -> str:
    """A MagicDraw 2022x id (``_2022x_<user>_<ms>_<random>_<counter>``) derived from ``key``."""
    digest = hashlib.sha256(key.encode("utf-8")).digest()
    ms = _EPOCH_MS + int.from_bytes(digest[0:5], "big") % (120 * 86_400_000)
    rnd = int.from_bytes(digest[5:8], "big") % 1_000_000
    counter = 1000 + int.from_bytes(digest[8:11], "big") % 60_000
    return f"_2022x_{user}_{ms}_{rnd}_{counter}"


def _earl_stereotype_id(name: str) -> str:
    return md_id(f"EARL Profile.mdzip\nStereotype\t{name}", user="2d8f1a0")


def _earl_tag_id(stereotype: str, tag: str) -> str:
    return md_id(f"EARL Profile.mdzip\nStereotype\t{stereotype}\nProperty\t{tag}", user="2d8f1a0")


# ---- the Cameo writer ---------------------------------------------------------------------------


def _typed(tag: str, xmi_type: str, xmi_id: str, *attrs: tuple[str, str | None]) -> XmlNode:
    return XmlNode(tag, [("xmi:type", xmi_type), ("xmi:id", xmi_id), *attrs])


@dataclass(frozen=True)
class _CameoApp:
    tag: str  # prefix:Stereotype
    base_attr: str
    base_id: str
    attrs: tuple[tuple[str, str], ...] = ()


class ModelBuilder(BaseModelBuilder):
    """Build one Cameo Systems Modeler 2022x model file (``com.nomagic.magicdraw.uml_model.model``)."""

    def to_bytes(self) -> bytes:
        """Return the XMI document (UTF-8, deterministic)."""
        return _CameoWriter(self).render()


class _CameoWriter:
    def __init__(self, builder: ModelBuilder):
        self.builder = builder
        self.ids: dict[str, str] = {}
        self.apps: list[_CameoApp] = []

    # -- ids

    def id(self, element: Element) -> str:
        if element is self.builder.model:
            return ROOT_MODEL_ID
        return self._id(element.key)

    def _id(self, key: str) -> str:
        found = self.ids.get(key)
        if found is None:
            found = md_id(key)
            if found in self.ids.values():  # pragma: no cover - a hash collision
                raise ValueError(f"id collision for {key!r}")
            self.ids[key] = found
        return found

    # -- document

    def render(self) -> bytes:
        model = self.model_node(self.builder.model)
        namespaces = [
            ("uml", UML_NS),
            ("xmi", XMI_NS),
            ("StandardProfile", f"{UML_NS}/StandardProfile"),
            ("MagicDraw_Profile", f"{UML_NS}/MagicDrawProfile"),
            (MD_CUSTOM, MD_CUSTOM_NS),
            ("sysml", SYSML_NS),
        ]
        if self.builder.stereotypes:
            namespaces.append(("EARL", EARL_NS))
        root = XmlNode("xmi:XMI", [(f"xmlns:{p}", uri) for p, uri in namespaces])
        doc = root.sub("xmi:Documentation")
        doc.sub("xmi:exporter", text="MagicDraw UML")
        doc.sub("xmi:exporterVersion", text="2022x v7")
        plugins = root.sub("xmi:Extension", [("extender", EXTENDER)])
        plugins.sub("plugin", [("pluginName", "SysML"), ("pluginVersion", "2022x")])
        plugins.sub("plugin", [("pluginName", "Cameo Requirements Modeler"), ("pluginVersion", "2022x")])
        for value in (
            "SysML Block Definition Diagram",
            "SysML Internal Block Diagram",
            "SysML State Machine Diagram",
            "SysML Activity Diagram",
            "SysML",
        ):
            plugins.sub(
                "req_resource", [("resourceID", "1440"), ("resourceName", "SysML"), ("resourceValueName", value)]
            )
        root.add(model)
        hrefs = root.sub("xmi:Extension", [("extender", EXTENDER)]).sub("stereotypesHREFS")
        self.stereotype_hrefs(hrefs)
        counts: dict[str, int] = {}
        for app in self.apps:
            n = counts.get(app.base_id, 0)
            counts[app.base_id] = n + 1
            app_id = f"{app.base_id}_application" + (str(n) if n else "")
            root.sub(app.tag, [("xmi:id", app_id), (app.base_attr, app.base_id), *app.attrs])
        out = ["<?xml version='1.0' encoding='UTF-8'?>\n"]
        root.write(out, 0, MD_STYLE)
        return "".join(out).rstrip("\n").encode("utf-8")

    def stereotype_hrefs(self, node: XmlNode) -> None:
        seen: list[str] = []
        for app in self.apps:
            if app.tag not in seen:
                seen.append(app.tag)
        set_tags = {(app.tag, attr) for app in self.apps for attr, _ in app.attrs}
        for tag in seen:
            if tag.startswith("EARL:"):
                name = tag.split(":", 1)[1]
                href = f"{_EARL_PROJECT}#{_earl_stereotype_id(name)}"
                node.sub("stereotype", [("name", tag), ("stereotypeHREF", href)])
                for tag_name in (t for t in _EARL_TAGS.get(name, ()) if (tag, t) in set_tags):
                    tag_id = _earl_tag_id(name, tag_name)
                    node.sub(
                        "tag",
                        [("name", f"{tag}:{tag_name}"), ("tagID", tag_id), ("tagURI", f"{_EARL_PROJECT}#{tag_id}")],
                    )
                continue
            stereo_id, project, tags = _MD_STEREOTYPES[tag]
            node.sub("stereotype", [("name", tag), ("stereotypeHREF", f"{project}#{stereo_id}")])
            for tag_name, tag_id, tag_project in tags:
                uri = f"{tag_project}#{tag_id}"
                node.sub("tag", [("name", f"{tag}:{tag_name}"), ("tagID", tag_id), ("tagURI", uri)])

    # -- stereotype applications

    def apply_earl(self, element: Element, base_attr: str | None = None) -> None:
        for applied in element.applied:
            attr = base_attr or f"base_{applied.metaclass}"
            self.apps.append(_CameoApp(f"EARL:{applied.name}", attr, self.id(element), applied.tags))

    # -- elements

    def comments(self, node: XmlNode, element: Element) -> None:
        for note in element.comments:
            c = node.add(_typed("ownedComment", "uml:Comment", self.id(note), ("body", note.body)))
            assert c is not None
            c.sub("annotatedElement", [("xmi:idref", self.id(element))])

    def model_node(self, model: Model) -> XmlNode:
        node = _typed("uml:Model", "uml:Model", self.id(model), ("name", model.name))
        self.comments(node, model)
        for member in model.members:
            node.add(self.packaged(member))
        app_id = self._id(model.key + "\nProfileApplication\tSysML")
        app = node.sub("profileApplication", [("xmi:type", "uml:ProfileApplication"), ("xmi:id", app_id)])
        href = app.sub("appliedProfile", [("href", f"{SYSML_XMI}#SysML")])
        href.sub("xmi:Extension", [("extender", EXTENDER)]).sub("referenceExtension", [
            ("referentPath", "SysML"), ("referentType", "Profile"),
            ("originalID", "_11_5EAPbeta_be00301_1147434586638_637562_1900"),
        ])  # fmt: skip
        return node

    def packaged(self, element: Element) -> XmlNode:
        if isinstance(element, Package):
            node = _typed("packagedElement", "uml:Package", self.id(element), ("name", element.name))
            self.comments(node, element)
            for member in element.members:
                node.add(self.packaged(member))
            return node
        if isinstance(element, DataType):
            node = _typed("packagedElement", "uml:DataType", self.id(element), ("name", element.name))
            self.comments(node, element)
            for prop in element.fields:
                node.add(self.property(prop))
            return node
        assert isinstance(element, Block)
        return self.block(element)

    def block(self, block: Block) -> XmlNode:
        cb = block.classifier_behavior
        node = _typed(
            "packagedElement", "uml:Class", self.id(block), ("name", block.name),
            ("classifierBehavior", self.id(cb) if cb is not None else None),
            ("isActive", "true" if cb is not None else None),
        )  # fmt: skip
        self.apps.append(_CameoApp("sysml:Block", "base_Class", self.id(block)))
        self.apply_earl(block)
        self.comments(node, block)
        for rule in block.rules:
            node.add(self.constraint("ownedRule", rule))
        for behavior in block.behaviors:
            if isinstance(behavior, StateMachine):
                node.add(self.state_machine(behavior))
            else:
                assert isinstance(behavior, OpaqueBehavior)
                node.add(self.opaque_behavior(behavior))
        for prop in block.attributes:
            node.add(self.property(prop))
        for conn in block.connectors:
            node.add(self.connector(conn))
        return node

    def type_ref(self, node: XmlNode, type_: TypeRef | None) -> None:
        if isinstance(type_, Primitive):
            fragment, original = _VALUE_TYPES[type_]
            ref = node.sub("type", [("href", f"{SYSML_XMI}#{fragment}")])
            ref.sub("xmi:Extension", [("extender", EXTENDER)]).sub(
                "referenceExtension",
                [
                    ("referentPath", f"SysML::Libraries::PrimitiveValueTypes::{type_.value}"),
                    ("referentType", "DataType"),
                    ("originalID", original),
                ],
            )

    def multiplicity(self, node: XmlNode, key: str, mult: Multiplicity | None) -> None:
        if mult is None:
            return
        node.sub("lowerValue", [
            ("xmi:type", "uml:LiteralInteger"), ("xmi:id", self._id(key + "\nlowerValue")),
            ("value", None if mult.lower == 0 else str(mult.lower)),
        ])  # fmt: skip
        node.sub("upperValue", [
            ("xmi:type", "uml:LiteralUnlimitedNatural"), ("xmi:id", self._id(key + "\nupperValue")),
            ("value", "*" if mult.upper is None else str(mult.upper)),
        ])  # fmt: skip

    def property(self, prop: Property) -> XmlNode:
        local_type = None if prop.type is None or isinstance(prop.type, Primitive) else self.id(prop.type)
        node = _typed(
            "ownedAttribute",
            "uml:Port" if prop.is_port else "uml:Property",
            self.id(prop),
            ("name", prop.name),
            ("visibility", "public"),
            ("aggregation", "composite" if prop.is_port or prop.is_part or prop.is_value else None),
            ("type", local_type),
        )
        if prop.is_part:
            self.apps.append(_CameoApp(f"{MD_CUSTOM}:PartProperty", "base_Property", self.id(prop)))
        elif prop.is_value:
            self.apps.append(_CameoApp(f"{MD_CUSTOM}:ValueProperty", "base_Property", self.id(prop)))
        self.apply_earl(prop)
        self.comments(node, prop)
        self.type_ref(node, prop.type)
        self.multiplicity(node, prop.key, prop.multiplicity)
        return node

    def connector(self, conn: Connector) -> XmlNode:
        node = _typed("ownedConnector", "uml:Connector", self.id(conn), ("name", conn.name), ("visibility", "public"))
        self.apply_earl(conn)
        self.comments(node, conn)
        for end in conn.ends:
            part = end.end.part_with_port
            node.add(_typed(
                "end", "uml:ConnectorEnd", self.id(end),
                ("partWithPort", self.id(part) if part is not None else None), ("role", self.id(end.end.role)),
            ))  # fmt: skip
            if len(end.end.path) >= 2:
                path = " ".join(self.id(p) for p in end.end.path)
                self.apps.append(
                    _CameoApp("sysml:NestedConnectorEnd", "base_ConnectorEnd", self.id(end), (("propertyPath", path),))
                )
        return node

    def expression(self, tag: str, key: str, body: str, language: str) -> XmlNode:
        node = _typed(tag, "uml:OpaqueExpression", self._id(key + "\n" + tag))
        node.sub("body", text=body)
        node.sub("language", text=language)
        return node

    def constraint(self, tag: str, rule: Constraint) -> XmlNode:
        node = _typed(tag, "uml:Constraint", self.id(rule), ("name", rule.name))
        self.apply_earl(rule)
        self.comments(node, rule)
        for element in rule.constrained:
            node.sub("constrainedElement", [("xmi:idref", self.id(element))])
        if rule.body is not None:
            node.add(self.expression("specification", rule.key, rule.body, rule.language))
        return node

    def opaque_behavior(self, behavior: OpaqueBehavior) -> XmlNode:
        xmi_type = "uml:FunctionBehavior" if behavior.function else "uml:OpaqueBehavior"
        node = _typed("ownedBehavior", xmi_type, self.id(behavior), ("name", behavior.name))
        self.apply_earl(behavior)
        self.comments(node, behavior)
        for param in behavior.parameters:
            p = param.param
            local_type = None if p.type is None or isinstance(p.type, Primitive) else self.id(p.type)
            pnode = node.add(_typed(
                "ownedParameter", "uml:Parameter", self.id(param), ("name", p.name), ("visibility", "public"),
                ("direction", None if p.direction == "in" else p.direction), ("type", local_type),
            ))  # fmt: skip
            assert pnode is not None
            self.type_ref(pnode, p.type)
            self.multiplicity(pnode, param.key, param.multiplicity)
        node.sub("body", text=behavior.body)
        node.sub("language", text=behavior.language)
        return node

    def state_machine(self, machine: StateMachine) -> XmlNode:
        node = _typed("ownedBehavior", "uml:StateMachine", self.id(machine), ("name", machine.name))
        self.apply_earl(machine)
        self.comments(node, machine)
        region_id = self._id(machine.region_key)
        region = node.sub("region", [("xmi:type", "uml:Region"), ("xmi:id", region_id), ("visibility", "public")])
        if machine.initial is not None:
            region.add(_typed("subvertex", "uml:Pseudostate", self.id(machine.initial), ("visibility", "public")))
        for st in machine.states:
            region.add(self.state(st))
        for tr in machine.transitions:
            region.add(self.transition(tr))
        return node

    def state(self, st: State) -> XmlNode:
        node = _typed("subvertex", "uml:State", self.id(st), ("name", st.name), ("visibility", "public"))
        self.apply_earl(st)
        self.comments(node, st)
        if st.do is not None:
            node.add(self.activity("doActivity", st.do))
        return node

    def transition(self, tr: Transition) -> XmlNode:
        node = _typed(
            "transition", "uml:Transition", self.id(tr), ("name", tr.name), ("visibility", "public"),
            ("guard", self.id(tr.guard) if tr.guard is not None else None),
            ("source", self.id(tr.source)), ("target", self.id(tr.target)),
        )  # fmt: skip
        self.apply_earl(tr)
        self.comments(node, tr)
        if tr.guard is not None:
            node.add(self.constraint("ownedRule", tr.guard))
        return node

    def activity(self, tag: str, act: Activity) -> XmlNode:
        node = _typed(tag, "uml:Activity", self.id(act), ("name", act.name))
        self.apply_earl(act)
        self.comments(node, act)
        for rule in act.rules:
            node.add(self.constraint("ownedRule", rule))
        for edge in act.edges:
            e = node.add(_typed(
                "edge", "uml:ControlFlow", self.id(edge), ("visibility", "public"),
                ("source", self.id(edge.source)), ("target", self.id(edge.target)),
            ))  # fmt: skip
            assert e is not None
            weight_id = self._id(edge.key + "\nweight")
            e.sub("weight", [("xmi:type", "uml:LiteralUnlimitedNatural"), ("xmi:id", weight_id), ("value", "1")])
        for act_node in act.nodes:
            # MagicDraw leaves actions and control nodes unnamed; the diagram shows the behaviour.
            node.add(_typed(
                "node", f"uml:{act_node.node_type}", self.id(act_node), ("visibility", "public"),
                ("behavior", self.id(act_node.behavior) if act_node.behavior is not None else None),
            ))  # fmt: skip
        return node
