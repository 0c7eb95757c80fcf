"""A ROS 2 process's environment (harness/sut/ros2/environment.py): what it sets, a domain id
no other holder on this machine has (other processes included), its log folder removed."""
import subprocess
import sys

import pytest

from harness import ROOT
from harness.sut.ros2.environment import (DOMAIN_IDS, DISTROS, PROFILE, PROFILE_VARIABLE, Ros2Environment,
                                               Ros2Error, hold_domain_id, installed)

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


def test_a_distro_not_installed_or_unknown_is_refused_naming_the_remedy(tmp_path):
    assert "make ros2" in installed(tmp_path, "jazzy") and str(tmp_path) in installed(tmp_path, "jazzy")
    assert "'humble'" in installed(ROOT, "humble") and "jazzy" in installed(ROOT, "humble")
    with pytest.raises(Ros2Error, match="make ros2"):
        Ros2Environment(tmp_path, "kilted", 0)


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
        # LOCALHOST would swap the profile's transports for rmw_fastrtps's own, shared memory included
        assert env["ROS_AUTOMATIC_DISCOVERY_RANGE"] == "SUBNET" and env[PROFILE_VARIABLE[distro]] == str(PROFILE)
        assert env["RMW_IMPLEMENTATION"] == "rmw_fastrtps_cpp"
        shown = subprocess.run([str(ros.python), "-c", "import rclpy, untimely_msgs.action as a, untimely_msgs.srv as s;"
                                "print(a.Request.__name__, s.Call.__name__, rclpy.__file__)"],
                               env=env, capture_output=True, text=True, timeout=60)
        assert shown.returncode == 0, shown.stderr
        assert shown.stdout.split()[:2] == ["Request", "Call"] and f".venv-ros2-{distro}" in shown.stdout
    assert not log_dir.exists() and ros.domain_id is None
