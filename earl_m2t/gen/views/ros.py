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
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

from earl_m2t.gen.errors import GenError
from earl_m2t.gen.names import cpp_identifier, cpp_string
from earl_m2t.gen.views.cpp import CppView
from earl_m2t.gen.views.msg import MsgTarget, MsgView, field_name, ros_type
from earl_m2t.model.elements import EarlModel

Data = dict[str, Any]

ROS_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
PACKAGE_NAME = re.compile(r"^[a-z][a-z0-9_]*$")


@dataclass(frozen=True)
class RosTarget:
    """The data of ``transforms/ros/target.toml`` the view needs."""

    period: float  # seconds, the default period of every node
    queue: int  # subscriber and publisher queue size
    bringup_suffix: str
    std_msgs: dict[str, str]  # ROS primitive type -> std_msgs message

    @classmethod
    def from_spec(cls, spec: dict[str, Any]) -> RosTarget:
        node = spec.get("node", {})
        return cls(period=float(node.get("period", 0.01)), queue=int(node.get("queue", 10)),
                   bringup_suffix=str(spec.get("bringup_suffix", "_bringup")),
                   std_msgs=dict(spec["std_msgs"]))


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
    system = model.system
    if system is None:
        raise GenError("the model has no EARL System to generate")
    model_ns = cpp.system["ns"]
    stem = field_name(model.name or system.name or "model")
    msg_names = {m["key"]: m for m in msgs.messages}
    names = {key: m["name"] for key, m in msg_names.items()}

    def ros_msg(datatype: str, where: str) -> tuple[str, str, str]:
        """(C++ message type, header, field suffix) of a buffer of this dataType."""
        if datatype in msg_names:
            name = msg_names[datatype]["name"]
            return f"{msgs.package}::{name}", f"{msgs.package}/{name}.h", ""
        ros = ros_type(model, datatype, names, msg_target, where)
        wrapper = target.std_msgs.get(ros)
        if wrapper is None:
            raise GenError(f"{where}: no std_msgs message for the ROS type {ros}")
        return f"std_msgs::{wrapper}", f"std_msgs/{wrapper}.h", ".data"

    # topics: buffer path -> absolute topic; inputs: buffer path -> link sources
    agent_of: dict[str, Data] = {}
    packages: list[Data] = []
    taken_packages = {msgs.package}
    namespaces = _Scope("namespace", strict)
    for agent_view in cpp.agents:
        package_name = f"{stem}_{field_name(agent_view['ns'])}"
        if not PACKAGE_NAME.match(package_name):
            raise GenError(f"D003 agent {agent_view['path']}: the package name {package_name} is not a ROS name")
        if package_name in taken_packages:
            raise GenError(f"D004 agent {agent_view['path']}: the package name {package_name} is taken")
        taken_packages.add(package_name)
        entry: Data = {"name": package_name, "ns": namespaces.take(agent_view["ns"], agent_view["path"]),
                       "path": agent_view["path"], "trace": agent_view["path"],
                 "comment": agent_view["comment"], "nodes": [], "instances": [], "depends": set()}
        packages.append(entry)
        agent_of[agent_view["path"]] = entry
    bringup = stem + target.bringup_suffix
    if bringup in taken_packages:
        raise GenError(f"D004 the package name {bringup} is taken")

    # subsystem definitions -> nodes
    first_instance: dict[str, Any] = {}
    for sub in model.subsystems:
        first_instance.setdefault(sub.block_id, sub)
    nodes: list[Data] = []
    node_of_block: dict[str, Data] = {}
    package: Data
    executables: dict[str, _Scope] = {}
    for definition in cpp.subsystems:
        sub = first_instance[definition["block_id"]]
        package = agent_of[sub.agent]
        exe = executables.setdefault(package["name"], _Scope("executable", strict)).take(
            definition["sub"], sub.path) + "_node"
        topics = _Scope("topic", strict)
        ports = {p["member"]: p for p in definition["ports"]}
        by_template: dict[str, list[Any]] = {}
        for buf in sub.buffers:
            by_template.setdefault(buf.template, []).append(buf)
        elements: list[Data] = []
        headers: set[str] = set()
        for template, bufs in by_template.items():
            member = definition["port_members"][template]
            port = ports[member]
            msg_type, header, suffix = ros_msg(bufs[0].datatype, bufs[0].path)
            headers.add(header)
            for buf in sorted(bufs, key=lambda b: b.index):
                access = f"data.{member}" + (f"[{buf.index - 1}]" if buf.index else "")
                topic = topics.take(buf.name, buf.path)
                n = len(elements)
                elements.append({"kind": port["kind"], "access": access, "topic": topic, "type": port["type"],
                                 "msg": msg_type, "suffix": suffix, "links": port["links"], "id": n,
                                 # a queued input: roscpp keeps every message (0: no limit) and the
                                 # runtime's queue reports an overflow; roscpp would drop the oldest
                                 "queue": 0 if port.get("queue", 0) else target.queue,
                                 "template": template, "index": buf.index, "trace": buf.path,
                                 "topics": [topic] if port["links"] == 1 or port["kind"] == "ob"
                                 else [topics.take(f"{topic}_link{k + 1}", buf.path) for k in range(port["links"])]})
        node = {"target": f"{package['name']}_{exe}", "exe": exe, "source": f"src/{exe}.cpp", "package": package["name"],
                "cls": f"::{definition['ns']}::Subsystem",
                "include": f"{model_ns}/{definition['agent']}/{definition['sub']}/subsystem.hpp",
                "path": cpp_string(sub.path), "comment": definition["comment"], "model_ns": model_ns, "trace": sub.path,
                "headers": sorted(headers), "inputs": [e for e in elements if e["kind"] == "ib"],
                "outputs": [e for e in elements if e["kind"] == "ob"], "period": target.period,
                "queue": target.queue, "convert": f"{model_ns}/ros/convert.hpp",
                "convert_ns": f"{model_ns}_ros", "model": cpp.system["model"]}
        nodes.append(node)
        node_of_block[definition["block_id"]] = node
        package["nodes"].append(node)

    # instances and links
    topic_of: dict[str, str] = {}
    instance_of: dict[str, Data] = {}
    for agent_view, agent in zip(cpp.agents, system.agents):
        package = agent_of[agent_view["path"]]
        node_names = _Scope("node", strict)
        for instance_view, sub in zip(agent_view["instances"], agent.subsystems):
            node = node_of_block[sub.block_id]
            name = node_names.take(instance_view["member"], sub.path)
            instance = {"name": name, "ns": package["ns"], "pkg": node["package"], "type": node["exe"],
                        "path": sub.path, "remaps": [], "trace": sub.path}
            if node["package"] != package["name"]:
                package["depends"].add(node["package"])
            package["instances"].append(instance)
            instance_of[sub.path] = instance
            by_end = {(e["template"], e["index"]): e for e in node["inputs"] + node["outputs"]}
            for buf in sub.buffers:
                element = by_end[(buf.template, buf.index)]
                topic_of[buf.path] = f"/{package['ns']}/{name}/{element['topic']}"
    used: dict[str, int] = {}
    counts: dict[tuple[str, str], int] = {}  # (instance path, topic) -> links to wait for
    links: list[Data] = []
    for link in model.links:
        if not link.source or not link.target or link.source not in topic_of or link.target not in topic_of:
            raise GenError(f"{link.path}: a link goes from an Output Buffer to an Input Buffer (rule C001)")
        target_sub = model.subsystem_of(link.target)
        assert target_sub is not None
        instance = instance_of[target_sub.path]
        node = node_of_block[target_sub.block_id]
        buf = model.buffer(link.target)
        assert buf is not None
        element = next(e for e in node["inputs"] if (e["template"], e["index"]) == (buf.template, buf.index))
        k = used.get(link.target, 0)
        used[link.target] = k + 1
        source = topic_of[link.source]
        remap_from = f"/{instance['ns']}/{instance['name']}/{element['topics'][k]}"
        instance["remaps"].append({"from": remap_from, "to": source, "link": link.name, "trace": link.path})
        counts[(target_sub.path, element["topics"][k])] = 1
        source_name = source.rpartition("/")[2]
        source_sub = model.subsystem_of(link.source)
        assert source_sub is not None
        counts[(source_sub.path, source_name)] = counts.get((source_sub.path, source_name), 0) + 1
        links.append({"name": link.name, "source": link.source, "target": link.target, "topic": source,
                      "trace": link.path})
    for package in packages:
        package["depends"] = sorted(package["depends"])
    for path, instance in instance_of.items():
        instance["links"] = sorted((topic, n) for (p, topic), n in counts.items() if p == path)

    structs: list[Data] = []
    for t in cpp.system["types"]:
        message = msg_names.get(t["key"])
        if message is None:
            continue
        if t["kind"] == "enum":
            structs.append({"kind": "enum", "cpp": f"::{model_ns}::types::{t['name']}",
                            "msg": f"{msgs.package}::{message['name']}", "trace": t["key"]})
            continue
        fields = [{"cpp": f["name"], "msg": m["name"], "trace": f["trace"]}
                  for f, m in zip(t["fields"], message["fields"])]
        structs.append({"kind": "struct", "cpp": f"::{model_ns}::types::{t['name']}",
                        "msg": f"{msgs.package}::{message['name']}", "fields": fields,
                        "header": f"{msgs.package}/{message['name']}.h", "trace": t["key"]})
    convert: Data = {"ns": f"{model_ns}_ros", "structs": structs, "model": cpp.system["model"],
               "include": f"{model_ns}/types.hpp",
               "headers": sorted({f"{msgs.package}/{m['name']}.h" for m in msgs.messages})}
    system_data = {"model": cpp.system["model"], "msgs": msgs.package, "messages": [m["name"] for m in msgs.messages],
                   "bringup": bringup, "stem": stem, "agents": packages, "links": links, "period": target.period,
                   "nodes": len(instance_of)}
    system_data["trace"] = cpp.system["trace"]
    return RosView(system=system_data, packages=packages, nodes=nodes, convert=convert)
