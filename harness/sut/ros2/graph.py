"""Reads the ROS 2 graph of the domain it runs in and prints it as one JSON object (the input of
harness.target.ros2_graph): each node's name, its services and action servers with their types
and the fields of their requests and goals. Runs under a distro's interpreter, in the environment
`untimely init --from-ros2` made (harness/sut/ros2/init.py); not started by hand.

The graph is taken once it has stopped changing for --settle seconds (nodes create their servers
after they appear), or at --timeout; a domain with no node other than this one is an error.
"""
from __future__ import annotations

import argparse
import json
import sys
import time

import rclpy
from rclpy.action import get_action_server_names_and_types_by_node

from harness.sut.ros2.types import interface_class
from harness.errors import UntimelyError

OWN_NAME = "untimely_graph"
POLL_S = 0.2


def snapshot(node) -> list[dict]:
    """Every other node of the domain with its services and action servers (name, type)."""
    nodes = []
    for name, namespace in sorted(node.get_node_names_and_namespaces()):
        if name == OWN_NAME:
            continue
        services = node.get_service_names_and_types_by_node(name, namespace)
        actions = get_action_server_names_and_types_by_node(node, name, namespace)
        nodes.append({"name": (namespace.rstrip("/") + "/" + name),
                      "services": sorted([n, types[0]] for n, types in services),
                      "actions": sorted([n, types[0]] for n, types in actions)})
    return nodes


def settled(node, settle_s: float, timeout_s: float) -> list[dict]:
    deadline, last, since = time.monotonic() + timeout_s, None, time.monotonic()
    while time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=POLL_S)
        now = snapshot(node)
        if now != last:
            last, since = now, time.monotonic()
        elif now and time.monotonic() - since >= settle_s:
            return now
    if not last:
        raise SystemExit(f"no ROS 2 node appeared within {timeout_s:g} s")
    return last


def described(name: str, full_type: str, kind: str) -> dict:
    """A service or action server with the fields of its request or goal (name -> ROS type: "int32",
    "string", ...) and a service's response fields; None when this venv cannot import the type
    (the derivation then says so)."""
    try:
        cls = interface_class(full_type, kind)
    except UntimelyError:
        return {"name": name, "type": full_type, "fields": None, "response": None}
    request, response = (cls.Goal, None) if kind == "action" else (cls.Request, cls.Response)
    return {"name": name, "type": full_type, "fields": dict(request.get_fields_and_field_types()),
            "response": dict(response.get_fields_and_field_types()) if response else None}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--settle", type=float, default=2.0)
    parser.add_argument("--timeout", type=float, default=30.0)
    args = parser.parse_args(argv)
    rclpy.init()
    node = rclpy.create_node(OWN_NAME)
    try:
        graph = settled(node, args.settle, args.timeout)
        for entry in graph:
            for key, kind in (("services", "srv"), ("actions", "action")):
                entry[key] = [described(name, type_, kind) for name, type_ in entry[key]]
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    json.dump({"nodes": graph}, sys.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(main())
