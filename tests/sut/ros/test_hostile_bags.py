"""Bags that do not match their mapping (issue 36): a clear error naming the bag, the topic or
field and the value, never a traceback; a reply received before its goal is kept as the goal's,
with a note that says so; two goals of one id are refused, not one of them dropped."""
import pytest
from rosbags.rosbag2 import StoragePlugin

from harness import DEFAULT_MISSION_DIR
from harness.cli import main
from tests.support.bags1 import ACTIVE, SUCCEEDED, Bag as Bag1
from tests.support.bags1 import imported as imported1
from tests.support.bags2 import BASE, MAPPING, Bag as Bag2, robot_day

INTERFACE = str(DEFAULT_MISSION_DIR / "interface.toml")


def refused(bag, tmp_path, capsys, ros: str | None = None) -> str:
    """What `import` says of `bag`, which it must refuse (exit 2) without a traceback or a store."""
    db = tmp_path / "store.duckdb"
    code = main(["import", str(bag), "--interface", INTERFACE, *(["--ros", ros] if ros else []), "--db", str(db)])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith("error: ") and "Traceback" not in err, err
    assert not db.exists(), "a refused bag left a store"
    return err


def test_an_action_topic_of_another_message_type_is_refused_naming_topic_and_type(tmp_path, capsys):
    bag = Bag1(tmp_path / "foreign.bag")
    bag.write("/dala/ndd/goal", "std_msgs/msg/String", 1.0, bag.types["std_msgs/msg/String"](data="GotoPosition"))
    bag.close()
    assert ("foreign.bag: topic /dala/ndd/goal carries std_msgs/msg/String, not an actionlib goal (...ActionGoal)"
            in refused(tmp_path / "foreign.bag", tmp_path, capsys))


@pytest.mark.parametrize("where", ["result", "status"])
def test_a_goal_status_outside_actionlibs_is_refused_naming_topic_goal_and_value(tmp_path, capsys, where):
    bag = Bag1(tmp_path / "status.bag")
    bag.goal(1.0, "g1", "Init")
    if where == "result":
        bag.result(1.5, "g1", 12, "ok")
    else:
        bag.status(1.5, 1.5, ("g1", 12, ""))
    bag.close()
    assert (f"status.bag: topic /dala/ndd/{where}: goal 'g1' has status 12, which is no actionlib GoalStatus (0 to 9"
            in refused(tmp_path / "status.bag", tmp_path, capsys))


def test_a_result_received_before_its_goal_is_the_goals_final_with_a_note_that_says_so(tmp_path, interface, capsys):
    bag = Bag1(tmp_path / "early.bag")
    bag.goal(1.0, "g0", "Stop")  # the bag's origin
    bag.feedback(1.998, "g1")  # recorded 2 ms before its goal
    bag.result(1.999, "g1", SUCCEEDED, "ok")
    bag.goal(2.0, "g1", "Init")
    bag.close()
    rows = imported1(tmp_path / "early.bag", interface)
    assert [(r[3], r[4], r[5], r[7]) for r in rows if r[4] == 2] == [
        ("request", 2, "Init", None), ("intermediate", 2, "Init", None), ("final", 2, "Init", "ok")]
    assert {r[2] for r in rows if r[4] == 2} == {1.0}, "the replies are no earlier than their goal"
    err = capsys.readouterr().err
    assert "the result of goal 'g1' was received 1.0 ms before the goal" in err
    assert "the feedback of goal 'g1' was received 2.0 ms before the goal" in err
    assert "left out" not in err, "no reply was left out, and none is said to be"


def test_a_reply_to_a_goal_the_bag_lacks_is_still_left_out_and_counted(tmp_path, interface, capsys):
    bag = Bag1(tmp_path / "late.bag")
    bag.result(1.0, "before-recording", SUCCEEDED, "ok")
    bag.goal(2.0, "g1", "Init")
    bag.close()
    assert [r[3] for r in imported1(tmp_path / "late.bag", interface)] == ["request"]
    assert "1 replies to goals whose request the bag does not hold were left out" in capsys.readouterr().err


def test_two_goals_of_one_id_are_refused_naming_the_id(tmp_path, capsys):
    bag = Bag1(tmp_path / "twice.bag")
    bag.goal(1.0, "g1", "Init")
    bag.feedback(1.2, "g1")
    bag.goal(2.0, "g1", "Stop")
    bag.close()
    assert ("twice.bag: two goals carry the id 'g1' (received 0.000 s and 1.000 s into the bag): their replies "
            "cannot be told apart" in refused(tmp_path / "twice.bag", tmp_path, capsys))


def test_a_mapping_naming_a_service_the_interface_lacks_is_refused(tmp_path, capsys):
    bag = Bag1(tmp_path / "any.bag")
    bag.goal(1.0, "g1", "Init")
    bag.close()
    mapping = tmp_path / "ros.toml"
    mapping.write_text((DEFAULT_MISSION_DIR / "ros.toml").read_text() + '\n[services]\n"ndd.GotoPositon" = "/goto"\n')
    err = refused(tmp_path / "any.bag", tmp_path, capsys, ros=str(mapping))
    assert "ros.toml: [services] names 'ndd.GotoPositon', which the interface" in err
    assert "does not declare; its services are " in err and "ndd.GotoPosition" in err


def test_a_typed_route_naming_a_field_the_goal_lacks_is_refused_naming_route_and_field(tmp_path, capsys):
    mapping = tmp_path / "rover.toml"
    mapping.write_text(MAPPING.read_text().replace('fields = { x = "x", y = "y" }', 'fields = { x = "x", y = "z" }'))
    bag = robot_day(tmp_path / "day", StoragePlugin.MCAP)
    assert ("rover.toml: [services] ndd.GotoPosition reads the field 'z' of its goal, which the bag's "
            "rover_msgs/action/Drive_Goal lacks (its fields: x, y)" in refused(bag, tmp_path, capsys, str(mapping)))


def test_a_rosbag2_status_topic_of_a_foreign_type_is_refused_naming_topic_and_type(tmp_path, capsys):
    bag = Bag2(tmp_path / "foreign", StoragePlugin.MCAP)
    bag.send_goal(BASE, 1, 9.0, 4.0, True)
    bag.write("/navigate/_action/status", "std_msgs/msg/String", None, BASE + 0.1,
              bag.types["std_msgs/msg/String"](data="ACTIVE"))
    bag.close()
    assert ("topic /navigate/_action/status carries std_msgs/msg/String, not a status message "
            "(action_msgs/msg/GoalStatusArray)" in refused(tmp_path / "foreign", tmp_path, capsys, str(MAPPING)))


def test_an_active_status_alone_still_imports(tmp_path, interface):
    """The checks refuse what does not match, not what does: a goal seen only ACTIVE imports."""
    bag = Bag1(tmp_path / "open.bag")
    bag.goal(1.0, "g1", "Init")
    bag.status(1.1, 1.1, ("g1", ACTIVE, ""))
    bag.close()
    assert [r[3] for r in imported1(tmp_path / "open.bag", interface)] == ["request"]
