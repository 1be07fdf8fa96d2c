"""The view of the Orocos RTT 2.x target: FABRIC-style components around the C++ target's code.

It is built from the C++ view (namespaces, port and memory members, pf accessors, condition
members, FSM tables) and the msg view (ROS message types of the buffers, named in the FABRIC
files), so the targets never disagree on a name. Per subsystem definition: one component
library holding a master component (the generated ``Subsystem``: FSM, conditions, predicates
as operations) and one component per pf, plus the FABRIC subsystem model; per subsystem
instance: a deployer script and the FABRIC run-time configuration. See docs/orocos-target.md.

Port names: an element of a buffer or of a pf accessor is ``<name>`` or, replicated,
``<name>_<k>`` (k = 1 .. N, the instance index of the model). A master talks to its pf
components through its ports ``<pf>_<port>``, connected to port ``<port>`` of the pf.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any
from xml.sax.saxutils import escape

from earl_m2t.gen.errors import GenError
from earl_m2t.gen.names import cpp_comment
from earl_m2t.gen.views.cpp import CppView
from earl_m2t.gen.views.fabric import FabricTarget, definition_spec, instance_configuration
from earl_m2t.gen.views.msg import MsgTarget, MsgView, field_name, ros_type
from earl_m2t.gen.views.orocos_switch import (
    definition_switch,
    fabric_variable_buffers,
    instance_switch,
    link_port,
    system_switch,
)
from earl_m2t.gen.views.switch_wiring import switch_wiring
from earl_m2t.model.elements import EarlModel, Subsystem, System

Data = dict[str, Any]

FABRIC_FOLDER = "fabric"  # the FABRIC packages' folder in the output (transforms/orocos/target.toml)

# subsystem kinds by their distance from the control subsystem (FABRIC's top/bottom sides)
_RANK = {"cs": 0, "ve": 1, "vr": 1, "re": 2, "rr": 2}


@dataclass(frozen=True)
class OrocosTarget:
    """The data of ``transforms/orocos/target.toml`` the view needs."""

    period: float
    priority: int
    scheduler: str
    policy: str
    package_suffix: str  # <model>_orocos: the CMake project, the deployer's import() package
    std_msgs: dict[str, str]  # ROS primitive type -> std_msgs message (the ROS target's table)
    fabric: FabricTarget
    latest_queue: int = 64  # [switch]: the buffer of a variable link into a latest-value Input Buffer
    control_queue: int = 16  # [switch]: the buffer of a command or acknowledgement connection
    fabric_switch_note: str = ""  # [switch]: gen's note for a model with configurations

    @classmethod
    def from_spec(cls, spec: dict[str, Any], std_msgs: dict[str, str]) -> OrocosTarget:
        activity, connection, switch = spec.get("activity", {}), spec.get("connection", {}), spec.get("switch", {})
        return cls(period=float(activity.get("period", 0.01)), priority=int(activity.get("priority", 0)),
                   scheduler=str(activity.get("scheduler", "ORO_SCHED_OTHER")),
                   policy=str(connection.get("policy", "data")),
                   package_suffix=str(spec.get("package_suffix", "_orocos")), std_msgs=std_msgs,
                   fabric=FabricTarget.from_spec(spec["fabric"]),
                   latest_queue=int(switch.get("latest_queue", 64)), control_queue=int(switch.get("control_queue", 16)),
                   fabric_switch_note=str(switch.get("fabric_note", "")))


@dataclass
class OrocosView:
    system: Data  # libraries, instances, links
    definitions: list[Data]  # one per subsystem definition: a component library, a FABRIC subsystem model
    instances: list[Data]  # one per subsystem instance: a deployer script, a FABRIC run-time configuration
    notes: list[str]  # the subsystem definitions FABRIC cannot express (no FABRIC package written)


def xml_text(text: str) -> str:
    """Text safe in an XML attribute value (double quotes) and element content."""
    clean = "".join(c for c in " ".join(text.split()) if c >= " ")
    return escape(clean, {'"': "&quot;"})


def xml_comment(text: str) -> str:
    """Text safe inside an XML comment ``<!-- … -->``: one line, no ``--`` (which XML forbids
    there) and no ``-`` at its end (which would make ``--->``)."""
    clean = "".join(c for c in " ".join(text.split()) if c >= " ")
    while "--" in clean:
        clean = clean.replace("--", "- -")
    return clean + " " if clean.endswith("-") else clean


def _elements(name: str, replicated: bool, count: int) -> list[tuple[str, str]]:
    """(port name, index suffix) of every element of a (possibly replicated) member."""
    if not replicated:
        return [(name, "")]
    return [(f"{name}_{k + 1}", f"[{k}]") for k in range(count)]


class _Ports:
    """The port names of one component: distinct, or generation stops (rule D004)."""

    def __init__(self, owner: str) -> None:
        self.owner = owner
        self.taken: set[str] = set()

    def take(self, name: str) -> str:
        if name in self.taken:
            raise GenError(f"D004 {self.owner}: two ports are named {name}")
        self.taken.add(name)
        return name


def build_view(model: EarlModel, cpp: CppView, msgs: MsgView, msg_target: MsgTarget,
               target: OrocosTarget) -> OrocosView:
    """The view of a model from its C++ and msg views; raises GenError when it cannot be generated."""
    system = model.system
    if system is None:
        raise GenError("the model has no EARL System to generate")
    return _Builder(model, system, cpp, msgs, msg_target, target).build()


class _Builder:
    """Builds the view in order: definitions, instances (their component names), links, then what
    needs every link (FABRIC's channels, each instance's connections)."""

    def __init__(self, model: EarlModel, system: System, cpp: CppView, msgs: MsgView, msg_target: MsgTarget,
                 target: OrocosTarget) -> None:
        self.model = model
        self.system = system
        self.cpp = cpp
        self.msgs = msgs
        self.msg_target = msg_target
        self.target = target
        self.model_ns = cpp.system["ns"]
        self.msg_names = {m["key"]: m["name"] for m in msgs.messages}
        self.components: dict[str, str] = {}  # component name in lower case -> what it is, for D004
        self.port_of: dict[str, tuple[str, str]] = {}  # buffer path -> (master component, port)
        self.wiring = switch_wiring(model)  # None without configurations

    def build(self) -> OrocosView:
        definitions = self._definitions()
        by_block = {definition["block_id"]: entry for definition, entry in zip(self.cpp.subsystems, definitions)}
        placed = self._instances(by_block)
        instances = [instance for instance, _ in placed]
        links = self._links()
        for instance in instances:
            instance["switch"] = instance_switch(self.wiring, instance["trace"], links, instance["name"])
        several = self._fabric_configurations(placed, links)
        self._connections(instances, links)
        notes = [d["fabric_note"] for d in definitions if d["fabric_note"]] + several
        if self.wiring is not None:
            notes.append(self.target.fabric_switch_note)
        return OrocosView(system=self._system(definitions, instances, links), definitions=definitions,
                          instances=instances, notes=notes)

    def _ros_message(self, datatype: str, where: str) -> str:
        """The ROS message type of a buffer of this dataType, as the FABRIC files name it."""
        external = self.target.fabric.external_message(self.model.datatypes.get(datatype))
        if external is not None:
            return external
        if datatype in self.msg_names:
            return f"{self.msgs.package}::{self.msg_names[datatype]}"
        ros = ros_type(self.model, datatype, self.msg_names, self.msg_target, where)
        wrapper = self.target.std_msgs.get(ros)
        if wrapper is None:
            raise GenError(f"{where}: no std_msgs message for the ROS type {ros}")
        return f"std_msgs::{wrapper}"

    def _definitions(self) -> list[Data]:
        """One entry per subsystem definition, made from its first instance."""
        first: dict[str, Subsystem] = {}
        for sub in self.model.subsystems:
            first.setdefault(sub.block_id, sub)
        blocks = {sub.path: sub.block_id for sub in self.model.subsystems}
        entries = []
        for definition in self.cpp.subsystems:
            entry = _definition(self.model, first[definition["block_id"]], definition, self.model_ns,
                                self._ros_message, self.target, self.wiring is not None)
            entry["switch"] = definition_switch(self.wiring, self.cpp.system, definition["block_id"], blocks)
            entries.append(entry)
        return entries

    def _component(self, name: str, what: str) -> str:
        """A component name, refused (rule D004) when it equals another one but for case."""
        if name.lower() in self.components:
            raise GenError(f"D004 {what}: the component name {name} is also that of {self.components[name.lower()]}")
        self.components[name.lower()] = what
        return name

    def _instances(self, by_block: dict[str, Data]) -> list[tuple[Data, Data]]:
        """(instance, its definition) of every subsystem instance."""
        placed: list[tuple[Data, Data]] = []
        for agent_view, agent in zip(self.cpp.agents, self.system.agents):
            for instance_view, sub in zip(agent_view["instances"], agent.subsystems):
                entry = by_block[sub.block_id]
                placed.append((self._instance(f"{agent_view['ns']}_{instance_view['member']}", sub, entry), entry))
        return placed

    def _instance(self, name: str, sub: Subsystem, entry: Data) -> Data:
        """A subsystem instance: its master component, named ``name``, and its pf components."""
        master = self._component(name, sub.path)
        pfs = [_pf_instance(master, pf, self._component(f"{master}_{pf['role']}", f"{sub.path} pf {pf['role']}"))
               for pf in entry["pfs"]]
        ports = {(b["template"], b["index"]): b for b in entry["buffers"]}
        for buf in sub.buffers:
            self.port_of[buf.path] = (master, ports[(buf.template, buf.index)]["port"])
        target = self.target
        return {"name": master, "path": xml_comment(sub.path), "comment": cpp_comment(sub.path),
                "type": entry["master_type"],
                "library": entry["library"], "pfs": pfs, "buffers": entry["buffers"], "io": [],
                "event_driven": entry["event_driven"],
                "period": 0.0 if entry["event_driven"] else target.period,
                "priority": target.priority, "scheduler": target.scheduler,
                "policy": target.policy, "package": entry["library"], "trace": sub.path}

    def _links(self) -> list[Data]:
        """The connection of every link, from output port to input port, with its queue."""
        model, port_of = self.model, self.port_of
        links: list[Data] = []
        for link in model.links:
            if not link.source or not link.target or link.source not in port_of or link.target not in port_of:
                raise GenError(f"{link.path}: a link goes from an Output Buffer to an Input Buffer (rule C001)")
            source, destination = port_of[link.source], port_of[link.target]
            target_buffer = model.buffer(link.target)
            queue = target_buffer.queue_size if target_buffer is not None and target_buffer.receive == "queue" else 0
            entry = {"name": xml_text(link.name), "from": f"{source[0]}.{source[1]}",
                     "to": f"{destination[0]}.{destination[1]}", "queue": queue,
                     "policy": f"queue{queue}" if queue else "links", "trace": link.path}
            variable = self.wiring.link_index(link.path) if self.wiring is not None else -1
            if variable >= 0:  # its own ports at both ends, a buffer connection (orocos_switch)
                queue = queue or self.target.latest_queue
                entry.update(variable=variable, source_port=source[1], target_port=destination[1],
                             queue=queue, policy=f"queue{queue}",
                             **{"from": f"{source[0]}.{link_port(source[1], link)}",
                                "to": f"{destination[0]}.{link_port(destination[1], link)}"})
            links.append(entry)
        return links

    def _fabric_configurations(self, placed: list[tuple[Data, Data]], links: list[Data]) -> list[str]:
        """FABRIC's run-time configuration of every instance whose definition FABRIC can express,
        and whose every Input Buffer reads one IPC channel: FABRIC's deployer names one channel
        per buffer (``<io_buffer alias name>``, the first of an alias counts). An instance with an
        Input Buffer fed by several outputs gets none, and a note says so; its components and
        deployment connect every link (an RTT input port takes several connections)."""
        channels: dict[str, str] = {}  # "<master>.<input port>" -> the IPC channel of the linked output
        several: dict[str, list[str]] = {}  # the same, of an input port fed by several channels
        variable: dict[str, list[str]] = {}  # the same, of the variable links (several per input port)
        # the channel a buffer names (import fabric carries FABRIC's <io_buffer name>), else one of its own
        carried = {".".join(self.port_of[buf.path]): buf.channel
                   for sub in self.model.subsystems for buf in sub.buffers if buf.channel and buf.path in self.port_of}
        for connection in links:  # an output without a channel of its own writes the one its reader names
            if connection.get("variable", -1) < 0 and connection["to"] in carried:
                carried.setdefault(connection["from"], carried[connection["to"]])
        alias_of = {f"{i['name']}.{b['port']}": carried.get(f"{i['name']}.{b['port']}", f"{i['name']}_{b['alias']}")
                    for i, _ in placed for b in i["buffers"]}
        for connection in links:
            if connection.get("variable", -1) >= 0:
                source = f"{connection['from'].partition('.')[0]}.{connection['source_port']}"
                target = f"{connection['to'].partition('.')[0]}.{connection['target_port']}"
                variable.setdefault(target, []).append(alias_of[source])
                continue
            channel = alias_of[connection["from"]]
            if channels.setdefault(connection["to"], channel) != channel:
                several.setdefault(connection["to"], [channels[connection["to"]]])
                if channel not in several[connection["to"]]:
                    several[connection["to"]].append(channel)
        for port, channel in carried.items():
            channels.setdefault(port, channel)
        buffer_of = {f"{master}.{port}": path for path, (master, port) in self.port_of.items()}
        notes: list[str] = []
        for instance, definition in placed:
            fed = sorted(port for port in several if port.partition(".")[0] == instance["name"])
            if fed and definition["fabric"] is not None:
                notes.append(f"{instance['trace']}: FABRIC reads an Input Buffer from one IPC channel, and "
                             + "; ".join(f"{buffer_of.get(port, port)} is fed by {len(several[port])} channels "
                                         f"({', '.join(several[port])})" for port in fed)
                             + f": {FABRIC_FOLDER}/{instance['package']}/config/{instance['name']}.xml is not "
                             "written (the Orocos components and deploy/ connect every link)")
            instance["fabric"] = None if definition["fabric"] is None or fed else instance_configuration(
                instance, definition["fabric"], definition["pfs"], channels, self.target.fabric)
            if instance["fabric"] is not None and variable:
                fabric_variable_buffers(instance, channels, variable)
        return notes

    @staticmethod
    def _connections(instances: list[Data], links: list[Data]) -> None:
        """The links into each instance, and the ends each of its buffers is connected to (itself if none)."""
        for instance in instances:
            master = instance["name"]
            instance["links"] = [link for link in links if link["to"].partition(".")[0] == master]
            for buf in instance["buffers"]:
                own = f"{master}.{buf['port']}"
                ends = [link["from"] if buf["direction"] == "in" else link["to"] for link in links
                        if own == (link["to"] if buf["direction"] == "in" else link["from"])]
                instance["io"] += [{"alias": buf["port"], "name": end} for end in ends or [own]]

    def _system(self, definitions: list[Data], instances: list[Data], links: list[Data]) -> Data:
        """The CMake project: its component libraries; the deployment: instances and links."""
        libraries = [{"name": d["library"], "source": d["source"],
                      "types": [d["master_type"]] + [p["type"] for p in d["pfs"]]} for d in definitions]
        project = field_name(self.model.name or self.system.name or "model") + self.target.package_suffix
        return {"model": self.cpp.system["model"], "ns": self.model_ns, "project": project, "libraries": libraries,
                "instances": instances, "links": links, "includes": ["runtime", "generated/include", "user"],
                "queues": sorted({link["queue"] for link in links if link["queue"]}), "trace": self.cpp.system["trace"],
                "switch": system_switch(self.wiring, {i["trace"]: i["name"] for i in instances},
                                        self.target.control_queue)}


def _pf_instance(master: str, pf: Data, name: str) -> Data:
    """A pf component of a master component: its name, type and connections to the master."""
    connections = []
    for port in pf["ports"]:
        master_end, pf_end = f"{master}.{port['master_port']}", f"{name}.{port['port']}"
        connections.append({"from": master_end, "to": pf_end} if port["to_pf"] else {"from": pf_end, "to": master_end})
    return {"name": name, "role": pf["role"], "type": pf["type"], "connections": connections}


def _pf_ports(pf: Data, where: str, master_ports: _Ports, sync_memory: bool) -> list[Data]:
    """The ports of a pf component and their peers on the master. ``sync_memory`` (a model with
    configurations, whose agents restart or resume): a memory the pf writes (mo) also comes
    from the master before each run (kind ms), so that every pf of the subsystem and a
    reactivation see the master's value."""
    pf_ports = _Ports(f"{where} pf {pf['cls']}")
    entries: list[Data] = []
    for accessor in pf["accessors"]:
        kind = accessor["kind"]
        if kind == "m":
            kind = "mo" if accessor["mutable"] else "mi"
        for name, at in _elements(accessor["name"], accessor["replicated"], accessor["count"]):
            access = f"{accessor['member']}{at}"
            kinds = [kind, "ms"] if kind == "mo" and sync_memory else [kind]
            for k in kinds:
                port = pf_ports.take(f"{name}_in" if k == "ms" else name)
                entries.append({
                    "port": port, "master_port": master_ports.take(f"{pf['cls']}_{port}"), "kind": k,
                    "type": accessor["type"], "to_pf": k in ("ib", "mi", "ms"),
                    "master_access": f"data.{access}", "pf_access": f"data_.{access}",
                })
    return entries


def _definition(model: EarlModel, sub: Subsystem, definition: Data, model_ns: str,
                ros_message: Callable[[str, str], str], target: OrocosTarget, sync_memory: bool = False) -> Data:
    """A subsystem definition: its master component, its pf components, its FABRIC model."""
    ns = definition["ns"]
    where = sub.path
    master_ports = _Ports(f"{where} master component")
    ports = {p["member"]: p for p in definition["ports"]}
    template_of = {definition["port_members"][b.template]: b for b in sub.buffers}
    kinds = _sides(model, sub)
    # inputs obligatory in some buffer group: event ports, whose data wakes the master
    obligatory = {p["member"] for group in definition["groups"] for p in group["ports"]}
    buffers: list[Data] = []
    for member, port in ports.items():
        buf = template_of[member]
        for k, (name, at) in enumerate(_elements(member, port["replicated"], port["count"])):
            index = k + 1 if port["replicated"] else 0
            instance_path = next(b.path for b in sub.buffers if b.template == buf.template and b.index == index)
            buffers.append({"port": master_ports.take(name), "type": port["type"], "access": f"data.{member}{at}",
                            "direction": buf.direction, "template": buf.template, "index": index,
                            "queue": port.get("queue", 0),
                            "event": buf.direction == "in" and member in obligatory,
                            "ros": xml_text(ros_message(buf.datatype, buf.path)),
                            "side": kinds.get(instance_path, "top"), "member": member, "trace": instance_path})

    functions = definition["functions"]
    pfs: list[Data] = []
    run_index: dict[str, int] = {}
    for n, (pf, model_pf) in enumerate(zip(functions, sub.functions)):
        run_index[pf["run"]] = n
        pf_entries = _pf_ports(pf, where, master_ports, sync_memory)
        pfs.append({"role": pf["cls"], "cls": pf["cls"], "user": pf["qualified"], "run": pf["run"], "index": n,
                    "name": pf["name"], "check": pf["check"],
                    "type": f"{ns}::orocos::{pf['cls']}", "ports": pf_entries,
                    "include": f"{definition['agent']}/{definition['sub']}/{pf['cls']}.hpp",
                    "model": cpp_comment(model_pf.name), "model_name": model_pf.name, "trace": model_pf.path})

    operations = _Ports(f"{where} master component operations")
    predicates = [{"name": operations.take(p["method"]), "method": p["method"], "text": xml_text(pp.body or pp.name),
                   "model": xml_text(pp.name), "trace": pp.path}
                  for p, pp in zip(definition["predicates"], sub.predicates)]
    conditions: list[Data] = []
    for row, bb in zip(definition["behaviours"], sub.behaviours):
        conditions += [{"name": operations.take(row["tc"]), "method": row["tc"], "trace": bb.path},
                       {"name": operations.take(row["ec"]), "method": row["ec"], "trace": bb.path}]
    for row in definition["transitions"]:
        conditions.append({"name": operations.take(row["guard"]), "method": row["guard"], "trace": row["trace"]})

    library = f"{definition['agent']}_{definition['sub']}"
    fabric: Data | None = definition_spec(model, sub, buffers, pfs, target.period, target.fabric)
    note = ""
    if fabric is None:
        note = (f"no FABRIC package for {sub.path}: a FABRIC subsystem needs an Input Buffer in a buffer "
                "group, it has none")
    else:
        fabric.update(path=xml_comment(sub.path), block=xml_comment(sub.block), trace=sub.path)
    return {
        "ns": ns, "agent": definition["agent"], "sub": definition["sub"], "path": xml_text(sub.path),
        "definition": cpp_comment(sub.block),
        "comment": definition["comment"], "model_ns": model_ns,
        "include": f"{model_ns}/{definition['agent']}/{definition['sub']}/subsystem.hpp",
        "data_include": definition["data_include"], "master_type": f"{ns}::orocos::Master",
        "library": library, "source": f"orocos/{definition['agent']}/{definition['sub']}/components.cpp",
        "buffers": buffers, "pfs": pfs, "predicates": predicates, "conditions": conditions,
        "fabric": fabric, "fabric_note": note, "model": definition["comment"], "trace": sub.path,
        "event_driven": bool(definition["activations"]), "period_ns": round(target.period * 1e9),
        "priority": target.priority, "scheduler": target.scheduler,
    }


def _sides(model: EarlModel, sub: Subsystem) -> dict[str, str]:
    """FABRIC's side of every linked buffer instance: ``bottom`` towards the hardware (a peer
    further from the control subsystem), ``top`` otherwise (and between agents)."""
    rank = _RANK.get(sub.kind, 0)
    sides: dict[str, str] = {}
    for link in model.links:
        for own, other in ((link.source, link.target), (link.target, link.source)):
            if not own or not other or model.subsystem_of(own) is not sub:
                continue
            peer = model.subsystem_of(other)
            if peer is not None and peer.agent == sub.agent and _RANK.get(peer.kind, 0) > rank:
                sides[own] = "bottom"
            else:
                sides.setdefault(own, "top")
    return sides
