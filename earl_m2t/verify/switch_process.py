"""The Promela process that carries a switch out (docs/verify.md, *Variable structure*): a
leaving agent stops, the next configuration opens, or the switch timeout fires.

Each step prints a ``SWITCH_MARK`` line saying what it did, read back from SPIN's replay into
the counterexample (switch_trace.py). The lines carry numbers and Promela identifiers only (an
agent's index, a configuration's number, a counter's variable), never model names, which could
hold what a printf string or the reading back cannot take.
"""

from __future__ import annotations

from dataclasses import dataclass

from earl_m2t.model.elements import State, Subsystem
from earl_m2t.model.kinds import SubsystemKind
from earl_m2t.verify.promela_text import promela_comment
from earl_m2t.verify.switching import SWITCH_MARK, Reconfiguration, VariableAgent

HEADER = (
    "active proctype reconfiguration() {{ /* the switches of {coordinator} */",
    "end:",
    "  do",
)
FOOTER = ("  od", "}")
STOP = ("  :: atomic {{ {leaving} && {active}{quiet}{empty} -> {active} = false; "
        "printf(\"{mark} stop {agent}{shown}\\n\"{state}) }}")
OPEN = (  # one step per state of the coordinator naming the configuration: it enters that state
    "  :: atomic {{ switching && nxt == {number} && pending == {state}{stopped} ->",
    "       {effects};",
    "       printf(\"{mark} open {number} %d {state}\\n\", {coordinator});",
    "       {coordinator} = {state}; cfg = {number}; switching = false }}",
)
ENTERS = 2  # the line of OPEN that marks the state entered
TIMEOUT = "  :: atomic {{ timeout && switching -> printf(\"{mark} timeout %d\\n\", nxt);"
STUCK = "       if :: {leaving} && {active} -> printf(\"{mark} stuck {agent}{shown}\\n\"{state});"
LOST = ("         if :: {counter} > 0 -> printf(\"{mark} lost {counter} %d\\n\", {counter}); lost = true "
        ":: else -> skip fi; {counter} = 0;")
STUCK_END = "         {active} = false :: else -> skip fi;"
TIMEOUT_END = "       timedout = true }"


@dataclass(frozen=True, slots=True)
class ProcessState:
    subsystem: Subsystem
    variable: str  # the global holding its state number, "" when it is left out (stays initial)
    states: tuple[State, ...]


@dataclass(frozen=True, slots=True)
class SwitchView:
    """What the switch process reads: the subsystems' states and the counters into each agent."""

    processes: dict[str, ProcessState]  # by subsystem path
    inputs: dict[str, list[tuple[str, str]]]  # agent path -> (counter, the link or buffer it counts)

    def control(self, agent: VariableAgent) -> list[ProcessState]:
        return [p for p in self.processes.values()
                if p.subsystem.agent == agent.agent.path and p.subsystem.kind == SubsystemKind.CS]


def switch_process(rc: Reconfiguration, view: SwitchView) -> list[str | tuple[str, State]]:
    """The process's lines; a line that enters a state of the coordinator comes with that state."""
    coordinator = view.processes.get(rc.coordinator.path)
    if coordinator is None or not coordinator.variable:
        return []
    shown = promela_comment(rc.coordinator.path)
    lines: list[str | tuple[str, State]] = [line.format(coordinator=shown) for line in HEADER]
    lines += [_stop(index, agent, view) for index, agent in enumerate(rc.agents)]
    for number, structure in enumerate(rc.structures):
        for index, state in enumerate(coordinator.states):
            if state.configuration == structure.configuration.name:
                opened = _open(rc, number, view, coordinator.variable, index)
                lines += [(text, state) if k == ENTERS else text for k, text in enumerate(opened)]
    lines.append(TIMEOUT.format(mark=SWITCH_MARK))
    for index, agent in enumerate(rc.agents):
        lines.append(STUCK.format(mark=SWITCH_MARK, leaving=agent.leaving, active=agent.active,
                                  agent=index, **_shown(agent, view)))
        lines += [LOST.format(mark=SWITCH_MARK, counter=counter)
                  for counter, _ in view.inputs.get(agent.agent.path, [])]
        lines.append(STUCK_END.format(active=agent.active))
    lines.append(TIMEOUT_END)
    return lines + list(FOOTER)


def _shown(agent: VariableAgent, view: SwitchView) -> dict[str, str]:
    """The state of the agent's control subsystem, printed with a stop."""
    control = [p for p in view.control(agent) if p.variable]
    return {"shown": " %d", "state": f", {control[0].variable}"} if control else {"shown": "", "state": ""}


def _stop(index: int, agent: VariableAgent, view: SwitchView) -> str:
    """A leaving agent stops in a quiescent state with every tracked input empty."""
    quiet = []
    for process in view.control(agent):
        states = agent.quiescent(process.subsystem)
        if states is None:
            continue
        if not process.variable:  # left out: it stays in its initial state
            fsm = process.subsystem.fsm
            if fsm is None or not any(s.name == fsm.initial for s in states):
                quiet.append("false")
            continue
        quiet.append("(" + " || ".join(f"{process.variable} == {process.states.index(s)}" for s in states) + ")")
    empty = [f"{counter} == 0" for counter, _ in view.inputs.get(agent.agent.path, [])]
    return STOP.format(leaving=agent.leaving, active=agent.active, mark=SWITCH_MARK, agent=index,
                       quiet="".join(f" && {q}" for q in quiet), empty="".join(f" && {e}" for e in empty),
                       **_shown(agent, view))


def _open(rc: Reconfiguration, number: int, view: SwitchView, coordinator: str, state: int) -> list[str]:
    """Once every agent the configuration lacks has stopped, it opens: a joining agent restarts
    (from its initial states) or resumes, with its inputs empty, and the coordinator enters the
    state that began the switch."""
    structure = rc.structures[number]
    stopped = "".join(f" && !{a.active}" for a in rc.agents if not structure.has_agent(a.agent.path))
    effects = []
    for agent in (a for a in rc.agents if structure.has_agent(a.agent.path)):
        if agent.restarts:
            for process in view.processes.values():
                fsm = process.subsystem.fsm
                if process.variable and process.subsystem.agent == agent.agent.path and fsm is not None:
                    initial = next(i for i, s in enumerate(process.states) if s.name == fsm.initial)
                    effects.append(f"{process.variable} = ({agent.active} -> {process.variable} : {initial})")
        effects += [f"{counter} = ({agent.active} -> {counter} : 0)"
                    for counter, _ in view.inputs.get(agent.agent.path, [])]
        effects.append(f"{agent.active} = true")
    effects += [f"{a.leaving} = false" for a in rc.agents]
    return [line.format(number=number, stopped=stopped, effects="; ".join(effects), mark=SWITCH_MARK,
                        coordinator=coordinator, state=state) for line in OPEN]
