"""ROS 1 bags written without ROS (rosbags' rosbag1 writer), holding the actionlib topics of the
generic action, and what they import to."""
import json

from rosbags.rosbag1 import Writer
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from harness.campaign.importing import import_path
from harness.store.database import connect

ACTION = {  # what genaction.py writes for Request.action
    "RequestActionGoal": "Header header\nactionlib_msgs/GoalID goal_id\nRequestGoal goal\n",
    "RequestActionResult": "Header header\nactionlib_msgs/GoalStatus status\nRequestResult result\n",
    "RequestActionFeedback": "Header header\nactionlib_msgs/GoalStatus status\nRequestFeedback feedback\n",
    "RequestGoal": "string service\nstring args_json\n",
    "RequestResult": "string code\n",
    "RequestFeedback": "string phase\n",
}


PENDING, ACTIVE, PREEMPTED, SUCCEEDED, ABORTED, REJECTED = range(6)


class Bag:
    def __init__(self, path):
        self.store = get_typestore(Stores.ROS1_NOETIC)
        for name, text in ACTION.items():
            self.store.register(get_types_from_msg(text, f"untimely_msgs/msg/{name}"))
        self.types = self.store.types
        self.writer = Writer(path)
        self.writer.open()
        self.connections = {}

    def _time(self, s):
        return self.types["builtin_interfaces/msg/Time"](sec=int(s), nanosec=round((s % 1) * 1e9))

    def _header(self, s):
        return self.types["std_msgs/msg/Header"](seq=0, stamp=self._time(s), frame_id="")

    def _status(self, goal, status, text, s):
        goal_id = self.types["actionlib_msgs/msg/GoalID"](stamp=self._time(s), id=goal)
        return self.types["actionlib_msgs/msg/GoalStatus"](goal_id=goal_id, status=status, text=text)

    def write(self, topic, name, at, message):
        msgtype = f"untimely_msgs/msg/{name}" if "/" not in name else name
        if topic not in self.connections:
            self.connections[topic] = self.writer.add_connection(topic, msgtype, typestore=self.store)
        self.writer.write(self.connections[topic], int(at * 1e9), self.store.serialize_ros1(message, msgtype))

    def goal(self, at, goal, service, sent=None, **args):
        types = self.types
        message = types["untimely_msgs/msg/RequestActionGoal"](
            header=self._header(at), goal_id=types["actionlib_msgs/msg/GoalID"](stamp=self._time(sent or at), id=goal),
            goal=types["untimely_msgs/msg/RequestGoal"](service=service, args_json=json.dumps(args)))
        self.write("/dala/ndd/goal", "RequestActionGoal", at, message)

    def feedback(self, at, goal, stamp=None):
        message = self.types["untimely_msgs/msg/RequestActionFeedback"](
            header=self._header(stamp or at), status=self._status(goal, ACTIVE, "", at),
            feedback=self.types["untimely_msgs/msg/RequestFeedback"](phase="running"))
        self.write("/dala/ndd/feedback", "RequestActionFeedback", at, message)

    def result(self, at, goal, status, code, stamp=None):
        message = self.types["untimely_msgs/msg/RequestActionResult"](
            header=self._header(stamp or at), status=self._status(goal, status, code, at),
            result=self.types["untimely_msgs/msg/RequestResult"](code=code))
        self.write("/dala/ndd/result", "RequestActionResult", at, message)

    def status(self, at, stamp, *goals):
        """A status list stamped `stamp` by the server: (goal, status, text) each."""
        message = self.types["actionlib_msgs/msg/GoalStatusArray"](
            header=self._header(stamp), status_list=[self._status(goal, status, text, at) for goal, status, text in goals])
        self.write("/dala/ndd/status", "actionlib_msgs/msg/GoalStatusArray", at, message)

    def close(self):
        self.writer.close()


def imported(path, interface, **options):
    con = connect(":memory:")
    import_path(con, path, interface, **options)
    rows = con.execute("select label, seq, round(t, 3), kind, rqst_id, service, args::varchar, reply "
                       "from events join traces using (trace_id) order by trace_id, seq").fetchall()
    return [(*row[:6], json.loads(row[6]) if row[6] else None, row[7]) for row in rows]
