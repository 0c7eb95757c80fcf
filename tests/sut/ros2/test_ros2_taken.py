"""The ROS 2 adapter's `taken` replies from the servers' introspection events
(harness/sut/ros2/introspection.py): a call's event names it by its sequence number, a goal's by its
goal id, a cancel's by the goal it cancels, only the server's event of receiving the request counts, and only on a topic its server
was found publishing. Real message classes, no node: the order of events is the test's own."""
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
from harness.sut.roscommon.replies import Replies
from action_msgs.msg import GoalInfo
from action_msgs.srv import CancelGoal
from harness.sut.ros2.introspection import call_taken, cancel_taken, goal_taken

written, after_each, goal_id = [], [], bytes(range(16))
adapter = SimpleNamespace(lock=threading.Lock(), replies=Replies(written.append), calls={("/rflex", 7): 3,
                          ("/sick", 7): 5}, goal_ids={goal_id.hex(): 4, bytes([8] * 16).hex(): 6},
                          cancelling={goal_id.hex(): [9, 10]},
                          introspected={"/rflex/_service_event", "/ndd/_action/send_goal/_service_event",
                                        "/ndd/_action/cancel_goal/_service_event"})
info = lambda kind, number=0: ServiceEventInfo(event_type=getattr(ServiceEventInfo, kind), sequence_number=number)
for kind, number in (("REQUEST_SENT", 7), ("REQUEST_RECEIVED", 8), ("REQUEST_RECEIVED", 7), ("RESPONSE_SENT", 7)):
    call_taken(adapter, "/rflex", Call.Event(info=info(kind, number)))
    after_each.append(len(written))
call_taken(adapter, "/sick", Call.Event(info=info("REQUEST_RECEIVED", 7)))  # a server found publishing none
after_each.append(len(written))
goal = [Request.Impl.SendGoalService.Request(goal_id=UUID(uuid=list(goal_id)))]
other = [Request.Impl.SendGoalService.Request(goal_id=UUID(uuid=[9] * 16))]
for kind, request in (("REQUEST_SENT", goal), ("REQUEST_RECEIVED", other), ("REQUEST_RECEIVED", goal)):
    goal_taken(adapter, "/ndd", Request.Impl.SendGoalService.Event(info=info(kind), request=request))
    after_each.append(len(written))
unseen = [Request.Impl.SendGoalService.Request(goal_id=UUID(uuid=[8] * 16))]
goal_taken(adapter, "/aspect", Request.Impl.SendGoalService.Event(info=info("REQUEST_RECEIVED"), request=unseen))
after_each.append(len(written))
cancel = [CancelGoal.Request(goal_info=GoalInfo(goal_id=UUID(uuid=list(goal_id))))]
for kind in ("REQUEST_SENT", "REQUEST_RECEIVED", "REQUEST_RECEIVED"):  # two cancels of the goal, in the order sent
    cancel_taken(adapter, "/ndd", Request.Impl.CancelGoalService.Event(info=info(kind), request=cancel))
    after_each.append(len(written))
print(json.dumps([written, after_each]))
"""


@requires_ros2("kilted")
def test_only_the_servers_event_of_receiving_a_known_request_on_a_published_topic_gives_its_taken():
    with Ros2Environment(ROOT, "kilted", slot=0) as ros:
        done = subprocess.run([str(ros.python), "-c", EVENTS], cwd=ROOT, env=ros.env, capture_output=True,
                              text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    written, after_each = json.loads(done.stdout)
    assert written == [{"op": "reply", "id": n, "kind": "taken"} for n in (3, 4, 9, 10)]
    # the replies written after each event: the received ones gave them, not those of servers not found publishing
    assert after_each == [0, 0, 1, 1, 1, 1, 1, 2, 2, 2, 3, 4]
