"""Two ends of a small ROS 2 exchange, run by the ROS 2 tests under a distro's venv python in the
bench's environment (harness/sut/ros2/environment.py):

    python tests/support/ros2_peer.py serve NAME    # node NAME: service /ndd/set_params (untimely_msgs/srv/Call)
                                            # and action /dala/ndd (untimely_msgs/action/Request), as
                                            # tests/bags/ros2_recording.toml maps ndd.SetParams and
                                            # ndd.GotoPosition; introspection on where the distro
                                            # has it; prints "ready"
    python tests/support/ros2_peer.py call [recorded]  # one call and one goal (a feedback, a result); prints
                                            # their replies and timings as JSON; `recorded`: first
                                            # waits for a recorder's subscription to its call events
    python tests/support/ros2_peer.py nodes SECONDS [NAME]  # the names of the nodes it sees after SECONDS
                                            # (or once it sees NAME), as JSON
"""
import json
import os
import signal
import sys
import threading
import time

import rclpy
from rclpy.action import ActionClient, ActionServer
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor
from rclpy.qos import qos_profile_system_default
from rclpy.service_introspection import ServiceIntrospectionState
from untimely_msgs.action import Request
from untimely_msgs.srv import Call

from harness.sut.ros2.teardown import release

TIMEOUT_S = 20.0
GOAL_S = 0.2  # how long a goal runs between its feedback and its result
SERVICE, ACTION = "/ndd/set_params", "/dala/ndd"
OPENED = {"nodes": [], "executor": None}  # released before the process exits (teardown.release)
# SIGTERM ends `serve` between two spins: shutting the context down from the signal handler while
# rclpy.spin waited crashed the server (SIGSEGV) about once in 30 stops on Jazzy.
STOP = threading.Event()


def _node(name: str):
    node = rclpy.create_node(name)
    OPENED["nodes"].append(node)
    return node


def _introspect(entity, node) -> None:
    """Contents of requests and responses on the _service_event topics (actions: Kilted only)."""
    if hasattr(entity, "configure_introspection"):
        entity.configure_introspection(node.get_clock(), qos_profile_system_default, ServiceIntrospectionState.CONTENTS)


def serve(name: str) -> None:
    node = _node(name)

    def call(request, response):
        response.code = "ok"
        return response

    def execute(goal):
        goal.publish_feedback(Request.Feedback(phase="running"))
        # the goal runs a while, as a real one does: a feedback and a result sent back to back travel
        # on separate topics and may arrive in either order (then the trace has no intermediate reply)
        time.sleep(GOAL_S)
        goal.succeed()
        return Request.Result(code="ok")
    _introspect(node.create_service(Call, SERVICE, call), node)
    _introspect(ActionServer(node, Request, ACTION, execute), node)
    print("ready", flush=True)
    while not STOP.is_set():
        rclpy.spin_once(node, timeout_sec=0.05)


def call(recorded: bool = False) -> None:
    node = _node("untimely_caller")
    executor = OPENED["executor"] = MultiThreadedExecutor()
    executor.add_node(node)
    threading.Thread(target=executor.spin, daemon=True).start()
    client, actions = node.create_client(Call, SERVICE), ActionClient(node, Request, ACTION)
    _introspect(client, node)
    _introspect(actions, node)
    started = time.monotonic()
    if not (client.wait_for_service(timeout_sec=TIMEOUT_S) and actions.wait_for_server(timeout_sec=TIMEOUT_S)):
        sys.exit(f"no server of {SERVICE} or {ACTION}")
    discovered = time.monotonic()
    while recorded and not node.count_subscribers(f"{SERVICE}/_service_event") and time.monotonic() < started + TIMEOUT_S:
        time.sleep(0.01)
    reply = client.call(Call.Request(service="SetParams", args_json='{"speed": 0.5}'), timeout_sec=TIMEOUT_S)
    call_ms = (time.monotonic() - discovered) * 1e3
    phases = []
    goal = actions.send_goal(Request.Goal(service="GotoPosition", args_json='{"x": 3.0, "y": 4.0}'),
                             feedback_callback=lambda f: phases.append(f.feedback.phase))
    print(json.dumps({"code": reply.code, "goal": goal.result.code, "accepted": goal.status,
                      "phases": phases, "discovery_s": discovered - started, "call_ms": call_ms}), flush=True)


def nodes(seconds: float, awaited: str = "") -> None:
    node = _node("untimely_watcher")
    deadline = time.monotonic() + seconds
    names = []
    while time.monotonic() < deadline and awaited not in names:
        rclpy.spin_once(node, timeout_sec=0.1)
        names = sorted(name for name, _ in node.get_node_names_and_namespaces())
    print(json.dumps(names), flush=True)


def main(argv: list[str]) -> None:
    signal.signal(signal.SIGTERM, lambda *_: STOP.set())
    rclpy.init()
    try:
        {"serve": lambda: serve(argv[2]), "call": lambda: call("recorded" in argv[2:]), "nodes": lambda: nodes(float(argv[2]), *argv[3:])}[argv[1]]()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        release(OPENED["nodes"], OPENED["executor"])


if __name__ == "__main__":
    main(sys.argv)
    # All it had to say is printed and flushed. The interpreter's own exit may abort in rclpy's C++
    # static destructors ("terminate called without an active exception", seen in a full-suite run
    # on a loaded machine), a teardown race of the middleware, not of what this peer checks.
    os._exit(0)
