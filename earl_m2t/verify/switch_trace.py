"""The switch events of SPIN's replay (switch_process.py; a send a closed link drops, counters.py)
as steps of a counterexample."""

from __future__ import annotations

from dataclasses import dataclass, field

from earl_m2t.model.kinds import SubsystemKind
from earl_m2t.model.variability import link_agents, system_links
from earl_m2t.verify.promela import ProcessInfo, Specification
from earl_m2t.verify.switching import Reconfiguration


@dataclass(frozen=True, slots=True)
class SwitchEvent:
    """One line of a counterexample: who, from, to, and why (as run.TraceStep without its number)."""

    subsystem: str
    source: str
    target: str
    why: str


@dataclass
class SwitchReader:
    """Reads the switch marks in replay order, keeping the configuration and the running agents."""

    spec: Specification
    rc: Reconfiguration
    configuration: str = ""
    running: set[str] = field(default_factory=set)
    lost: list[tuple[str, int]] = field(default_factory=list)  # link (or buffer), values cleared
    # agent, the state its control subsystem was stopped in ("" when unknown), and why it was stuck
    stuck: list[tuple[str, str, str]] = field(default_factory=list)
    timed_out: tuple[str, str] | None = None  # the switch its timeout ended: from, to
    dropped: list[tuple[str, str, str]] = field(default_factory=list)  # link, its sender, the switch (from → to)

    def __post_init__(self) -> None:
        self.configuration = self.rc.structures[self.rc.initial].configuration.name
        self.running = {a.agent.path for a in self.rc.agents if a.initially}

    def begins(self, number: str) -> str:
        """What is added to the coordinator's step that begins a switch to configuration ``number``."""
        structure = self.rc.structures[int(number)]
        name = structure.configuration.name
        leaving = sorted(path for path in self.running if not structure.has_agent(path))
        return f"; the switch {self.configuration} → {name} begins" + (
            f", leaving: {', '.join(leaving)}" if leaving else "")

    def event(self, kind: str, numbered: list[str]) -> SwitchEvent | None:
        words = self._named(kind, numbered)
        if kind == "stop":
            self.running.discard(words[0])
            why = f"the drain: quiescent{self._in(words)}, its inputs empty"
            return SwitchEvent(words[0], "running", "stopped", why)
        if kind == "open":
            return self._open(words)
        if kind == "timeout":
            target = int(words[0]) if words else self.rc.initial
            self.timed_out = (self.configuration, self.rc.structures[target].configuration.name)
            return SwitchEvent(self.rc.coordinator.path, "switching", "timed out",
                               "the switch timeout: nothing else can move")
        if kind == "stuck":
            self.running.discard(words[0])
            self.stuck.append((words[0], self._state(words), self._why(words)))
            return SwitchEvent(words[0], "running", "stopped", f"the switch timeout: stuck{self._in(words)}")
        if kind == "lost" and len(words) == 2:
            self.lost.append((words[0], int(words[1])))
            return SwitchEvent(words[0], f"{words[1]} queued", "cleared", "the switch timeout: undelivered")
        if kind == "dropped" and len(words) == 2:
            return self._dropped(words[0], int(words[1]))
        return None

    def _dropped(self, label: str, target: int) -> SwitchEvent:
        link = next((lk for lk in system_links(self.rc.system) if lk.path == label), None)
        sender = link_agents(self.rc.system, link)[0] if link is not None else ""
        switch = f"{self.configuration} → {self.rc.structures[target].configuration.name}"
        self.dropped.append((label, sender, switch))
        return SwitchEvent(label, "sent", "dropped", f"the closed link: {sender or 'its sender'} leaves in the "
                           f"switch {switch}")

    def _named(self, kind: str, words: list[str]) -> list[str]:
        """The words of a mark with the model's names in place of the numbers and identifiers the
        Promela prints (switch_process.py): an agent's index, a configuration's number, a counter."""
        if not words:
            return words
        first = words[0]
        if kind in ("stop", "stuck"):
            first = self.rc.agents[int(first)].agent.path
        elif kind == "open":
            first = self.rc.structures[int(first)].configuration.name
        elif kind in ("lost", "dropped"):
            first = next((label for t in self.spec.tracked for counter, label in t.counters if counter == first), first)
        return [first, *words[1:]]

    def _open(self, words: list[str]) -> SwitchEvent:
        name, before, after = words[0], int(words[1]), int(words[2])
        structure = self.rc.structures[self.rc.configuration(name) or 0]
        joining = sorted(a.agent.path for a in self.rc.agents
                         if structure.has_agent(a.agent.path) and a.agent.path not in self.running)
        how = ", ".join(f"{a} {'restarts' if (va := self.rc.agent(a)) and va.restarts else 'resumes'}"
                        for a in joining)
        self.running |= set(joining)
        states = self._coordinator().states
        event = SwitchEvent(self.rc.coordinator.path, states[before].name, states[after].name,
                            f"the switch {self.configuration} → {name} is done" + (f": {how}" if how else ""))
        self.configuration = name
        return event

    def _coordinator(self) -> ProcessInfo:
        info = self.spec.state_variable(self.rc.coordinator.path)
        assert info is not None
        return info

    def _state(self, words: list[str]) -> str:
        control = self._control(words[0])
        if len(words) < 2 or not control:
            return ""
        return f"{control[0].subsystem.path}@{control[0].states[int(words[1])].name}"

    def _control(self, agent: str) -> list[ProcessInfo]:
        return [p for p in self.spec.processes if p.subsystem.agent == agent and p.subsystem.kind == SubsystemKind.CS]

    def _why(self, words: list[str]) -> str:
        control = self._control(words[0])
        if len(words) < 2 or not control:
            return "not quiescent or its inputs not received"
        state = control[0].states[int(words[1])]
        agent = self.rc.agent(words[0])
        quiet = agent.quiescent(control[0].subsystem) if agent is not None else None
        if quiet is not None and state not in quiet:
            return "not quiescent"
        return "its inputs not received there"

    def _in(self, words: list[str]) -> str:
        state = self._state(words)
        return f" in {state}" if state else ""
