"""The lifted model as a Promela specification (docs/verify.md, *The abstraction*).

One process per subsystem instance whose iterations can change anything: its FSM state, or
the count of values waiting in an Input Buffer that some state waits for without a timeout
(a *tracked* buffer). An iteration of a subsystem in a state is one atomic step: wait for the
state's obligatory inputs, receive them, send on every Output Buffer its behaviour's
functions write, and take one of the state's outcomes. An iteration that would change nothing
is left out (it only repeats a state already explored), so a system where no process can
move is one where every subsystem waits or has nothing left to do: a watchdog process asserts
then that nobody waits for an obligatory input. A model with configurations adds the switch
between them (switching.py, switch_process.py): iterations of a variable agent's subsystems
while it runs, sends on a variable link while it is open, the coordinator's transitions to
another configuration as the beginning of a switch.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from earl_m2t.analysis.receiving import state_inputs
from earl_m2t.analysis.switching import fed_inputs, leaving_agents
from earl_m2t.model.directives import LtlProperty
from earl_m2t.model.elements import Buffer, EarlModel, Link, State, Subsystem
from earl_m2t.model.variability import link_agents
from earl_m2t.predicate import BuiltInPredicate
from earl_m2t.verify.counters import CountedLink, TrackedBuffer
from earl_m2t.verify.ltl import AgentAtom, ConfigAtom, PredicateAtom, StateAtom, SwitchingAtom, Token
from earl_m2t.verify.ltl import tokens as ltl_tokens
from earl_m2t.verify.outcomes import Outcome, StateOutcomes, state_outcomes
from earl_m2t.verify.promela_text import promela_comment
from earl_m2t.verify.switch_process import ProcessState, SwitchView, switch_process
from earl_m2t.verify.switching import DROP_CLAIM, SWITCH_MARK, Reconfiguration, claims, declarations, reconfiguration

OUTCOME_MARK = "EARL"  # the printf tag of a taken outcome, read back from SPIN's replay

__all__ = ["OUTCOME_MARK", "ProcessInfo", "Specification", "Step", "TrackedBuffer", "translate", "waits_forever"]


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
    leaving: str = ""  # the global leaving() reads, the last of Outcome.observed ("" when not read)


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
    reconfiguration: Reconfiguration | None = None  # the variable structure, None for a fixed one
    # lines that enter a state other than by a Step: the coordinator's, when a switch opens
    entries: list[tuple[int, Subsystem, State]] = field(default_factory=list)

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


def translate(model: EarlModel, properties: tuple[LtlProperty, ...] = (), claim: str = "") -> Specification:
    """The Promela text of ``model`` with the never claims of ``properties``; a primitive
    predicate they read gets a global set by every iteration of its subsystem (only then, so
    that models checked without such properties keep their state space). ``claim`` names one
    never claim of the built-in checks of a variable structure (switching.claims) to add."""
    spec = Specification("", reconfiguration=reconfiguration(model))
    rc = spec.reconfiguration
    tokens = {prop.name: ltl_tokens(prop, model) for prop in properties}
    watched: dict[tuple[str, str], ObservedPredicate] = {}
    for written in tokens.values():
        for token in written:
            if isinstance(token, PredicateAtom) and (token.subsystem, token.predicate) not in watched:
                watched[(token.subsystem, token.predicate)] = ObservedPredicate(
                    token.subsystem, token.predicate, f"pp{len(watched)}")
    tracked = _tracked(model, spec, rc, drops=claim == DROP_CLAIM)
    senders = _senders(model)
    lines: list[str] = [f"/* {promela_comment(model.name)}: earl-m2t verify, see docs/verify.md */"]
    for t in spec.tracked:
        lines.extend(t.declarations())
    for seen in watched.values():
        lines.append(f"bool {seen.variable} = false; /* {promela_comment(seen.subsystem)} "
                     f"{promela_comment(seen.predicate)} in its latest iteration */")
    if rc is not None:
        lines.extend(declarations(rc))
    bodies: list[list[str | tuple[str, Step]]] = []
    for sub in model.subsystems:
        fsm = sub.fsm
        if fsm is None or fsm.initial is None or fsm.state(fsm.initial) is None:
            spec.skipped.append((sub, "no FSM with one initial state"))
            continue
        observed = tuple(w for w in watched.values() if w.subsystem == sub.path)
        outcomes, leaving = _outcomes(model, sub, observed, rc)
        info = ProcessInfo(sub, f"st{len(spec.processes)}", fsm.states, outcomes, observed, leaving)
        body = _process_body(info, tracked, senders, len(spec.processes), rc, paused_while_switching=bool(claim))
        if not any(isinstance(item, tuple) for item in body):
            spec.skipped.append((sub, "its iterations change nothing the properties observe"))
            spec.static.append(info)
            continue
        spec.processes.append(info)
        bodies.append(body)
        names = " ".join(f"{i}={s.name}" for i, s in enumerate(fsm.states))
        initial = next(i for i, s in enumerate(fsm.states) if s.name == fsm.initial)
        # written and read by its own process only: `local` lets SPIN's partial order reduction
        # use that; a never claim, the watchdog or a switch reads the states, so not with those
        prefix = "" if properties or spec.waits or rc is not None else "local "
        lines.append(f"{prefix}byte {info.variable} = {initial}; "
                     f"/* {promela_comment(sub.path)}: {promela_comment(names)} */")
    _write_processes(spec, bodies, lines)
    if not spec.processes and rc is None:  # SPIN needs a process: every subsystem stays where it starts
        lines.append("init { skip } /* no subsystem's iteration changes what the checks observe */")
    if rc is not None:
        for item in switch_process(rc, _switch_view(model, spec)):
            lines.append(item[0] if isinstance(item, tuple) else item)
            if isinstance(item, tuple):
                spec.entries.append((len(lines), rc.coordinator, item[1]))
    if spec.waits and not claim:  # a built-in check's search stops at its claim alone
        lines.extend(_watchdog(spec, tracked))
    for name, written in tokens.items():
        spec.formulas[name] = _formula(spec, written, watched)
        lines.append(f"ltl {name} {{ {spec.formulas[name]} }}")
    if rc is not None and claim:
        lines.extend(text for text in claims(rc) if text.startswith(f"ltl {claim} "))
    spec.text = "\n".join(lines) + "\n"
    return spec


def _tracked(model: EarlModel, spec: Specification, rc: Reconfiguration | None,
             drops: bool = False) -> dict[str, TrackedBuffer]:
    """The Input Buffers some state waits for without a timeout, and in a variable structure
    every linked input of an agent a switch can remove (what a switch must drain), counted (per
    link when a variable link delivers to them). With ``drops`` (the search of V009) also every
    input a variable link from a variable agent delivers to (what a leaving agent sends while it
    drains), and a send a closed link drops sets ``dropped``. The other searches leave both out:
    an iteration whose send goes nowhere still changes nothing there, and a receiver that stays
    (a robot queueing its task commands) adds no counter to their state space. In V009's search
    an input tracked for that alone counts one value at most: whether a send is dropped does not
    depend on how many wait."""
    tracked: dict[str, TrackedBuffer] = {}
    counters = 0

    def track(buf: Buffer, counted: bool = True) -> None:
        nonlocal counters
        if buf.path in tracked:
            return
        capacity = max(buf.queue_size, 1) if buf.receive == "queue" and counted else 1
        incoming = [link for link in model.links if link.target == buf.path] if rc else []
        if rc is not None and any(link.path in rc.varying for link in incoming):
            links = tuple(CountedLink(link, f"q{counters + n}", rc.link_open(link),
                                      rc.link_drops(link) if drops else None)
                          for n, link in enumerate(incoming))
            tracked[buf.path] = TrackedBuffer(buf, links[0].variable, capacity, links)
            counters += len(links)
        else:
            tracked[buf.path] = TrackedBuffer(buf, f"q{counters}", capacity)
            counters += 1

    for sub in model.subsystems:
        for state in sub.fsm.states if sub.fsm else ():
            for buf in waits_forever(sub, state):
                track(buf)
                spec.waits = True
    if rc is not None:
        fed = fed_inputs(model)
        for agent in leaving_agents(rc.system):
            for buf in (b for sub in agent.subsystems for b in sub.inputs if b.path in fed):
                track(buf)
        for buf in _from_variable_agents(model, rc) if drops else ():
            track(buf, counted=False)
    spec.tracked = list(tracked.values())
    return tracked


def _from_variable_agents(model: EarlModel, rc: Reconfiguration) -> list[Buffer]:
    """The Input Buffers a variable link whose sender is a variable agent delivers to."""
    targets = [link.target for link in model.links if link.path in rc.varying
               and rc.agent(link_agents(rc.system, link)[0]) is not None]
    return [buf for path in targets if (buf := model.buffer(path)) is not None]


def _outcomes(model: EarlModel, sub: Subsystem, observed: tuple[ObservedPredicate, ...],
              rc: Reconfiguration | None) -> tuple[tuple[StateOutcomes, ...], str]:
    """The outcomes of each state of ``sub``, and the global its ``leaving()`` reads: in a
    variable structure they are told apart by the value of ``leaving()``, which is false in an
    agent that is always present."""
    names = tuple(w.predicate for w in observed)
    outcomes = state_outcomes(model, sub, names)
    label = f"{BuiltInPredicate.LEAVING}()"
    if rc is None or not any(term == label for so in outcomes for o in so.outcomes for term, _ in o.witness):
        return outcomes, ""
    split = state_outcomes(model, sub, names, (BuiltInPredicate.LEAVING,))
    agent = rc.agent(sub.agent)
    if agent is not None:
        return split, agent.leaving
    return tuple(replace(so, outcomes=tuple(o for o in so.outcomes if not o.observed[-1])) for so in split), ""


def _write_processes(spec: Specification, bodies: list[list[str | tuple[str, Step]]], lines: list[str]) -> None:
    for info, body in zip(spec.processes, bodies):
        lines.append(f"active proctype subsystem{info.variable[2:]}() {{ /* {promela_comment(info.subsystem.path)} */")
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


def _switch_view(model: EarlModel, spec: Specification) -> SwitchView:
    """What the switch process reads of the subsystem processes and the counters."""
    processes = {p.subsystem.path: ProcessState(p.subsystem, p.variable, p.states) for p in spec.processes}
    statics = {p.subsystem.path: ProcessState(p.subsystem, "", p.states) for p in spec.static}
    inputs: dict[str, list[tuple[str, str]]] = {}
    for t in spec.tracked:
        owner = model.subsystem_of(t.buffer.path)
        inputs.setdefault(owner.agent if owner else "", []).extend(t.counters)
    return SwitchView({**statics, **processes}, inputs)


def _formula(spec: Specification, tokens: tuple[Token, ...],
             watched: dict[tuple[str, str], ObservedPredicate]) -> str:
    out: list[str] = []
    for token in tokens:
        if isinstance(token, PredicateAtom):
            out.append(watched[(token.subsystem, token.predicate)].variable)
        elif isinstance(token, (ConfigAtom, AgentAtom, SwitchingAtom)):
            out.append(_structure_atom(spec.reconfiguration, token))
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


def _structure_atom(rc: Reconfiguration | None, token: ConfigAtom | AgentAtom | SwitchingAtom) -> str:
    """An atom of the variable structure; in a fixed one the only configuration never holds,
    nothing switches and every agent runs."""
    if isinstance(token, SwitchingAtom):
        return "switching" if rc is not None else "false"
    if isinstance(token, ConfigAtom):
        number = rc.configuration(token.configuration) if rc is not None else None
        return f"(cfg == {number})" if number is not None else "false"
    agent = rc.agent(token.agent) if rc is not None else None
    return agent.active if agent is not None else "true"


def _senders(model: EarlModel) -> dict[str, list[Link]]:
    """Output Buffer path → the links from it to an Input Buffer."""
    result: dict[str, list[Link]] = {}
    for link in model.links:
        if link.source and link.target:
            result.setdefault(link.source, []).append(link)
    return result


def _process_body(info: ProcessInfo, tracked: dict[str, TrackedBuffer], senders: dict[str, list[Link]],
                  number: int, rc: Reconfiguration | None = None,
                  paused_while_switching: bool = False) -> list[str | tuple[str, Step]]:
    """The steps of a subsystem's process. With ``paused_while_switching`` (the searches of the
    switch checks) only the leaving agents iterate while a switch is pending: nothing the others
    do reaches a leaving agent (its links are closed at their senders), and an agent that stays
    and can always iterate would otherwise keep Promela's ``timeout``, the switch timeout, from
    ever firing, which would hide a leaving agent stuck with values it never takes."""
    sub = info.subsystem
    body: list[str | tuple[str, Step]] = []
    index = {s.name: i for i, s in enumerate(info.states)}
    agent = rc.agent(sub.agent) if rc is not None else None
    coordinating = rc is not None and rc.coordinator is sub
    # a variable agent's subsystem iterates while it runs; the coordinator not during a switch
    before = (f"{agent.active} && " if agent else "") + ("!switching && " if coordinating else "")
    if rc is not None and paused_while_switching and not coordinating:
        before += f"(!switching || {agent.leaving}) && " if agent else "!switching && "
    for i, (state, so) in enumerate(zip(info.states, info.outcomes)):
        waits = [tracked[b.path] for b in waits_forever(sub, state)]
        received = _received(sub, state, tracked)
        sent = _sent(sub, state, tracked, senders)
        ready = "".join(f" && {t.count} > 0" for t in waits)
        changes = " || ".join([f"{t.count} > 0" for t in received] + [t.can_send(links) for t, links in sent])
        actions = [t.receive() for t in received] + [a for t, links in sent for a in t.send(links)]
        for k, outcome in enumerate(so.outcomes):
            target = index.get(outcome.transition.target, i) if outcome.transition else i
            moves = target != i
            seen = [(w.variable, "true" if value else "false") for w, value in zip(info.observed, outcome.observed)]
            records = [f"{variable} = {value}" for variable, value in seen]
            differs = [f"{variable} != {value}" for variable, value in seen]
            if not moves and not changes and not differs:
                continue
            either = " || ".join(c for c in (changes, *differs) if c)
            leaving = "" if not info.leaving else f" && {'' if outcome.observed[-1] else '!'}{info.leaving}"
            guard = f"{before}{info.variable} == {i}{ready}{leaving}" + ("" if moves else f" && ({either})")
            effect = "; ".join([*actions, *records, f"{info.variable} = {target}"])
            label = outcome.transition.name if outcome.transition else ("ended, stays" if outcome.ended else "goes on")
            mark = f'printf("{OUTCOME_MARK} {number} {i} {k}\\n")'
            switch = rc.configuration(info.states[target].configuration) if rc and coordinating and moves else None
            if rc is not None and switch is not None:  # entered in the configuration it names, else a switch begins
                begin = "; ".join([*actions, *records, rc.begin(switch, target)])
                body.append(f"  :: atomic {{ {guard} && cfg != {switch} -> {begin}; "
                            f"/* {promela_comment(state.name)}: {promela_comment(label)}, a switch begins */")
                # not a Step: the state is entered when the switch opens (Specification.entries)
                body.append(f'       {mark}; printf("{SWITCH_MARK} begin {switch}\\n") }}')
                guard += f" && cfg == {switch}"
            body.append(f"  :: atomic {{ {guard} -> {effect}; "
                        f"/* {promela_comment(state.name)}: {promela_comment(label)} */")
            body.append((f"       {mark} }}", Step(sub, state, outcome, 0)))
    return body


def _received(sub: Subsystem, state: State, tracked: dict[str, TrackedBuffer]) -> list[TrackedBuffer]:
    """Tracked inputs an iteration in ``state`` receives (earl_m2t.analysis.receiving)."""
    return [tracked[b.path] for b in state_inputs(sub, state) if b.path in tracked]


def _sent(sub: Subsystem, state: State, tracked: dict[str, TrackedBuffer],
          senders: dict[str, list[Link]]) -> list[tuple[TrackedBuffer, frozenset[str]]]:
    """Tracked inputs an iteration in ``state`` sends to, with the links it sends on."""
    bb = sub.behaviour(state.behaviours[0]) if len(state.behaviours) == 1 else None
    if bb is None:
        return []
    written = {path for name in bb.functions if (pf := sub.function(name)) for path in pf.writes}
    links = [link for path in written for link in senders.get(path, ())]
    return [(t, frozenset(link.path for link in links if link.target == path)) for path, t in tracked.items()
            if any(link.target == path for link in links)]


def _watchdog(spec: Specification, tracked: dict[str, TrackedBuffer]) -> list[str]:
    rc = spec.reconfiguration
    waiting = []
    for info in spec.processes:
        for i, state in enumerate(info.states):
            waits = [tracked[b.path] for b in waits_forever(info.subsystem, state)]
            if waits:
                ready = " && ".join(f"{t.count} > 0" for t in waits)
                agent = rc.agent(info.subsystem.agent) if rc is not None else None
                running = f"{agent.active} && " if agent is not None else ""
                waiting.append(f"({running}{info.variable} == {i} && !({ready}))")
    condition = " || ".join(waiting) or "false"
    if rc is not None:  # a pending switch ends, by its timeout if need be
        condition = f"!switching && ({condition})"
    return [
        "active proctype watchdog() {",
        "end:",
        "  do",
        f"  :: timeout -> assert(!({condition}))",
        "  od",
        "}",
    ]
