"""A ROS 1 bag recorded with Debian's rosbag during a run on the ROS Dala layer (`run --rosbag`)
imports to the run's own trace and judges the same (harness/sut/ros/recorder.py,
harness/sut/bags/ros1.py). One run in real time: a bag's clock is the wall clock. The launcher
answers the hello only once every publisher has accepted the recorder, so the bag holds the first
goal even on a loaded machine (docs/ros.md, "Recording a run's bag")."""
import shutil
import time

import pytest

from harness import DEFAULT_MISSION_DIR, store
from harness.cli import main as cli

from tests.support.ros_driver import ensure_ros_venv, requires_ros

pytestmark = [requires_ros, pytest.mark.skipif(shutil.which("rosbag") is None,
                                                reason="Debian's rosbag is not installed (apt-get install python3-rosbag)"), pytest.mark.slow]


def test_a_recorded_bag_judges_like_the_live_trace_of_its_run(tmp_path, capsys):
    ensure_ros_venv()
    db, bags = str(tmp_path / "s.duckdb"), tmp_path / "bags"
    assert cli(["run", str(DEFAULT_MISSION_DIR / "golden.mission"), "--sut", "ros-reference", "--db", db,
                "--rosbag", str(bags)]) == 0
    deadline = time.monotonic() + 30  # the recorder closes the bag by itself, if the bench's grace ran out
    while (bags / "trace-1.bag.active").exists() and time.monotonic() < deadline:
        time.sleep(0.1)
    assert [p.name for p in bags.iterdir()] == ["trace-1.bag"]  # closed: no .bag.active left
    assert cli(["import", str(bags), "--interface", str(DEFAULT_MISSION_DIR / "interface.toml"), "--db", db]) == 0
    assert "Imported 1 trace" in capsys.readouterr().out
    assert cli(["analyze", "--db", db]) == 0
    con = store.connect(db, read_only=True)
    events = "select rqst_id, module, service, kind, args, reply from events where trace_id = ? order by all"
    live, bag = (con.execute(events, [trace]).fetchall() for trace in (1, 2))
    assert bag == live and len(live) > 40  # every request, reply and argument, numbered alike
    # The server's header stamps (the bag's SUT clock) stand for the ground truth the node published.
    sut = "select rqst_id, kind, reply from internal_events where trace_id = ? and kind <> 'request' order by all"
    live_sut, bag_sut = (con.execute(sut, [trace]).fetchall() for trace in (1, 2))
    assert bag_sut == live_sut and len(bag_sut) > 20
    pairs, unflagged = con.execute("""
        select count(*), count(*) filter (where l.verdict <> b.verdict and not (l.suspicious or b.suspicious))
        from verdicts l join verdicts b using (property_id, rqst_id)
        where l.trace_id = 1 and b.trace_id = 2""").fetchone()
    assert pairs > 30 and unflagged == 0
