"""The ROS launcher over stdio against a real rosmaster: replies, liveness, teardown (docs/ros.md)."""
import os
import signal
import time
import xmlrpc.client

import pytest

from harness.sut.processes import stop_all
from harness.sut.ros import master
from tests.support.ros_driver import MAPPING, Launcher, assert_run_after_run, descendants, finished, request, requires_ros, wait_gone

pytestmark = [requires_ros, pytest.mark.slow]


def test_golden_first_steps_through_ros():
    launcher = Launcher("reference")
    try:
        answer = launcher.start(time_scale=1.0)
        assert answer["op"] == "hello" and answer["proto"] == "untimely/1", answer
        assert set(answer["caps"]) == {"internal", "world", "reuse"}
        launcher.send(request(1, "ndd.GotoPosition", x=9, y=4))  # before ndd.Init: rejected
        assert launcher.final(1) == "wait_init"
        inits = {10 + n: f"{m}.Init" for n, m in enumerate(["rflex", "sick", "aspect", "ndd", "antenna"])}
        for rqst_id, service in inits.items():
            launcher.send(request(rqst_id, service))
        assert {launcher.final(rqst_id) for rqst_id in inits} == {"ok"}
        launcher.send(request(20, "rflex.SetMode", mode="velocity"))
        launcher.send(request(21, "sick.SetParams", fov=180, range=8))
        launcher.send(request(22, "rflex.SetMode", mode="sideways"))
        assert [launcher.final(n) for n in (20, 21, 22)] == ["ok", "ok", "bad_params"]
        launcher.send(request(30, "aspect.Reset"))
        assert launcher.final(30) == "ok"
        launcher.send(request(31, "rflex.TrackSpeedStart"))
        launcher.expect(lambda m: m["op"] == "reply" and m["id"] == 31)
        launcher.send({"op": "ping", "id": 1})
        launcher.expect(lambda m: m["op"] == "pong" and m["id"] == 1 and m["held_s"] >= 0, timeout=30)
        launcher.send(request(32, "rflex.Stop"))  # dominates the running TrackSpeedStart: PREEMPTED
        assert (launcher.final(31), launcher.final(32)) == ("interrupted", "ok")
        # Exec goals got the feedback (intermediate) first; control and init goals none; one final each.
        for rqst_id in [1, *inits, 20, 21, 22, 30, 31, 32]:
            kinds = [m["kind"] for m in launcher.replies(rqst_id)]
            expected = ["intermediate", "final"] if rqst_id in (30, 31, 32) else ["final"]
            assert kinds == expected, (rqst_id, kinds)
        # Ground truth: the layer took each request before it ended it, on the SUT's clock.
        internal = launcher.internal({(n, kind) for n in (1, 10, 20, 30, 31) for kind in ("request", "final")})
        assert all(internal[(n, "request")] <= internal[(n, "final")] for n in (1, 10, 20, 30, 31))
        assert 0.4 < internal[(10, "final")] - internal[(10, "request")] < 1.5  # Init lasts 0.5 s
        assert finished(launcher) == set()
    finally:
        launcher.kill()


def test_exclusion_and_failure_endings_keep_their_codes():
    """PREEMPTED with interrupted_excl, ABORTED with goal_unreachable: the catalogue's codes, not the fallbacks."""
    launcher = Launcher("reference")
    try:
        assert launcher.start(time_scale=10.0)["op"] == "hello"
        steps = [request(1, "ndd.Init"), request(2, "antenna.Init"), request(3, "ndd.SetParams", speed=0.6),
                 request(4, "antenna.SetChannel", channel=3)]
        for step in steps:
            launcher.send(step)
        assert {launcher.final(n) for n in (1, 2, 3, 4)} == {"ok"}
        launcher.send(request(5, "antenna.Point", az=135))
        assert launcher.final(5) == "ok"
        launcher.send(request(6, "antenna.Communication", duration=30))
        launcher.expect(lambda m: m["op"] == "reply" and m["id"] == 6)  # running
        launcher.send(request(7, "ndd.GotoPosition", x=3, y=2))  # EXC: the latest request wins
        assert launcher.final(6) == "interrupted_excl"
        assert launcher.final(7) == "goal_unreachable"  # rflex is not tracking: the rover never moves
        assert finished(launcher) == set()
    finally:
        launcher.kill()


def test_a_deadlocked_module_silences_the_heartbeat():
    """bip-a deadlocks when Stop reaches a TrackSpeedStart still starting: no pong, no final."""
    launcher = Launcher("bip-a")
    try:
        assert launcher.start(time_scale=1.0)["op"] == "hello"
        launcher.send(request(1, "rflex.Init"))
        assert launcher.final(1) == "ok"
        launcher.send({"op": "ping", "id": 1})
        launcher.expect(lambda m: m["op"] == "pong" and m["id"] == 1 and m["held_s"] >= 0, timeout=30)
        launcher.send(request(2, "rflex.TrackSpeedStart"))
        launcher.send(request(3, "rflex.Stop"))
        launcher.expect(lambda m: m["op"] == "internal" and m["id"] == 3 and m["kind"] == "request")
        time.sleep(2.0)  # the last heartbeat goes stale 1 s (ros.toml) after the deadlock
        launcher.send({"op": "ping", "id": 2})
        assert launcher.wait(lambda m: m["op"] == "pong" and m["id"] == 2, timeout=5) is None
        assert [m for m in launcher.replies(2) + launcher.replies(3) if m["kind"] == "final"] == []
        assert finished(launcher) == set()
    finally:
        launcher.kill()


def test_a_server_killed_mid_goal_hangs_and_gets_no_invented_final():
    launcher = Launcher("reference")
    try:
        assert launcher.start(time_scale=1.0)["op"] == "hello"
        launcher.send(request(1, "ndd.Init"))
        launcher.send(request(2, "ndd.SetParams", speed=0.6))
        assert (launcher.final(1), launcher.final(2)) == ("ok", "ok")
        launcher.send(request(3, "ndd.GotoPosition", x=9, y=4))  # some 12 s of driving
        launcher.expect(lambda m: m["op"] == "reply" and m["id"] == 3 and m["kind"] == "intermediate")
        node = launcher.node_pid()
        launcher.send({"op": "ping", "id": 1})
        launcher.expect(lambda m: m["op"] == "pong" and m["id"] == 1 and m["held_s"] >= 0, timeout=30)
        os.kill(node, signal.SIGKILL)
        assert wait_gone({node}) == set()
        time.sleep(2.0)  # the last heartbeat goes stale 1 s (ros.toml) after the kill
        launcher.send({"op": "ping", "id": 2})
        assert launcher.wait(lambda m: m["op"] == "pong" and m["id"] == 2, timeout=6) is None
        launcher.send(request(4, "ndd.Stop"))  # nobody serves it any more
        assert launcher.wait(lambda m: m["op"] == "reply" and m["kind"] == "final" and m["id"] in (3, 4),
                             timeout=3) is None
        assert finished(launcher) == set()
    finally:
        launcher.kill()


def test_end_of_input_and_a_killed_launcher_leave_no_process():
    launcher = Launcher("reference")
    try:
        assert launcher.start(time_scale=1.0)["op"] == "hello"
        children = descendants(launcher.process.pid)
        assert len(children) >= 2  # the master and the node
        launcher.process.stdin.close()
        assert launcher.process.wait(60) == 0
        assert wait_gone(children, timeout=10) == set()
    finally:
        launcher.kill()
    launcher = Launcher("reference")
    try:
        assert launcher.start(time_scale=1.0)["op"] == "hello"
        children = descendants(launcher.process.pid)
        launcher.kill()  # SIGKILL: no teardown runs; the children die with their parent
        assert wait_gone(children, timeout=10) == set()
    finally:
        launcher.kill()


def test_a_node_that_cannot_start_is_an_error_line():
    launcher = Launcher("no-such-variant")
    try:
        answer = launcher.start(time_scale=1.0)
        assert answer["op"] == "error", answer
        assert "the node exited with status 2" in answer["message"] and "no-such-variant" in answer["message"]
        assert launcher.process.wait(60) == 2
        assert descendants(launcher.process.pid) == set()
    finally:
        launcher.kill()


def test_virtual_damage_reaches_the_bench():
    """Driving to site 1 without the map: the rover hits the rock on the way, reported as `world`."""
    launcher = Launcher("reference")
    try:
        assert launcher.start(time_scale=10.0)["op"] == "hello"
        steps = [request(1, "rflex.Init"), request(2, "ndd.Init"), request(3, "rflex.SetMode", mode="velocity"),
                 request(4, "ndd.SetParams", speed=0.6)]
        for step in steps:
            launcher.send(step)
        assert [launcher.final(n) for n in (1, 2, 3, 4)] == ["ok"] * 4
        launcher.send(request(5, "rflex.TrackSpeedStart"))
        launcher.expect(lambda m: m["op"] == "reply" and m["id"] == 5)  # tracking
        launcher.send(request(6, "ndd.GotoPosition", x=9, y=4))
        hit = launcher.expect(lambda m: m["op"] == "world" and m["kind"] == "collision", timeout=60)
        assert hit["detail"]["with"].startswith("rock"), hit
        went = launcher.internal({(6, "request")})[(6, "request")]
        assert went < hit["t"] < went + 30  # mission seconds on the SUT's clock, since the hello
        assert finished(launcher) == set()
    finally:
        launcher.kill()


def test_a_master_whose_port_was_taken_meanwhile_is_replaced(monkeypatch, tmp_path):
    """The other run's master on that port would answer in its place: ours must, on a port of its own."""
    first, env = master.start_master(str(tmp_path), 30)
    taken = int(env["ROS_MASTER_URI"].rsplit(":", 1)[1])
    offers = iter([taken])
    free_port = master.free_port
    monkeypatch.setattr(master, "free_port", lambda: next(offers, None) or free_port())
    second = None
    try:
        second, env2 = master.start_master(str(tmp_path), 30)
        assert env2["ROS_MASTER_URI"] != env["ROS_MASTER_URI"]
        assert xmlrpc.client.ServerProxy(env2["ROS_MASTER_URI"]).getPid("/test")[2] == second.process.pid
    finally:
        stop_all([first] + ([second] if second else []))


def test_a_ros_service_of_a_package_debian_lacks_is_generated_from_its_srv_file(tmp_path):
    """ndd.SetParams as a call of made_srvs/SetParams, which no package has: the adapter and the node
    both generate it from SetParams.srv beside the mapping, and their MD5 sums agree on the wire."""
    (tmp_path / "SetParams.srv").write_text("float64 speed\n---\nstring code\nbool success\n")
    mapping = tmp_path / "ros.toml"
    mapping.write_text(MAPPING.read_text() + '[services."ndd.SetParams"]\nservice = "/ndd/set_params"\n'
                       'type = "made_srvs/SetParams"\ndefinition = "SetParams.srv"\nfields = { speed = "speed" }\n'
                       'code = "code"\nsuccess = "success"\n')
    launcher = Launcher("reference", mapping)
    try:
        assert launcher.start(time_scale=10.0)["op"] == "hello", "".join(launcher.stderr[-20:])
        launcher.send(request(1, "ndd.SetParams", speed=0.6))
        launcher.send(request(2, "ndd.SetParams", speed=5.0))
        assert (launcher.final(1), launcher.final(2)) == ("ok", "bad_params")
        assert [m["kind"] for m in launcher.replies(1)] == ["final"]  # a ROS service: no intermediate
        assert finished(launcher) == set()
    finally:
        launcher.kill()


def test_run_after_run_on_one_master_and_node_each_on_a_fresh_layer():
    assert_run_after_run(Launcher("reference"))

