"""The lifted model as a Promela specification (docs/verify.md, *The abstraction*).

One process per subsystem instance whose iterations can change anything: its FSM state, or
the count of values waiting in an Input Buffer that some state waits for without a timeout
(a *tracked* buffer). An iteration of a subsystem in a state is one atomic step: wait for the
state's obligatory inputs, receive them, send on every Output Buffer its behaviour's
functions write, and take one of the state's outcomes. An iteration that would change nothing
is left out (it only repeats a state already explored), so a system where no process can
move is one where every subsystem waits or has nothing left to do: a watchdog process asserts
then that nobody waits for an obligatory input.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from earl_m2t.model.directives import LtlProperty
from earl_m2t.model.elements import Buffer, EarlModel, State, Subsystem
from earl_m2t.verify.ltl import PredicateAtom, StateAtom, Token
from earl_m2t.verify.ltl import tokens as ltl_tokens
from earl_m2t.verify.outcomes import Outcome, StateOutcomes, state_outcomes

OUTCOME_MARK = "EARL"  # the printf tag of a taken outcome, read back from SPIN's replay


@dataclass(frozen=True, slots=True)
class TrackedBuffer:
    buffer: Buffer
    variable: str
    capacity: int


@dataclass(frozen=True, slots=True)
class Step:
    """One generated outcome: which process, from which state, and what it decided."""

    subsystem: Subsystem
    state: State
    outcome: Outcome
    line: int  # the line of its printf in the specification


@dataclass(frozen=True, slots=True)
class ObservedPredicate:
    """A primitive predicate an LTL property reads: a global holding its latest value."""

    subsystem: str  # path
    predicate: str
    variable: str


@dataclass
class ProcessInfo:
    subsystem: Subsystem
    variable: str  # the global holding its state number
    states: tuple[State, ...]
    outcomes: tuple[StateOutcomes, ...]
    observed: tuple[ObservedPredicate, ...] = ()  # in the order of Outcome.observed


@dataclass
class Specification:
    text: str
    processes: list[ProcessInfo] = field(default_factory=list)
    steps: list[Step] = field(default_factory=list)
    tracked: list[TrackedBuffer] = field(default_factory=list)
    waits: bool = False  # some state waits for obligatory inputs without a timeout
    skipped: list[tuple[Subsystem, str]] = field(default_factory=list)  # left out, and why
    # left out because no iteration changes anything: they stay in their initial state
    static: list[ProcessInfo] = field(default_factory=list)
    formulas: dict[str, str] = field(default_factory=dict)  # property name -> its Promela formula

    def state_variable(self, subsystem_path: str) -> ProcessInfo | None:
        return next((p for p in self.processes if p.subsystem.path == subsystem_path), None)


def waits_forever(subsystem: Subsystem, state: State) -> tuple[Buffer, ...]:
    """The obligatory inputs an iteration in ``state`` may wait for without end."""
    activation = state.activation
    if not activation.group or (activation.first_timeout is not None and activation.next_timeout is not None):
        return ()
    group = next((g for g in subsystem.buffer_groups if g.name == activation.group), None)
    if group is None:
        return ()
    return tuple(b for name in group.obligatory for b in subsystem.inputs if name in (b.name, b.template))


def translate(model: EarlModel, properties: tuple[LtlProperty, ...] = ()) -> Specification:
    """The Promela text of ``model`` with the never claims of ``properties``; a primitive
    predicate they read gets a global set by every iteration of its subsystem (only then, so
    that models checked without such properties keep their state space)."""
    spec = Specification("")
    tokens = {prop.name: ltl_tokens(prop, model) for prop in properties}
    watched: dict[tuple[str, str], ObservedPredicate] = {}
    for written in tokens.values():
        for token in written:
            if isinstance(token, PredicateAtom) and (token.subsystem, token.predicate) not in watched:
                watched[(token.subsystem, token.predicate)] = ObservedPredicate(
                    token.subsystem, token.predicate, f"pp{len(watched)}")
    tracked: dict[str, TrackedBuffer] = {}
    for sub in model.subsystems:
        for state in sub.fsm.states if sub.fsm else ():
            for buf in waits_forever(sub, state):
                if buf.path not in tracked:
                    capacity = max(buf.queue_size, 1) if buf.receive == "queue" else 1
                    tracked[buf.path] = TrackedBuffer(buf, f"q{len(tracked)}", capacity)
                spec.waits = True
    spec.tracked = list(tracked.values())
    senders = _senders(model)
    lines: list[str] = [f"/* {model.name}: earl-m2t verify, see docs/verify.md */"]
    for t in spec.tracked:
        lines.append(f"byte {t.variable} = 0; /* {t.buffer.path}, up to {t.capacity} */")
    for seen in watched.values():
        lines.append(f"bool {seen.variable} = false; /* {seen.subsystem} {seen.predicate} in its latest iteration */")
    bodies: list[list[str | tuple[str, Step]]] = []
    for sub in model.subsystems:
        fsm = sub.fsm
        if fsm is None or fsm.initial is None:
            spec.skipped.append((sub, "no FSM with one initial state"))
            continue
        observed = tuple(w for w in watched.values() if w.subsystem == sub.path)
        outcomes = state_outcomes(model, sub, tuple(w.predicate for w in observed))
        info = ProcessInfo(sub, f"st{len(spec.processes)}", fsm.states, outcomes, observed)
        body = _process_body(info, tracked, senders, len(spec.processes))
        if not any(isinstance(item, tuple) for item in body):
            spec.skipped.append((sub, "its iterations change nothing the properties observe"))
            spec.static.append(info)
            continue
        spec.processes.append(info)
        bodies.append(body)
        names = " ".join(f"{i}={s.name}" for i, s in enumerate(fsm.states))
        initial = next(i for i, s in enumerate(fsm.states) if s.name == fsm.initial)
        # written and read by its own process only: `local` lets SPIN's partial order reduction
        # use that; a never claim or the watchdog reads the states, so not with those
        prefix = "" if properties or spec.waits else "local "
        lines.append(f"{prefix}byte {info.variable} = {initial}; /* {sub.path}: {names} */")
    for info, body in zip(spec.processes, bodies):
        lines.append(f"active proctype subsystem{info.variable[2:]}() {{ /* {info.subsystem.path} */")
        lines.append("end:")
        lines.append("  do")
        for item in body:
            if isinstance(item, tuple):
                text, step = item
                lines.append(text)
                spec.steps.append(Step(step.subsystem, step.state, step.outcome, len(lines)))
            else:
                lines.append(item)
        lines.append("  od")
        lines.append("}")
    if spec.waits:
        lines.extend(_watchdog(spec, tracked))
    for name, written in tokens.items():
        spec.formulas[name] = _formula(spec, written, watched)
        lines.append(f"ltl {name} {{ {spec.formulas[name]} }}")
    spec.text = "\n".join(lines) + "\n"
    return spec


def _formula(spec: Specification, tokens: tuple[Token, ...],
             watched: dict[tuple[str, str], ObservedPredicate]) -> str:
    out: list[str] = []
    for token in tokens:
        if isinstance(token, PredicateAtom):
            out.append(watched[(token.subsystem, token.predicate)].variable)
        elif isinstance(token, StateAtom):
            info = spec.state_variable(token.subsystem)
            if info is not None:
                out.append(f"({info.variable} == {[s.name for s in info.states].index(token.state)})")
            else:  # a subsystem left out never leaves its initial state
                fsm = next(sub.fsm for sub, _ in spec.skipped if sub.path == token.subsystem)
                out.append("true" if fsm is not None and fsm.initial == token.state else "false")
        else:
            out.append(token)
    return " ".join(out)


def _senders(model: EarlModel) -> dict[str, list[str]]:
    """Output Buffer path → the Input Buffer paths its links deliver to."""
    result: dict[str, list[str]] = {}
    for link in model.links:
        if link.source and link.target:
            result.setdefault(link.source, []).append(link.target)
    return result


def _process_body(info: ProcessInfo, tracked: dict[str, TrackedBuffer], senders: dict[str, list[str]],
                  number: int) -> list[str | tuple[str, Step]]:
    sub = info.subsystem
    body: list[str | tuple[str, Step]] = []
    index = {s.name: i for i, s in enumerate(info.states)}
    for i, (state, so) in enumerate(zip(info.states, info.outcomes)):
        waits = [tracked[b.path] for b in waits_forever(sub, state)]
        received = _received(sub, state, tracked)
        sent = _sent(sub, state, tracked, senders)
        ready = "".join(f" && {t.variable} > 0" for t in waits)
        changes = " || ".join([f"{t.variable} > 0" for t in received] + [f"{t.variable} < {t.capacity}" for t in sent])
        actions = [f"{t.variable} = ({t.variable} > 0 -> {t.variable} - 1 : 0)" if t.capacity > 1
                   else f"{t.variable} = 0" for t in received]
        actions += [f"{t.variable} = ({t.variable} < {t.capacity} -> {t.variable} + 1 : {t.capacity})" for t in sent]
        for k, outcome in enumerate(so.outcomes):
            target = index.get(outcome.transition.target, i) if outcome.transition else i
            moves = target != i
            seen = [(w.variable, "true" if value else "false") for w, value in zip(info.observed, outcome.observed)]
            records = [f"{variable} = {value}" for variable, value in seen]
            differs = [f"{variable} != {value}" for variable, value in seen]
            if not moves and not changes and not differs:
                continue
            either = " || ".join(c for c in (changes, *differs) if c)
            guard = f"{info.variable} == {i}{ready}" + ("" if moves else f" && ({either})")
            effect = "; ".join([*actions, *records, f"{info.variable} = {target}"])
            label = outcome.transition.name if outcome.transition else ("ended, stays" if outcome.ended else "goes on")
            body.append(f"  :: atomic {{ {guard} -> {effect}; /* {state.name}: {label} */")
            body.append((f'       printf("{OUTCOME_MARK} {number} {i} {k}\\n") }}', Step(sub, state, outcome, 0)))
    return body


def _received(sub: Subsystem, state: State, tracked: dict[str, TrackedBuffer]) -> list[TrackedBuffer]:
    """Tracked inputs an iteration in ``state`` receives: those of its buffer group."""
    group = next((g for g in sub.buffer_groups if g.name == state.activation.group), None)
    if group is None:
        return [tracked[b.path] for b in sub.inputs if b.path in tracked]
    names = set(group.obligatory) | set(group.optional)
    return [tracked[b.path] for b in sub.inputs if b.path in tracked and (b.name in names or b.template in names)]


def _sent(sub: Subsystem, state: State, tracked: dict[str, TrackedBuffer],
          senders: dict[str, list[str]]) -> list[TrackedBuffer]:
    bb = sub.behaviour(state.behaviours[0]) if len(state.behaviours) == 1 else None
    if bb is None:
        return []
    written = {path for name in bb.functions if (pf := sub.function(name)) for path in pf.writes}
    targets = {t for path in written for t in senders.get(path, ())}
    return [t for path, t in tracked.items() if path in targets]


def _watchdog(spec: Specification, tracked: dict[str, TrackedBuffer]) -> list[str]:
    waiting = []
    for info in spec.processes:
        for i, state in enumerate(info.states):
            waits = [tracked[b.path] for b in waits_forever(info.subsystem, state)]
            if waits:
                ready = " && ".join(f"{t.variable} > 0" for t in waits)
                waiting.append(f"({info.variable} == {i} && !({ready}))")
    condition = " || ".join(waiting) or "false"
    return [
        "active proctype watchdog() {",
        "end:",
        "  do",
        f"  :: timeout -> assert(!({condition}))",
        "  od",
        "}",
    ]
