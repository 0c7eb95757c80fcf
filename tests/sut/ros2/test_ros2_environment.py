"""A ROS 2 process's environment (harness/sut/ros2/environment.py): what it sets, a domain id
no other holder on this machine has (other processes included), its log folder removed, the
shared memory of dead Fast DDS participants swept."""
import fcntl
import os
import subprocess
import sys
import time

import pytest

from harness import ROOT
from harness.errors import Ros2Error
from harness.sut.ros2 import environment
from harness.sut.ros2.environment import (DOMAIN_IDS, DISTROS, PROFILE, PROFILE_VARIABLE, Ros2Environment,
                                               SETTLE_S, domain_ids_in_use, hold_domain_id,
                                               installed, sweep_dead_segments)

HOLDER = """
import sys
from harness.sut.ros2.environment import hold_domain_id
lock, domain_id = hold_domain_id(int(sys.argv[1]))
print(domain_id, flush=True)
sys.stdin.read()
"""


def test_ids_held_at_once_are_distinct_and_free_again_once_closed():
    held = [hold_domain_id(slot=3) for _ in range(8)]
    ids = [domain_id for _, domain_id in held]
    assert len(set(ids)) == 8 and set(ids) <= set(DOMAIN_IDS)
    for lock, _ in held:
        lock.close()
    again = [hold_domain_id(slot=3) for _ in range(8)]
    assert {domain_id for _, domain_id in again} & set(ids), "closed ids should be handed out again"
    for lock, _ in again:
        lock.close()


def test_an_id_held_by_another_process_is_skipped_until_it_ends():
    holder = subprocess.Popen([sys.executable, "-c", HOLDER, "40"], cwd=ROOT, stdin=subprocess.PIPE,
                              stdout=subprocess.PIPE, text=True)
    try:
        theirs = int(holder.stdout.readline())
        mine = [hold_domain_id(slot=theirs - 1) for _ in range(3)]
        assert theirs not in [domain_id for _, domain_id in mine]
        for lock, _ in mine:
            lock.close()
    finally:
        holder.stdin.close()
        holder.wait(timeout=10)
    lock, domain_id = hold_domain_id(slot=theirs - 1)  # the kernel released the ended process's lock
    lock.close()
    assert domain_id <= theirs


def test_an_id_a_living_process_was_started_with_is_not_handed_out_until_it_ends():
    """A slot gives its id back while its node may still be tearing down: a process that runs with
    ROS_DOMAIN_ID (here a sleeper, holding no lock) keeps its id from a new holder."""
    lock, free = hold_domain_id(slot=60)
    lock.close()
    # Popen returns once exec closed its error pipe, which the kernel does before it fills in the
    # new image's environment: /proc/PID/environ may still read empty. The sleeper says when it runs.
    dying = subprocess.Popen([sys.executable, "-c", "print(flush=True); import time; time.sleep(30)"],
                             env={**os.environ, "ROS_DOMAIN_ID": str(free)}, stdout=subprocess.PIPE)
    try:
        dying.stdout.readline()
        lock, domain_id = hold_domain_id(slot=60)
        lock.close()
        assert domain_id != free and free in domain_ids_in_use()
    finally:
        dying.kill()
        dying.wait(timeout=10)
        dying.stdout.close()
    assert free not in domain_ids_in_use()


def test_a_distro_not_installed_or_unknown_is_refused_naming_the_remedy(tmp_path):
    assert "make ros2" in installed(tmp_path, "jazzy") and str(tmp_path) in installed(tmp_path, "jazzy")
    assert "'humble'" in installed(ROOT, "humble") and "jazzy" in installed(ROOT, "humble")
    with pytest.raises(Ros2Error, match="make ros2"):
        Ros2Environment(tmp_path, "kilted", 0)


@pytest.mark.slow
@pytest.mark.parametrize("distro", DISTROS)
def test_the_environment_is_the_distros_and_its_log_folder_goes_away(distro):
    missing = installed(ROOT, distro)
    if missing:
        pytest.skip(missing)
    with Ros2Environment(ROOT, distro, slot=2) as ros:
        env, log_dir = ros.env, ros.log_dir
        assert log_dir.is_dir() and env["ROS_LOG_DIR"] == str(log_dir)
        assert env["PATH"].split(":")[0] == str(ROOT / f".venv-ros2-{distro}" / "bin")
        assert env["ROS_DOMAIN_ID"] == str(ros.domain_id)
        assert env["ROS_AUTOMATIC_DISCOVERY_RANGE"] == "LOCALHOST" and env[PROFILE_VARIABLE[distro]] == str(PROFILE)
        assert env["RMW_IMPLEMENTATION"] == "rmw_fastrtps_cpp"
        shown = subprocess.run([str(ros.python), "-c", "import rclpy, untimely_msgs.action as a, untimely_msgs.srv as s;"
                                "print(a.Request.__name__, s.Call.__name__, rclpy.__file__)"],
                               env=env, capture_output=True, text=True, timeout=60)
        assert shown.returncode == 0, shown.stderr
        assert shown.stdout.split()[:2] == ["Request", "Call"] and f".venv-ros2-{distro}" in shown.stdout
    assert not log_dir.exists() and ros.domain_id is None


def test_the_sweep_removes_the_shared_memory_of_dead_owners_only(tmp_path, monkeypatch):
    """A segment whose lock file nobody holds (its owner was killed) goes, with its lock files and
    semaphore; one whose lock is held (a living owner), one just created (without waiting for it to
    settle), and other files stay."""
    # "just created" must stay young until the sweep, however slow the disk of a busy machine
    monkeypatch.setattr(environment, "SETTLE_S", 60.0)
    def segment(name: str, age_s: float) -> None:
        for path in (tmp_path / name, tmp_path / f"{name}_el", tmp_path / f"sem.{name}_mutex"):
            path.write_bytes(b"")
            os.utime(path, (time.time() - age_s,) * 2)
    segment("fastdds_0123456789abcdef", 600)  # dead
    segment("fastrtps_port7411", 600)         # dead port
    segment("fastdds_fedcba9876543210", 600)  # alive: its lock is held below
    segment("fastrtps_aaaaaaaaaaaaaaaa", 0)   # being created: not locked yet
    (tmp_path / "lttng-ust-wait-6").write_bytes(b"")
    with open(tmp_path / "fastdds_fedcba9876543210_el") as held:
        fcntl.flock(held, fcntl.LOCK_EX)
        assert sweep_dead_segments(tmp_path, settle=False) == ["fastdds_0123456789abcdef", "fastrtps_port7411"]
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "fastdds_fedcba9876543210", "fastdds_fedcba9876543210_el", "fastrtps_aaaaaaaaaaaaaaaa",
        "fastrtps_aaaaaaaaaaaaaaaa_el", "lttng-ust-wait-6", "sem.fastdds_fedcba9876543210_mutex",
        "sem.fastrtps_aaaaaaaaaaaaaaaa_mutex"]


def test_the_sweep_waits_for_young_files_to_settle(tmp_path):
    """A port with no lock file left (its listener gone) is dead once nobody has written it for a
    moment, a segment whose lock nobody took once its creator had time to: files written just now
    are waited for, then removed."""
    for name in ("fastdds_port7000", "sem.fastdds_port7000_mutex", "fastrtps_0123456789abcdef",
                 "fastrtps_0123456789abcdef_el"):
        (tmp_path / name).write_bytes(b"")
    started = time.monotonic()
    assert sweep_dead_segments(tmp_path) == ["fastdds_port7000", "fastrtps_0123456789abcdef"]
    assert time.monotonic() - started >= SETTLE_S and not any(tmp_path.iterdir())
