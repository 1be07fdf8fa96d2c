"""The view of the ROS 2 target: ament_cmake packages around the C++ target's generated code.

It starts from the ROS 1 target's view (:mod:`earl_m2t.gen.views.ros`), whose packages, node
instances, topics, remaps and link counts mean the same in ROS 2: a package per agent, a
subsystem instance is a node ``/<agent>/<subsystem>`` whose buffers are the topics
``/<agent>/<subsystem>/<buffer>``, and a link remaps the input's topic onto the output's. What
changes is how the code reaches them: a subsystem definition is an rclcpp component (class
``<package>::<Node>``, registered with ``rclcpp_components_register_node`` so that it also runs
as the executable ``<node>_node``), messages are ``<package>::msg::<Name>`` from
``<package>/msg/<name>.hpp``, every node is a managed (lifecycle) node that the bringup's
manager configures, then activates, and each topic gets the QoS of its receive mode
(``[qos]`` of ``transforms/ros2/target.toml``): an input of the latest value is transient
local, depth 1; a queued input keeps every value. An output's publisher keeps every value when
one of its links ends in a queued input, and is transient local when one of them ends in an
input of the latest value, so it matches every subscriber. Reliability follows each buffer's
tag reliability (``[qos.reliability]``): a reliable publisher serves best-effort subscriptions
too; a best-effort publisher and a reliable subscription never match (rule C010).

The messages are the msg target's, in ROS 2's syntax: a variable array with an upper bound is
a bounded sequence (``JointPosition[<=1]`` for ``[0..1]``), and no comment holds brackets,
which rosidl would read as a unit annotation (``q: Real[6]`` is written ``q: Real, 6 of them``).
"""

from __future__ import annotations

import posixpath
import re
from dataclasses import dataclass, field
from typing import Any

from earl_m2t.gen.errors import GenError
from earl_m2t.gen.views.msg import MsgView
from earl_m2t.gen.views.ros import RosView
from earl_m2t.gen.views.ros2_switch import component_switch, instance_switch, switch_counts
from earl_m2t.model.elements import EarlModel
from earl_m2t.model.naming import host_problem, host_ros_name

Data = dict[str, Any]

QOS_KEYS = ("durability", "history", "depth")


def header_stem(message: str) -> str:
    """rosidl's file name of a message's C++ header (``UInt64`` -> ``u_int64``): its
    ``convert_camel_case_to_lower_case_underscore``."""
    value = re.sub(r"(.)([A-Z][a-z]+)", r"\1_\2", message)
    value = re.sub(r"([a-z0-9])([A-Z])", r"\1_\2", value)
    return value.lower()


def camel(snake: str) -> str:
    """``motor_controller_k_ve`` -> ``MotorControllerKVe``."""
    return "".join(part[:1].upper() + part[1:] for part in snake.split("_") if part)


@dataclass(frozen=True)
class Ros2Target:
    """The data of ``transforms/ros2/target.toml`` the view needs."""

    library_suffix: str
    plugin_suffix: str
    ready_topic: str
    manager: str
    connect_timeout: float
    qos: dict[str, Data]  # "latest" / "queue" -> durability, history, depth
    parameters: dict[str, Data]  # a declared parameter -> its min, max and description
    default_host: str = "default_host"  # the host of the agents without the tag host
    parameter_file: str = "config/{agent}.yaml"  # an agent's parameter file, in the bringup package
    non_finite: str = "error"  # the value of every node's non_finite in the parameter files
    quiet: bool = False  # the value of every node's quiet in the parameter files
    reliability: dict[str, str] = field(default_factory=dict)  # a buffer's tag reliability -> rclcpp's
    switch: Data | None = None  # [switch]: a model with configurations (views/ros2_switch.py)

    @classmethod
    def from_spec(cls, spec: dict[str, Any]) -> Ros2Target:
        qos = {mode: {key: spec["qos"][mode][key] for key in QOS_KEYS} for mode in ("latest", "queue")}
        return cls(library_suffix=str(spec.get("component_library_suffix", "_components")),
                   plugin_suffix=str(spec.get("plugin_suffix", "")),
                   ready_topic=str(spec.get("ready_topic", "/earl/ready")),
                   manager=str(spec.get("manager", "earl_lifecycle_manager")),
                   connect_timeout=float(spec.get("node", {}).get("connect_timeout", 10.0)), qos=qos,
                   parameters={name: dict(value) for name, value in sorted(spec["parameters"].items())},
                   default_host=str(spec.get("default_host", "default_host")),
                   parameter_file=str(spec.get("parameter_file", "config/{agent}.yaml")),
                   non_finite=str(spec.get("node", {}).get("non_finite", "error")),
                   quiet=bool(spec.get("node", {}).get("quiet", False)),
                   reliability={str(tag): str(value) for tag, value in spec["qos"]["reliability"].items()},
                   switch=spec.get("switch"))


@dataclass
class Ros2View:
    system: Data  # model, msgs, bringup, agents (packages with their components and instances)
    packages: list[Data]  # one per agent
    components: list[Data]  # one per subsystem definition
    convert: Data
    messages: list[Data]  # the msg view's messages in ROS 2 syntax
    launch: Data  # system.launch.py: every agent, the manager of all their nodes
    hosts: list[Data]  # one launch per host (name, agents, manager_node), sorted by name; none without hosts


def message_type(ros1: str) -> tuple[str, str]:
    """(C++ type, header) in ROS 2 of a message the ROS 1 view names ``package::Name``."""
    package, _, name = ros1.partition("::")
    if not package or not name or "::" in name:
        raise GenError(f"cannot name the ROS 2 message of {ros1}")
    return f"{package}::msg::{name}", f"{package}/msg/{header_stem(name)}.hpp"


_BRACKETS = re.compile(r"\[([^\]]*)\]")


def plain_comment(text: str) -> str:
    """A comment rosidl keeps as it is: ``Real[6]`` -> ``Real, 6 of them``, ``[0..1]`` -> ``, 0..1 of them``."""
    return _BRACKETS.sub(r", \1 of them", text)


def ros2_messages(msgs: MsgView) -> list[Data]:
    """The messages of the msg view with bounded sequences and comments without brackets."""
    messages = []
    for message in msgs.messages:
        fields = []
        for f in message["fields"]:
            ros_type = f["type"]
            if f.get("bound") is not None and ros_type.endswith("[]"):
                ros_type = f"{ros_type[:-2]}[<={f['bound']}]"
            fields.append({**f, "type": ros_type, "comment": plain_comment(f["comment"])})
        constants = [{**c, "comment": plain_comment(c["comment"])} for c in message["constants"]]
        messages.append({**message, "what": plain_comment(message["what"]), "fields": fields,
                         "constants": constants})
    return messages


def build_view(model: EarlModel, ros: RosView, msgs: MsgView, target: Ros2Target) -> Ros2View:
    """The ROS 2 view of a model from its ROS 1 view."""
    block_of = {sub.path: sub.block_id for sub in model.subsystems}
    blocks = {(n["package"], n["exe"]): block_of[n["trace"]] for n in ros.nodes}  # its first instance's
    queued = {(blocks[(n["package"], n["exe"])], e["template"], e["index"])
              for n in ros.nodes for e in n["inputs"] if e["queue"] == 0}
    publishers = _publisher_modes(model, queued)
    components: list[Data] = []
    plugin_of: dict[tuple[str, str], str] = {}
    for node in ros.nodes:
        components.append(_component(model, node, blocks[(node["package"], node["exe"])], target, publishers))
        plugin_of[(node["package"], node["exe"])] = components[-1]["plugin"]
    packages = []
    for package in ros.packages:
        instances = []
        for instance in package["instances"]:
            switched = {**instance, **instance_switch(instance)}
            instances.append({**switched, "plugin": plugin_of[(instance["pkg"], instance["type"])],
                              "fqn": f"/{instance['ns']}/{instance['name']}",
                              "parameters": _node_parameters(switched, ros.system, target)})
        parameter_file = target.parameter_file.format(agent=package["ns"])
        packages.append({**package, "library": package["name"] + target.library_suffix,
                         "components": [c for c in components if c["package"] == package["name"]],
                         "instances": instances, "parameter_file": parameter_file,
                         "parameter_dir": posixpath.dirname(parameter_file)})
    system = {**ros.system, "agents": packages, "ready_topic": target.ready_topic, "manager": target.manager,
              "connect_timeout": target.connect_timeout, "switch_counts": switch_counts(model)}
    structs = []
    for struct in ros.convert["structs"]:
        cpp_type, header = message_type(struct["msg"])
        structs.append({**struct, "msg": cpp_type, "header": header})
    convert = {**ros.convert, "ns": ros.convert["ns"].removesuffix("_ros") + "_ros2", "structs": structs,
               "headers": sorted({s["header"] for s in structs})}
    launch = {"host": "", "agents": packages, "manager_node": target.manager}
    return Ros2View(system=system, packages=packages, components=components, convert=convert,
                    messages=ros2_messages(msgs), launch=launch, hosts=_hosts(model, packages, target))


def _node_parameters(instance: Data, system: Data, target: Ros2Target) -> list[tuple[str, Any]]:
    """(name, value) of the parameters a node gets from its agent's parameter file, sorted by
    name: every parameter it declares but autostart (which the lifecycle manager replaces)."""
    values: dict[str, Any] = {"path": instance["path"], "period": float(system["period"]),
                              "non_finite": target.non_finite, "quiet": target.quiet,
                              "expected_nodes": int(system["nodes"]), "connect_timeout": target.connect_timeout}
    values.update((f"{name}_links", count) for name, count in instance["links"])
    values.update(instance.get("switch_parameters", []))
    return sorted(values.items())


def _hosts(model: EarlModel, packages: list[Data], target: Ros2Target) -> list[Data]:
    """The launch of each host the model names (the «Agent» tag host), its untagged agents on
    the default host; none when no agent has the tag. Each starts only its agents' nodes, and
    a lifecycle manager of its own for them."""
    host_of = {agent.path: agent.host for agent in model.agents}
    if not any(host_of.get(package["path"]) for package in packages):
        return []
    on: dict[str, list[Data]] = {}  # a host's ROS name -> its agents' packages
    written: dict[str, str] = {}  # a host's ROS name -> the host as first written (its launch file)
    for package in packages:
        host = host_of.get(package["path"]) or target.default_host
        problem = host_problem(host)
        if problem:
            raise GenError(f"D007 agent {package['path']}: host {host!r}: {problem}")
        # hosts that are one name to ROS (a-b, a_b) are one host; rule D007 reports two tagged ones
        on.setdefault(host_ros_name(host), []).append(package)
        written.setdefault(host_ros_name(host), host)
    return [{"host": written[name], "agents": on[name], "manager_node": f"{target.manager}_{name}"}
            for name in sorted(on)]


def _publisher_modes(model: EarlModel,
                     queued: set[tuple[str, str, int]]) -> dict[tuple[str, str, int], set[str]]:
    """(block id, template, index) of an output buffer -> the receive modes its links end in."""
    modes: dict[tuple[str, str, int], set[str]] = {}
    for link in model.links:
        source, target = model.buffer(link.source), model.buffer(link.target)
        source_sub, target_sub = model.subsystem_of(link.source), model.subsystem_of(link.target)
        if source is None or target is None or source_sub is None or target_sub is None:
            raise GenError(f"{link.path}: a link goes from an Output Buffer to an Input Buffer (rule C001)")
        mode = "queue" if (target_sub.block_id, target.template, target.index) in queued else "latest"
        modes.setdefault((source_sub.block_id, source.template, source.index), set()).add(mode)
    return modes


def _qos(mode: str, target: Ros2Target, reliability: str) -> Data:
    """The QoS of a receive mode, with the reliability of a buffer's tag (one the table does not
    name, which B011 reports, as written)."""
    return {**target.qos[mode], "reliability": target.reliability.get(reliability, reliability)}


def _publisher_qos(modes: set[str], target: Ros2Target, reliability: str) -> Data:
    """Matches every subscriber its links end in: keeps every value for a queue, transient local
    for a latest value; an output without links publishes as for the latest value. Its
    reliability is the output's own: a reliable writer serves best-effort readers too."""
    if not modes or modes == {"latest"}:
        return _qos("latest", target, reliability)
    qos = _qos("queue", target, reliability)
    if "latest" in modes:
        qos["durability"] = target.qos["latest"]["durability"]
    return qos


def _reliability(model: EarlModel, element: Data) -> str:
    """The tag reliability of the buffer of a ROS view's element (its first instance's)."""
    buffer = model.buffer(element["trace"])
    return buffer.reliability if buffer is not None else "reliable"


def _component(model: EarlModel, node: Data, block: str, target: Ros2Target,
               publishers: dict[tuple[str, str, int], set[str]]) -> Data:
    name = node["exe"].removesuffix("_node")
    inputs = []
    for e in node["inputs"]:
        cpp_type, header = message_type(e["msg"])
        inputs.append({**e, "msg": cpp_type, "header": header,
                       "mode": "queue" if e["queue"] == 0 else "latest",
                       "qos": _qos("queue" if e["queue"] == 0 else "latest", target, _reliability(model, e))})
    outputs = []
    for e in node["outputs"]:
        cpp_type, header = message_type(e["msg"])
        modes = publishers.get((block, e["template"], e["index"]), set())
        outputs.append({**e, "msg": cpp_type, "header": header,
                        "qos": _publisher_qos(modes, target, _reliability(model, e))})
    cls = camel(name) + target.plugin_suffix
    return {**node, "name": name, "cls_name": cls, "plugin": f"{node['package']}::{cls}",
            "source": f"src/{name}_component.cpp", "inputs": inputs, "outputs": outputs,
            "headers": sorted({e["header"] for e in inputs + outputs}),
            "convert": node["convert"].replace("/ros/convert.hpp", "/ros2/convert.hpp"),
            "convert_ns": node["convert_ns"].removesuffix("_ros") + "_ros2",
            "ready_topic": target.ready_topic, "connect_timeout": target.connect_timeout,
            "parameters": target.parameters,
            "switch": component_switch(node["switch"], target.switch or {}, message_type)}

