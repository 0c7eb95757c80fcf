"""The generic ROS 1 adapter: `untimely/1` requests become actionlib goals or ROS service calls,
goal statuses and responses become replies.

Nothing here knows Dala: the services come from the bench's hello, the routes and the status
codes from the mapping file. Rules (docs/ros.md):

- a request is a goal of its route's action: the generic `untimely_msgs/Request` (service name,
  JSON arguments) or a typed goal whose fields its arguments fill (messages.fill); or it is a
  call of its route's ROS service, whose response is the final reply (Route.response_code);
- the first feedback before the result is the intermediate reply; ACTIVE alone is none (a short
  goal's result may come without ACTIVE ever being seen); feedback after the result is dropped
  (replies.py);
- the result gives the final reply (Mapping.final_code); LOST, the client's verdict when a
  server's status list forgets a goal, gives none: the adapter never invents a final;
- a ping is answered once every action server's status heartbeat is fresh and, if the mapping
  has a ping topic, the SUT has echoed it; a dead or deadlocked server leaves its goals ACTIVE
  forever and its pings unanswered, so the bench records `hung`;
- the clients and subscriptions outlive a run, the run's goals do not: each hello starts a run
  (a generation), and whatever ROS delivers of an earlier run, or between runs, is dropped.
"""
from __future__ import annotations

import json
import threading
import time
from typing import Callable

import actionlib
import rospy
from actionlib_msgs.msg import GoalStatus, GoalStatusArray
from std_msgs.msg import String

from harness.sut.roscommon.bridge import Bridge
from harness.sut.roscommon.mapping import Mapping, interface_services
from harness.sut.ros.messages import action_classes, fill, service_class
from harness.sut.roscommon.replies import Replies
from harness.sut.roscommon.routes import Route
from harness.errors import UntimelyError

STATUS_NAMES = {getattr(GoalStatus, name): name for name in
                ("PENDING", "ACTIVE", "PREEMPTED", "SUCCEEDED", "ABORTED", "REJECTED",
                 "PREEMPTING", "RECALLING", "RECALLED", "LOST")}


class Ros1Adapter(Bridge):
    def __init__(self, mapping: Mapping, interface: dict, time_scale: float, write: Callable[[dict], None]):
        super().__init__(mapping, interface, time_scale, write)
        self.routes = mapping.routes(interface_services(interface))
        actions = {route.name: route for route in self.routes.values() if route.kind == "action"}
        self.classes = {name: action_classes(route, mapping.folder) for name, route in actions.items()}
        self.clients = {name: actionlib.ActionClient(name, classes.Action) for name, classes in self.classes.items()}
        self.services = {route.name: service_class(route, mapping.folder) for route in self.routes.values() if route.kind == "service"}
        self.heartbeats: dict[str, float] = {}  # action -> monotonic time of its last status
        self.goals: dict[int, actionlib.ClientGoalHandle] = {}  # kept: actionlib holds only weak references
        for name in self.clients:
            rospy.Subscriber(f"{name}/status", GoalStatusArray, self._heartbeat, callback_args=name)
        self.topics = [rospy.Subscriber(topic, String, handler) for topic, handler in
                       ((mapping.world_topic, self._world), (mapping.internal_topic, self._internal),
                        (mapping.pong_topic, self._pong)) if topic]
        self.pinger = rospy.Publisher(mapping.ping_topic, String, queue_size=100) if mapping.ping_topic else None
        if self.pinger:
            self.topics.append(self.pinger)

    def forget(self) -> None:
        self.goals = {}

    def publish_ping(self, data: str) -> None:
        self.pinger.publish(data)

    def alive(self) -> bool:
        """Every action server's status heartbeat is fresh."""
        now = time.monotonic()
        return all(now - self.heartbeats.get(name, -1e9) <= self.mapping.heartbeat_stale_s for name in self.clients)

    def wait_for_servers(self, timeout_s: float, alive: Callable[[], str | None]) -> None:
        """Block until every action server and topic is connected (a message published before its
        subscriber connects is lost); `alive()` names a reason to give up."""
        deadline = time.monotonic() + timeout_s
        waits = [(name, lambda c=client: c.wait_for_server(rospy.Duration(0.1))) for name, client in self.clients.items()]
        waits += [(name, lambda n=name: self._service_up(n)) for name in self.services]
        waits += [(topic.name, lambda t=topic: t.get_num_connections() > 0 or time.sleep(0.1)) for topic in self.topics]
        if self.pinger:  # the SUT echoes once its side of every topic is connected too
            waits.append((f"an echo on {self.mapping.pong_topic}", self.echoed))
        for name, connected in waits:
            while not connected():
                problem = alive()
                if problem or time.monotonic() > deadline:
                    raise UntimelyError(problem or f"{name} did not come up within {timeout_s:g} s")

    @staticmethod
    def _service_up(name: str) -> bool:
        try:
            rospy.wait_for_service(name, 0.1)
            return True
        except rospy.ROSException:
            return False

    # -- bench -> ROS --------------------------------------------------------------------------
    def request(self, message: dict) -> None:
        rqst_id, module, service = message["id"], message["module"], message["service"]
        route = self.routes.get(f"{module}.{service}")
        if route is None:
            raise UntimelyError(f"request {rqst_id} names {module}.{service}, which the hello's interface does not declare")
        if route.kind == "service":
            self._call(rqst_id, route, message["args"])
            return
        classes = self.classes[route.name]
        if route.generic:
            goal = classes.Goal(service=service, args_json=json.dumps(message["args"]))
        else:
            goal = fill(classes.Goal(), route, message["args"])
        with self.lock:
            replies = self.replies  # this run's: a late event of this goal cannot reach the next run
            handle = self.clients[route.name].send_goal(
                goal, transition_cb=lambda gh: self._transition(replies, rqst_id, route, gh),
                feedback_cb=lambda gh, fb: replies.feedback(rqst_id))
            self.goals[rqst_id] = handle
            self.goal_ids[handle.comm_state_machine.action_goal.goal_id.id] = rqst_id

    def _call(self, rqst_id: int, route: Route, args: dict) -> None:
        """A ROS service call blocks until its response: each runs on its own thread. The call's
        connection header names it, so the SUT's ground truth can say which request it was."""
        kind = self.services[route.name]
        request = fill(kind._request_class(), route, args)
        call_id = f"call-{rqst_id}"
        with self.lock:
            self.goal_ids[call_id] = rqst_id
            replies = self.replies

        def call() -> None:
            try:
                response = rospy.ServiceProxy(route.name, kind, headers={"untimely_call": call_id})(request)
            except (rospy.ServiceException, rospy.ROSException) as e:
                replies.ended(rqst_id, f"a failed call ({e})", None)
                return
            replies.ended(rqst_id, "RESPONSE", route.response_code(response, self.catalogue))
        threading.Thread(target=call, name=f"call {rqst_id}", daemon=True).start()

    # -- ROS -> bench (ROS threads) ------------------------------------------------------------
    def _transition(self, replies: Replies, rqst_id: int, route: Route, handle) -> None:
        if handle.get_comm_state() == actionlib.CommState.DONE:
            status = STATUS_NAMES.get(handle.get_goal_status())
            result = handle.get_result()
            texts = (getattr(result, route.code or "code", None), handle.get_goal_status_text())
            replies.ended(rqst_id, status, self.mapping.final_code(status, texts, self.catalogue))

    def _heartbeat(self, _statuses, action: str) -> None:
        with self.lock:
            self.heartbeats[action] = time.monotonic()
            self._answer_pings()
