"""The ROS 2 adapter on a node written as the rclpy tutorials write one (tests/support/
ros2_tutorial_node.py: an action server and a SetBool service without introspection), on Jazzy and
Kilted: no `taken` reply is promised or given (none is made up), the outcomes keep their own codes,
and a cancel needs no route: it names its goal, or cancels the latest one."""
import sys

import pytest

from harness import ROOT
from harness.target.suts import ExternalSut
from harness.sut.external.runner import run_external
from harness.sut.ros2.environment import installed
from harness.target.interface import load_interface
from harness.target.script import parse
from tests.support.ros_driver import Launcher, descendants, request, requires_ros2, wait_gone

pytestmark = pytest.mark.slow

NODE = ROOT / "tests" / "support" / "ros2_tutorial_node.py"
MAPPING = """
node = "/tutorial"
heartbeat_stale_s = 3.0
[status_codes]
ABORTED = "aborted"
CANCELED = "canceled"
REJECTED = "rejected"
[services."tutorial.count"]
action = "/count"
[services."tutorial.set"]
service = "/set"
type = "std_srvs/srv/SetBool"
fields = { on = "data" }
defaults = { data = false }
success = "success"
failure = "refused"
[cancels]
"tutorial.count_cancel" = "tutorial.count"
[cancel_codes]
ERROR_NONE = "ok"
ERROR_REJECTED = "cancel_rejected"
ERROR_UNKNOWN_GOAL_ID = "unknown_goal"
ERROR_GOAL_TERMINATED = "goal_terminated"
"""
REPLIES = {"ok": "T", "aborted": "Z", "canceled": "Z", "rejected": "R", "refused": "R", "cancel_rejected": "R",
           "unknown_goal": "R", "goal_terminated": "R"}
HELLO = {"op": "hello", "proto": "untimely/1", "run": 1, "seed": 1, "time_scale": 1.0,
         "interface": {"modules": {"tutorial": {"count": "exec", "count_cancel": "control", "set": "control"}},
                       "replies": REPLIES}}


def launcher(tmp_path, distro: str, mapping: str = MAPPING) -> Launcher:
    path = tmp_path / "ros2.toml"
    path.write_text(mapping)
    return Launcher(command=[sys.executable, "-m", "harness.sut.ros2", "--distro", distro, "--mapping", str(path),
                             "--", "python", str(NODE)])


@pytest.mark.parametrize("distro", ["jazzy", "kilted"])
def test_servers_without_introspection_get_no_taken_and_cancels_need_no_route(tmp_path, distro):
    if installed(ROOT, distro):
        pytest.skip(installed(ROOT, distro))
    run = launcher(tmp_path, distro)
    try:
        run.send(HELLO)
        answer = run.expect(lambda m: m["op"] in ("hello", "error"), timeout=90)
        assert answer["op"] == "hello" and answer["taken_services"] == [], (answer, "".join(run.stderr[-20:]))
        assert "taken" not in answer["caps"]
        run.send(request(1, "tutorial.set", on=True))
        run.send(request(2, "tutorial.set", on=False))
        assert (run.final(1), run.final(2)) == ("ok", "refused")
        run.send(request(3, "tutorial.count"))
        run.expect(lambda m: m["op"] == "reply" and m["id"] == 3 and m["kind"] == "intermediate")
        run.send(request(4, "tutorial.count_cancel", goal=3))  # `cancel HANDLE`: the goal named
        assert (run.final(4), run.final(3)) == ("ok", "canceled")
        run.send(request(5, "tutorial.count"))
        assert run.final(5) == "ok"
        run.send(request(6, "tutorial.count_cancel"))  # the latest goal, ended
        run.send(request(7, "tutorial.count_cancel", goal=3.0))  # a goal canceled already (a float argument)
        assert (run.final(6), run.final(7)) == ("goal_terminated", "goal_terminated")
        kinds = {n: [m["kind"] for m in run.replies(n)] for n in range(1, 8)}
        assert all("taken" not in replies for replies in kinds.values()), kinds
        children = descendants(run.process.pid)
        run.send(request(8, "tutorial.count_cancel", goal=1))  # a call, no goal: the script is wrong
        error = run.expect(lambda m: m["op"] == "error")["message"]
        assert "request 8 (tutorial.count_cancel) cancels goal = 1, which is no request of tutorial.count" in error
        assert run.process.wait(30) == 2
        assert wait_gone(children, timeout=15) == set()
    finally:
        run.kill()


@requires_ros2("jazzy")
def test_a_cancel_without_its_entry_is_refused_before_the_node_starts(tmp_path):
    """The interface names tutorial.count_cancel, the mapping has no [cancels] entry for it: an
    error at once naming the key to add, not a start-up timeout (nor a goal of a server that
    does not exist)."""
    run = launcher(tmp_path, "jazzy", MAPPING.split("[cancels]")[0])
    try:
        run.send(HELLO)
        answer = run.expect(lambda m: m["op"] in ("hello", "error"), timeout=30)
        assert answer["op"] == "error", answer
        assert 'add "tutorial.count_cancel" = "tutorial.count" to [cancels]' in answer["message"], answer
        assert str(tmp_path / "ros2.toml") in answer["message"]
        assert run.process.wait(30) == 2
    finally:
        run.kill()


INTERFACE = """
[replies]
""" + "".join(f'{code} = "{cls}"\n' for code, cls in REPLIES.items()) + """
[modules.tutorial]
services.count = { kind = "exec" }
services.count_cancel = { kind = "control" }
services.set = { kind = "control" }
"""
SCRIPT = """send tutorial.set as s
wait s
send tutorial.count as c
sleep 0.5
send tutorial.count_cancel as k
wait all
"""


@pytest.mark.parametrize("distro", ["jazzy", "kilted"])
def test_through_the_bench_no_taken_is_stored_and_the_outcomes_keep_their_codes(tmp_path, distro):
    """The bench runs a script on the node (set without `on`: data false; a goal cancelled while
    it runs): the trace it would store holds no taken_events, and each final its own code."""
    if installed(ROOT, distro):
        pytest.skip(installed(ROOT, distro))
    (tmp_path / "interface.toml").write_text(INTERFACE)
    (tmp_path / "ros2.toml").write_text(MAPPING)
    interface = load_interface(tmp_path / "interface.toml")
    sut = ExternalSut("tutorial", command=f"{{python}} -m harness.sut.ros2 --distro {distro} --mapping "
                      f"{tmp_path / 'ros2.toml'} -- python {NODE}", startup_s=90.0, probe_timeout_s=5.0)
    trace = run_external(parse(SCRIPT, "tutorial"), sut, 1, interface)
    assert trace.outcome == "completed", trace.error
    finals = {e[5]: e[-1] for e in trace.events if e[2] == "final"}
    assert finals == {"set": "refused", "count": "canceled", "count_cancel": "ok"}, trace.events
    assert trace.taken_events == []
