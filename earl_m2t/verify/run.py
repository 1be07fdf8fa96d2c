"""``verify``: translate, run SPIN within the bounds, and map what it found back to the model."""

from __future__ import annotations

import re
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from earl_m2t.model.directives import LtlProperty
from earl_m2t.model.elements import EarlModel, Subsystem
from earl_m2t.model.location import Location
from earl_m2t.verify import spin
from earl_m2t.verify.promela import OUTCOME_MARK, Specification, Step, translate
from earl_m2t.verify.switch_trace import SwitchEvent, SwitchReader
from earl_m2t.verify.switching import (
    DROP_CLAIM,
    EXCLUSIVE_CLAIM,
    LOSS_CLAIM,
    SWITCH_MARK,
    TIMEOUT_CLAIM,
    Reconfiguration,
    exclusive_pairs,
)

MEMORY_MB = 1024  # pan's state storage (-DMEMLIM)
UNREACHABLE, DEADLOCK, NEVER_ENDS, NO_WAY_OUT, LTL_VIOLATED = "V001", "V002", "V003", "V004", "V005"
SWITCH_LOSES, SWITCH_TIMES_OUT, SWITCH_OVERLAPS, SWITCH_DROPS = "V006", "V007", "V008", "V009"
_MARKS = re.compile(rf"{OUTCOME_MARK} (\d+) (\d+) (\d+)|{SWITCH_MARK} (\w+)([^\n]*)")


# the checks each search decides: every one runs unless VerifyOptions.checks leaves all its codes out
REACHABILITY_CHECKS = frozenset({UNREACHABLE, NEVER_ENDS, NO_WAY_OUT})
CHECK_CODES = (UNREACHABLE, DEADLOCK, NEVER_ENDS, NO_WAY_OUT, LTL_VIOLATED, SWITCH_LOSES, SWITCH_TIMES_OUT,
               SWITCH_OVERLAPS, SWITCH_DROPS)


@dataclass(frozen=True, slots=True)
class VerifyOptions:
    depth: int = 100_000
    timeout: float = 120.0
    properties: tuple[LtlProperty, ...] = ()
    checks: frozenset[str] = frozenset()  # the codes to decide (CHECK_CODES); empty: all of them

    def runs(self, *codes: str) -> bool:
        """Whether a search deciding ``codes`` is to run."""
        return not self.checks or any(code in self.checks for code in codes)


@dataclass(frozen=True, slots=True)
class TraceStep:
    number: int
    subsystem: str
    source: str
    target: str
    why: str  # the transition taken, or what the behaviour did
    values: tuple[tuple[str, bool], ...]


@dataclass(frozen=True, slots=True)
class Finding:
    code: str
    message: str
    element: str
    location: Location
    trace: tuple[TraceStep, ...] = ()


@dataclass
class VerifyResult:
    findings: list[Finding] = field(default_factory=list)
    proven: list[str] = field(default_factory=list)  # what holds, one line each
    not_proven: list[str] = field(default_factory=list)  # what the bounds left open
    states: int = 0
    transitions: int = 0
    depth: int = 0
    processes: list[str] = field(default_factory=list)
    left_out: list[str] = field(default_factory=list)


def verify_model(model: EarlModel, options: VerifyOptions) -> VerifyResult:
    started = time.monotonic()
    result = VerifyResult()

    def left() -> float:
        return options.timeout - (time.monotonic() - started)

    spec = translate(model)
    result.processes = [p.subsystem.path for p in spec.processes]
    result.left_out = [f"{sub.path}: {why}" for sub, why in spec.skipped]
    with tempfile.TemporaryDirectory(prefix="earl-verify-") as name:
        folder = Path(name)
        try:
            if options.runs(*REACHABILITY_CHECKS):
                _reachability(spec, folder, options, left, result)
            if options.runs(DEADLOCK):
                _deadlock(spec, folder, options, left, result)
            if spec.reconfiguration is not None:
                _switches(model, spec.reconfiguration, folder, options, left, result)
            for prop in options.properties if options.runs(LTL_VIOLATED) else ():
                _ltl(model, prop, folder, options, left, result)
        except spin.OutOfTime as exc:
            result.not_proven.append(f"the time limit of {options.timeout:g} s ran out in {exc}")
    return result


def _pan_flags(options: VerifyOptions) -> tuple[str, ...]:
    return (f"-m{options.depth}", "-w22")


def _account(run: spin.PanRun, result: VerifyResult) -> None:
    result.states = max(result.states, run.states)
    result.transitions = max(result.transitions, run.transitions)
    result.depth = max(result.depth, run.depth)


def _bounded(run: spin.PanRun, options: VerifyOptions) -> str:
    if run.interrupted:
        bound = f"the time limit of {options.timeout:g} s"
    elif "out of memory" in run.output.lower():
        bound = f"the memory limit of {MEMORY_MB} MB"
    else:
        bound = f"the depth limit {options.depth}"
    return f"the search stopped at {bound} after {run.states} states, {run.transitions} transitions"


def _reachability(spec: Specification, folder: Path, options: VerifyOptions, left: Callable[[], float],
                  result: VerifyResult) -> None:
    binary = spin.build(folder, spec.text, "pan_reach", ("-DSAFETY", f"-DMEMLIM={MEMORY_MB}"), left())
    run = spin.search(binary, ("-A", "-E", *_pan_flags(options)), left())
    _account(run, result)
    if not run.complete:
        result.not_proven.append("reachability: " + _bounded(run, options))
        return
    taken = [step for step in spec.steps if step.line not in run.unreached]
    for info in [*spec.processes, *spec.static]:
        sub, fsm = info.subsystem, info.subsystem.fsm
        assert fsm is not None
        entered = {fsm.initial} | {s.outcome.transition.target for s in taken
                                   if s.subsystem is sub and s.outcome.transition is not None}
        entered |= {state.name for line, by, state in spec.entries if by is sub and line not in run.unreached}
        for state, outcomes in zip(info.states, info.outcomes):
            if state.name not in entered:
                result.findings.append(Finding(
                    UNREACHABLE, f"state {state.path} is never entered: no run of the system reaches it",
                    state.path, state.location))
                continue
            bb = sub.behaviour(state.behaviours[0]) if len(state.behaviours) == 1 else None
            ends = [o for o in outcomes.outcomes if o.ended]
            if not ends and not outcomes.never_ends_by_design and outcomes.exact and bb is not None:
                result.findings.append(Finding(
                    NEVER_ENDS, f"behaviour {bb.path} of state {state.path} never ends: its tc and ec cannot "
                    "become true with the model's exclusions, yet they are not written FALSE",
                    bb.path, bb.tc.location if bb.tc is not None else bb.location))
            elif ends and outcomes.exact and all(o.transition is None or o.transition.target == state.name
                                                 for o in ends):
                result.findings.append(Finding(
                    NO_WAY_OUT, f"state {state.path} has no way out: its behaviour {bb.path if bb else ''} ends, "
                    "but no transition to another state can be taken when it does",
                    state.path, state.location))
    result.proven.append(f"which FSM states are reachable, in {len(spec.processes)} subsystem process(es) "
                         "(exhaustive search)")


def _deadlock(spec: Specification, folder: Path, options: VerifyOptions, left: Callable[[], float],
              result: VerifyResult) -> None:
    if not spec.waits:
        result.proven.append("no deadlock: no state waits for an obligatory input without a timeout")
        return
    binary = spin.build(folder, spec.text, "pan_safety", ("-DSAFETY", f"-DMEMLIM={MEMORY_MB}"), left())
    run = spin.search(binary, (*_pan_flags(options), "-E"), left())
    _account(run, result)
    if run.errors:
        trace = _trace(spec, spin.replay(folder, left()))
        stuck = _waiting_at_end(spec, trace)
        first = stuck[0][0] if stuck else spec.processes[0].subsystem
        waiting = "; ".join(text for _, text in stuck)
        result.findings.append(Finding(
            DEADLOCK, f"the system can deadlock: {waiting}, and no subsystem can send any more",
            first.path, first.location, trace))
    elif not run.complete:
        result.not_proven.append("deadlock freedom: " + _bounded(run, options))
    else:
        result.proven.append("no deadlock: no reachable state has a subsystem waiting for an input nobody sends")


_SWITCH_CHECKS = ((SWITCH_LOSES, LOSS_CLAIM, "no switch loses values"),
                  (SWITCH_TIMES_OUT, TIMEOUT_CLAIM, "every switch can end without its timeout"),
                  (SWITCH_OVERLAPS, EXCLUSIVE_CLAIM, "exclusivity"),
                  (SWITCH_DROPS, DROP_CLAIM, "no leaving agent's send is dropped"))


def _switches(model: EarlModel, rc: Reconfiguration, folder: Path, options: VerifyOptions,
              left: Callable[[], float], result: VerifyResult) -> None:
    """V006-V009: a switch that loses values, one that only its timeout ends, agents of
    different configurations running together, a leaving agent's send that goes nowhere."""
    pairs = exclusive_pairs(rc)
    together = ", ".join(f"{a.agent.path} and {b.agent.path}" for a, b in pairs) or "none"
    proven = {
        SWITCH_LOSES: "no switch loses values: every leaving agent can stop in a quiescent state once it has "
                      "received every value sent to it",
        SWITCH_TIMES_OUT: "every switch can end without its timeout",
        SWITCH_OVERLAPS: f"exclusivity: agents that share no configuration never run together ({together})",
        SWITCH_DROPS: "no leaving agent's send is dropped: what a leaving agent sends until it stops reaches "
                      "its receiver",
    }
    for code, claim, what in _SWITCH_CHECKS:
        if not options.runs(code):
            continue
        if code == SWITCH_TIMES_OUT and any(f.code == SWITCH_LOSES for f in result.findings):
            continue  # a switch that loses values is one its timeout ended
        claimed = translate(model, (), claim)
        # safety properties: the never claim ends at the first bad state, and -i makes the
        # counterexample the shortest one
        binary = spin.build(folder, claimed.text, f"pan_{claim}", ("-DREACH", f"-DMEMLIM={MEMORY_MB}"), left())
        run = spin.search(binary, ("-i", *_pan_flags(options)), left())
        # not counted as explored: the same state space as reachability's, searched again (-DREACH)
        if run.errors:
            trace, reader = _read_trace(claimed, spin.replay(folder, left()))
            result.findings.append(_switch_finding(model, rc, code, trace, reader))
        elif not run.complete:
            result.not_proven.append(f"{what}: " + _bounded(run, options))
        else:
            result.proven.append(proven[code])


def _switch_finding(model: EarlModel, rc: Reconfiguration, code: str, trace: tuple[TraceStep, ...],
                    reader: SwitchReader | None) -> Finding:
    stuck = reader.stuck if reader is not None else []
    where = "; ".join(f"{agent} stuck in {state or 'its state'}, {why}" for agent, state, why in stuck)
    switch = " → ".join(reader.timed_out) if reader is not None and reader.timed_out else ""
    if code == SWITCH_LOSES and reader is not None and reader.lost:
        label, count = reader.lost[0]
        link = next((lk for lk in model.links if lk.path == label), None)
        return Finding(code, f"a switch can lose values on {label}: the switch {switch} ends by its timeout with "
                       f"{count} value(s) not received ({where})", label,
                       link.location if link else rc.system.location, trace)
    if code == SWITCH_DROPS and reader is not None and reader.dropped:
        label, sender, dropping = reader.dropped[0]
        link = next((lk for lk in model.links if lk.path == label), None)
        return Finding(code, f"a leaving agent's send is dropped on {label}: {sender} sends on it while the switch "
                       f"{dropping} is pending, and the link is closed: the value goes nowhere", label,
                       link.location if link else rc.system.location, trace)
    if code == SWITCH_TIMES_OUT and stuck:
        agent = next((a for a in model.agents if a.path == stuck[0][0]), None)
        return Finding(code, f"the switch {switch} can only end by its timeout: {where}", stuck[0][0],
                       agent.location if agent else rc.system.location, trace)
    running = sorted(reader.running) if reader is not None else []
    return Finding(code, f"agents of different configurations run together: {', '.join(running)}",
                   rc.system.path, rc.system.location, trace)


def _ltl(model: EarlModel, prop: LtlProperty, folder: Path, options: VerifyOptions, left: Callable[[], float],
         result: VerifyResult) -> None:
    spec = translate(model, (prop,))
    binary = spin.build(folder, spec.text, f"pan_{prop.name}", (f"-DMEMLIM={MEMORY_MB}",), left())
    run = spin.search(binary, ("-a", "-N", prop.name, *_pan_flags(options)), left())
    _account(run, result)
    if run.errors:
        trace = _trace(spec, spin.replay(folder, left()))
        result.findings.append(Finding(LTL_VIOLATED, f"property {prop.text} does not hold", prop.title,
                                       prop.location, trace))
    elif not run.complete:
        result.not_proven.append(f"{prop.text}: " + _bounded(run, options))
    else:
        result.proven.append(f"{prop.text} holds")


def _trace(spec: Specification, replay: str) -> tuple[TraceStep, ...]:
    return _read_trace(spec, replay)[0]


def _read_trace(spec: Specification, replay: str) -> tuple[tuple[TraceStep, ...], SwitchReader | None]:
    """The counterexample, and what its switches did (None for a fixed structure)."""
    by_key = {}
    for generated in spec.steps:
        info = next(i for i, p in enumerate(spec.processes) if p.subsystem is generated.subsystem)
        state = spec.processes[info].states.index(generated.state)
        outcome = spec.processes[info].outcomes[state].outcomes.index(generated.outcome)
        by_key[(info, state, outcome)] = generated
    reader = SwitchReader(spec, spec.reconfiguration) if spec.reconfiguration is not None else None
    steps: list[TraceStep] = []
    # a send's drop is printed inside the iteration that sends, before its outcome: shown after it
    after_step: list[SwitchEvent] = []

    def add(event: SwitchEvent) -> None:
        steps.append(TraceStep(len(steps) + 1, event.subsystem, event.source, event.target, event.why, ()))

    for match in _MARKS.finditer(replay):
        if match.group(4) is not None:
            kind, words = match.group(4), match.group(5).split()
            if reader is None:
                continue
            if kind == "begin" and steps and words:
                last = steps[-1]
                steps[-1] = TraceStep(last.number, last.subsystem, last.source, last.target,
                                      last.why + reader.begins(words[0]), last.values)
            elif (event := reader.event(kind, words)) is not None:
                if kind == "dropped":
                    after_step.append(event)
                else:
                    add(event)
            continue
        step: Step = by_key[(int(match.group(1)), int(match.group(2)), int(match.group(3)))]
        o = step.outcome
        target = o.transition.target if o.transition else step.state.name
        why = o.transition.name if o.transition else ("behaviour ended, no transition" if o.ended else "iteration")
        steps.append(TraceStep(len(steps) + 1, step.subsystem.path, step.state.name, target, why, o.witness))
        for event in after_step:
            add(event)
        after_step.clear()
    for event in after_step:
        add(event)
    return tuple(steps), reader


def _waiting_at_end(spec: Specification, trace: tuple[TraceStep, ...]) -> list[tuple[Subsystem, str]]:
    from earl_m2t.verify.promela import waits_forever

    current = {p.subsystem.path: p.subsystem.fsm.initial for p in spec.processes if p.subsystem.fsm}
    for step in trace:
        current[step.subsystem] = step.target
    stuck = []
    for info in spec.processes:
        state = next((s for s in info.states if s.name == current.get(info.subsystem.path)), None)
        if state is None:
            continue
        waits = waits_forever(info.subsystem, state)
        if waits:
            stuck.append((info.subsystem,
                          f"{info.subsystem.path} in {state.name} waits for {', '.join(b.name for b in waits)}"))
    return stuck
