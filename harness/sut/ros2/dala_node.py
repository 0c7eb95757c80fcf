"""The simulated Dala layer as a ROS 2 lifecycle node (rclpy): the mapping's action servers and
services, the layer hosted on a LayerHost (harness/sut/simulated/host.py), as the ROS 1 node does.

Lifecycle: `configure` builds a fresh layer of the variant, `activate` starts its clock,
`deactivate` stops it (the open goals and calls end `reset`: the adapter has forgotten them),
`cleanup` drops it. The adapter brings the node up (configure, activate) before a run and resets it
between runs (deactivate, cleanup, configure, activate), so one node serves run after run. A goal
or call that reaches an inactive node is refused: the goal is rejected, the call answers `inactive`.

A goal (an `exec` service, untimely_msgs/action/Request or a typed action) is accepted at once and
handed to the layer; the layer's intermediate reply is one feedback (`phase` = running); its final
reply is the result's `code`: `ok` succeeds the goal, any other code aborts it with that code
(a rejection's reason included: ROS 2's goal response carries none, so the layer's refusals are
accepted goals aborted with their R code, as GenoM3's ROS template does). A service (`control` and
`init`: untimely_msgs/srv/Call or a typed service) answers with the final reply.

Liveness: the node's executor serves `/dala/get_parameters`, which the adapter probes; the node
echoes the adapter's pings (ping_topic -> pong_topic) once the layer answers them, never while a
module is deadlocked, and only once each of its topics has its subscriber.

Ground truth: each reply of the layer is published on internal_topic, a goal's named by its UUID,
a call's as "SERVICE#n" (the n-th call of that service since the layer was made). Introspection:
its services publish their events (with contents) from Jazzy on, its action servers from Kilted on,
so the adapter can relay `taken` replies and a recorder can name every request.

    python -m harness.sut.ros2.dala_node --variant reference [--mission DIR] [--mapping FILE]
"""
from __future__ import annotations

import itertools
import json
import os
import sys
from pathlib import Path

import rclpy
from rclpy.action import ActionServer, CancelResponse, GoalResponse
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor
from rclpy.lifecycle import LifecycleNode, TransitionCallbackReturn
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.service_introspection import ServiceIntrospectionState
from rclpy.task import Future
from std_msgs.msg import String

from harness.sut.roscommon.mapping import load_mapping
from harness.sut.roscommon.node_args import dala_arguments
from harness.sut.roscommon.layer_face import LayerFace
from harness.sut.roscommon.routes import Route, generic_arguments, read_field
from harness.sut.ros2.teardown import release
from harness.sut.ros2.types import route_class
from harness.errors import UntimelyError
from harness.sut.simulated.host import LayerHost
from harness.target.interface import load_interface
from harness.target.mission import INTERFACE_FILE, ROS2_MAPPING_FILE, WORLD_FILE

QOS = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)


class AwaitedEnding:
    """A request's replies as the layer gives them, awaited on the node's executor."""

    def __init__(self, executor, goal_id: str | None):
        self.id, self.code = goal_id, None
        self.started, self.ended = Future(executor=executor), Future(executor=executor)
        for future in (self.started, self.ended):  # its done callback wakes the executor's awaiting task
            future.add_done_callback(lambda _f: None)

    def reply(self, kind: str, code: str | None) -> None:
        if kind == "intermediate" and not self.started.done():
            self.started.set_result(True)
        elif kind == "final":
            self.code = code
            if not self.started.done():
                self.started.set_result(False)
            self.ended.set_result(code)


class Ros2DalaNode(LayerFace, LifecycleNode):
    def __init__(self, variant: str, mission: Path, mapping_file: Path, time_scale: float):
        self.mapping = load_mapping(mapping_file)
        if not self.mapping.node:
            raise UntimelyError(f"{mapping_file}: the Dala ROS 2 node needs `node`, its name (e.g. \"/dala\")")
        super().__init__(self.mapping.node.rsplit("/", 1)[1], namespace=self.mapping.node.rsplit("/", 1)[0] or "/")
        self.interface = load_interface(mission / INTERFACE_FILE)
        self.variant, self.world_file, self.time_scale = variant, mission / WORLD_FILE, time_scale
        self.host: LayerHost | None = None
        self.active, self.origin, self.failure = False, 0.0, None
        self.ids = itertools.count(1)
        self.open: dict[int, AwaitedEnding] = {}
        group = ReentrantCallbackGroup()
        topics = {name: self.create_publisher(String, topic, QOS) for name, topic in
                  (("world", self.mapping.world_topic), ("internal", self.mapping.internal_topic),
                   ("pong", self.mapping.pong_topic)) if topic}
        self.world_pub, self.internal_pub, self.pong_pub = (topics.get(n) for n in ("world", "internal", "pong"))
        services = self.interface.services
        routes = self.mapping.routes([(s.module, s.name) for s in services.values()],
                                     {qualified: s.kind for qualified, s in services.items()})
        # generic action name -> {goal's service name -> "module.Service"}
        self.generic: dict[str, dict[str, str]] = {}
        for qualified, route in routes.items():
            if route.generic:
                self.generic.setdefault(route.name, {})[services[qualified].name] = qualified
        for qualified, route in routes.items():
            kind = route_class(route)
            if route.kind == "action":
                server = ActionServer(
                    self, kind, route.name, execute_callback=self._execute_for(qualified, route, kind),
                    goal_callback=lambda _goal: GoalResponse.ACCEPT if self.active else GoalResponse.REJECT,
                    cancel_callback=self._cancel_for(qualified),
                    callback_group=group)
                if hasattr(server, "configure_introspection"):  # rclpy 9 (Kilted) on; the contents name the goal
                    server.configure_introspection(self.get_clock(), QOS, ServiceIntrospectionState.CONTENTS)
            else:
                service = self.create_service(kind, route.name, self._serve_for(qualified, route), callback_group=group)
                service.configure_introspection(self.get_clock(), QOS, ServiceIntrospectionState.CONTENTS)
        if self.mapping.ping_topic:
            self.create_subscription(String, self.mapping.ping_topic, self._ping, QOS, callback_group=group)

    # -- lifecycle -----------------------------------------------------------------------------
    def on_configure(self, state) -> TransitionCallbackReturn:
        self.calls: dict[str, int] = {}  # service -> calls received since the layer was made
        self.host = LayerHost(self.variant, self.interface, self.world_file, self.time_scale,
                              on_world=self._world, on_error=self._failed)
        return TransitionCallbackReturn.SUCCESS

    def on_activate(self, state) -> TransitionCallbackReturn:
        self._start_host()
        self.active = True
        return super().on_activate(state)

    def on_deactivate(self, state) -> TransitionCallbackReturn:
        self.active = False
        self.host.stop()  # its thread joined: no reply of this layer follows
        for ending in list(self.open.values()):
            ending.reply("final", "reset")
        self.open.clear()
        return super().on_deactivate(state)

    def on_cleanup(self, state) -> TransitionCallbackReturn:
        self.host = None
        return TransitionCallbackReturn.SUCCESS

    # -- goals and calls -> layer requests -------------------------------------------------------
    def _execute_for(self, qualified: str, route: Route, kind):
        async def execute(goal_handle):
            goal = goal_handle.request
            args = self._arguments(goal, route)
            ending = AwaitedEnding(self.executor, bytes(goal_handle.goal_id.uuid).hex())
            target = self.generic[route.name].get(goal.service) if route.generic else qualified
            if target is None or args is None:
                ending.reply("final", f"{route.name} serves {sorted(self.generic.get(route.name, {qualified: 0}))}; "
                                      f"goal {goal.service!r} {goal.args_json!r}")
            else:
                self._request(target, args, ending)
            if await ending.started:
                goal_handle.publish_feedback(kind.Feedback(**({"phase": "running"} if route.generic else {})))
            code = await ending.ended
            result = kind.Result()
            if route.code or route.generic:
                setattr(result, route.code or "code", code)
            if code == "ok":
                goal_handle.succeed()
            else:
                goal_handle.canceled() if goal_handle.is_cancel_requested else goal_handle.abort()
            return result
        return execute

    def _cancel_for(self, qualified: str):
        """Dala's goals end by its modules' Stop services. A mapping whose [cancels] names this
        service makes a cancel of one of its goals (rclpy asks only for goals still running) that
        service of the layer, e.g. rflex.Stop for rflex.TrackSpeedStart; otherwise it is refused."""
        canceller = next((c for c, target in self.mapping.cancels.items() if target == qualified), None)

        def cancel(_goal) -> CancelResponse:
            if canceller is None or not self.active:
                return CancelResponse.REJECT
            self._request(canceller, {}, AwaitedEnding(self.executor, None))  # no ground truth: no request of the bench's
            return CancelResponse.ACCEPT
        return cancel

    def _serve_for(self, qualified: str, route: Route):
        async def serve(request, response):
            args = self._arguments(request, route)
            if not self.active or args is None:
                code = "inactive" if not self.active else f"{route.name} cannot read {request}"
            else:
                # A call carries no id: the n-th call of a service (one client, in order) is named
                # "SERVICE#n" in the ground truth, as the adapter names the n-th it made.
                self.calls[route.name] = self.calls.get(route.name, 0) + 1
                ending = AwaitedEnding(self.executor, f"{route.name}#{self.calls[route.name]}")
                self._request(qualified, args, ending)
                code = await ending.ended
            if route.code or route.generic:
                setattr(response, route.code or "code", code)
            if route.success:
                setattr(response, route.success, code == "ok")
            return response
        return serve

    @staticmethod
    def _arguments(message, route: Route) -> dict | None:
        if not route.generic:
            return {arg: read_field(message, path) for arg, path in route.fields.items()}
        return generic_arguments(message)

    def _publish_json(self, publisher, payload: dict) -> None:
        publisher.publish(String(data=json.dumps(payload)))

    def _shut_down(self, reason: str) -> None:
        self.context.try_shutdown()  # the executor's spin ends; main exits 1

    def _ping(self, ping: String) -> None:
        """Echoed once the layer answers, and once every topic this node publishes has its
        subscriber (what is published before is lost; the adapter's first ping waits for it)."""
        publishers = [p for p in (self.world_pub, self.internal_pub, self.pong_pub) if p]
        if self.active and all(p.get_subscription_count() > 0 for p in publishers):
            self.host.ping(lambda: self.pong_pub.publish(ping))


def main(argv: list[str] | None = None) -> int:
    args = dala_arguments(argv, __doc__.split("\n\n")[0], ROS2_MAPPING_FILE)
    rclpy.init()
    try:
        node = Ros2DalaNode(args.variant, args.mission, args.mapping, args.time_scale)
    except (UntimelyError, ValueError) as e:
        print(f"dala_node: {e}", file=sys.stderr, flush=True)
        return 2
    executor = MultiThreadedExecutor(num_threads=4)
    executor.add_node(node)
    try:
        executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    if node.host and node.active:  # a configured layer that was never activated has no thread to stop
        node.host.stop()
    release([node], executor)  # its participant's shared memory goes with it
    sys.stderr.flush()
    # Not the interpreter's finalisation: rclpy's C++ destructors can abort it, and nothing is left to save.
    os._exit(1 if node.failure else 0)


if __name__ == "__main__":
    sys.exit(main())
