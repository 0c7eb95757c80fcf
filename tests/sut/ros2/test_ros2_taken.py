"""The ROS 2 adapter's `taken` replies from the servers' introspection events
(harness/sut/ros2/adapter.py): a call's event names it by its sequence number, a goal's by its goal
id, and only the server's event of receiving the request counts. Real message classes, no node:
the live test cannot tell these replies from the ones a response proves when its event comes late."""
import json
import subprocess

from harness import ROOT
from harness.sut.ros2.environment import Ros2Environment
from tests.support.ros_driver import requires_ros2

EVENTS = """
import json, threading
from types import SimpleNamespace
from service_msgs.msg import ServiceEventInfo
from unique_identifier_msgs.msg import UUID
from untimely_msgs.action import Request
from untimely_msgs.srv import Call
from harness.sut.ros.replies import Replies
from harness.sut.ros2.adapter import Adapter

written, after_each, goal_id = [], [], bytes(range(16))
adapter = SimpleNamespace(lock=threading.Lock(), replies=Replies(written.append, taken_promised=True),
                          calls={("/rflex", 7): 3}, goal_ids={goal_id.hex(): 4})
info = lambda kind, number=0: ServiceEventInfo(event_type=getattr(ServiceEventInfo, kind), sequence_number=number)
for kind, number in (("REQUEST_SENT", 7), ("REQUEST_RECEIVED", 8), ("REQUEST_RECEIVED", 7), ("RESPONSE_SENT", 7)):
    Adapter._called(adapter, "/rflex", Call.Event(info=info(kind, number)))
    after_each.append(len(written))
goal = [Request.Impl.SendGoalService.Request(goal_id=UUID(uuid=list(goal_id)))]
other = [Request.Impl.SendGoalService.Request(goal_id=UUID(uuid=[9] * 16))]
for kind, request in (("REQUEST_SENT", goal), ("REQUEST_RECEIVED", other), ("REQUEST_RECEIVED", goal)):
    Adapter._goal_taken(adapter, Request.Impl.SendGoalService.Event(info=info(kind), request=request))
    after_each.append(len(written))
print(json.dumps([written, after_each]))
"""


@requires_ros2("kilted")
def test_only_the_servers_event_of_receiving_a_known_request_gives_its_taken_reply():
    with Ros2Environment(ROOT, "kilted", slot=0) as ros:
        done = subprocess.run([str(ros.python), "-c", EVENTS], cwd=ROOT, env=ros.env, capture_output=True,
                              text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    written, after_each = json.loads(done.stdout)
    assert written == [{"op": "reply", "id": 3, "kind": "taken"}, {"op": "reply", "id": 4, "kind": "taken"}]
    assert after_each == [0, 0, 1, 1, 1, 1, 2]  # the replies written after each event: the received ones gave them
