"""ROS 2's outcomes as reply codes that keep them apart (docs/reference/ros2-requests.md), and the
mapping's cancels checked against the interface before any node starts. No ROS needed."""
from types import SimpleNamespace

import pytest

from harness.errors import InputFileError, UntimelyError
from harness.sut.roscommon.mapping import DEFAULT_CANCEL_CODES, DEFAULT_STATUS_CODES, check_cancels, load_mapping

REPLIES = {"ok": "T", "aborted": "Z", "canceled": "Z", "rejected": "R", "refused": "R", "transition_refused": "R",
           "cancel_rejected": "R", "unknown_goal": "R", "goal_terminated": "R"}
INTERFACE = {"modules": {"arm": {"move": "exec", "move_cancel": "control", "grip": "control", "activate": "control"}},
             "replies": REPLIES}
# An arm's mapping as a derived target writes it: a goal's ends, a call's and a transition's
# refusals, each cancel return code, each a code of its own.
ARM = """
node = "/arm"
[status_codes]
ABORTED = "aborted"
CANCELED = "canceled"
REJECTED = "rejected"
[services."arm.move"]
action = "/arm/move"
type = "example_interfaces/action/Fibonacci"
[services."arm.grip"]
service = "/arm/grip"
type = "std_srvs/srv/SetBool"
success = "success"
failure = "refused"
[services."arm.activate"]
service = "/arm/change_state"
type = "lifecycle_msgs/srv/ChangeState"
defaults = { "transition.id" = 3 }
success = "success"
failure = "transition_refused"
[cancels]
"arm.move_cancel" = "arm.move"
[cancel_codes]
ERROR_NONE = "ok"
ERROR_REJECTED = "cancel_rejected"
ERROR_UNKNOWN_GOAL_ID = "unknown_goal"
ERROR_GOAL_TERMINATED = "goal_terminated"
"""


def arm(tmp_path, text=ARM):
    path = tmp_path / "ros2.toml"
    path.write_text(text)
    return load_mapping(path)


def test_a_goals_ends_and_refusals_have_codes_of_their_own_classes_apart(tmp_path):
    mapping = arm(tmp_path)
    ends = {status: mapping.final_code(status, (None,), REPLIES)
            for status in ("SUCCEEDED", "ABORTED", "CANCELED", "REJECTED", "LOST")}
    assert ends == {"SUCCEEDED": "ok", "ABORTED": "aborted", "CANCELED": "canceled", "REJECTED": "rejected",
                    "LOST": None}
    assert [REPLIES[ends[s]] for s in ("SUCCEEDED", "ABORTED", "CANCELED", "REJECTED")] == ["T", "Z", "Z", "R"]
    grip, activate = mapping.overrides["arm.grip"], mapping.overrides["arm.activate"]
    answers = [route.response_code(SimpleNamespace(success=success), REPLIES)
               for route in (grip, activate) for success in (True, False)]
    assert answers == ["ok", "refused", "ok", "transition_refused"]
    assert mapping.cancel_codes == {"ERROR_NONE": "ok", "ERROR_REJECTED": "cancel_rejected",
                                    "ERROR_UNKNOWN_GOAL_ID": "unknown_goal", "ERROR_GOAL_TERMINATED": "goal_terminated"}


def test_a_mapping_without_the_new_keys_keeps_its_meaning(tmp_path):
    mapping = arm(tmp_path, 'node = "/arm"\n[cancels]\n"arm.move_cancel" = "arm.move"\n')
    assert mapping.status_codes == DEFAULT_STATUS_CODES and mapping.cancel_codes == DEFAULT_CANCEL_CODES
    assert (DEFAULT_STATUS_CODES["ABORTED"], DEFAULT_STATUS_CODES["CANCELED"]) == ("aborted", "interrupted")
    assert set(DEFAULT_CANCEL_CODES.values()) == {"ok", "rejected"}


def test_a_cancel_is_served_by_its_actions_cancel_goal_and_needs_no_route(tmp_path):
    assert check_cancels(arm(tmp_path), INTERFACE) == {"arm.move_cancel": "/arm/move"}


@pytest.mark.parametrize("edit, where, says", [
    (('"arm.move_cancel" = "arm.move"', '"arm.move_cancel" = "arm.lift"'), '[cancels] "arm.move_cancel"',
     "arm.lift is no service of the interface"),
    (('"arm.move_cancel" = "arm.move"', '"arm.stop" = "arm.move"'), '[cancels] "arm.stop"',
     "arm.stop is no service of the interface"),
    (('"arm.move_cancel" = "arm.move"', '"arm.move_cancel" = "arm.grip"'), '[cancels] "arm.move_cancel"',
     "arm.grip is not served by an action"),
    (('"arm.move_cancel" = "arm.move"', ''), "[cancels]",
     'arm.move_cancel has no entry; add "arm.move_cancel" = "arm.move" to [cancels]'),
    (('ERROR_UNKNOWN_GOAL_ID = "unknown_goal"', 'ERROR_UNKNOWN_GOAL_ID = "no_such_goal"'),
     "[cancel_codes] ERROR_UNKNOWN_GOAL_ID", "'no_such_goal' is not in the interface's reply catalogue"),
])
def test_a_cancel_that_cannot_be_served_is_refused_naming_the_key(tmp_path, edit, where, says):
    mapping = arm(tmp_path, ARM.replace(*edit))
    with pytest.raises(InputFileError) as refused:
        check_cancels(mapping, INTERFACE)
    assert refused.value.where == where and says in refused.value.problem, str(refused.value)
    assert str(tmp_path / "ros2.toml") in str(refused.value)


def test_default_cancel_codes_outside_the_catalogue_are_refused_before_any_run(tmp_path):
    """A mapping that gives no [cancel_codes] replies `rejected` to a refused cancel: a catalogue
    without it is refused at load, not mid-run."""
    mapping = arm(tmp_path, ARM.split("[cancel_codes]")[0])
    with pytest.raises(UntimelyError, match=r"\[cancel_codes\] ERROR_REJECTED: 'rejected' is not"):
        check_cancels(mapping, {**INTERFACE, "replies": {k: v for k, v in REPLIES.items() if k != "rejected"}})
