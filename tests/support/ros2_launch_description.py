"""The nodes a launch file would start, as launch itself reads them, without starting anything
(run with ROS 2 Jazzy's Python, ``Installation.python``, in the workspace's environment).

Reads a JSON request on stdin: ``{"launch_file": path, "arguments": {name: value}}`` (the
``name:=value`` of ``ros2 launch``). Loads the file with launch's own loader, sets the
arguments in a ``LaunchContext`` and evaluates the launch description as launch would, but
only the actions that start no process (launch arguments, launch configurations, groups,
opaque functions); an action it does not know stops it. For each node, composed or not, it
performs launch_ros's substitutions and prints JSON: ``{"nodes": [{"name": its fully qualified
name, "package", "executable" (a composed node's plugin), "container": the fully qualified name of
the container it is loaded into or null,
"remappings": [[from, to]], "parameters": [{"file": path} | {"values": {name: value}}] in the
order given}]}``; a composed node also has ``"loaded"``: the values its container is sent, the
files' and the overrides' merged by launch_ros for its name.

launch_ros has no public getter for a container's composable node descriptions nor for a
Node's parameters before it runs: those two are read from its attributes (Jazzy's names).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

from launch import LaunchContext, LaunchDescription, LaunchDescriptionEntity
from launch.actions import (
    DeclareLaunchArgument,
    GroupAction,
    OpaqueFunction,
    PopLaunchConfigurations,
    PushLaunchConfigurations,
    SetLaunchConfiguration,
)
from launch.launch_description_sources import get_launch_description_from_python_launch_file
from launch_ros.actions import ComposableNodeContainer, Node
from launch_ros.actions.load_composable_nodes import get_composable_node_load_request
from launch_ros.descriptions import ComposableNode
from launch_ros.utilities import evaluate_parameters
from rclpy.parameter import parameter_value_to_python

# actions that only change the context: executed
CONTEXT_ACTIONS = (DeclareLaunchArgument, SetLaunchConfiguration, OpaqueFunction, GroupAction,
                   PushLaunchConfigurations, PopLaunchConfigurations)


def parameters(context: LaunchContext, given: Any) -> list[dict[str, Any]]:
    """Parameters as launch_ros evaluates them: a file's path, or a dict of values."""
    evaluated = evaluate_parameters(context, given or ())
    return [{"file": str(item)} if isinstance(item, Path) else {"values": dict(item)} for item in evaluated]


def composed(context: LaunchContext, description: ComposableNode, container: str) -> dict[str, Any] | None:
    """A composable node as the request its container would be sent (None when its condition is false)."""
    request = get_composable_node_load_request(description, context)
    if request is None:
        return None
    return {"name": f"{request.node_namespace.rstrip('/')}/{request.node_name}", "container": container,
            "package": request.package_name, "executable": request.plugin_name,
            "remappings": [rule.split(":=", 1) for rule in request.remap_rules],
            "parameters": parameters(context, description.parameters),
            "loaded": {p.name: parameter_value_to_python(p.value) for p in request.parameters}}


def process(context: LaunchContext, node: Node) -> dict[str, Any]:
    node._perform_substitutions(context)  # what Node.execute does first, before it starts the process
    name = node.node_name
    if name.startswith(Node.UNSPECIFIED_NODE_NAMESPACE):  # no namespace given: the process runs in "/"
        name = name[len(Node.UNSPECIFIED_NODE_NAMESPACE):]
    return {"name": name, "container": None, "package": node.node_package,
            "executable": node.node_executable,
            "remappings": [list(rule) for rule in node.expanded_remapping_rules or ()],
            "parameters": parameters(context, node._Node__parameters)}


def visit(entity: LaunchDescriptionEntity, context: LaunchContext, nodes: list[dict[str, Any]]) -> None:
    if isinstance(entity, LaunchDescription):
        for child in entity.entities:
            visit(child, context, nodes)
        return
    condition = getattr(entity, "condition", None)
    if condition is not None and not condition.evaluate(context):
        return
    if isinstance(entity, CONTEXT_ACTIONS):
        for child in entity.execute(context) or ():
            visit(child, context, nodes)
    elif isinstance(entity, ComposableNodeContainer):
        node = process(context, entity)
        nodes.append(node)
        for description in entity._ComposableNodeContainer__composable_node_descriptions or ():
            loaded = composed(context, description, node["name"])
            if loaded is not None:
                nodes.append(loaded)
    elif isinstance(entity, Node):
        nodes.append(process(context, entity))
    else:
        raise SystemExit(f"an action this reader does not evaluate: {type(entity).__name__}")


def main() -> int:
    request = json.load(sys.stdin)
    context = LaunchContext()
    context.launch_configurations.update({str(k): str(v) for k, v in request.get("arguments", {}).items()})
    nodes: list[dict[str, Any]] = []
    visit(get_launch_description_from_python_launch_file(request["launch_file"]), context, nodes)
    print(json.dumps({"nodes": nodes}, sort_keys=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())
