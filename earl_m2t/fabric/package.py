"""One FABRIC package read as FABRIC reads it: the subsystem definition checked as FABRIC's
``parse_subsystem_xml.py`` checks it, the run-time configurations as the deployer's
``runXmls()`` reads them. Anything either would refuse is one :class:`ModelReadError` naming
file and line (exit 2)."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from lxml import etree

from earl_m2t.diagnostics import ModelReadError
from earl_m2t.read.safe_xml import parse_xml_file

SPEC = Path("spec") / "subsystem.xml"
CONFIG = "config"
SECTIONS = ("buffers", "buffer_groups", "predicates", "behaviors", "states")
GROUP_TIMES = ("min_period", "min_period_sim", "first_timeout", "next_timeout", "first_timeout_sim")
USED_TIME = ("sim", "real")
SIDES = ("top", "bottom")


@dataclass(frozen=True)
class Where:
    file: str
    line: int


@dataclass(frozen=True)
class FabricBuffer:
    alias: str
    direction: str  # "in" | "out"
    type: str  # package::Message
    side: str
    converter: str
    where: Where


@dataclass(frozen=True)
class FabricGroup:
    name: str
    obligatory: tuple[str, ...]
    optional: tuple[str, ...]
    where: Where


@dataclass(frozen=True)
class FabricBehaviour:
    name: str
    stop_cond: str
    err_cond: str
    running: tuple[str, ...]
    where: Where


@dataclass(frozen=True)
class FabricStateGroup:
    name: str
    min_period: float
    min_period_sim: float
    first_timeout: float
    next_timeout: float
    first_timeout_sim: float
    used_time: str


@dataclass(frozen=True)
class FabricState:
    name: str
    behaviours: tuple[str, ...]
    next_states: tuple[tuple[str, str, Where], ...]  # (state, init_cond, where)
    group: FabricStateGroup
    where: Where


@dataclass(frozen=True)
class FabricSimulation:
    use_ros_sim_clock: bool
    use_sim_clock: bool
    trigger_gazebo: bool | None  # None: not given


@dataclass(frozen=True)
class FabricComponent:
    name: str
    type: str
    running: bool
    where: Where


@dataclass(frozen=True)
class FabricConfiguration:
    name: str  # the file's name without .xml: FABRIC's deployer runs one subsystem per file
    channels: tuple[tuple[str, str], ...]  # (alias, IPC channel name) of its <io_buffer>s
    where: Where


@dataclass(frozen=True)
class FabricPackage:
    name: str  # the package folder's name
    spec_file: str
    buffers: tuple[FabricBuffer, ...]
    groups: tuple[FabricGroup, ...]
    predicates: tuple[tuple[str, Where], ...]
    behaviours: tuple[FabricBehaviour, ...]
    states: tuple[FabricState, ...]
    initial: str
    where: Where
    components: tuple[FabricComponent, ...]  # of every configuration, first declaration wins
    configurations: tuple[FabricConfiguration, ...]  # in file name order
    simulation: FabricSimulation | None = None

    @property
    def channels(self) -> tuple[tuple[str, str], ...]:
        """(alias, IPC channel name) of every configuration."""
        return tuple(c for configuration in self.configurations for c in configuration.channels)


def read_package(folder: Path) -> FabricPackage:
    """The package in ``folder``: ``spec/subsystem.xml`` and every ``config/*.xml``."""
    spec = folder / SPEC
    if not spec.is_file():
        raise ModelReadError(str(folder), f"not a FABRIC package: no {SPEC.as_posix()}")
    root = parse_xml_file(spec).getroot()
    file = str(spec)
    if root.tag != "subsystem_definition":
        raise ModelReadError(file, f"the root is <{root.tag}>, FABRIC wants <subsystem_definition>",
                             root.sourceline or 0)
    sections = {name: _one(root, name, file) for name in SECTIONS}
    buffers = tuple(_buffer(e, file) for e in sections["buffers"] if e.tag in ("in", "out"))
    inputs = {b.alias for b in buffers if b.direction == "in"}
    groups = tuple(_group(e, file, inputs) for e in sections["buffer_groups"] if e.tag == "buffer_group")
    predicates = tuple((_required(e, "name", file), _where(e, file))
                       for e in sections["predicates"] if e.tag == "predicate")
    behaviours = tuple(_behaviour(e, file) for e in sections["behaviors"] if e.tag == "behavior")
    states_element = sections["states"]
    initial = _required(states_element, "initial", file)
    states = tuple(_state(e, file) for e in states_element if e.tag == "state")
    _check_references(file, groups, behaviours, states, initial, states_element)
    simulation = _simulation(root, file)
    components: dict[str, FabricComponent] = {}
    config = folder / CONFIG
    configurations = tuple(_configuration(path, components)
                           for path in (sorted(config.glob("*.xml")) if config.is_dir() else []))
    return FabricPackage(name=folder.resolve().name, spec_file=file, buffers=buffers, groups=groups,
                         predicates=predicates, behaviours=behaviours, states=states, initial=initial,
                         where=_where(root, file), components=tuple(components.values()),
                         configurations=configurations, simulation=simulation)


def _where(element: etree._Element, file: str) -> Where:
    return Where(file, element.sourceline or 0)


def _fail(element: etree._Element, file: str, message: str) -> ModelReadError:
    return ModelReadError(file, message, element.sourceline or 0)


def _one(root: etree._Element, name: str, file: str) -> etree._Element:
    found = list(root.iter(name))
    if len(found) != 1:
        raise _fail(found[1] if found else root, file,
                    f"FABRIC wants exactly one <{name}> in <subsystem_definition>, there are {len(found)}")
    return found[0]


def _required(element: etree._Element, attribute: str, file: str) -> str:
    value = element.get(attribute)
    if not value:
        raise _fail(element, file, f"<{element.tag}> must have the attribute '{attribute}'")
    return value


def _buffer(element: etree._Element, file: str) -> FabricBuffer:
    alias = _required(element, "alias", file)
    kind = _required(element, "type", file)
    if len(kind.split("::")) != 2:
        raise _fail(element, file, f"<{element.tag} alias=\"{alias}\">: type '{kind}' is not 'package::Message'")
    side = element.get("side", "").lower()
    if side not in SIDES:
        raise _fail(element, file, f"<{element.tag} alias=\"{alias}\">: side must be top or bottom")
    return FabricBuffer(alias, str(element.tag), kind, side, element.get("converter", ""), _where(element, file))


def _group(element: etree._Element, file: str, inputs: set[str]) -> FabricGroup:
    name = element.get("name", "")
    members: dict[str, list[str]] = {"obligatory": [], "optional": []}
    for child in element:
        if child.tag in members:
            member = _required(child, "name", file)
            if member not in inputs:
                raise _fail(child, file, f"buffer group '{name}' names '{member}', which is no <in> buffer")
            members[str(child.tag)].append(member)
    if not members["obligatory"] and not members["optional"]:
        raise _fail(element, file, f"buffer group '{name}' needs at least one <obligatory> or <optional>")
    return FabricGroup(name, tuple(members["obligatory"]), tuple(members["optional"]), _where(element, file))


def _behaviour(element: etree._Element, file: str) -> FabricBehaviour:
    return FabricBehaviour(
        name=_required(element, "name", file), stop_cond=element.get("stop_cond", ""),
        err_cond=element.get("err_cond", ""),
        running=tuple(_required(c, "name", file) for c in element if c.tag == "running_component"),
        where=_where(element, file))


def _state(element: etree._Element, file: str) -> FabricState:
    name = _required(element, "name", file)
    groups = [c for c in element if c.tag == "buffer_group"]
    if len(groups) != 1:
        raise _fail(element, file, f"state '{name}': FABRIC wants exactly one <buffer_group>")
    group = groups[0]
    times: dict[str, float] = {}
    for attribute in GROUP_TIMES:
        text = _required(group, attribute, file)
        try:
            times[attribute] = float(text)
        except ValueError:
            raise _fail(group, file, f"state '{name}': {attribute}='{text}' is not a number") from None
    used_time = _required(group, "used_time", file)
    if used_time not in USED_TIME:
        raise _fail(group, file, f"state '{name}': used_time must be sim or real, not '{used_time}'")
    return FabricState(
        name=name, behaviours=tuple(_required(c, "name", file) for c in element if c.tag == "behavior"),
        next_states=tuple((_required(c, "name", file), c.get("init_cond", ""), _where(c, file))
                          for c in element if c.tag == "next_state"),
        group=FabricStateGroup(name=_required(group, "name", file), used_time=used_time, **times),
        where=_where(element, file))


def _simulation(root: etree._Element, file: str) -> FabricSimulation | None:
    """``<simulation use_ros_sim_clock use_sim_clock [trigger_gazebo]>``, read as FABRIC does."""
    found = list(root.iter("simulation"))
    if len(found) > 1:
        raise _fail(found[1], file, "FABRIC wants at most one <simulation>")
    if not found:
        return None
    element = found[0]
    return FabricSimulation(bool(_boolean(element, "use_ros_sim_clock", file, True)),
                            bool(_boolean(element, "use_sim_clock", file, True)),
                            _boolean(element, "trigger_gazebo", file, False))


def _boolean(element: etree._Element, attribute: str, file: str, required: bool) -> bool | None:
    text = _required(element, attribute, file) if required else element.get(attribute, "")
    if not text:
        return None
    if text.upper() not in ("TRUE", "FALSE"):
        raise _fail(element, file, f"<{element.tag}> {attribute}='{text}' is neither true nor false")
    return text.upper() == "TRUE"


def _check_references(file: str, groups: tuple[FabricGroup, ...], behaviours: tuple[FabricBehaviour, ...],
                      states: tuple[FabricState, ...], initial: str, element: etree._Element) -> None:
    group_names = {g.name for g in groups}
    behaviour_names = {b.name for b in behaviours}
    state_names = {s.name for s in states}
    if initial not in state_names:
        raise _fail(element, file, f"the initial state '{initial}' is not a <state>")
    for state in states:
        if state.group.name not in group_names:
            raise ModelReadError(file, f"state '{state.name}' has the unknown buffer group '{state.group.name}'",
                                 state.where.line)
        for name in state.behaviours:
            if name not in behaviour_names:
                raise ModelReadError(file, f"state '{state.name}' runs the unknown behavior '{name}'",
                                     state.where.line)
        for target, _, where in state.next_states:
            if target not in state_names:
                raise ModelReadError(file, f"state '{state.name}' has the unknown next state '{target}'", where.line)


def _configuration(path: Path, components: dict[str, FabricComponent]) -> FabricConfiguration:
    file = str(path)
    channels: list[tuple[str, str]] = []
    root = parse_xml_file(path).getroot()
    if root.tag != "subsystem_configuration":
        raise _fail(root, file, f"the root is <{root.tag}>, FABRIC's deployer wants <subsystem_configuration>")
    for element in root:
        if element.tag == "component":
            name = _required(element, "name", file)
            running = element.get("running", "") in ("true", "True", "TRUE")
            components.setdefault(name, FabricComponent(name, element.get("type", ""), running,
                                                        _where(element, file)))
        elif element.tag == "io_buffer":
            channels.append((_required(element, "alias", file), _required(element, "name", file)))
    return FabricConfiguration(path.stem, tuple(channels), _where(root, file))
