"""The simulated Dala layer as a ROS node: one actionlib server per module on a real rosmaster.

The layer's logic runs on a LayerHost (harness/sim/host.py) in wall-clock or scaled time; this
node is only its ROS face. A goal is a request; the layer's replies drive the goal's status:

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
includes the ROS transport.

    python -m harness.adapters.ros.dala_node --variant reference [--time-scale 10] [--mission DIR]
"""
from __future__ import annotations

import argparse
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

from harness import DEFAULT_MISSION_DIR
from harness.adapters.ros.mapping import load_mapping
from harness.adapters.ros.messages import RequestAction, RequestFeedback, RequestResult
from harness.errors import UntimelyError
from harness.target.interface import load_interface
from harness.sim.host import LayerHost

HEARTBEAT_HZ = 5.0  # actionlib's default status rate


class DalaNode:
    def __init__(self, variant: str, mission: Path, time_scale: float):
        self.interface = load_interface(mission / "interface.toml")
        self.mapping = load_mapping(mission / "ros.toml")
        self.time_scale = time_scale
        self.failure: str | None = None
        self.world_pub = rospy.Publisher(self.mapping.world_topic, String, queue_size=100) \
            if self.mapping.world_topic else None
        self.internal_pub = rospy.Publisher(self.mapping.internal_topic, String, queue_size=1000) \
            if self.mapping.internal_topic else None
        self.host = LayerHost(variant, self.interface, mission / "world.toml", time_scale,
                              on_world=self._world, on_error=self._failed)
        self.origin = time.time() - self.host.env.clock() / time_scale  # wall-clock epoch of the host's t = 0
        self.pong = rospy.Publisher(self.mapping.pong_topic, String, queue_size=100) \
            if self.mapping.ping_topic else None
        self.ids = itertools.count(1)
        self.goals: dict[int, actionlib.ServerGoalHandle] = {}
        # action name -> {goal's service name -> "module.Service"}
        self.routes: dict[str, dict[str, str]] = {}
        actions = self.mapping.actions([(s.module, s.name) for s in self.interface.services.values()])
        for qualified, action in actions.items():
            self.routes.setdefault(action, {})[self.interface.services[qualified].name] = qualified
        # Heartbeats are ours (see the module doc): actionlib's own status timer stays off.
        rospy.set_param("actionlib_status_frequency", 0.0)
        self.servers = {action: actionlib.ActionServer(action, RequestAction, self._goal_for(action),
                                                       auto_start=False) for action in self.routes}

    def start(self) -> None:
        self.host.start()
        for server in self.servers.values():
            server.start()
        if self.pong:
            rospy.Subscriber(self.mapping.ping_topic, String, self._ping)
        threading.Thread(target=self._heartbeat, name="heartbeat", daemon=True).start()

    def _stamp(self, t: float) -> float:
        """The wall-clock epoch of host time t (mission seconds)."""
        return self.origin + t / self.time_scale

    # -- goals -> layer requests (ROS threads) -------------------------------------------------
    def _goal_for(self, action: str):
        def receive(handle) -> None:
            goal = handle.get_goal()
            qualified = self.routes[action].get(goal.service)
            try:
                args = json.loads(goal.args_json or "{}")
            except ValueError:
                args = None
            if qualified is None or not isinstance(args, dict):
                problem = f"{action} serves {sorted(self.routes[action])}; goal {goal.service!r} {goal.args_json!r}"
                handle.set_rejected(RequestResult(code=problem), problem)
                return
            rqst_id = next(self.ids)
            self.goals[rqst_id] = handle
            # The layer reads argument values as text, whatever their JSON type (as the simulator adapter).
            self.host.request(rqst_id, qualified, {k: str(v) for k, v in args.items()}, self._reply)
        return receive

    # -- layer replies -> goal statuses (the host's thread) ------------------------------------
    def _reply(self, rqst_id: int, kind: str, code: str | None, t: float) -> None:
        handle = self.goals[rqst_id]
        if self.internal_pub:
            self.internal_pub.publish(json.dumps({"goal_id": handle.get_goal_id().id, "kind": kind,
                                                  "code": code, "stamp": self._stamp(t)}))
        if kind == "intermediate":
            handle.set_accepted()
            handle.publish_feedback(RequestFeedback(phase="running"))
        elif kind == "final":
            del self.goals[rqst_id]
            self._end(handle, code)

    def _end(self, handle, code: str) -> None:
        result, cls = RequestResult(code=code), self.interface.replies.get(code)
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

    def _world(self, t: float, kind: str, detail: str) -> None:
        if self.world_pub:
            self.world_pub.publish(json.dumps({"stamp": self._stamp(t), "kind": kind, "detail": json.loads(detail)}))

    def _failed(self, message: str) -> None:
        self.failure = message
        print(f"dala_node: the simulated layer failed: {message}", file=sys.stderr, flush=True)
        rospy.signal_shutdown(message)

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
    parser = argparse.ArgumentParser(prog="dala_node", description=__doc__.split("\n\n")[0])
    parser.add_argument("--variant", required=True,
                        help="a variant of the mission folder's layer.toml "
                             "(Dala: genom, bip-a, bip-b, bare, reference)")
    parser.add_argument("--time-scale", type=float, default=float(os.environ.get("UNTIMELY_TIME_SCALE", "1")),
                        help="mission seconds per wall second (default: $UNTIMELY_TIME_SCALE, else 1)")
    parser.add_argument("--mission", type=Path, default=DEFAULT_MISSION_DIR,
                        help="folder of interface.toml, world.toml and ros.toml")
    args = parser.parse_args(argv)
    stopped = threading.Event()
    for signum in (signal.SIGTERM, signal.SIGINT):
        signal.signal(signum, lambda *_: stopped.set())
    rospy.init_node("dala", disable_rosout=True, disable_signals=True)
    try:
        node = DalaNode(args.variant, args.mission, args.time_scale)
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
