"""The generic ROS 2 adapter (rclpy): `untimely/1` requests become action goals or service calls,
goal results and responses become replies (docs/ros2.md, the table in docs/adapters.md).

Nothing here knows Dala: the services come from the bench's hello, the routes and status codes
from the mapping file (ros2.toml). Rules:

- an `exec` request is a goal of its route's action (untimely_msgs/action/Request: service name and
  JSON arguments, or a typed goal whose fields its arguments fill), sent with a goal id of the
  adapter's making, so the node's ground truth names it before the goal response arrives;
- a goal response that does not accept is a final reply: the mapping's REJECTED code (ROS 2's
  response carries no reason; a layer that wants its reason told accepts the goal and aborts it
  with the code in the result, as the Dala node does);
- the first feedback before the result is the intermediate reply; acceptance alone is none;
- the result ends the request: SUCCEEDED, ABORTED or CANCELED with the result's code when the
  catalogue knows it, else the mapping's status code (Mapping.final_code); an unknown status
  gives no final reply: the adapter never invents one;
- a `control` or `init` request on a service route is a call; its response is the final reply; a
  call has no id, so the node's ground truth names the n-th call of a service "SERVICE#n", as the
  adapter counts them (one client per service: they arrive in the order sent);
- `taken`, only for the services whose server publishes introspection (found in the graph once
  the node is up, introspection.py; the hello's `taken_services`): the server's event of receiving
  the request, a goal's named by its id, a call's by its sequence number, is relayed as a `taken`
  reply when it is the request's first news; one arriving after the feedback or response gives
  none (harness/sut/roscommon/replies.py); no `taken` is ever made up;
- a request of a service the mapping's [cancels] names is a cancel request, of the goal its
  `goal` argument names or else of the latest goal of the service it names, sent to that action's
  cancel_goal (the cancel service needs no route); the cancel's response is its final reply
  (cancels.py);
- liveness: the node's executor must answer NODE/get_parameters (probed every PROBE_PERIOD_S) within
  the mapping's heartbeat_stale_s, the node must echo the ping, and a probe sent with the ping must
  come back; otherwise the pings go unanswered (the trace is `hung`) and stderr says why.
"""
from __future__ import annotations

import os
import sys
import threading
import time
from typing import Callable

import rclpy
from action_msgs.msg import GoalStatus
from rcl_interfaces.srv import GetParameters
from rclpy.action import ActionClient
from rclpy.callback_groups import ReentrantCallbackGroup
from rclpy.executors import MultiThreadedExecutor
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.service_introspection import ServiceIntrospectionState
from std_msgs.msg import String
from unique_identifier_msgs.msg import UUID

from harness.sut.roscommon.bridge import Bridge
from harness.sut.roscommon.mapping import Mapping, check_cancels, interface_kinds, interface_services
from harness.sut.roscommon.replies import Replies
from harness.sut.roscommon.routes import Route
from harness.sut.ros2 import introspection
from harness.sut.ros2.cancels import send_cancel
from harness.sut.ros2.lifecycle import Lifecycle
from harness.sut.ros2.teardown import release
from harness.sut.ros2.types import fill, interface_name, route_class
from harness.errors import UntimelyError

STATUS_NAMES = {GoalStatus.STATUS_SUCCEEDED: "SUCCEEDED", GoalStatus.STATUS_ABORTED: "ABORTED",
                GoalStatus.STATUS_CANCELED: "CANCELED"}
QOS = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
PROBE_PERIOD_S = 0.2
# rclpy counts no client's unanswered requests publicly; these are its tables of them (Jazzy, Kilted)
PENDING_TABLES = ("_pending_requests", "_pending_goal_requests", "_pending_cancel_requests", "_pending_result_requests")


class Ros2Adapter(Bridge):
    def __init__(self, mapping: Mapping, interface: dict, time_scale: float, write: Callable[[dict], None]):
        super().__init__(mapping, interface, time_scale, write)
        # "module.Service" cancelled -> its action route; a cancel service has no route of its own
        self.cancelled = check_cancels(mapping, interface)
        self.routes = mapping.routes([s for s in interface_services(interface) if ".".join(s) not in mapping.cancels],
                                     interface_kinds(interface))
        self.node = rclpy.create_node("untimely_adapter")
        group = ReentrantCallbackGroup()
        self.types = {route.name: route_class(route) for route in self.routes.values()}
        self.clients = {route.name: (ActionClient(self.node, self.types[route.name], route.name, callback_group=group)
                                     if route.kind == "action" else
                                     self.node.create_client(self.types[route.name], route.name, callback_group=group))
                        for route in self.routes.values()}
        self.calls: dict[tuple[str, int], int] = {}  # (service, the call's sequence number) -> request id
        self.call_counts: dict[str, int] = {}  # service -> calls made this run (the node counts them too)
        self.introspected: set[str] = set()  # the event topics their servers publish (find_introspection)
        introspection.subscribe(self, QOS, group)
        for topic, handler in ((mapping.world_topic, self._world), (mapping.internal_topic, self._internal),
                               (mapping.pong_topic, self._pong)):
            if topic:
                self.node.create_subscription(String, topic, handler, QOS, callback_group=group)
        self.pinger = self.node.create_publisher(String, mapping.ping_topic, QOS) if mapping.ping_topic else None
        node = mapping.node
        self.probe = self.node.create_client(GetParameters, f"{node}/get_parameters", callback_group=group) \
            if node else None
        self.lifecycle = Lifecycle(self.node, node, group) if mapping.lifecycle else None
        # when the probe in flight was sent (None: none unanswered): the executor's silence is its age,
        # not the time since the last answer, which also counts this process's own delays under load
        self.probe_sent: float | None = None
        self.stale_said = False
        self.goals: dict[int, object] = {}  # request id -> ClientGoalHandle of this run
        self.latest: dict[str, UUID] = {}  # "module.Service" -> the id of its latest goal of this run
        self.sent_goals: dict[int, tuple[str, UUID]] = {}  # request id -> ("module.Service", goal id), this run's
        self.cancelling: dict[str, list[int]] = {}  # goal id (hex) -> the cancel requests of it not yet taken
        self.unprobed: set[int] = set()  # the bench's pings whose own probe has not come back
        self.executor = MultiThreadedExecutor(num_threads=4)
        self.executor.add_node(self.node)
        self.stopped = threading.Event()
        threading.Thread(target=self.executor.spin, name="executor", daemon=True).start()

    def find_introspection(self) -> list[str]:
        """Once the node is up: the "module.Service" whose servers publish introspection (the hello's
        `taken_services`), whose events are relayed from now on."""
        return introspection.find(self)

    def forget(self) -> None:
        self.goals, self.calls, self.call_counts, self.unprobed = {}, {}, {}, set()
        self.latest, self.cancelling, self.sent_goals = {}, {}, {}

    def ping(self, message: dict) -> None:
        """The echo through the ping topic, and a round trip of its own through the node's executor
        (a service, as goal results and responses travel): the pong waits for both, so the round
        trip the bench measures, and the epsilon it judges with, include the executor's delays."""
        if self.probe:
            with self.lock:
                self.unprobed.add(message["id"])
            self.probe.call_async(GetParameters.Request()).add_done_callback(
                lambda _f, ping_id=message["id"]: self._ping_probed(ping_id))
        super().ping(message)

    def _ping_probed(self, ping_id: int) -> None:
        with self.lock:
            self.unprobed.discard(ping_id)
            self._answer_pings()

    def ping_done(self, ping_id: int) -> bool:
        return ping_id not in self.unprobed

    def publish_ping(self, data: str) -> None:
        self.pinger.publish(String(data=data))

    def alive(self) -> bool:
        """The node's executor answered a probe within heartbeat_stale_s (no node named: always)."""
        sent = self.probe_sent
        silent = 0.0 if sent is None else time.monotonic() - sent
        if self.probe is None or silent <= self.mapping.heartbeat_stale_s:
            return True
        if not self.stale_said:
            self.stale_said = True
            print(f"ros2 adapter: the node's executor has not answered {self.mapping.node}/get_parameters for "
                  f"{silent:.1f} s (heartbeat_stale_s = {self.mapping.heartbeat_stale_s:g}): it is stuck or dead; "
                  "no more pongs", file=sys.stderr, flush=True)
        return False

    # -- start-up, liveness, lifecycle -----------------------------------------------------------
    def wait_for_servers(self, timeout_s: float, alive: Callable[[], str | None]) -> None:
        """Block until every server, service and topic is connected; `alive()` names a reason to give up."""
        deadline = time.monotonic() + timeout_s
        waits = [(name, lambda c=client: c.server_is_ready() if isinstance(c, ActionClient) else c.service_is_ready())
                 for name, client in self.clients.items()]
        waits += [(client.srv_name, client.service_is_ready)
                  for client in ([self.probe] if self.probe else []) + (self.lifecycle.clients() if self.lifecycle else [])]
        for name, connected in waits:
            while not connected():
                problem = alive()
                if problem or time.monotonic() > deadline:
                    raise UntimelyError(problem or f"{name} did not come up within {timeout_s:g} s")
                time.sleep(0.05)

    def wait_echo(self, timeout_s: float, alive: Callable[[], str | None]) -> None:
        """Block until the node echoes a start-up ping: its topics are connected and its layer answers."""
        deadline = time.monotonic() + timeout_s
        while not self.echoed():
            problem = alive()
            if problem or time.monotonic() > deadline:
                raise UntimelyError(problem or f"no echo on {self.mapping.pong_topic} within {timeout_s:g} s")

    def start_probing(self) -> None:
        if self.probe:
            threading.Thread(target=self._probing, name="probe", daemon=True).start()

    def _probing(self) -> None:
        """One probe at a time: a stuck executor leaves it unanswered, and `alive` sees the silence."""
        while not self.stopped.is_set():
            self.probe_sent = time.monotonic()
            answer = self.probe.call_async(GetParameters.Request())
            done = threading.Event()
            answer.add_done_callback(lambda _f: done.set())
            while not done.wait(PROBE_PERIOD_S) and not self.stopped.is_set():
                with self.lock:
                    self._answer_pings()  # says once, on stderr, that the executor fell silent
            with self.lock:
                self.probe_sent, self.stale_said = None, False
                self._answer_pings()
            self.stopped.wait(PROBE_PERIOD_S)

    def unanswered(self, timeout_s: float) -> int:
        """How many requests of the ended run the node still has not answered (a call, a goal's
        acceptance, cancel or result: a goal still executing), once they are none or `timeout_s` is past."""
        deadline = time.monotonic() + timeout_s
        while (count := sum(len(getattr(client, table, ())) for client in self.clients.values()
                            for table in PENDING_TABLES)) and time.monotonic() < deadline:
            time.sleep(0.05)
        return count

    def transition(self, transitions: tuple[int, ...], timeout_s: float) -> None:
        self.lifecycle.transition(transitions, timeout_s)

    def record(self, path, timeout_s: float):
        """A McapRecorder of this run's traffic into the bag `path`, spun by this adapter's executor, once
        every topic it records has its publisher: each route's topics and introspection (the clients'
        side too), and the ground truth and virtual damage topics."""
        from harness.sut.ros2.recorder import McapRecorder, action_topics, service_topics

        distro, topics = os.environ.get("UNTIMELY_ROS2_DISTRO"), []
        for route in {route.name: route for route in self.routes.values()}.values():
            full = interface_name(route)
            topics += action_topics(route.name, full, distro) if route.kind == "action" else service_topics(route.name, full)
            client = self.clients[route.name]
            if hasattr(client, "configure_introspection"):  # services from Jazzy on, actions from Kilted on
                client.configure_introspection(self.node.get_clock(), QOS, ServiceIntrospectionState.CONTENTS)
        topics += [(topic, "std_msgs/msg/String") for topic in (self.mapping.internal_topic, self.mapping.world_topic)
                   if topic]
        recorder = McapRecorder(path, topics)
        missing = recorder.wait_for_publishers(timeout_s)
        if missing:
            recorder.close()
            raise UntimelyError(f"the recorder found no publisher of {', '.join(missing)} within {timeout_s:g} s")
        self.executor.add_node(recorder.node)
        return recorder

    def close(self) -> None:
        self.stopped.set()
        release([self.node], self.executor)

    # -- bench -> ROS 2 --------------------------------------------------------------------------
    def request(self, message: dict) -> None:
        rqst_id, module, service = message["id"], message["module"], message["service"]
        if f"{module}.{service}" in self.cancelled:
            return send_cancel(self, rqst_id, f"{module}.{service}", message["args"])
        route = self.routes.get(f"{module}.{service}")
        if route is None:
            raise UntimelyError(f"request {rqst_id} names {module}.{service}, which the hello's interface does not declare")
        kind = self.types[route.name]
        body = kind.Goal if route.kind == "action" else kind.Request
        body = fill(body(**({"service": service} if route.generic else {})), route, message["args"])
        with self.lock:
            replies = self.replies  # this run's: a late event of this request cannot reach the next run
            if route.kind == "service":
                client = self.clients[route.name]
                future = client.call_async(body)
                # rclpy keeps no public record of a call's sequence number, which its introspection names
                self.calls[(route.name, next(n for n, f in client._pending_requests.items() if f is future))] = rqst_id
                self.call_counts[route.name] = self.call_counts.get(route.name, 0) + 1
                self.goal_ids[f"{route.name}#{self.call_counts[route.name]}"] = rqst_id  # its ground truth's name
                future.add_done_callback(lambda f: self._responded(replies, rqst_id, route, f))
                return
            goal_id = os.urandom(16)
            self.goal_ids[goal_id.hex()] = rqst_id
            uuid = self.latest[f"{module}.{service}"] = UUID(uuid=list(goal_id))
            self.sent_goals[rqst_id] = (f"{module}.{service}", uuid)
            future = self.clients[route.name].send_goal_async(
                body, feedback_callback=lambda _fb: replies.feedback(rqst_id), goal_uuid=uuid)
        future.add_done_callback(lambda f: self._accepted(replies, rqst_id, route, f))

    # -- ROS 2 -> bench (executor threads) -------------------------------------------------------
    def _responded(self, replies: Replies, rqst_id: int, route: Route, future) -> None:
        if future.exception() is not None:
            replies.ended(rqst_id, f"a failed call ({future.exception()})", None)
        else:
            replies.ended(rqst_id, "RESPONSE", route.response_code(future.result(), self.catalogue))

    def _accepted(self, replies: Replies, rqst_id: int, route: Route, future) -> None:
        handle = future.result()
        if not handle.accepted:
            replies.ended(rqst_id, "REJECTED", self.mapping.final_code("REJECTED", (), self.catalogue))
            return
        with self.lock:
            self.goals[rqst_id] = handle
        handle.get_result_async().add_done_callback(lambda f: self._result(replies, rqst_id, route, f))

    def _result(self, replies: Replies, rqst_id: int, route: Route, future) -> None:
        response = future.result()
        status = STATUS_NAMES.get(response.status, f"status {response.status}")
        text = getattr(response.result, route.code or "code", None)
        replies.ended(rqst_id, status, self.mapping.final_code(status, (text,), self.catalogue))
