"""Two ends of a small ROS 2 exchange, run by the ROS 2 tests under a distro's venv python in the
bench's environment (harness/adapters/ros2/environment.py):

    python tests/ros2_peer.py serve NAME    # node NAME: service /untimely/call (untimely_msgs/srv/Call)
                                            # and action /untimely/request (untimely_msgs/action/Request),
                                            # introspection on where the distro has it; prints "ready"
    python tests/ros2_peer.py call          # one service call and one goal (a feedback, a result);
                                            # prints their replies and timings as JSON
    python tests/ros2_peer.py nodes SECONDS # prints the names of the nodes it sees after SECONDS, as JSON
"""
import json
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

TIMEOUT_S = 20.0


def _introspect(entity, node) -> None:
    """Contents of requests and responses on the _service_event topics (actions: Kilted only)."""
    if hasattr(entity, "configure_introspection"):
        entity.configure_introspection(node.get_clock(), qos_profile_system_default, ServiceIntrospectionState.CONTENTS)


def serve(name: str) -> None:
    node = rclpy.create_node(name)

    def call(request, response):
        response.code = f"ok:{request.service}"
        return response

    def execute(goal):
        goal.publish_feedback(Request.Feedback(phase="running"))
        goal.succeed()
        return Request.Result(code=f"done:{goal.request.service}")
    _introspect(node.create_service(Call, "/untimely/call", call), node)
    _introspect(ActionServer(node, Request, "/untimely/request", execute), node)
    print("ready", flush=True)
    rclpy.spin(node)


def call() -> None:
    node = rclpy.create_node("untimely_caller")
    executor = MultiThreadedExecutor()
    executor.add_node(node)
    threading.Thread(target=executor.spin, daemon=True).start()
    client, actions = node.create_client(Call, "/untimely/call"), ActionClient(node, Request, "/untimely/request")
    _introspect(client, node)
    _introspect(actions, node)
    started = time.monotonic()
    if not (client.wait_for_service(timeout_sec=TIMEOUT_S) and actions.wait_for_server(timeout_sec=TIMEOUT_S)):
        sys.exit("no server of /untimely/call or /untimely/request")
    discovered = time.monotonic()
    reply = client.call(Call.Request(service="Init", args_json="{}"), timeout_sec=TIMEOUT_S)
    call_ms = (time.monotonic() - discovered) * 1e3
    phases = []
    goal = actions.send_goal(Request.Goal(service="GotoPosition", args_json="{}"),
                             feedback_callback=lambda f: phases.append(f.feedback.phase))
    print(json.dumps({"code": reply.code, "goal": goal.result.code, "accepted": goal.status,
                      "phases": phases, "discovery_s": discovered - started, "call_ms": call_ms}), flush=True)


def nodes(seconds: float) -> None:
    node = rclpy.create_node("untimely_watcher")
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.1)
    print(json.dumps(sorted(name for name, _ in node.get_node_names_and_namespaces())), flush=True)


def main(argv: list[str]) -> None:
    signal.signal(signal.SIGTERM, lambda *_: rclpy.try_shutdown())
    rclpy.init()
    try:
        {"serve": lambda: serve(argv[2]), "call": call, "nodes": lambda: nodes(float(argv[2]))}[argv[1]]()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        rclpy.try_shutdown()


if __name__ == "__main__":
    main(sys.argv)
