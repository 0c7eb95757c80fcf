"""ROS 2 bags (rosbag2, MCAP and SQLite3) import to the traces a robot recorded: written here with
rosbags' writer from the real action_msgs and service_msgs definitions and a made-up package's
action and service (tests/bags/rover.toml maps them), read raw by harness/sut/bags/ros2.py."""
import json
from pathlib import Path

import numpy as np
import pytest
from rosbags.rosbag2 import StoragePlugin, Writer

from harness import DEFAULT_MISSION_DIR
from harness.cli import main as cli
from harness.errors import InputFileError
from harness.sut.bags.ros2_types import register, typestore
from harness.store.database import connect
from harness.campaign.importing import import_path

MAPPING = Path(__file__).parent / "bags" / "rover.toml"
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


@pytest.mark.parametrize("plugin", [StoragePlugin.MCAP, StoragePlugin.SQLITE3])
def test_a_rosbag2_bag_imports_to_the_trace_the_robot_lived(tmp_path, interface, plugin):
    bag = robot_day(tmp_path / "day", plugin)
    assert imported(bag, interface) == [
        (1, 0.0, "request", 1, "ndd.SetParams", {"speed": 0.6}, None),  # the client's instants
        (2, 0.003, "final", 1, "ndd.SetParams", None, "ok"),
        (3, 1.0, "request", 2, "ndd.GotoPosition", {"x":9.0,"y":4.0}, None),
        (4, 1.5, "intermediate", 2, "ndd.GotoPosition", None, None),
        (5, 2.0, "request", 3, "ndd.GotoPosition", {"x":14.0,"y":11.0}, None),
        (6, 2.06, "final", 2, "ndd.GotoPosition", None, "interrupted"),  # preempted: the fallback code
        (7, 2.5, "intermediate", 3, "ndd.GotoPosition", None, None),
        (8, 5.01, "final", 3, "ndd.GotoPosition", None, "goal_unreachable"),  # aborted: the result's text
        (9, 6.0, "request", 4, "ndd.GotoPosition", {"x":30.0,"y":1.0}, None),
        (10, 6.01, "final", 4, "ndd.GotoPosition", None, "disallowed"),  # rejected: not accepted
    ]


@pytest.mark.parametrize("plugin", [StoragePlugin.MCAP, StoragePlugin.SQLITE3])
def test_the_servers_stamps_are_the_suts_clock_in_internal_events(tmp_path, interface, plugin):
    """From the bag's first receive stamp, on the server's clock (SKEW ahead): a request at its
    REQUEST_RECEIVED stamp, a final at its RESPONSE_SENT stamp (send_goal's for the rejected goal,
    get_result's for the preempted and the aborted one); feedback is unstamped, so no intermediate."""
    bag = robot_day(tmp_path / "day", plugin)
    assert imported(bag, interface, "internal_events") == [
        (1, 0.251, "request", 1, "ndd.SetParams", {"speed": 0.6}, None),
        (2, 0.252, "final", 1, "ndd.SetParams", None, "ok"),
        (3, 1.252, "request", 2, "ndd.GotoPosition", {"x": 9.0, "y": 4.0}, None),
        (4, 2.252, "request", 3, "ndd.GotoPosition", {"x": 14.0, "y": 11.0}, None),
        (5, 2.308, "final", 2, "ndd.GotoPosition", None, "interrupted"),  # preempted
        (6, 5.258, "final", 3, "ndd.GotoPosition", None, "goal_unreachable"),  # aborted
        (7, 6.252, "request", 4, "ndd.GotoPosition", {"x": 30.0, "y": 1.0}, None),
        (8, 6.254, "final", 4, "ndd.GotoPosition", None, "disallowed"),  # rejected
    ]


def test_without_introspection_the_suts_clock_has_the_accept_stamps_only(tmp_path, interface):
    """A status array carries no stamp of its own: its goals' accept stamps give their requests,
    and their terminal statuses no final on the SUT's clock. The origin is the first status array."""
    bag = robot_day(tmp_path / "day", StoragePlugin.SQLITE3, introspection=False)
    assert imported(bag, interface, "internal_events") == [
        (1, 0.235, "request", 1, "ndd.GotoPosition", None, None),
        (2, 1.235, "request", 2, "ndd.GotoPosition", None, None),
    ]


def test_the_mcap_file_alone_names_its_bag_and_the_cli_judges_it(tmp_path, capsys):
    robot_day(tmp_path / "day", StoragePlugin.MCAP)
    db = tmp_path / "s.duckdb"
    assert cli(["import", str(tmp_path / "day" / "day.mcap"), "--interface", str(DEFAULT_MISSION_DIR / "interface.toml"),
                "--ros", str(MAPPING), "--db", str(db)]) == 0
    assert "Imported 1 trace (10 events)" in capsys.readouterr().out
    assert cli(["analyze", "--db", str(db)]) == 0


def test_a_bag_without_introspection_says_what_it_lacks(tmp_path, interface, capsys):
    bag = robot_day(tmp_path / "day", StoragePlugin.MCAP, introspection=False)
    assert imported(bag, interface) == [  # from the status topic: no arguments, no rejected goal
        (1, 0.0, "request", 1, "ndd.GotoPosition", None, None),
        (2, 0.48, "intermediate", 1, "ndd.GotoPosition", None, None),
        (3, 1.03, "final", 1, "ndd.GotoPosition", None, "interrupted"),  # the status list that shows goal 2
        (4, 1.03, "request", 2, "ndd.GotoPosition", None, None),
        (5, 1.48, "intermediate", 2, "ndd.GotoPosition", None, None),
        (6, 3.98, "final", 2, "ndd.GotoPosition", None, "goal_unreachable"),
    ]
    err = capsys.readouterr().err
    assert "no goal introspection: requests come from the status topic, without arguments, and rejected goals are missing" in err
    assert "no call of the ROS services /ndd/set_params" in err and "configure_introspection" in err


def test_a_bag_of_other_topics_is_refused_naming_what_it_records(tmp_path, interface):
    bag = Bag(tmp_path / "other", StoragePlugin.MCAP)
    bag.write("/chatter", "builtin_interfaces/msg/Time", None, BASE, bag._t(1.0))
    bag.close()
    with pytest.raises(InputFileError, match=r"other.*no topic of the mapping .*rover.toml in this bag; it records /chatter"):
        imported(tmp_path / "other", interface)
