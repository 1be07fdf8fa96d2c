"""FABRIC's own files of a subsystem: ``spec/subsystem.xml`` and ``config/<instance>.xml``.

What FABRIC's parser (``parse_subsystem_xml.py``), its master generator (``logicExprToCpp`` in
``create_master_cpp.py``) and its deployer (``SubsystemDeployer::runXmls()``) read, taken from
the lifted model. See docs/orocos-target.md, *FABRIC files*.

Names: FABRIC names buffers (aliases), predicates, behaviours and running components with C++
identifiers (``p->name``, ``<alias>_INPORT``). An EARL name is written without its suffix
(``emergencyStop/pp`` → ``emergencyStop``) when that is an identifier FABRIC can use, else as
the generator's C++ identifier (``false/pp`` → ``false_pp``).

Conditions: earl_m2t/gen/views/fabric_conditions.py.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any
from xml.sax.saxutils import escape

from earl_m2t.gen.errors import GenError
from earl_m2t.gen.names import cpp_identifier, is_reserved
from earl_m2t.gen.views.fabric_conditions import ConditionWriter
from earl_m2t.model.datatypes import DataType
from earl_m2t.model.elements import BufferGroup, EarlModel, State, Subsystem
from earl_m2t.model.naming import split

Data = dict[str, Any]

IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


@dataclass(frozen=True)
class FabricTarget:
    """The ``[fabric]`` table of ``transforms/orocos/target.toml``."""

    reserved: frozenset[str]  # names logicExprToCpp adds to every predicate list
    operators: tuple[str, ...]  # and, or, not: a predicate name inside one would be replaced in it
    default_group: str
    used_time: str
    conn_policy: dict[str, str]  # receive mode -> <conn_policy type>
    master: str
    output_component: str
    external_suffix: str

    @classmethod
    def from_spec(cls, spec: dict[str, Any]) -> FabricTarget:
        return cls(reserved=frozenset(spec["reserved"]), operators=tuple(spec["operators"]),
                   default_group=str(spec["default_group"]), used_time=str(spec["used_time"]),
                   conn_policy=dict(spec["conn_policy"]), master=str(spec["master_component"]),
                   output_component=str(spec["output_component"]),
                   external_suffix=str(spec["external_message_package_suffix"]))

    def external_message(self, datatype: DataType | None) -> str | None:
        """The ROS message a field-less dataType of a ``*_msgs`` package names (``pkg::Msg``, also
        for ``pkg::pkg_Msg``, as import fabric names a message other packages have too), else None."""
        if datatype is None or datatype.fields or datatype.kind != "struct":
            return None
        package, _, message = datatype.qualified_name.rpartition("::")
        if "::" in package or not package.endswith(self.external_suffix):
            return None
        return f"{package}::{message.removeprefix(package + '_')}"


class FabricNames:
    """Distinct FABRIC names within one subsystem definition."""

    def __init__(self, target: FabricTarget, in_conditions: bool = False) -> None:
        self.target = target
        self.in_conditions = in_conditions  # predicate names: logicExprToCpp replaces them in the text
        self.taken: dict[str, str] = {}

    def usable(self, name: str) -> bool:
        return (IDENTIFIER.fullmatch(name) is not None and not is_reserved(name) and name not in self.target.reserved
                and not (self.in_conditions and any(name in op for op in self.target.operators))
                and name.lower() not in self.taken)

    def take(self, earl_name: str) -> str:
        base = split(earl_name)[0]
        name = base if self.usable(base) else cpp_identifier(earl_name)
        candidate, n = name, 1
        while not self.usable(candidate):
            n += 1
            candidate = f"{name}_{n}"
        self.taken[candidate.lower()] = earl_name
        return candidate


def definition_spec(model: EarlModel, sub: Subsystem, buffers: list[Data], pfs: list[Data],
                    period: float, target: FabricTarget) -> Data | None:
    """The data of ``spec/subsystem.xml`` for one subsystem definition (``sub`` is its first
    instance; ``buffers`` and ``pfs`` are the Orocos view's entries of its master and pf
    components), or None when FABRIC cannot express it: no Input Buffer to make a buffer group of."""
    where = sub.path
    aliases = FabricNames(target)
    for entry in buffers:
        buf = next(b for b in sub.buffers if b.template == entry["template"] and b.index == entry["index"])
        entry["alias"] = aliases.take(buf.name)
        entry["buffer"] = buf
        # as the model says when it says (import fabric carries FABRIC's), else from the links
        entry["side"] = buf.side or entry["side"]
        entry["converter"] = _xml(buf.converter)
    inputs = [b for b in buffers if b["direction"] == "in"]
    groups = _groups(sub, inputs, target)
    if not groups:
        return None

    names = FabricNames(target, in_conditions=True)
    pp_names = {pp.name: names.take(pp.name) for pp in sub.predicates}
    writer = ConditionWriter(sub, names, pp_names)

    components = FabricNames(target)
    pf_names = {pf["role"]: components.take(pf["model_name"]) for pf in pfs}
    for pf in pfs:
        pf["component"] = pf_names[pf["role"]]
    behaviour_names = FabricNames(target)
    bb_names: dict[str, str] = {}
    behaviours: list[Data] = []
    pf_by_model = {pf["model_name"]: pf for pf in pfs}
    fsm = sub.fsm
    assert fsm is not None  # the C++ view refuses a subsystem without an FSM
    composed = _composed(sub, fsm.states)
    for bb in sub.behaviours:
        if bb.name in composed:
            continue
        bb_names[bb.name] = behaviour_names.take(bb.name)
        running = [pf_by_model[name]["component"] for name in bb.functions if name in pf_by_model]
        behaviours.append({"name": bb_names[bb.name], "model": bb.name, "trace": bb.path,
                           "stop_cond": writer.text(bb.tc, False, f"{bb.path} tc"),
                           "err_cond": writer.text(bb.ec, False, f"{bb.path} ec"),
                           "running": list(dict.fromkeys(running))})
    transitions = sorted(fsm.transitions, key=lambda t: t.order)
    states: list[Data] = []
    for state in fsm.states:
        leaving = sorted((t for t in transitions if t.source == state.name), key=lambda t: -t.priority)
        next_states: list[Data] = []
        for t in leaving:
            higher = ([] if state.exclusive_guards else
                      [writer.expression(h.condition, True, h.path) for h in leaving[:leaving.index(t)]])
            next_states.append({"name": _xml(t.target), "init_cond": writer.guard(t.condition, t.path, higher),
                                "trace": t.path})
        states.append({
            "trace": state.path, "name": _xml(state.name),
            "behaviours": _state_behaviours(state, bb_names),
            "next": next_states,
            "group": _activation(state, groups, period, target, where),
        })
    predicates = list(pp_names.values()) + list(writer.derived.values())
    simulation = sub.simulation
    return {"buffers": buffers, "groups": groups, "predicates": predicates, "behaviours": behaviours,
            "states": states, "initial": _xml(fsm.initial or ""),
            "simulation": None if simulation is None else {
                "use_ros_sim_clock": _boolean(simulation.use_ros_sim_clock),
                "use_sim_clock": _boolean(simulation.use_sim_clock),
                "trigger_gazebo": None if simulation.trigger_gazebo is None else _boolean(simulation.trigger_gazebo)}}


def _composed(sub: Subsystem, states: tuple[State, ...]) -> set[str]:
    """The basic behaviours that only compose FABRIC's behaviours of states running several
    side by side: FABRIC gets those behaviours, not the composition."""
    plain = {b for s in states if not s.composes for b in s.behaviours}
    return {b for s in states if s.composes for b in s.behaviours if b not in plain}


def _state_behaviours(state: State, bb_names: dict[str, str]) -> list[str]:
    names = state.composes or state.behaviours
    missing = [b for b in state.composes if b not in bb_names]
    if missing:
        raise GenError(f"{state.path}: tag behaviours names {', '.join(missing)}, no basic behaviour of its subsystem")
    return [bb_names[b] for b in names if b in bb_names]


def _boolean(value: bool) -> str:
    return "true" if value else "false"


def _groups(sub: Subsystem, inputs: list[Data], target: FabricTarget) -> list[Data]:
    """The subsystem's buffer groups with FABRIC aliases; without any, one group reading every
    input when present (EARL's free-running default)."""
    if not sub.buffer_groups:
        if not inputs:
            return []
        return [{"name": target.default_group, "obligatory": [], "optional": [b["alias"] for b in inputs]}]
    return [{"name": _xml(group.name), "obligatory": _aliases(sub, group, group.obligatory, inputs),
             "optional": _aliases(sub, group, group.optional, inputs), "trace": group.path}
            for group in sub.buffer_groups]


def _aliases(sub: Subsystem, group: BufferGroup, names: Iterable[str], inputs: list[Data]) -> list[str]:
    """The aliases of the Input Buffers a group names (a template names all its instances)."""
    found: list[str] = []
    for name in names:
        matches = [b["alias"] for b in inputs
                   if name in (b["buffer"].name, b["buffer"].template)
                   or split(name)[0] in (split(b["buffer"].name)[0], split(b["buffer"].template)[0])]
        if not matches:
            raise GenError(f"{group.path}: the buffer group names {name}, not an Input Buffer of {sub.path}")
        found += [m for m in matches if m not in found]
    return found


def _activation(state: State, groups: list[Data], period: float, target: FabricTarget, where: str) -> Data:
    activation = state.activation
    group = _xml(activation.group) if activation.group else groups[0]["name"]
    if all(g["name"] != group for g in groups):
        raise GenError(f"{where}: state {state.name} names the buffer group {group}, which the subsystem lacks")
    min_period = activation.min_period if activation.min_period is not None else period
    first = activation.first_timeout if activation.first_timeout is not None else min_period
    following = activation.next_timeout if activation.next_timeout is not None else first
    min_period_sim = activation.min_period_sim if activation.min_period_sim is not None else min_period
    first_sim = activation.first_timeout_sim if activation.first_timeout_sim is not None else first
    return {"name": group, "min_period": _number(min_period), "min_period_sim": _number(min_period_sim),
            "first_timeout": _number(first), "next_timeout": _number(following),
            "first_timeout_sim": _number(first_sim), "used_time": _xml(activation.used_time or target.used_time)}


def _number(value: float) -> str:
    return repr(float(value))


def instance_configuration(instance: Data, spec: Data, pfs: list[Data], links: dict[str, str],
                           target: FabricTarget) -> Data:
    """The data of ``config/<instance>.xml``: the pf components, the IPC channel of every buffer,
    the connections between the master, the pf components and FABRIC's output component."""
    io: list[Data] = []
    connections: list[Data] = []
    for buf in spec["buffers"]:
        alias = buf["alias"]
        channel = links.get(f"{instance['name']}.{buf['port']}", f"{instance['name']}_{alias}")
        io.append({"alias": alias, "name": channel})
    access = {b["access"]: b for b in spec["buffers"]}
    writers: dict[str, list[Data]] = {}
    for pf in pfs:
        for port in pf["ports"]:
            if port["kind"] == "mo":
                writers.setdefault(port["master_access"], []).append({"pf": pf, "port": port})
    for pf in pfs:
        for port in pf["ports"]:
            end = f"{pf['component']}.{port['port']}"
            buf = access.get(port["master_access"])
            if buf is not None and port["kind"] == "ib":
                # a receive mode outside EARL's (a B011 error, generated with --force) is the
                # latest value, as the C++ and ROS targets take it
                queued = buf["buffer"].receive == "queue"
                policy: Data = {"type": target.conn_policy["queue" if queued else "latest"]}
                if queued:
                    policy["size"] = buf["buffer"].queue_size
                connections.append({"from": f"{target.master}.{buf['alias']}_OUTPORT", "to": end,
                                    "name": buf["alias"], "policy": policy})
            elif buf is not None and port["kind"] == "ob":
                connections.append({"from": end, "to": f"{target.output_component}.{buf['alias']}_INPORT",
                                    "name": buf["alias"], "policy": None})
            elif port["kind"] == "mi":
                for writer in writers.get(port["master_access"], []):
                    connections.append({"from": f"{writer['pf']['component']}.{writer['port']['port']}",
                                        "to": end, "name": port["port"], "policy": None})
    components = [{"component": pf["component"], "type": pf["type"]} for pf in pfs]
    return {"components": components, "io": io, "connections": connections}


def _xml(text: str) -> str:
    return escape(text, {'"': "&quot;"})
