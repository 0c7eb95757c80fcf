"""ROS 2 bags (rosbag2, MCAP and SQLite3) import to the traces a robot recorded: written here with
rosbags' writer from the real action_msgs and service_msgs definitions and a made-up package's
action and service (tests/bags/rover.toml maps them), read raw by harness/sut/bags/ros2.py."""
import pytest
from rosbags.rosbag2 import StoragePlugin

from harness import DEFAULT_MISSION_DIR
from harness.cli import main as cli
from harness.errors import InputFileError
from tests.support.bags2 import BASE, MAPPING, Bag, imported, robot_day


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
