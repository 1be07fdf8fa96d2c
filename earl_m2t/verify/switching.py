"""Variable structure in the Promela model (docs/verify.md, *Variable structure*).

A model with configurations and one coordinator gets: a global configuration number ``cfg``,
``switching`` while a switch is pending (with ``nxt``, the configuration it opens, and
``pending``, the coordinator's state once it is open), and per variable agent ``activeN`` and
``leavingN``. A variable link is open while the configuration holds it and, during a switch,
only when the next one holds it too (closed at its sender; the receiver still reads what it
holds), or when it lingers (variability.lingers): its sender leaves and has not stopped yet, its
receiver stays. A leaving agent's send on a link that is closed sets ``dropped``. The
coordinator's iteration that takes a transition to a state naming another
configuration begins a switch instead of entering the state; a leaving agent stops in a
quiescent state with its tracked inputs empty; the switch opens once every leaving agent has
stopped; its timeout is a step enabled only when nothing else can move (Promela ``timeout``),
which stops the leaving agents anyway, clears what they had not received and sets ``lost``.
"""

from __future__ import annotations

from dataclasses import dataclass

from earl_m2t.model.elements import Agent, EarlModel, Link, State, Subsystem, System
from earl_m2t.model.kinds import Reactivation
from earl_m2t.model.variability import (
    Structure,
    coordinator,
    lingers,
    link_agents,
    structures,
    variable_agents,
    variable_links,
)
from earl_m2t.verify.promela_text import promela_comment

SWITCH_MARK = "EARLSWITCH"  # the printf tag of a switch event, read back from SPIN's replay

DECLARATIONS = (
    "byte cfg = {initial}; /* configuration: {names} */",
    "byte nxt = {initial}; /* the configuration a pending switch opens */",
    "byte pending = 0; /* the coordinator's state once the switch is open */",
    "bool switching = false; /* a switch is pending: the coordinator does not iterate */",
    "bool lost = false; /* a switch timeout cleared values nobody received */",
    "bool dropped = false; /* a leaving agent sent on a link that is closed */",
    "bool timedout = false; /* a switch ended by its timeout */",
)
AGENT_DECLARATIONS = (
    "bool {active} = {initially}; /* {path} is running */",
    "bool {leaving} = false; /* a switch removes {path}: leaving() */",
)
# the never claims of the built-in checks (V006-V009), named apart from the users' properties
LOSS_CLAIM, TIMEOUT_CLAIM, EXCLUSIVE_CLAIM, DROP_CLAIM = "earl_lost", "earl_timedout", "earl_exclusive", "earl_dropped"
# what a send that a closed link drops does: the mark names the link's counter and the switch's target
DROP = 'printf("{mark} dropped {counter} %d\\n", nxt); dropped = true'


@dataclass(frozen=True, slots=True)
class VariableAgent:
    agent: Agent
    number: int
    initially: bool  # present in the coordinator's initial configuration

    @property
    def active(self) -> str:
        return f"active{self.number}"

    @property
    def leaving(self) -> str:
        return f"leaving{self.number}"

    def quiescent(self, sub: Subsystem) -> tuple[State, ...] | None:
        """The quiescent states of a control subsystem of the agent, None when it declares none
        (then any iteration boundary is quiescent)."""
        states = tuple(s for s in sub.fsm.states if s.quiescent) if sub.fsm is not None else ()
        return states or None

    @property
    def restarts(self) -> bool:
        return self.agent.reactivation != Reactivation.RESUME


@dataclass(frozen=True, slots=True)
class Reconfiguration:
    """What the Promela model needs of a variable-structure model."""

    system: System
    coordinator: Subsystem
    structures: tuple[Structure, ...]
    initial: int  # the configuration of the coordinator's initial state
    agents: tuple[VariableAgent, ...]
    varying: frozenset[str]  # paths of the variable links

    def configuration(self, name: str) -> int | None:
        return next((i for i, s in enumerate(self.structures) if s.configuration.name == name), None)

    def agent(self, path: str) -> VariableAgent | None:
        return next((a for a in self.agents if a.agent.path == path), None)

    def holds(self, link: Link) -> tuple[int, ...]:
        return tuple(i for i, s in enumerate(self.structures) if s.has_link(link.path))

    def link_open(self, link: Link) -> str | None:
        """The Promela condition under which ``link`` delivers, None when always: while the
        configuration holds it and, during a switch, while the next one holds it too or it lingers."""
        if link.path not in self.varying:
            return None
        held = self.holds(link)
        if not held:
            return "false"
        lingering = self.lingering(link)
        return f"({_one_of('cfg', held)}) && (!switching || {_one_of('nxt', held)}" + (
            f" || {lingering})" if lingering else ")")

    def lingering(self, link: Link) -> str:
        """The Promela condition under which ``link`` stays open through a pending switch the next
        configuration lacks it in (variability.lingers): its sender leaves and has not stopped yet,
        its receiver stays; "" when it never does."""
        switches: dict[tuple[int, ...], list[int]] = {}  # the next configurations -> the current ones
        for i, before in enumerate(self.structures):
            after = tuple(j for j, s in enumerate(self.structures) if lingers(self.system, link, before, s))
            if after:
                switches.setdefault(after, []).append(i)
        sender = self.agent(link_agents(self.system, link)[0])
        if not switches or sender is None:  # a sender that leaves is a variable agent
            return ""
        held = list(self.holds(link))
        if list(switches.values()) == [held]:  # the same from every configuration that holds it
            ((after, _),) = switches.items()
            when = _one_of("nxt", after)
        else:
            when = " || ".join(f"({_one_of('cfg', tuple(now))}) && ({_one_of('nxt', after)})"
                               for after, now in switches.items())
        return f"{sender.leaving} && {sender.active} && " + (f"({when})" if " || " in when else when)

    def link_drops(self, link: Link) -> str | None:
        """The Promela condition under which a send on ``link`` is dropped: its sender leaves and
        has not stopped, the configuration holds the link, and it is closed (not ``link_open``);
        None when its sender is always present or no configuration holds it."""
        held = self.holds(link)
        sender = self.agent(link_agents(self.system, link)[0])
        if link.path not in self.varying or sender is None or not held:
            return None
        return (f"switching && {sender.leaving} && {sender.active} && ({_one_of('cfg', held)}) "
                f"&& !({self.link_open(link)})")

    def begin(self, target: int, state: int) -> str:
        """The effects of the coordinator's iteration that begins a switch to configuration ``target``."""
        effects = ["switching = true", f"nxt = {target}", f"pending = {state}"]
        effects += [f"{a.leaving} = {a.active}" for a in self.agents
                    if not self.structures[target].has_agent(a.agent.path)]
        return "; ".join(effects)


def reconfiguration(model: EarlModel) -> Reconfiguration | None:
    """The variable structure of ``model``, None when it has no configurations or no single
    control subsystem switching them (rules X003/X004 report that)."""
    system = next((s for s in model.systems if s.configurations), None)
    switcher = coordinator(model)
    if system is None or switcher is None or switcher.fsm is None:
        return None
    built = structures(system)
    initial_state = switcher.fsm.state(switcher.fsm.initial) if switcher.fsm.initial else None
    names = [s.configuration.name for s in built]
    initial = names.index(initial_state.configuration) if initial_state and initial_state.configuration in names else 0
    varying = variable_agents(system)
    agents = tuple(VariableAgent(a, n, built[initial].has_agent(a.path))
                   for n, a in enumerate(a for a in system.agents if a.path in varying))
    return Reconfiguration(system, switcher, built, initial, agents, variable_links(system))


def declarations(rc: Reconfiguration) -> list[str]:
    names = promela_comment(" ".join(f"{i}={s.configuration.name}" for i, s in enumerate(rc.structures)))
    lines = [line.format(initial=rc.initial, names=names) for line in DECLARATIONS]
    for a in rc.agents:
        lines += [line.format(active=a.active, leaving=a.leaving, path=promela_comment(a.agent.path),
                              initially="true" if a.initially else "false") for line in AGENT_DECLARATIONS]
    return lines


def exclusive_pairs(rc: Reconfiguration) -> list[tuple[VariableAgent, VariableAgent]]:
    """Pairs of variable agents that no configuration holds together: one leaves when the other joins."""
    return [(a, b) for i, a in enumerate(rc.agents) for b in rc.agents[i + 1:]
            if not any(s.has_agent(a.agent.path) and s.has_agent(b.agent.path) for s in rc.structures)]


def claims(rc: Reconfiguration) -> list[str]:
    """The never claims of the built-in checks V006-V009."""
    pairs = exclusive_pairs(rc)
    together = " || ".join(f"({a.active} && {b.active})" for a, b in pairs) or "false"
    return [f"ltl {LOSS_CLAIM} {{ [] !lost }}", f"ltl {TIMEOUT_CLAIM} {{ [] !timedout }}",
            f"ltl {EXCLUSIVE_CLAIM} {{ [] !({together}) }}", f"ltl {DROP_CLAIM} {{ [] !dropped }}"]


def _one_of(variable: str, numbers: tuple[int, ...]) -> str:
    return " || ".join(f"{variable} == {i}" for i in numbers)
