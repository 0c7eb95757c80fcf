"""The reply rules for ROS events that arrive out of order (harness/sut/ros/replies.py). No ROS needed."""
from harness.sut.ros.replies import Replies


def lines_of(events):
    written = []
    replies = Replies(written.append)
    for event, *args in events:
        getattr(replies, event)(*args)
    return [(m["id"], m["kind"], m.get("code")) for m in written]


def test_feedback_before_the_result_is_the_one_intermediate_reply():
    assert lines_of([("feedback", 1), ("feedback", 1), ("ended", 1, "SUCCEEDED", "ok")]) == \
        [(1, "intermediate", None), (1, "final", "ok")]


def test_a_result_without_active_or_feedback_is_a_final_alone():
    assert lines_of([("ended", 2, "SUCCEEDED", "ok")]) == [(2, "final", "ok")]


def test_feedback_after_the_result_and_a_second_ending_are_dropped():
    events = [("ended", 3, "PREEMPTED", "interrupted"), ("feedback", 3), ("ended", 3, "PREEMPTED", "interrupted")]
    assert lines_of(events) == [(3, "final", "interrupted")]


def test_a_lost_goal_gets_no_final_and_requests_stay_apart(capsys):
    events = [("feedback", 4), ("ended", 4, "LOST", None), ("ended", 5, "REJECTED", "wait_init")]
    assert lines_of(events) == [(4, "intermediate", None), (5, "final", "wait_init")]
    assert "request 4 ended LOST without a result: no final reply" in capsys.readouterr().err


def test_a_promised_taken_goes_first_when_its_event_comes_after_the_response_or_the_feedback():
    """ROS 2 introspection travels on its own topic: the response (or the feedback) may arrive first,
    and proves the request taken, so its `taken` reply goes first and the late event is dropped."""
    written = []
    replies = Replies(written.append, taken_promised=True)
    for event, *args in [("ended", 6, "RESPONSE", "bad_params"), ("taken", 6),
                         ("feedback", 7), ("taken", 7), ("ended", 7, "SUCCEEDED", "ok"),
                         ("taken", 8), ("ended", 8, "RESPONSE", "ok"), ("ended", 9, "LOST", None)]:
        getattr(replies, event)(*args)
    assert [(m["id"], m["kind"]) for m in written] == [
        (6, "taken"), (6, "final"), (7, "taken"), (7, "intermediate"), (7, "final"), (8, "taken"), (8, "final")]


def test_without_the_promise_no_taken_is_made_up_or_relayed():
    assert lines_of([("taken", 10), ("feedback", 10), ("ended", 10, "SUCCEEDED", "ok")]) == \
        [(10, "intermediate", None), (10, "final", "ok")]
