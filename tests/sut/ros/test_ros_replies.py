"""The reply rules for ROS events that arrive out of order (harness/sut/roscommon/replies.py). No ROS needed."""
from harness.sut.roscommon.replies import Replies


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


def test_the_servers_record_of_taking_a_request_is_its_taken_reply_when_it_comes_first():
    """ROS 2 introspection: the server's event of receiving a request, arriving before anything
    else of it, is a `taken` reply, once, then the request's other replies as ever."""
    events = [("taken", 6), ("taken", 6), ("feedback", 6), ("ended", 6, "SUCCEEDED", "ok"),
              ("taken", 7), ("ended", 7, "RESPONSE", "refused")]
    assert lines_of(events) == [(6, "taken", None), (6, "intermediate", None), (6, "final", "ok"),
                                (7, "taken", None), (7, "final", "refused")]


def test_a_late_record_gives_no_taken_and_none_is_made_up():
    """The event travels on its own topic and may arrive after the response or feedback it preceded;
    the bench would stamp it when read, after them, so it is dropped: the request keeps its sending
    and receiving instants. A request whose server publishes no record never gets a `taken`."""
    events = [("ended", 8, "RESPONSE", "bad_params"), ("taken", 8),
              ("feedback", 9), ("taken", 9), ("ended", 9, "SUCCEEDED", "ok"),
              ("feedback", 10), ("ended", 10, "ABORTED", "aborted"), ("ended", 11, "REJECTED", "rejected")]
    assert lines_of(events) == [(8, "final", "bad_params"), (9, "intermediate", None), (9, "final", "ok"),
                                (10, "intermediate", None), (10, "final", "aborted"), (11, "final", "rejected")]
