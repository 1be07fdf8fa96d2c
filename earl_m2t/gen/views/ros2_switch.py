"""The ROS 2 target's part of a model with configurations (docs/ros2-target.md, *Variable
structure*): what a component and each of its node instances need to take part in the switch of
``earl/switch_protocol.hpp``, from the ROS 1 view's switch data (:mod:`earl_m2t.gen.views.ros`),
so that both targets number nodes, variable agents and variable links as
:mod:`earl_m2t.gen.views.switch_wiring` does and name each variable link's topic alike
(``<output>__<link>``).

A component gets the switch's message types, the QoS of the control topics and of the variable
links (``[switch.qos]`` of ``transforms/ros2/target.toml``) and the descriptions of its switch
parameters; a node instance gets the values of those parameters (``switch_node``,
``switch_nodes``, ``switch_agent``, ``switch_control``, ``switch_coordinator``, one
``<input topic>_switch_link`` per input topic fed by a variable link, one
``<output>_switch_links`` per output with variable links), typed as the node declares them,
next to its other parameters in the launch file. A variable link's topic is
``<output topic>/<link>`` (the ROS 1 target's ``<output topic>__<link>``: ROS 2 refuses a
repeated underscore in a name); the parameter of its link count keeps the ROS 1 name,
``<output>__<link>_links``.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from earl_m2t.gen.errors import GenError
from earl_m2t.gen.views.switch_wiring import switch_wiring
from earl_m2t.model.elements import EarlModel

Data = dict[str, Any]

QOS_KEYS = ("reliability", "durability", "history", "depth")
PARAMETERS = ("switch_node", "switch_nodes", "switch_agent", "switch_control", "switch_coordinator",
              "switch_link", "switch_links")


def settings(spec: dict[str, Any]) -> Data:
    """The ``[switch]`` table of ``transforms/ros2/target.toml``, checked: its topics, the QoS of
    the control topics and of the variable links, the descriptions of the switch parameters."""
    try:
        qos = {kind: {key: spec["qos"][kind][key] for key in QOS_KEYS} for kind in ("control", "link")}
        parameters = {name: str(spec["parameters"][name]) for name in PARAMETERS}
        return {"command_topic": str(spec["command_topic"]), "ack_topic": str(spec["ack_topic"]), "qos": qos,
                "parameters": parameters}
    except (KeyError, TypeError) as error:
        raise GenError(f"transforms/ros2/target.toml: [switch] lacks {error}") from None


def component_switch(ros1: Data | None, spec: dict[str, Any],
                     message_type: Callable[[str], tuple[str, str]]) -> Data | None:
    """A component's switch data from its ROS 1 node's (None without configurations):
    ``message_type`` maps a ROS 1 message type to its ROS 2 (C++ type, header)."""
    if ros1 is None:
        return None
    command, command_header = message_type(ros1["command"])
    ack, ack_header = message_type(ros1["ack"])
    return {**settings(spec), "system": ros1["system"], "include": ros1["include"], "nodes": ros1["nodes"],
            "initial": ros1["initial"], "initial_comment": ros1["initial_comment"], "command": command,
            "ack": ack, "headers": sorted({command_header, ack_header})}


def link_topic(ros1: str) -> str:
    """The ROS 2 topic of a variable link the ROS 1 view names ``<output topic>__<link>``:
    ``<output topic>/<link>`` (ROS 2 refuses a repeated underscore in a name). Any other topic
    is returned as it is."""
    namespace, _, name = ros1.rpartition("/")
    output, separator, link = name.partition("__")
    return f"{namespace}/{output}/{link}" if separator else ros1


def instance_switch(instance: Data) -> Data:
    """What a node instance of a model with configurations adds to the ROS 1 view's: its switch
    parameters, and its remaps onto the ROS 2 topics of the variable links."""
    if instance.get("switch") is None:
        return {"switch_parameters": []}
    remaps = [{**r, "to": link_topic(r["to"])} for r in instance["remaps"]]
    return {"switch_parameters": instance_parameters(instance), "remaps": remaps}


def instance_parameters(instance: Data) -> list[tuple[str, Any]]:
    """(name, value) of the switch parameters of a node instance, typed as the node declares
    them; none without configurations."""
    switch = instance.get("switch")
    if switch is None:
        return []
    parameters: list[tuple[str, Any]] = [
        ("switch_node", int(switch["node"])), ("switch_nodes", int(switch["nodes"])),
        ("switch_agent", int(switch["agent"])), ("switch_control", switch["control"] == "true"),
        ("switch_coordinator", switch["coordinator"] == "true")]
    parameters += [(f"{topic}_switch_link", int(link)) for topic, link in switch["inputs"]]
    parameters += [(f"{topic}_switch_links", str(links)) for topic, links in switch["outputs"]]
    return parameters


def switch_counts(model: EarlModel) -> int:
    """The length of the ``counts`` of the switch's messages: one per variable link (at least
    one, a fixed array: converting a command or an acknowledgement allocates nothing)."""
    wiring = switch_wiring(model)
    return max(1, len(wiring.links)) if wiring is not None else 0
