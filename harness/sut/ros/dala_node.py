"""The simulated Dala layer as a ROS node: the mapping's action servers and ROS services on a real rosmaster.

The layer's logic runs on a LayerHost (harness/sut/simulated/host.py) in wall-clock or scaled time; this
node is only its ROS face, serving every route of the mapping file it is given (routes.py): the
generic action (one server per module by default), typed actions (the goal's fields give the
arguments) and ROS services (the call waits for the final reply, which fills the response's code
and success fields). A goal is a request; the layer's replies drive the goal's status:

- intermediate (the activity started) -> ACTIVE, plus one feedback `running` (the adapter's
  intermediate reply);
- final: a rejection (class R) of a goal still PENDING -> REJECTED; `ok` -> SUCCEEDED;
  an interruption (class Z) -> PREEMPTED; any other ending -> ABORTED. The result's `code` and
  the status text carry the reply code. A final to a PENDING goal that was not rejected goes
  through ACTIVE first, as actionlib requires (the adapter may see ACTIVE or not).

Status heartbeats are this node's own, not actionlib's timer: each period the node pings the
layer and publishes every server's status only when the layer answers, which it never does while
a module is deadlocked. So a deadlock (or a dead node) silences the heartbeat, and the adapter's
pings go unanswered: the trace hangs, as in-process. The adapter's pings also cross ROS: the node
echoes each (ros.toml's ping_topic) once the layer answers it, so the bench's measured round trip
includes the ROS transport. When the mapping names a `reset_service`, the node serves it
(std_srvs/Trigger): the layer is replaced by a fresh one, and the goals of the ended run abort,
so the launcher can serve run after run on this node.

    python -m harness.sut.ros.dala_node --variant reference [--time-scale 10] [--mission DIR] [--mapping FILE]
"""
from __future__ import annotations

import itertools
import json
import os
import signal
import sys
import threading
import time
from pathlib import Path

import actionlib
import rospy
from actionlib_msgs.msg import GoalStatus
from std_msgs.msg import String
from std_srvs.srv import Trigger, TriggerResponse

from harness.sut.roscommon.mapping import load_mapping
from harness.sut.roscommon.node_args import dala_arguments
from harness.sut.ros.messages import action_classes, service_class
from harness.sut.roscommon.layer_face import LayerFace
from harness.sut.roscommon.routes import Route, generic_arguments, read_field
from harness.errors import UntimelyError
from harness.target.interface import load_interface
from harness.sut.simulated.host import LayerHost
from harness.target.mission import INTERFACE_FILE, ROS_MAPPING_FILE, WORLD_FILE

HEARTBEAT_HZ = 5.0  # actionlib's default status rate


class Ending:
    """A request's replies as the layer gives them (layer_face.py): `started` on its intermediate, `end` on
    its final."""

    def reply(self, kind: str, code: str | None) -> None:
        if kind == "intermediate":
            self.started()
        elif kind == "final":
            self.end(code)


class Goal(Ending):
    """A request that came as a goal: the layer's replies set its status (module doc)."""

    def __init__(self, handle, replies: dict[str, str], result_class, feedback_class, route: Route):
        self.handle, self.replies, self.route = handle, replies, route
        self.result_class, self.feedback_class = result_class, feedback_class
        self.id = handle.get_goal_id().id

    def started(self) -> None:
        self.handle.set_accepted()
        if self.route.generic:
            self.handle.publish_feedback(self.feedback_class(phase="running"))
        else:
            self.handle.publish_feedback(self.feedback_class())

    def end(self, code: str) -> None:
        result = self.result_class()
        if self.route.code or self.route.generic:
            setattr(result, self.route.code or "code", code)
        handle, cls = self.handle, self.replies.get(code)
        pending = handle.get_goal_status().status == GoalStatus.PENDING
        if cls == "R" and pending:
            handle.set_rejected(result, code)
            return
        if pending:
            handle.set_accepted()
        if code == "ok":
            handle.set_succeeded(result, code)
        elif cls == "Z":
            handle.set_canceled(result, code)
        else:
            handle.set_aborted(result, code)


class ServiceCall(Ending):
    """A request that came as a ROS service call: the call waits for the final reply."""

    def __init__(self, call_id: str):
        self.id, self.code, self.done = call_id, None, threading.Event()

    def started(self) -> None:
        pass  # a ROS service has no intermediate reply

    def end(self, code: str) -> None:
        self.code = code
        self.done.set()


class Ros1DalaNode(LayerFace):
    def __init__(self, variant: str, mission: Path, mapping: Path, time_scale: float):
        self.interface = load_interface(mission / INTERFACE_FILE)
        self.mapping = load_mapping(mapping)
        self.variant, self.world_file, self.time_scale = variant, mission / WORLD_FILE, time_scale
        self.failure: str | None = None
        self.world_pub = rospy.Publisher(self.mapping.world_topic, String, queue_size=100) \
            if self.mapping.world_topic else None
        self.internal_pub = rospy.Publisher(self.mapping.internal_topic, String, queue_size=1000) \
            if self.mapping.internal_topic else None
        self.host = self._new_host()
        self.pong = rospy.Publisher(self.mapping.pong_topic, String, queue_size=100) \
            if self.mapping.ping_topic else None
        self.ids = itertools.count(1)
        self.open: dict[int, Goal | ServiceCall] = {}
        routes = self.mapping.routes([(s.module, s.name) for s in self.interface.services.values()])
        # generic action name -> {goal's service name -> "module.Service"}
        self.generic: dict[str, dict[str, str]] = {}
        for qualified, route in routes.items():
            if route.generic:
                self.generic.setdefault(route.name, {})[self.interface.services[qualified].name] = qualified
        # Heartbeats are ours (see the module doc): actionlib's own status timer stays off.
        rospy.set_param("actionlib_status_frequency", 0.0)
        self.servers, self.services = {}, []
        for qualified, route in routes.items():
            if route.kind == "service":
                kind = service_class(route, self.mapping.folder)
                self.services.append((route.name, kind, self._call_for(qualified, route, kind._response_class)))
            elif route.name not in self.servers:
                classes = action_classes(route, self.mapping.folder)
                self.servers[route.name] = actionlib.ActionServer(
                    route.name, classes.Action, self._goal_for(qualified, route, classes), auto_start=False)

    def _new_host(self) -> LayerHost:
        return LayerHost(self.variant, self.interface, self.world_file, self.time_scale,
                         on_world=self._world, on_error=self._failed)

    def _reset(self, _request) -> TriggerResponse:
        """A fresh layer; the ended run's goals and calls end `reset` (the adapter has forgotten them)."""
        self.host.stop()  # its thread joined: no reply of the old layer follows
        for ending in list(self.open.values()):
            ending.end("reset")
        self.open.clear()
        self.host = self._new_host()
        self._start_host()
        return TriggerResponse(success=True, message=f"a fresh {self.variant} layer")

    def start(self) -> None:
        self._start_host()
        if self.mapping.reset_service:
            rospy.Service(self.mapping.reset_service, Trigger, self._reset)
        for server in self.servers.values():
            server.start()
        for name, kind, handler in self.services:
            rospy.Service(name, kind, handler)
        if self.pong:
            rospy.Subscriber(self.mapping.ping_topic, String, self._ping)
        threading.Thread(target=self._heartbeat, name="heartbeat", daemon=True).start()

    # -- goals -> layer requests (ROS threads) -------------------------------------------------
    def _goal_for(self, qualified: str, route: Route, classes):
        result_class, feedback_class = classes.Result, classes.Feedback
        services = self.generic.get(route.name, {})

        def receive(handle) -> None:
            goal = handle.get_goal()
            if route.generic:
                target, args = services.get(goal.service), generic_arguments(goal)
                if target is None or args is None:
                    problem = f"{route.name} serves {sorted(services)}; goal {goal.service!r} {goal.args_json!r}"
                    handle.set_rejected(result_class(code=problem), problem)
                    return
            else:
                target, args = qualified, {arg: read_field(goal, path) for arg, path in route.fields.items()}
            self._request(target, args, Goal(handle, self.interface.replies, result_class, feedback_class, route))
        return receive

    def _call_for(self, qualified: str, route: Route, response_class):
        def serve(request):
            call = ServiceCall(request._connection_header.get("untimely_call", ""))
            self._request(qualified, {arg: read_field(request, path) for arg, path in route.fields.items()}, call)
            call.done.wait()
            response = response_class()
            if route.code:
                setattr(response, route.code, call.code)
            if route.success:
                setattr(response, route.success, call.code == "ok")
            return response
        return serve

    def _publish_json(self, publisher, payload: dict) -> None:
        publisher.publish(json.dumps(payload))

    def _shut_down(self, reason: str) -> None:
        rospy.signal_shutdown(reason)

    # -- liveness ------------------------------------------------------------------------------
    def _ping(self, ping: String) -> None:
        """Echoed once the layer answers (never while a module is deadlocked), and only once every
        topic this node publishes has its subscriber: a subscriber may count a connection before
        the publisher does, and what is published in between is lost, so the adapter answers the
        bench's hello only after a first echo."""
        publishers = [p for p in (self.pong, self.world_pub, self.internal_pub) if p]
        publishers += [p for server in self.servers.values()
                       for p in (server.status_pub, server.result_pub, server.feedback_pub)]
        if all(p.get_num_connections() > 0 for p in publishers):
            self.host.ping(lambda: self.pong.publish(ping.data))

    def _heartbeat(self) -> None:
        while not rospy.is_shutdown():
            self.host.ping(self._publish_status)
            time.sleep(1.0 / HEARTBEAT_HZ)

    def _publish_status(self) -> None:
        for server in self.servers.values():
            server.publish_status()

    def stop(self) -> None:
        self.host.stop()


def main(argv: list[str] | None = None) -> int:
    args = dala_arguments(argv, __doc__.split("\n\n")[0], ROS_MAPPING_FILE)
    stopped = threading.Event()
    for signum in (signal.SIGTERM, signal.SIGINT):
        signal.signal(signum, lambda *_: stopped.set())
    rospy.init_node("dala", disable_rosout=True, disable_signals=True)
    try:
        node = Ros1DalaNode(args.variant, args.mission, args.mapping, args.time_scale)
    except (UntimelyError, ValueError) as e:
        print(f"dala_node: {e}", file=sys.stderr, flush=True)
        return 2
    rospy.on_shutdown(stopped.set)  # a layer failure
    node.start()
    stopped.wait()
    node.stop()
    # Not rospy's shutdown: it unregisters every topic, one call at a time, from a master that the
    # launcher is stopping too (most of a second); there is nothing else to save.
    sys.stderr.flush()
    os._exit(1 if node.failure else 0)


if __name__ == "__main__":
    sys.exit(main())
