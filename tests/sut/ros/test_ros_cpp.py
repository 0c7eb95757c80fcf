"""The C++ node (harness/sut/ros/cpp, built by `make ros-cpp`): roscpp and actionlib serving
MoveBase goals, Trigger calls and generic goals, forwarding each to the simulated layer, and its
reset service between runs. A campaign through it judges like the simulator in process."""
import functools
import subprocess

import pytest

from harness import DEFAULT_MISSION_DIR, ROOT

from tests.support.ros_driver import Launcher, ensure_ros_venv, requires_ros, requires_typed
from tests.support.ros_driver import assert_run_after_run
from tests.support.external import assert_judges_like_in_process, campaign

NODE = ROOT / "build" / "ros_cpp" / "dala_forward_node"


@functools.cache
def cpp_missing() -> str | None:
    """Why the C++ node is not there after `make ros-cpp` (which says why it did not build it)."""
    if not NODE.exists():
        ensure_ros_venv()
        made = subprocess.run(["make", "--no-print-directory", "ros-cpp"], cwd=ROOT, capture_output=True, text=True)
        if not NODE.exists():
            return (made.stdout + made.stderr).strip()[-500:] or "make ros-cpp built no node"
    return None


pytestmark = [requires_ros, requires_typed, pytest.mark.slow]


def test_a_campaign_through_the_cpp_node_judges_like_the_simulator_in_process(tmp_path, capsys):
    """Golden + 7 mutants (6 valid: the golden run, then one wave of the slots) on `reference` in
    process and on `ros-cpp-reference` on 8 slots, twice real time: every run completes on both,
    every verdict that differs is suspicious on one side."""
    if cpp_missing():
        pytest.skip(cpp_missing())
    db = tmp_path / "c.duckdb"
    assert campaign(db, "--mutants", "7", "--sut", "reference,ros-cpp-reference", "--jobs", "8",
                    "--time-scale", "2") == 0
    con = assert_judges_like_in_process(db, capsys.readouterr().out, "ros-cpp-reference", 2, min_runs=7)
    infos = [r[0] for r in con.execute("select sut_info from trace_runs join traces using (trace_id) "
                                        "where sut = 'ros-cpp-reference'").fetchall()]
    assert all("dala_forward_node" in info for info in infos)
    # its reset service: run after run on one master and node per slot, each on a fresh layer (the
    # verdicts above agree with in-process runs, each of which starts a fresh layer)
    fresh = sum(info.endswith("run 1 of this master)") for info in infos)
    assert fresh <= 8 and fresh < len(infos), infos  # at most one start per slot, and a node served again


def test_the_cpp_node_serves_run_after_run_each_on_a_fresh_layer():
    if cpp_missing():
        pytest.skip(cpp_missing())
    layer = [str(ensure_ros_venv()), "-m", "harness.sut.simulated", "--variant", "reference"]
    assert_run_after_run(Launcher(mapping=DEFAULT_MISSION_DIR / "ros-cpp.toml", node=[str(NODE), "--", *layer]))
