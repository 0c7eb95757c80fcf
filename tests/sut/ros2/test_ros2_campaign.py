"""The Dala layer behind ROS 2 (rclpy actions and services, a lifecycle node per slot) through the
bench: a campaign judges like the simulator in process (docs/ros2.md)."""
import pytest

from tests.support.external import assert_judges_like_in_process, campaign
from tests.support.ros_driver import requires_ros2

pytestmark = pytest.mark.slow


@requires_ros2("jazzy")
def test_ros2_campaign_judges_like_the_simulator_in_process(tmp_path, capsys):
    """Golden + 9 mutants (the golden run, then one wave of the 8 slots: a node's second run on the
    golden's slot) on `reference` in process and on `ros2-reference` on 8 slots, twice real
    time (to halve the test's minutes): every run completes on both, every verdict that differs is
    suspicious on one side, Table III is the same when none differs; the ground truth of every goal that
    started before the run's last second reached the bench; one node per slot served run after run, each on a fresh layer (the verdicts
    agree with in-process runs, each of which starts a fresh layer)."""
    db = tmp_path / "c.duckdb"
    assert campaign(db, "--mutants", "9", "--sut", "reference,ros2-reference", "--jobs", "8",
                    "--time-scale", "2") == 0
    con = assert_judges_like_in_process(db, capsys.readouterr().out, "ros2-reference", 2, min_runs=9)
    # The ground truth travels on a topic of its own, later than the replies on a loaded machine, and
    # the bench reads nothing of a run after its bye: only the run's last second may lack it.
    untold = con.execute("""
        select count(*) from events e join traces t using (trace_id)
        where t.sut = 'ros2-reference' and e.kind = 'request' and exists (
            select 1 from events x where x.trace_id = e.trace_id and x.rqst_id = e.rqst_id and x.kind = 'intermediate'
        ) and e.t < (select max(x.t) from events x where x.trace_id = e.trace_id) - 1.0 and not exists (
            select 1 from internal_events i
            where i.trace_id = e.trace_id and i.rqst_id = e.rqst_id and i.kind = 'request')""").fetchone()[0]
    assert untold == 0
    infos = [r[0] for r in con.execute("select sut_info from trace_runs join traces using (trace_id) "
                                        "where sut = 'ros2-reference'").fetchall()]
    fresh = sum(info.endswith("run 1 of this node)") for info in infos)
    assert fresh <= 8 < len(infos), infos
