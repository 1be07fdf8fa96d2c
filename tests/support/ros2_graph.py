"""The ROS 2 graph of a running system, as the middleware sees it (run with ROS 2 Jazzy's Python,
``Installation.python``, in the workspace's environment).

Reads a JSON request on stdin: ``{"topics": {topic: [subscriptions, publishers expected]}, "timeout": s,
"probe": {"topic": t, "durability": "transient_local"|"volatile", "reliability": …}}``. Waits
until every topic has at least its expected subscriptions and publishers (or the timeout
passed), then prints
JSON: per topic its publishers and subscriptions (node's fully qualified name, reliability,
durability, history, depth), and for the probe, a subscription of our own with the QoS asked
for on that topic, whether DDS matched it with the topic's publishers or reported the QoS
incompatible."""

from __future__ import annotations

import json
import sys
import time
from typing import Any

import rclpy
from rclpy.event_handler import SubscriptionEventCallbacks
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rosidl_runtime_py.utilities import get_message

UNKNOWN = "_NODE_NAME_UNKNOWN_"


def endpoint(info: Any) -> dict[str, Any]:
    qos = info.qos_profile
    namespace = info.node_namespace.rstrip("/")
    return {"node": f"{namespace}/{info.node_name}", "reliability": qos.reliability.name.lower(),
            "durability": qos.durability.name.lower(), "history": qos.history.name.lower(), "depth": qos.depth}


def all_named(node: Any, topics: dict[str, list[int]]) -> bool:
    """Whether discovery has told the node of every endpoint (an endpoint is seen before its node's
    name, which comes on another topic)."""
    return all(UNKNOWN not in info.node_name
               for topic in topics
               for info in node.get_publishers_info_by_topic(topic) + node.get_subscriptions_info_by_topic(topic))


def main() -> int:
    request = json.load(sys.stdin)
    rclpy.init()
    node = rclpy.create_node("earl_graph_probe")
    topics: dict[str, list[int]] = request["topics"]
    deadline = time.monotonic() + float(request.get("timeout", 20.0))
    while time.monotonic() < deadline:
        if all(node.count_subscribers(topic) >= subscriptions and node.count_publishers(topic) >= publishers
               for topic, (subscriptions, publishers) in topics.items()) and all_named(node, topics):
            break
        rclpy.spin_once(node, timeout_sec=0.1)
    graph = {topic: {"publishers": sorted((endpoint(i) for i in node.get_publishers_info_by_topic(topic)),
                                          key=lambda e: e["node"]),
                     "subscriptions": sorted((endpoint(i) for i in node.get_subscriptions_info_by_topic(topic)),
                                             key=lambda e: e["node"])}
             for topic in sorted(topics)}
    result: dict[str, Any] = {"graph": graph}
    probe = request.get("probe")
    if probe:
        types = dict(node.get_topic_names_and_types())
        message = get_message(types[probe["topic"]][0])
        incompatible: list[str] = []
        events = SubscriptionEventCallbacks(
            incompatible_qos=lambda event: incompatible.append(event.last_policy_kind.name))
        qos = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1,
                         reliability=ReliabilityPolicy[probe["reliability"].upper()],
                         durability=DurabilityPolicy[probe["durability"].upper()])
        subscription = node.create_subscription(message, probe["topic"], lambda _: None, qos,
                                                event_callbacks=events)
        until = time.monotonic() + 5.0
        while time.monotonic() < until and not incompatible and subscription.get_publisher_count() == 0:
            rclpy.spin_once(node, timeout_sec=0.1)
        result["probe"] = {"matched": subscription.get_publisher_count(), "incompatible": sorted(set(incompatible))}
    print(json.dumps(result))
    node.destroy_node()
    rclpy.shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
