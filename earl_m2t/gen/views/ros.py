"""The view of the ROS 1 target: catkin packages around the C++ target's generated code.

It is built from the C++ view (classes, port members, dataTypes) and the msg view (message
and field names), so the two targets never disagree on a name. Naming (see
docs/ros-target.md): packages, nodes and topics are snake_case (``field_name`` of the msg
target), messages CamelCase (the msg view); every buffer of a subsystem instance is the topic
``/<agent>/<subsystem>/<buffer>`` (``/manip_a/motor_controller3_ve/encoder_ib``). Two names
of one scope that map to the same ROS name are refused (D004), or with ``--force`` get
``_2``, ``_3`` …. A node publishes each
output buffer on its own topic and subscribes each input buffer on its own topic; a link
remaps the input's topic onto the output's, so the links of the model are exactly the
connections of the running graph.

A model with configurations (``switch_wiring``) adds, per node instance, its part in the switch
of ``earl/switch_protocol.hpp`` as private parameters of the launch file: its node number, its
variable agent, whether it is that agent's control subsystem or the coordinator, the variable
link of each input topic and the variable links of each output. Each variable link is its own
topic, ``<output topic>__<link>``, published only while the link is open; the commands and
acknowledgements of the switch go over ``/earl/switch`` and ``/earl/switch_ack``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

from earl_m2t.gen.errors import GenError
from earl_m2t.gen.names import cpp_identifier, cpp_string
from earl_m2t.gen.views.cpp import CppView
from earl_m2t.gen.views.msg import MsgTarget, MsgView, field_name, ros_type
from earl_m2t.gen.views.switch_wiring import SwitchWiring, switch_wiring
from earl_m2t.model.elements import Buffer, EarlModel, Subsystem, System

Data = dict[str, Any]

ROS_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
PACKAGE_NAME = re.compile(r"^[a-z][a-z0-9_]*$")


@dataclass(frozen=True)
class RosTarget:
    """The data of ``transforms/ros/target.toml`` the view needs."""

    period: float  # seconds, the default period of every node
    queue: int  # subscriber and publisher queue size
    bringup_suffix: str
    agent_suffix: str
    std_msgs: dict[str, str]  # ROS primitive type -> std_msgs message
    switch_messages: tuple[str, ...] = ()  # the switch's messages (a model with configurations)
    switch_queue: int = 1000  # queue size of the switch's control topics

    @classmethod
    def from_spec(cls, spec: dict[str, Any]) -> RosTarget:
        node = spec.get("node", {})
        return cls(period=float(node.get("period", 0.01)), queue=int(node.get("queue", 10)),
                   bringup_suffix=str(spec.get("bringup_suffix", "_bringup")),
                   agent_suffix=str(spec.get("agent_suffix", "_agent")),
                   std_msgs=dict(spec["std_msgs"]),
                   switch_messages=tuple(spec.get("switch", {}).get("messages", ())),
                   switch_queue=int(spec.get("switch", {}).get("queue", 1000)))


@dataclass
class RosView:
    system: Data  # model, packages, launch
    packages: list[Data]  # one per agent
    nodes: list[Data]  # one per subsystem definition
    convert: Data  # conversions between the C++ dataTypes and the messages


def _name(text: str, what: str) -> str:
    name = cpp_identifier(text)
    if not ROS_NAME.match(name):
        raise GenError(f"{what} '{text}' cannot become a ROS name ('{name}')")
    return name


class _Scope:
    """Hands out distinct snake_case ROS names in one scope (a namespace, a node, a package)."""

    def __init__(self, what: str, strict: bool) -> None:
        self.what = what
        self.strict = strict
        self.taken: dict[str, str] = {}  # ROS name -> the name it was made from
        self._last_number: dict[str, int] = {}

    def take(self, name: str, where: str) -> str:
        ros = base = _name(field_name(name), self.what)
        n = 1
        if ros in self.taken:  # numbering resumes where this base's last ended: linear, not quadratic
            n = self._last_number.get(base, 1)
            while ros in self.taken:
                n += 1
                ros = f"{base}_{n}"
            self._last_number[base] = n
        if n > 1 and self.strict:
            raise GenError(f"D004 {where}: '{name}' and '{self.taken[base]}' both map to the ROS {self.what} "
                           f"'{base}' (--force: '{ros}')")
        self.taken[ros] = name
        return ros


def build_view(model: EarlModel, cpp: CppView, msgs: MsgView, msg_target: MsgTarget,
               target: RosTarget, strict: bool = True) -> RosView:
    """The view of a model from its C++ and msg views; raises GenError when it cannot be generated."""
    system = model.system
    if system is None:
        raise GenError("the model has no EARL System to generate")
    return _Builder(model, system, cpp, msgs, msg_target, target, strict).build()


class _Builder:
    """Builds the view in the order its names are taken: packages, nodes, node instances."""

    def __init__(self, model: EarlModel, system: System, cpp: CppView, msgs: MsgView, msg_target: MsgTarget,
                 target: RosTarget, strict: bool) -> None:
        self.model = model
        self.system = system
        self.cpp = cpp
        self.msgs = msgs
        self.msg_target = msg_target
        self.target = target
        self.strict = strict
        self.model_ns = cpp.system["ns"]
        self.stem = field_name(model.name or system.name or "model")
        self.messages = {m["key"]: m for m in msgs.messages}  # dataType key -> its message
        self.message_names = {key: m["name"] for key, m in self.messages.items()}
        self.agent_of: dict[str, Data] = {}  # agent path -> its package
        self.node_of_block: dict[str, Data] = {}  # block id -> the node of that subsystem definition
        self.instance_of: dict[str, Data] = {}  # subsystem instance path -> its node instance
        self.topic_of: dict[str, str] = {}  # buffer instance path -> its absolute topic
        self.wiring: SwitchWiring | None = switch_wiring(model)
        self.link_names = _Scope("variable link", strict)
        self.link_topic: dict[str, str] = {}  # variable link path -> its ROS-safe name

    def build(self) -> RosView:
        packages = self._packages()
        bringup = self._bringup_name()
        nodes = self._nodes()
        self._instances()
        links = self._links()
        messages = [m["name"] for m in self.msgs.messages]
        if self.wiring is not None:
            messages += list(self.target.switch_messages)
        system = {"model": self.cpp.system["model"], "msgs": self.msgs.package,
                  "messages": messages, "bringup": bringup, "stem": self.stem,
                  "agents": packages, "links": links, "period": self.target.period, "nodes": len(self.instance_of),
                  "trace": self.cpp.system["trace"], "switch": self.wiring is not None}
        return RosView(system=system, packages=packages, nodes=nodes, convert=self._convert())

    def _message(self, datatype: str, where: str) -> tuple[str, str, str]:
        """(C++ message type, header, field suffix) of a buffer of this dataType."""
        package = self.msgs.package
        if datatype in self.messages:
            name = self.messages[datatype]["name"]
            return f"{package}::{name}", f"{package}/{name}.h", ""
        ros = ros_type(self.model, datatype, self.message_names, self.msg_target, where)
        wrapper = self.target.std_msgs.get(ros)
        if wrapper is None:
            raise GenError(f"{where}: no std_msgs message for the ROS type {ros}")
        return f"std_msgs::{wrapper}", f"std_msgs/{wrapper}.h", ".data"

    # ------------------------------------------------------------------ packages

    def _packages(self) -> list[Data]:
        """One package per agent, named after the model and the agent's C++ namespace. The names
        of the messages' and the bringup's packages are the model's: an agent whose name would
        take one (an agent named ``msgs``) gets the suffix ``_agent``, so that no model a check
        passes is refused here."""
        packages: list[Data] = []
        generated = {self.msgs.package, self._bringup_name()}
        taken = set(generated)
        namespaces = _Scope("namespace", self.strict)
        for agent_view in self.cpp.agents:
            path = agent_view["path"]
            name = f"{self.stem}_{field_name(agent_view['ns'])}"
            if not PACKAGE_NAME.match(name):
                raise GenError(f"D003 agent {path}: the package name {name} is not a ROS name")
            if name in generated:
                name = self._free(f"{name}{self.target.agent_suffix}", taken)
            if name in taken:
                raise GenError(f"D004 agent {path}: the package name {name} is taken")
            taken.add(name)
            package: Data = {"name": name, "ns": namespaces.take(agent_view["ns"], path), "path": path,
                             "trace": path, "comment": agent_view["comment"], "nodes": [], "instances": [],
                             "depends": set()}
            packages.append(package)
            self.agent_of[path] = package
        return packages

    @staticmethod
    def _free(name: str, taken: set[str]) -> str:
        """``name``, else the first of ``name2``, ``name3``, … not taken."""
        n, free = 1, name
        while free in taken:
            n += 1
            free = f"{name}{n}"
        return free

    def _bringup_name(self) -> str:
        """The name of the package of the system's launch file."""
        name = self.stem + self.target.bringup_suffix
        if name == self.msgs.package:
            raise GenError(f"D004 the package name {name} is taken")
        return name

    # ------------------------------------------------------------------ nodes

    def _nodes(self) -> list[Data]:
        """One node per subsystem definition, in the package of the agent of its first instance."""
        first_instance: dict[str, Subsystem] = {}
        for sub in self.model.subsystems:
            first_instance.setdefault(sub.block_id, sub)
        nodes: list[Data] = []
        executables: dict[str, _Scope] = {}  # package name -> the executables of the package
        for definition in self.cpp.subsystems:
            sub = first_instance[definition["block_id"]]
            package = self.agent_of[sub.agent]
            scope = executables.setdefault(package["name"], _Scope("executable", self.strict))
            exe = scope.take(definition["sub"], sub.path) + "_node"
            node = self._node(definition, sub, package["name"], exe)
            nodes.append(node)
            self.node_of_block[definition["block_id"]] = node
            package["nodes"].append(node)
        return nodes

    def _node(self, definition: Data, sub: Subsystem, package: str, exe: str) -> Data:
        elements, headers = self._topics(definition, sub)
        model_ns = self.model_ns
        return {"target": f"{package}_{exe}", "exe": exe, "source": f"src/{exe}.cpp", "package": package,
                "cls": f"::{definition['ns']}::Subsystem",
                "include": f"{model_ns}/{definition['agent']}/{definition['sub']}/subsystem.hpp",
                "path": cpp_string(sub.path), "comment": definition["comment"], "model_ns": model_ns,
                "trace": sub.path, "headers": sorted(headers),
                "inputs": [e for e in elements if e["kind"] == "ib"],
                "outputs": [e for e in elements if e["kind"] == "ob"], "period": self.target.period,
                "queue": self.target.queue, "convert": f"{model_ns}/ros/convert.hpp",
                "convert_ns": f"{model_ns}_ros", "model": self.cpp.system["model"], "switch": self._node_switch()}

    def _node_switch(self) -> Data | None:
        """What a node of a model with configurations needs to take part in the switch."""
        if self.wiring is None:
            return None
        switching = self.cpp.system["switching"]
        return {"system": f"::{self.model_ns}::System", "include": f"{self.model_ns}/system.hpp",
                "nodes": len(self.wiring.nodes), "initial": switching["initial"],
                "initial_comment": switching["initial_comment"], "queue": self.target.switch_queue,
                "command": f"{self.msgs.package}::{self.target.switch_messages[0]}",
                "ack": f"{self.msgs.package}::{self.target.switch_messages[1]}",
                "headers": [f"{self.msgs.package}/{m}.h" for m in self.target.switch_messages]}

    def _topics(self, definition: Data, sub: Subsystem) -> tuple[list[Data], set[str]]:
        """The topic of every buffer of a node, by port and index, and the message headers it needs.
        An input with several links has one topic per link."""
        topics = _Scope("topic", self.strict)
        ports = {p["member"]: p for p in definition["ports"]}
        by_template: dict[str, list[Buffer]] = {}
        for buf in sub.buffers:
            by_template.setdefault(buf.template, []).append(buf)
        elements: list[Data] = []
        headers: set[str] = set()
        for template, bufs in by_template.items():
            member = definition["port_members"][template]
            port = ports[member]
            msg_type, header, suffix = self._message(bufs[0].datatype, bufs[0].path)
            headers.add(header)
            for buf in sorted(bufs, key=lambda b: b.index):
                access = f"data.{member}" + (f"[{buf.index - 1}]" if buf.index else "")
                topic = topics.take(buf.name, buf.path)
                elements.append({"kind": port["kind"], "access": access, "topic": topic, "type": port["type"],
                                 "msg": msg_type, "suffix": suffix, "links": port["links"], "id": len(elements),
                                 # a queued input: roscpp keeps every message (0: no limit) and the
                                 # runtime's queue reports an overflow; roscpp would drop the oldest
                                 "queue": 0 if port.get("queue", 0) else self.target.queue,
                                 "template": template, "index": buf.index, "trace": buf.path,
                                 "topics": [topic] if port["links"] == 1 or port["kind"] == "ob"
                                 else [topics.take(f"{topic}_link{k + 1}", buf.path) for k in range(port["links"])]})
        return elements, headers

    # ------------------------------------------------------------------ node instances and links

    def _instances(self) -> None:
        """One node instance per subsystem instance, in the launch file of its agent's package."""
        for agent_view, agent in zip(self.cpp.agents, self.system.agents):
            package = self.agent_of[agent_view["path"]]
            node_names = _Scope("node", self.strict)
            for instance_view, sub in zip(agent_view["instances"], agent.subsystems):
                node = self.node_of_block[sub.block_id]
                name = node_names.take(instance_view["member"], sub.path)
                instance = {"name": name, "ns": package["ns"], "pkg": node["package"], "type": node["exe"],
                            "path": sub.path, "remaps": [], "trace": sub.path, "switch": self._instance_switch(sub)}
                if node["package"] != package["name"]:
                    package["depends"].add(node["package"])
                package["instances"].append(instance)
                self.instance_of[sub.path] = instance
                by_end = {(e["template"], e["index"]): e for e in node["inputs"] + node["outputs"]}
                for buf in sub.buffers:
                    element = by_end[(buf.template, buf.index)]
                    self.topic_of[buf.path] = f"/{package['ns']}/{name}/{element['topic']}"
            package["depends"] = sorted(package["depends"])

    def _instance_switch(self, sub: Subsystem) -> Data | None:
        """The part of a node instance in the switch (launch file parameters), None without one."""
        if self.wiring is None:
            return None
        wiring = self.wiring.node(sub.path)
        return {"node": wiring.index, "agent": wiring.agent, "control": str(wiring.control).lower(),
                "coordinator": str(wiring.coordinator).lower(), "nodes": len(self.wiring.nodes),
                "inputs": [], "outputs": {}}

    def _variable_link(self, path: str, name: str) -> tuple[int, str]:
        """(index, ROS-safe name) of a variable link, (-1, "") for a link of every configuration."""
        index = self.wiring.link_index(path) if self.wiring is not None else -1
        if index < 0:
            return -1, ""
        if path not in self.link_topic:
            self.link_topic[path] = self.link_names.take(name, path)
        return index, self.link_topic[path]

    def _links(self) -> list[Data]:
        """Every link: a remap of the input's topic onto the output's, and the link counts each node
        instance waits for (``~<topic>_links``)."""
        model, topic_of = self.model, self.topic_of
        used: dict[str, int] = {}  # input buffer path -> its links remapped so far
        counts: dict[tuple[str, str], int] = {}  # (instance path, topic) -> links to wait for
        links: list[Data] = []
        for link in model.links:
            if not link.source or not link.target or link.source not in topic_of or link.target not in topic_of:
                raise GenError(f"{link.path}: a link goes from an Output Buffer to an Input Buffer (rule C001)")
            target_sub = model.subsystem_of(link.target)
            assert target_sub is not None
            instance = self.instance_of[target_sub.path]
            node = self.node_of_block[target_sub.block_id]
            buf = model.buffer(link.target)
            assert buf is not None
            element = next(e for e in node["inputs"] if (e["template"], e["index"]) == (buf.template, buf.index))
            k = used.get(link.target, 0)
            used[link.target] = k + 1
            source = topic_of[link.source]
            variable, safe = self._variable_link(link.path, link.name)
            source_sub = model.subsystem_of(link.source)
            assert source_sub is not None
            if variable >= 0:  # its own topic, published while the link is open
                source = f"{source}__{safe}"
                instance["switch"]["inputs"].append((element["topics"][k], variable))
                outputs = self.instance_of[source_sub.path]["switch"]["outputs"]
                outputs.setdefault(topic_of[link.source].rpartition("/")[2], []).append(f"{variable}:{safe}")
            remap_from = f"/{instance['ns']}/{instance['name']}/{element['topics'][k]}"
            instance["remaps"].append({"from": remap_from, "to": source, "link": link.name, "trace": link.path})
            counts[(target_sub.path, element["topics"][k])] = 1
            source_name = source.rpartition("/")[2]
            counts[(source_sub.path, source_name)] = counts.get((source_sub.path, source_name), 0) + 1
            links.append({"name": link.name, "source": link.source, "target": link.target, "topic": source,
                          "trace": link.path})
        for path, instance in self.instance_of.items():
            instance["links"] = sorted((topic, n) for (p, topic), n in counts.items() if p == path)
            if instance["switch"] is not None:
                instance["switch"]["outputs"] = sorted((topic, " ".join(specs))
                                                       for topic, specs in instance["switch"]["outputs"].items())
        return links

    # ------------------------------------------------------------------ conversions

    def _convert(self) -> Data:
        """The conversions between the model's C++ dataTypes and their messages."""
        model_ns, package = self.model_ns, self.msgs.package
        structs: list[Data] = []
        for t in self.cpp.system["types"]:
            message = self.messages.get(t["key"])
            if message is None:
                continue
            if t["kind"] == "enum":
                structs.append({"kind": "enum", "cpp": f"::{model_ns}::types::{t['name']}",
                                "msg": f"{package}::{message['name']}", "trace": t["key"]})
                continue
            fields = [{"cpp": f["name"], "msg": m["name"], "trace": f["trace"]}
                      for f, m in zip(t["fields"], message["fields"])]
            structs.append({"kind": "struct", "cpp": f"::{model_ns}::types::{t['name']}",
                            "msg": f"{package}::{message['name']}", "fields": fields,
                            "header": f"{package}/{message['name']}.h", "trace": t["key"]})
        return {"ns": f"{model_ns}_ros", "structs": structs, "model": self.cpp.system["model"],
                "include": f"{model_ns}/types.hpp",
                "headers": sorted({f"{package}/{m['name']}.h" for m in self.msgs.messages})}
