"""What an iteration takes from its Input Buffers: the one meaning of "a state receives an input"
that the generated runtimes implement (tf.pf.ib.receive()), that the variable-structure rules
count on and that verify's Promela model follows.

An iteration in a state runs the state's basic behaviour, and receives the inputs that
behaviour uses: those its pfs read, and those its terminal and error conditions and the guards
of the transitions leaving its states read, directly or through the primitive predicates they
call (a predicate written in user code may read any input). It also takes the obligatory inputs
of those states' buffer groups: a state that waits for a value takes it, or the value it waited
for would make it ready again at once. An optional input of a group that the behaviour never
reads is not taken: it stays in its buffer (rule X008 counts on that for a leaving agent).

Functions of the lifted model only: the conditions are the lift's parsed and expanded ones.
"""

from __future__ import annotations

from collections.abc import Iterable

from earl_m2t.model.conditions import Condition
from earl_m2t.model.elements import BasicBehaviour, Buffer, State, Subsystem
from earl_m2t.predicate import Expr, FieldRef, NewData, PredicateRef, walk


def behaviour_conditions(sub: Subsystem, behaviour: BasicBehaviour) -> tuple[Condition, ...]:
    """The conditions an iteration running ``behaviour`` evaluates: its tc and ec, and the guard
    of every transition leaving a state whose behaviour it is."""
    own = tuple(c for c in (behaviour.tc, behaviour.ec) if c is not None)
    fsm = sub.fsm
    if fsm is None:
        return own
    sources = {s.name for s in fsm.states if s.behaviours[:1] == (behaviour.name,)}
    guards = tuple(t.condition for t in sorted(fsm.transitions, key=lambda t: t.order)
                   if t.source in sources and t.condition is not None)
    return own + guards


def behaviour_inputs(sub: Subsystem, behaviour: BasicBehaviour) -> tuple[Buffer, ...]:
    """The Input Buffers an iteration running ``behaviour`` receives, in the subsystem's order."""
    read = {path for name in behaviour.functions if (pf := sub.function(name)) is not None for path in pf.reads}
    names = _names_read(sub, (c.expanded for c in behaviour_conditions(sub, behaviour)))
    names |= _awaited(sub, behaviour)
    return tuple(b for b in sub.inputs if b.path in read or b.name in names or b.template in names)


def state_inputs(sub: Subsystem, state: State) -> tuple[Buffer, ...]:
    """The Input Buffers an iteration in ``state`` receives: those of its basic behaviour (none
    when the state does not name exactly one that the subsystem has: rule B002)."""
    behaviour = sub.behaviour(state.behaviours[0]) if len(state.behaviours) == 1 else None
    return behaviour_inputs(sub, behaviour) if behaviour is not None else ()


def receives(sub: Subsystem, state: State, buffer: Buffer) -> bool:
    """True when an iteration in ``state`` takes values from the Input Buffer ``buffer``."""
    return any(b.path == buffer.path for b in state_inputs(sub, state))


def _awaited(sub: Subsystem, behaviour: BasicBehaviour) -> set[str]:
    """The names the buffer groups of the states running ``behaviour`` make obligatory."""
    fsm = sub.fsm
    groups = {s.activation.group for s in (fsm.states if fsm is not None else ())
              if s.behaviours[:1] == (behaviour.name,) and s.activation.group}
    return {name for g in sub.buffer_groups if g.name in groups for name in g.obligatory}


def _names_read(sub: Subsystem, expressions: Iterable[Expr | None]) -> set[str]:
    """The buffer names the expressions read, through the primitive predicates they call."""
    names: set[str] = set()
    seen: set[str] = set()
    pending = [e for e in expressions if e is not None]
    while pending:
        for node in walk(pending.pop()):
            if isinstance(node, FieldRef):
                names.add(node.head)
            elif isinstance(node, NewData):
                names.add(node.ref.head)
            elif isinstance(node, PredicateRef):
                resolved = sub.scope.predicate(node.name) if sub.scope is not None else None
                if resolved is None:
                    names.add(node.name)  # a buffer used as a truth value
                elif resolved not in seen:
                    seen.add(resolved)
                    pp = sub.predicate(resolved)
                    if pp is not None and pp.fun is None:
                        names |= {b.name for b in sub.inputs}  # user code may read any input
                    elif pp is not None and pp.fun is not None and pp.fun.expanded is not None:
                        pending.append(pp.fun.expanded)
    return names


__all__ = ["behaviour_conditions", "behaviour_inputs", "receives", "state_inputs"]
