"""Typed routes through the ROS launcher (missions/dala/ros-typed.toml, docs/ros.md): navigation as
Debian's move_base_msgs/MoveBase goals, the Inits as std_srvs/Trigger ROS services."""
import pytest

from harness import DEFAULT_MISSION_DIR
from tests.support.external import assert_judges_like_in_process, campaign
from tests.support.ros_driver import Launcher, descendants, ensure_ros_venv, request, requires_ros, requires_typed, wait_gone

pytestmark = [requires_ros, requires_typed, pytest.mark.slow]
TYPED = DEFAULT_MISSION_DIR / "ros-typed.toml"


def test_typed_goals_and_service_calls_reply_like_generic_goals():
    launcher = Launcher("reference", TYPED)
    try:
        answer = launcher.start(time_scale=10.0)
        assert answer["op"] == "hello", (answer, "".join(launcher.stderr[-20:]))
        launcher.send(request(1, "ndd.GotoPosition", x=9, y=4))  # a MoveBase goal before ndd.Init: REJECTED
        assert launcher.final(1) == "wait_init"
        launcher.send(request(2, "ndd.Init"))  # a Trigger call; its response's message is the code
        assert launcher.final(2) == "ok"
        for rqst_id, service in ((4, "rflex.Init"), (5, "ndd.SetParams")):
            launcher.send(request(rqst_id, service, **({"speed": 0.6} if rqst_id == 5 else {})))
            assert launcher.final(rqst_id) == "ok"
        launcher.send(request(6, "ndd.GotoPosition", x=3, y=2))  # rflex is not tracking: never arrives
        assert launcher.final(6) == "goal_unreachable"
        assert [m["kind"] for m in launcher.replies(6)] == ["intermediate", "final"]  # MoveBase feedback
        assert [m["kind"] for m in launcher.replies(2)] == ["final"]  # a ROS service: no intermediate
        # Ground truth names service calls too (through the call's connection header).
        truth = {(2, "request"), (2, "final"), (6, "request"), (6, "final")}
        assert truth <= launcher.internal(truth).keys()
        children = descendants(launcher.process.pid)
        assert launcher.bye() == 0, "".join(launcher.stderr[-20:])
        assert wait_gone(children, timeout=10) == set()
    finally:
        launcher.kill()


def test_a_typed_campaign_judges_like_the_simulator_in_process(tmp_path, capsys):
    """Golden + 7 mutants (6 valid: the golden run, then one wave of the slots) on `reference` in
    process and on `ros-typed-reference` (MoveBase goals, Trigger calls, generic goals for the
    rest) on 8 slots, twice real time: every run completes on both, every verdict that differs is
    flagged suspicious on one side."""
    ensure_ros_venv()
    db = tmp_path / "c.duckdb"
    assert campaign(db, "--mutants", "7", "--sut", "reference,ros-typed-reference", "--jobs", "8",
                    "--time-scale", "2") == 0
    con = assert_judges_like_in_process(db, capsys.readouterr().out, "ros-typed-reference", 2, min_runs=7)
    runs = con.execute("select count(*) from traces where sut = 'ros-typed-reference'").fetchone()[0]
    calls = con.execute("""select count(*) from events e join traces t using (trace_id)
                           where t.sut = 'ros-typed-reference' and e.service in ('Init', 'GotoPosition')
                             and e.kind = 'final'""").fetchone()[0]
    assert calls >= runs * 5  # every run's Inits went through Trigger, its drives through MoveBase
