"""ROS 1 bags without ROS: bags written here with rosbags' rosbag1 writer, holding the actionlib
topics of the generic action (untimely_msgs/Request, the seven messages genaction derives from
harness/sut/ros/untimely_msgs/Request.action), import to the traces the test expects
(harness/sut/bags/ros1.py). The bag recorded by Debian's rosbag during a live run is in
test_ros_bags1.py."""
import pytest

from harness import DEFAULT_MISSION_DIR
from harness.errors import InputFileError
from harness.store.database import connect
from harness.campaign.importing import import_path
from tests.support.bags1 import ABORTED, ACTIVE, PREEMPTED, REJECTED, SUCCEEDED, Bag, imported


def test_a_ros1_bag_imports_rejected_aborted_and_preempted_goals(tmp_path, interface):
    bag = Bag(tmp_path / "drive.bag")
    bag.goal(10.0, "g1", "GotoPosition", x=9.0, y=4.0)  # before Init: REJECTED, the result's code
    bag.result(10.01, "g1", REJECTED, "wait_init")
    bag.goal(11.0, "g2", "Init")
    bag.result(11.5, "g2", SUCCEEDED, "ok")
    bag.goal(12.0, "g3", "GotoPosition", x=3.0, y=2.0)
    bag.feedback(12.01, "g3")
    bag.goal(13.0, "g4", "GotoPosition", x=5.0, y=5.0)
    bag.result(13.01, "g3", PREEMPTED, "")  # preempted by g4: the fallback of [status_codes]
    bag.result(14.0, "g4", ABORTED, "")  # the result names no code, the status text neither
    bag.feedback(14.02, "g4", stamp=13.5)  # received after its result, sent before it: kept
    bag.close()
    with pytest.raises(InputFileError, match=r"drive.bag:.*'aborted' is not in the reply catalogue"):
        imported(tmp_path / "drive.bag", interface)  # Dala's ros.toml: ABORTED = "aborted", not catalogued
    mapping = tmp_path / "ros.toml"
    mapping.write_text((DEFAULT_MISSION_DIR / "ros.toml").read_text().replace('ABORTED = "aborted"',
                                                                              'ABORTED = "goal_unreachable"'))
    assert imported(tmp_path / "drive.bag", interface, ros=str(mapping)) == [
        ("drive.bag", 1, 0.0, "request", 1, "GotoPosition", {"x": 9.0, "y": 4.0}, None),
        ("drive.bag", 2, 0.01, "final", 1, "GotoPosition", None, "wait_init"),
        ("drive.bag", 3, 1.0, "request", 2, "Init", {}, None),
        ("drive.bag", 4, 1.5, "final", 2, "Init", None, "ok"),
        ("drive.bag", 5, 2.0, "request", 3, "GotoPosition", {"x": 3.0, "y": 2.0}, None),
        ("drive.bag", 6, 2.01, "intermediate", 3, "GotoPosition", None, None),
        ("drive.bag", 7, 3.0, "request", 4, "GotoPosition", {"x": 5.0, "y": 5.0}, None),
        ("drive.bag", 8, 3.01, "final", 3, "GotoPosition", None, "interrupted"),
        ("drive.bag", 9, 4.0, "intermediate", 4, "GotoPosition", None, None),
        ("drive.bag", 10, 4.0, "final", 4, "GotoPosition", None, "goal_unreachable"),
    ]


def test_requests_are_numbered_in_the_order_their_client_sent_them(tmp_path, interface):
    bag = Bag(tmp_path / "order.bag")
    bag.goal(1.0, "late", "Init", sent=0.6)  # received first, sent second
    bag.goal(1.1, "early", "Stop", sent=0.5)
    bag.close()
    rows = imported(tmp_path / "order.bag", interface)
    assert [(r[3], r[4], r[5]) for r in rows] == [("request", 2, "Init"), ("request", 1, "Stop")]


def test_a_folder_of_bags_is_one_trace_each(tmp_path, interface):
    for name in ("a.bag", "b.bag"):
        bag = Bag(tmp_path / name)
        bag.goal(1.0, "g", "Init")
        bag.result(1.5, "g", SUCCEEDED, "ok")
        bag.close()
    assert [(r[0], r[3]) for r in imported(tmp_path, interface)] == [
        ("a.bag", "request"), ("a.bag", "final"), ("b.bag", "request"), ("b.bag", "final")]


def test_a_bag_without_the_mapped_topics_is_refused_naming_them(tmp_path, interface):
    bag = Bag(tmp_path / "chat.bag")
    bag.write("/chatter", "std_msgs/msg/String", 1.0, bag.types["std_msgs/msg/String"](data="hi"))
    bag.close()
    with pytest.raises(InputFileError, match=r"chat.bag:+ no actionlib topic of the mapping .*ros.toml in this bag; "
                                             r"it records /chatter"):
        imported(tmp_path / "chat.bag", interface)


def test_a_file_that_is_no_bag_is_refused_naming_it(tmp_path, interface):
    (tmp_path / "broken.bag").write_text("not a bag")
    with pytest.raises(InputFileError, match=r"broken.bag:+ cannot read the bag \(AnyReaderError: File magic is "
                                             r"invalid.\); is it whole\?"):
        imported(tmp_path / "broken.bag", interface)


def test_the_servers_header_stamps_are_the_suts_clock_in_internal_events(tmp_path, interface):
    """The receive stamps are `events`; the server's stamps on status, feedback and result are
    `internal_events`, from the same origin: a request at the first status naming it, a final at
    its result's stamp or, without a result, its terminal status's; a goal never stamped is left out."""
    bag = Bag(tmp_path / "clock.bag")
    bag.goal(10.0, "g1", "Init")
    bag.status(10.2, 10.05, ("g1", ACTIVE, ""))
    bag.feedback(10.3, "g1", stamp=10.1)
    bag.result(10.6, "g1", SUCCEEDED, "ok", stamp=10.4)
    bag.goal(11.0, "g2", "Stop")  # nothing from the server: no SUT instant
    bag.goal(12.0, "g3", "GotoPosition", x=1.0, y=1.0)
    bag.status(12.3, 12.25, ("g3", REJECTED, "wait_init"))  # its result is not in the bag
    bag.close()
    con = connect(":memory:")
    import_path(con, tmp_path / "clock.bag", interface)
    assert con.execute("select rqst_id, kind, round(t, 3), reply, args::varchar from internal_events "
                       "order by seq").fetchall() == [
        (1, "request", 0.05, None, "{}"), (1, "intermediate", 0.1, None, None), (1, "final", 0.4, "ok", None),
        (3, "request", 2.25, None, '{"x": 1.0, "y": 1.0}'), (3, "final", 2.25, "wait_init", None)]
    assert con.execute("select rqst_id, kind, round(t, 3) from events where kind = 'final' order by seq").fetchall() \
        == [(1, "final", 0.6), (3, "final", 2.3)]
