"""ROS 2 bags written without ROS (rosbags' rosbag2 writer) as a robot with introspection on records
them: a day of navigation goals mapped by tests/bags/rover.toml, and what a bag imports to."""
import json
from pathlib import Path

import numpy as np
from rosbags.rosbag2 import StoragePlugin, Writer

from harness.campaign.importing import import_path
from harness.store.database import connect
from harness.sut.bags.ros2_types import register, typestore
from tests.support.paths import BAGS

MAPPING = BAGS / "rover.toml"


DRIVE = "float64 x\nfloat64 y\n---\nstring message\n---\nfloat64 distance\n"


CONFIGURE = "float64 speed\n---\nbool success\nstring message\n"


BASE = 100.0  # the bag's clock: its first message


CLIENT, SERVER = np.arange(16, dtype=np.uint8), np.zeros(16, dtype=np.uint8)


SENT, RECEIVED, ANSWERED, GOT = range(4)


SKEW = 0.25  # the server's clock runs this far ahead of the recorder's: its stamps are the SUT's clock


ACCEPT = {1: BASE + 1.005, 2: BASE + 2.005}  # when the server accepted each goal (the recorder's clock)


ACCEPTED, EXECUTING, CANCELED, ABORTED = 1, 2, 5, 6


class Bag:
    """Writes one rosbag2 bag, message by message, as a robot with introspection on would record it."""

    def __init__(self, path: Path, plugin: StoragePlugin):
        self.store = typestore()
        register(self.store, "rover_msgs/action/Drive_SendGoal_Event", DRIVE)
        register(self.store, "rover_msgs/srv/Configure_Event", CONFIGURE)
        self.types = self.store.types
        self.writer = Writer(path, version=9, storage_plugin=plugin)
        self.writer.open()
        self.connections = {}

    def _t(self, s: float):
        return self.types["builtin_interfaces/msg/Time"](sec=int(s), nanosec=round((s % 1) * 1e9))

    def _uuid(self, goal: int):
        return self.types["unique_identifier_msgs/msg/UUID"](uuid=np.frombuffer(goal.to_bytes(16, "big"), np.uint8).copy())

    def write(self, topic: str, msgtype: str, definition: str | None, at: float, message) -> None:
        if topic not in self.connections:
            extra = {"msgdef": definition, "rihs01": "RIHS01_" + "0" * 64} if definition else {}
            self.connections[topic] = self.writer.add_connection(topic, msgtype, typestore=self.store, **extra)
        self.writer.write(self.connections[topic], int(at * 1e9), self.store.serialize_cdr(message, msgtype))

    def event(self, topic, msgtype, definition, at, kind, sequence, request=None, response=None) -> None:
        """An introspection event received at `at`; the server stamps its own on its clock."""
        stamp = at + SKEW if kind in (RECEIVED, ANSWERED) else at
        info = self.types["service_msgs/msg/ServiceEventInfo"](
            event_type=kind, stamp=self._t(stamp), client_gid=CLIENT, sequence_number=sequence)
        event = self.types[msgtype](info=info, request=[request] if request else [], response=[response] if response else [])
        self.write(topic, msgtype, definition, at, event)

    def configure(self, at: float, sequence: int, speed: float, success: bool, message: str) -> None:
        kind = "rover_msgs/srv/Configure_Event"
        request = self.types["rover_msgs/srv/Configure_Request"](speed=speed)
        response = self.types["rover_msgs/srv/Configure_Response"](success=success, message=message)
        for step, when in ((SENT, at), (RECEIVED, at + 0.001)):
            self.event("/ndd/set_params/_service_event", kind, CONFIGURE, when, step, sequence, request=request)
        for step, when in ((ANSWERED, at + 0.002), (GOT, at + 0.003)):
            self.event("/ndd/set_params/_service_event", kind, CONFIGURE, when, step, sequence, response=response)

    def send_goal(self, at: float, goal: int, x: float, y: float, accepted: bool) -> None:
        kind = "rover_msgs/action/Drive_SendGoal_Event"
        request = self.types["rover_msgs/action/Drive_SendGoal_Request"](
            goal_id=self._uuid(goal), goal=self.types["rover_msgs/action/Drive_Goal"](x=x, y=y))
        response = self.types["rover_msgs/action/Drive_SendGoal_Response"](accepted=accepted, stamp=self._t(0))  # rclcpp leaves it zero
        topic = "/navigate/_action/send_goal/_service_event"
        for step, when in ((SENT, at), (RECEIVED, at + 0.002)):
            self.event(topic, kind, DRIVE, when, step, goal, request=request)
        for step, when in ((ANSWERED, at + 0.004), (GOT, at + 0.01)):
            self.event(topic, kind, DRIVE, when, step, goal, response=response)

    def status(self, at: float, *goals: tuple[int, int]) -> None:
        types = self.types
        array = types["action_msgs/msg/GoalStatusArray"](status_list=[types["action_msgs/msg/GoalStatus"](
            goal_info=types["action_msgs/msg/GoalInfo"](goal_id=self._uuid(goal), stamp=self._t(ACCEPT[goal] + SKEW)),
            status=status)
            for goal, status in goals])
        self.write("/navigate/_action/status", "action_msgs/msg/GoalStatusArray", None, at, array)

    def feedback(self, at: float, goal: int) -> None:
        kind = "rover_msgs/action/Drive_FeedbackMessage"
        message = self.types[kind](goal_id=self._uuid(goal), feedback=self.types["rover_msgs/action/Drive_Feedback"](distance=1.0))
        self.write("/navigate/_action/feedback", kind, DRIVE, at, message)

    def result(self, at: float, goal: int, status: int, message: str) -> None:
        kind = "rover_msgs/action/Drive_GetResult_Event"
        request = self.types["rover_msgs/action/Drive_GetResult_Request"](goal_id=self._uuid(goal))
        response = self.types["rover_msgs/action/Drive_GetResult_Response"](
            status=status, result=self.types["rover_msgs/action/Drive_Result"](message=message))
        topic = "/navigate/_action/get_result/_service_event"
        for step, when in ((SENT, at - 0.5), (RECEIVED, at - 0.499)):
            self.event(topic, kind, DRIVE, when, step, 100 + goal, request=request)
        for step, when in ((ANSWERED, at - 0.002), (GOT, at)):
            self.event(topic, kind, DRIVE, when, step, 100 + goal, response=response)

    def close(self) -> None:
        self.writer.close()


def robot_day(path: Path, plugin: StoragePlugin, introspection: bool = True) -> Path:
    """Navigation settings; goal 1 preempted by goal 2, which aborts; goal 3 rejected."""
    bag = Bag(path, plugin)
    if introspection:
        bag.configure(BASE, 1, 0.6, True, "ok")
        bag.send_goal(BASE + 1.0, 1, 9.0, 4.0, True)
    bag.status(BASE + 1.02, (1, ACCEPTED))
    bag.status(BASE + 1.03, (1, EXECUTING))
    bag.feedback(BASE + 1.5, 1)
    if introspection:
        bag.send_goal(BASE + 2.0, 2, 14.0, 11.0, True)
    bag.status(BASE + 2.05, (1, CANCELED), (2, EXECUTING))
    if introspection:
        bag.result(BASE + 2.06, 1, CANCELED, "")
    bag.feedback(BASE + 2.5, 2)
    bag.status(BASE + 5.0, (1, CANCELED), (2, ABORTED))
    if introspection:
        bag.result(BASE + 5.01, 2, ABORTED, "goal_unreachable")
        bag.send_goal(BASE + 6.0, 3, 30.0, 1.0, False)
    bag.close()
    return path


def imported(path: Path, interface, table: str = "events"):
    con = connect(":memory:")
    import_path(con, path, interface, str(MAPPING))
    rows = con.execute("select seq, round(t, 4), kind, rqst_id, module || '.' || service, args::varchar, reply "
                       f"from {table} order by seq").fetchall()
    return [(*row[:5], json.loads(row[5]) if row[5] else None, row[6]) for row in rows]
