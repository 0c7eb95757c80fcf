"""A campaign on the Dala layer behind real ROS 1 middleware judges like the simulator in process."""
import re

from harness import store
from tests.ros_driver import ensure_ros_venv, requires_ros
from tests.test_external_campaign import campaign, verdict_pairs

pytestmark = requires_ros


def test_ros_campaign_judges_like_the_simulator_in_process(tmp_path, capsys):
    """Golden + 20 mutants on `reference` in process and on `ros-reference` (missions/dala/suts.toml:
    actionlib servers on a rosmaster per run) on 8 slots: every verdict that differs is flagged
    suspicious on one side, so Table III matches except for suspicious verdicts; the measured
    interface latency is printed. Twice real time, to halve the test's minutes (in real time the
    same comparison took 6 minutes on a loaded 2-core machine, with every verdict alike)."""
    ensure_ros_venv()
    db = tmp_path / "c.duckdb"
    assert campaign(db, "--mutants", "20", "--sut", "reference,ros-reference", "--jobs", "8",
                    "--time-scale", "2") == 0
    out = capsys.readouterr().out
    assert re.search(r"ros-reference +\d+ +\d+ +2 +[\d.e-]+ +[\d.e-]+ +[\d.e-]+ +[\d.e-]+", out), out
    con = store.connect(db, read_only=True)
    outcomes = con.execute("select sut, outcome, count(*) from traces group by all order by all").fetchall()
    runs = outcomes[0][2]
    assert outcomes == [("reference", "completed", runs), ("ros-reference", "completed", runs)] and runs > 15
    pairs, differ, unflagged = verdict_pairs(con, "reference", "ros-reference")
    assert pairs > 500 and unflagged == 0, f"{differ} of {pairs} verdicts differ, {unflagged} not suspicious"
    if differ == 0:  # then Table III is the same, row for row
        table = "select * exclude (sut) from tp_rates where sut = ? order by all"
        assert con.execute(table, ["ros-reference"]).fetchall() == con.execute(table, ["reference"]).fetchall()
    latency = con.execute("select pings, rtt_p95_s from interface_latency where sut = 'ros-reference'").fetchone()
    assert latency[0] >= runs and 0 < latency[1] < 1.0
