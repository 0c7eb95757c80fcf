"""The ROS 2 adapter and the Dala lifecycle node over stdio, on ROS 2 from PyPI wheels (`make ros2`):
goals, feedback, results, calls, ground truth, run after run, a stuck executor, Kilted (docs/ros2.md)."""
import contextlib
import fcntl
import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from harness import DEFAULT_MISSION_DIR, ROOT
from harness.sut.ros2.environment import LOCK_DIR, installed
from harness.sut.definitions import load_suts_file
from harness.sut.external.runner import run_external
from harness.target.interface import load_interface
from harness.target.script import parse, validate
from tests.support.ros_driver import Launcher, descendants, request, requires_ros2, running_module, wait_gone

pytestmark = pytest.mark.slow

MAPPING = DEFAULT_MISSION_DIR / "ros2.toml"
NODE = "harness.sut.ros2.dala_node"


def launcher(variant: str = "reference", distro: str = "jazzy", mapping: Path = MAPPING) -> Launcher:
    return Launcher(command=[sys.executable, "-m", "harness.sut.ros2", "--distro", distro, "--mapping",
                             str(mapping), "--", "python", "-m", NODE, "--variant", variant, "--mapping", str(mapping)])


INITS = {10 + n: f"{m}.Init" for n, m in enumerate(["rflex", "sick", "aspect", "ndd", "antenna"])}


def first_steps(run: Launcher, base: int = 0) -> None:
    """A goal before its module's Init (refused wait_init, through an aborted goal), the Inits (calls),
    settings (calls, one refused), an exec goal with its feedback, a Stop interrupting a running goal."""
    run.send(request(base + 1, "ndd.GotoPosition", x=9, y=4))
    assert run.final(base + 1) == "wait_init"
    for rqst_id, service in INITS.items():
        run.send(request(base + rqst_id, service))
    assert {run.final(base + rqst_id) for rqst_id in INITS} == {"ok"}
    run.send(request(base + 20, "rflex.SetMode", mode="velocity"))
    run.send(request(base + 22, "rflex.SetMode", mode="sideways"))
    assert [run.final(base + n) for n in (20, 22)] == ["ok", "bad_params"]
    run.send(request(base + 30, "aspect.Reset"))
    assert run.final(base + 30) == "ok"
    run.send(request(base + 31, "rflex.TrackSpeedStart"))
    run.expect(lambda m: m["op"] == "reply" and m["id"] == base + 31 and m["kind"] == "intermediate")
    run.send(request(base + 32, "rflex.Stop"))
    assert (run.final(base + 31), run.final(base + 32)) == ("interrupted", "ok")
    assert_taken_only_where_published(run, {base + n: s for n, s in [(1, "ndd.GotoPosition"), *INITS.items(),
                                          (20, "rflex.SetMode"), (22, "rflex.SetMode"), (30, "aspect.Reset"),
                                          (31, "rflex.TrackSpeedStart"), (32, "rflex.Stop")]},
                                     intermediate={base + 30, base + 31, base + 32})


def assert_taken_only_where_published(run: Launcher, services: dict[int, str], intermediate: set[int]) -> None:
    """Each request's replies in order: a `taken` first only where the hello names its service in
    `taken_services` (its server publishes introspection), and there only when the server's event
    came before the request's other replies (a late one gives none); some did on such a node."""
    promised = set(next(m for _, m in run.lines if m["op"] == "hello")["taken_services"])
    taken = 0
    for rqst_id, service in services.items():
        kinds = [m["kind"] for m in run.replies(rqst_id)]
        rest = ["intermediate", "final"] if rqst_id in intermediate else ["final"]
        assert kinds in ([rest, ["taken", *rest]] if service in promised else [rest]), (rqst_id, service, kinds)
        taken += kinds[0] == "taken"
    assert taken > 0 or not promised & set(services.values()), "no request got the taken its server publishes"


@requires_ros2("jazzy")
def test_golden_first_steps_then_a_second_run_on_the_reset_node():
    """Run 1: the replies of goals and calls, the goals' ground truth on the node's clock, a ping
    through ROS 2. bye, hello: run 2 on the same node, whose reset gave a fresh layer (the Inits of
    run 1 are forgotten: a goal before Init is refused again), and no process is left behind."""
    run = launcher()
    try:
        answer = run.start(time_scale=1.0)
        assert answer["op"] == "hello" and set(answer["caps"]) == {"internal", "world", "reuse"}, answer
        first_steps(run)
        internal = run.internal({(n, kind) for n in (1, 30, 31, 32) for kind in ("request", "final")}
                                | {(31, "intermediate")})
        assert all(internal[(n, "request")] <= internal[(n, "final")] for n in (1, 30, 31, 32))
        assert internal[(31, "intermediate")] < internal[(31, "final")]
        run.send({"op": "ping", "id": 1})
        run.expect(lambda m: m["op"] == "pong" and m["id"] == 1 and m["held_s"] >= 0, timeout=30)
        node = run.node_pid()
        confined_to_localhost_in_its_domain(run, answer["sut"], node)
        run.send({"op": "bye"})
        run.expect(lambda m: m["op"] == "bye")
        run.lines.clear()
        assert run.start(time_scale=1.0)["op"] == "hello"
        assert "run 2 of this node" in run.lines[-1][1]["sut"] and run.node_pid() == node
        first_steps(run, base=100)  # its first step fails on a reset that keeps run 1's Inits
        children = descendants(run.process.pid)
        assert run.bye() == 0, "".join(run.stderr[-20:])
        assert wait_gone(children, timeout=15) == set()
    finally:
        run.kill()


def confined_to_localhost_in_its_domain(run: Launcher, sut: str, node: int) -> None:
    """The node and the adapter run with discovery on this machine only, in the domain the
    launcher holds for the slot (the hello names it)."""
    domain = re.search(r"\(domain (\d+);", sut).group(1)
    adapter = next(p for p in descendants(run.process.pid) if running_module(p) == "harness.sut.ros2.serve")
    for pid in (node, adapter):
        env = dict(v.split("=", 1) for v in Path(f"/proc/{pid}/environ").read_bytes().decode().split("\0") if "=" in v)
        assert (env["ROS_AUTOMATIC_DISCOVERY_RANGE"], env["ROS_DOMAIN_ID"]) == ("LOCALHOST", domain), (pid, sut)
    with pytest.raises(BlockingIOError):  # the launcher's flock holds the domain id
        with open(LOCK_DIR / f"{domain}.lock") as lock:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)


# The golden mission's set-up, then one long drive (about 37 s of mission time): a stop of the
# node anywhere in it is a stop during the drive, however long the start-up took on a loaded machine.
LONG_DRIVE = """
send rflex.Init as ri
send sick.Init as si
send aspect.Init as ai
send ndd.Init as ni
send antenna.Init as ani
wait all
send rflex.SetMode mode=velocity as mode
send sick.SetParams fov=180 range=8 as laser_params
send ndd.SetParams speed=0.6 as nav_params
send antenna.SetChannel channel=3 as channel
wait all
# Start perception and wheel tracking on a fresh map.
send aspect.Reset as reset
wait reset
send rflex.TrackSpeedStart as track
send sick.ContinuousShot as laser
send aspect.Fuse as map
sleep 1
send ndd.GotoPosition x=18 y=16 as far
wait far
"""


def _stopped_during_the_drive(sut, script, interface, after_s: float):
    """The script run through the bench, the Dala node stopped (SIGSTOP) `after_s` after it appeared:
    (its trace, the run's other processes, the node, its log folder)."""
    traces, earlier = [], descendants(os.getpid())  # processes of earlier tests are not this run's
    bench = threading.Thread(target=lambda: traces.append(run_external(script, sut, 0, interface)))
    bench.start()
    deadline, node = time.monotonic() + 120, None
    while node is None:
        assert time.monotonic() < deadline, "the Dala node never started"
        node = next((p for p in descendants(os.getpid()) - earlier if running_module(p) == NODE), None)
        time.sleep(0.2)
    time.sleep(after_s)
    children = descendants(os.getpid()) - earlier - {node}
    log_dir = next(v for v in Path(f"/proc/{node}/environ").read_bytes().decode().split("\0")
                   if v.startswith("ROS_LOG_DIR=")).split("=", 1)[1]
    os.kill(node, signal.SIGSTOP)
    try:
        bench.join(120)
    finally:
        with contextlib.suppress(ProcessLookupError):  # the launcher's teardown killed it already
            os.kill(node, signal.SIGKILL)
    return traces[0], children, node, log_dir


@requires_ros2("jazzy")
def test_a_stuck_executor_hangs_the_trace_with_its_reason():
    """The Dala node on ros2-reference is stopped (SIGSTOP: its executor serves nothing more) while
    the rover drives: the probe of /dala/get_parameters goes unanswered, so do the pings (hung),
    stderr says why, the drive gets no final, and nothing is left behind (a stopped node outlives
    the SIGTERM of the bench's teardown: its log folder goes anyway). A start-up slower than the
    first wait (a loaded machine) is tried again with a longer one."""
    sut = load_suts_file(DEFAULT_MISSION_DIR / "suts.toml")["ros2-reference"]
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    script = parse(LONG_DRIVE)
    validate(script, interface)
    for after_s in (12.0, 30.0):
        trace, children, node, log_dir = _stopped_during_the_drive(sut, script, interface, after_s)
        drives = [e[3] for e in trace.events if e[2] == "request" and e[5] == "GotoPosition"]
        if drives:
            break
    assert trace.outcome == "hung", trace.error
    assert "executor has not answered /dala/get_parameters" in trace.error
    assert len(drives) == 1, f"the node was stopped before the drive, even after 30 s: {trace.events}"
    assert [e for e in trace.events if e[3] == drives[0] and e[2] == "final"] == []
    assert wait_gone(children | {node}, timeout=30) == set()
    assert not os.path.exists(log_dir), "the run's ROS 2 log folder was left behind"


# A client of the node's lifecycle in the node's own environment (its domain): an invalid transition.
INVALID_TRANSITION = """
import rclpy
from lifecycle_msgs.msg import Transition
from lifecycle_msgs.srv import ChangeState
rclpy.init()
node = rclpy.create_node("untimely_test_client")
client = node.create_client(ChangeState, "/dala/change_state")
assert client.wait_for_service(timeout_sec=60)
answer = client.call_async(ChangeState.Request(transition=Transition(id=Transition.TRANSITION_CONFIGURE)))
rclpy.spin_until_future_complete(node, answer, timeout_sec=5)
print("answered" if answer.done() else "no answer")
"""


@requires_ros2("jazzy")
def test_an_invalid_lifecycle_transition_kills_the_executor_and_the_run_hangs():
    """rclpy#1209, still in Jazzy's rclpy 7.1.6: `configure` sent to the active node raises inside
    its executor, which dies while the process lives on. The adapter's probe of
    /dala/get_parameters goes unanswered: no pong (the bench would record `hung`), no reply, stderr
    says why; bye still ends everything."""
    run = launcher()
    try:
        assert run.start(time_scale=1.0)["op"] == "hello"
        node = next(p for p in descendants(run.process.pid) if running_module(p) == NODE)
        env = dict(v.split("=", 1) for v in Path(f"/proc/{node}/environ").read_bytes().decode().split("\0") if "=" in v)
        poke = subprocess.run([str(ROOT / ".venv-ros2-jazzy" / "bin" / "python"), "-c", INVALID_TRANSITION], env=env,
                              capture_output=True, text=True, timeout=60)
        assert poke.stdout.strip() == "no answer", poke.stderr[-2000:]
        run.send({"op": "ping", "id": 1})
        run.send(request(2, "ndd.Init"))
        assert run.wait(lambda m: m["op"] in ("pong", "reply"), timeout=5) is None
        assert any("executor has not answered /dala/get_parameters" in line for line in run.stderr), run.stderr[-5:]
        assert any("Transition is not registered" in line for line in run.stderr)  # the node's own words
        children = descendants(run.process.pid)
        run.bye()
        assert wait_gone(children, timeout=15) == set()
    finally:
        run.kill()


@requires_ros2("jazzy")
def test_typed_routes_serve_the_inits_as_std_srvs_trigger():
    """ros2-typed.toml: two Inits are std_srvs/srv/Trigger services of the distro's wheels, their
    response's message the reply code: the first steps go as with the generic types."""
    run = launcher(mapping=DEFAULT_MISSION_DIR / "ros2-typed.toml")
    try:
        assert run.start(time_scale=1.0)["op"] == "hello"
        first_steps(run)
        assert run.bye() == 0, "".join(run.stderr[-20:])
    finally:
        run.kill()


@requires_ros2("jazzy")
def test_on_jazzy_taken_is_promised_for_the_services_only():
    """Jazzy's services have introspection, its actions none: with ros2.toml (exec services as
    actions, the others services, all of them publishing introspection where the distro has it)
    the hello names the control and init services only, and no goal gets a `taken`."""
    run = launcher()
    try:
        answer = run.start(time_scale=1.0)
        interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
        assert "taken" not in answer["caps"], answer
        assert set(answer["taken_services"]) == {q for q, s in interface.services.items() if s.kind != "exec"}, answer
        run.send(request(2, "ndd.GotoPosition", x=9, y=4))  # before its module's Init: refused
        assert run.final(2) == "wait_init"
        run.send(request(1, "ndd.Init"))
        assert run.final(1) == "ok"
        assert_taken_only_where_published(run, {1: "ndd.Init", 2: "ndd.GotoPosition"}, intermediate=set())
        assert run.bye() == 0
    finally:
        run.kill()


@requires_ros2("kilted")
def test_first_steps_on_kilted_with_taken_replies():
    """On Kilted both actions and services have introspection, which the Dala node publishes: the
    hello names every service, and a request gets a `taken` reply from the server's event of
    receiving it, before any other reply, unless that event came late (first_steps checks)."""
    run = launcher(distro="kilted")
    try:
        answer = run.start(time_scale=1.0)
        interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
        assert answer["op"] == "hello" and "ROS 2 kilted" in answer["sut"] and "taken" not in answer["caps"], answer
        assert set(answer["taken_services"]) == set(interface.services), answer
        first_steps(run)
        children = descendants(run.process.pid)
        assert run.bye() == 0, "".join(run.stderr[-20:])
        assert wait_gone(children, timeout=15) == set()
    finally:
        run.kill()


CANCELS = """
[cancels]
"rflex.Stop" = "rflex.TrackSpeedStart"
"aspect.Stop" = "aspect.Reset"
"sick.Stop" = "sick.ContinuousShot"

[cancel_codes]
ERROR_NONE = "ok"
ERROR_REJECTED = "too_many_activities"
ERROR_UNKNOWN_GOAL_ID = "bad_params"
ERROR_GOAL_TERMINATED = "disallowed"
"""


@pytest.mark.parametrize("distro", ["jazzy", "kilted"])
def test_a_cancel_ends_a_running_goal_and_one_after_success_is_refused(tmp_path, distro):
    """With [cancels] in the mapping, a module's Stop is a cancel request of the latest goal of the
    service it names: a running TrackSpeedStart is canceled (the cancel answers ERROR_NONE, the goal
    ends CANCELED with the layer's `interrupted`); a cancel of a Reset that succeeded is refused
    ERROR_GOAL_TERMINATED, one of a ContinuousShot never sent ERROR_UNKNOWN_GOAL_ID, each with the
    mapping's reply code. On Kilted a cancel may be `taken` first (the server's introspection).
    The Stop services need no route of their own: each is served by its action's cancel_goal."""
    if installed(ROOT, distro):
        pytest.skip(installed(ROOT, distro))
    mapping = tmp_path / "ros2.toml"
    mapping.write_text(MAPPING.read_text().replace("[status_codes]", CANCELS + "\n[status_codes]"))
    run = launcher(distro=distro, mapping=mapping)
    try:
        assert run.start(time_scale=1.0)["op"] == "hello", "".join(run.stderr[-20:])
        for rqst_id, service in INITS.items():
            run.send(request(rqst_id, service))
        assert {run.final(rqst_id) for rqst_id in INITS} == {"ok"}
        run.send(request(20, "rflex.SetMode", mode="velocity"))
        assert run.final(20) == "ok"
        run.send(request(1, "rflex.TrackSpeedStart"))
        run.expect(lambda m: m["op"] == "reply" and m["id"] == 1 and m["kind"] == "intermediate")
        run.send(request(2, "rflex.Stop"))
        assert (run.final(2), run.final(1)) == ("ok", "interrupted")
        run.send(request(3, "aspect.Reset"))
        assert run.final(3) == "ok"
        run.send(request(4, "aspect.Stop"))
        run.send(request(5, "sick.Stop"))
        refused = (run.final(4), run.final(5))
        assert refused == ("disallowed", "bad_params"), refused
        assert_taken_only_where_published(run, {2: "rflex.Stop", 4: "aspect.Stop", 5: "sick.Stop"}, intermediate=set())
        assert run.bye() == 0, "".join(run.stderr[-20:])
    finally:
        run.kill()
