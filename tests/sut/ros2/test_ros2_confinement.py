"""Nothing of a ROS 2 run of the bench leaves loopback (docs/ros2.md, "Confined to this machine").

A service round trip and an action goal between two processes, in the bench's environment, inside
a private network namespace holding a veth pair (both ends inside it: nothing of it reaches the
machine's own interfaces), while a raw socket counts the RTPS packets on the veth: none may show.
The same exchange with the environment's confinement taken out (Fast DDS's defaults: discovery
multicast on every interface) does show some, so the sniffer sees what it should. Then: two slots
never see each other's nodes, and a run that ends, or is killed, leaves no process, no Fast DDS
shared memory (rmw_fastrtps gives LOCALHOST participants the shared-memory transport) and no log
folder.
"""
import fcntl
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import psutil
import pytest

from harness import ROOT
from harness.sut.ros2.environment import DEFAULT_DISTRO, DISTROS, Ros2Environment, installed
from tests.support.paths import SUPPORT

PEER, SNIFF = SUPPORT / "ros2_peer.py", SUPPORT / "ros2_sniff.py"
PROFILES = ("FASTDDS_DEFAULT_PROFILES_FILE", "FASTRTPS_DEFAULT_PROFILES_FILE")
FAST_DDS_FILE = re.compile(r"(sem\.)?(fastrtps|fastdds)_(\w+?)(_el|_sl|_mutex)?")
TIMEOUT_S = 60

pytestmark = [pytest.mark.skipif(bool(installed(ROOT, DEFAULT_DISTRO)), reason=str(installed(ROOT, DEFAULT_DISTRO))), pytest.mark.slow]


def _ip(*argv: str) -> None:
    subprocess.run(["ip", *argv], check=True, capture_output=True, timeout=10)


@pytest.fixture
def namespace():
    """A network namespace with loopback and a veth pair va (10.231.0.1) - vb (10.231.0.2), IPv6 off."""
    if os.geteuid() != 0 or not shutil.which("ip"):
        pytest.skip("needs root and iproute2's ip (apt-get install iproute2) for a network namespace")
    name = f"untimely-{os.getpid()}"
    _ip("netns", "add", name)
    try:
        _ip("-n", name, "link", "add", "va", "type", "veth", "peer", "name", "vb")
        for sysctl in ("all", "default", "va", "vb"):
            subprocess.run(["ip", "netns", "exec", name, "sysctl", "-qw", f"net.ipv6.conf.{sysctl}.disable_ipv6=1"],
                           check=True, timeout=10)
        for device, address in (("va", "10.231.0.1/24"), ("vb", "10.231.0.2/24")):
            _ip("-n", name, "addr", "add", address, "dev", device)
            _ip("-n", name, "link", "set", device, "up", "multicast", "on")
        _ip("-n", name, "link", "set", "lo", "up")
        _ip("-n", name, "route", "add", "224.0.0.0/4", "dev", "va")
        yield ["ip", "netns", "exec", name]
    finally:
        _ip("netns", "del", name)


def exchange(env: dict, prefix: list[str] = ()) -> dict:
    """A server and a client in `env`: the client's replies and timings."""
    server = subprocess.Popen([*prefix, str(env["VIRTUAL_ENV"] + "/bin/python"), str(PEER), "serve", "untimely_server"],
                              env=env, stdout=subprocess.PIPE, text=True)
    try:
        assert server.stdout.readline().strip() == "ready"
        client = subprocess.run([*prefix, env["VIRTUAL_ENV"] + "/bin/python", str(PEER), "call"], env=env,
                                capture_output=True, text=True, timeout=TIMEOUT_S)
        assert client.returncode == 0, client.stderr[-3000:]
        return json.loads(client.stdout)
    finally:
        server.terminate()
        server.wait(timeout=TIMEOUT_S)


def sniffed(prefix: list[str], env: dict) -> tuple[dict, dict]:
    """The exchange's replies, and the packets counted on va while it ran."""
    sniffer = subprocess.Popen([*prefix, sys.executable, str(SNIFF), "va"], stdout=subprocess.PIPE, text=True)
    try:
        assert sniffer.stdout.readline().strip() == "ready"
        replies = exchange(env, prefix)
    finally:
        sniffer.terminate()
        counts = json.loads(sniffer.communicate(timeout=TIMEOUT_S)[0])
    return replies, counts


@pytest.mark.parametrize("distro", DISTROS)
def test_a_run_sends_no_ros_packet_on_a_non_loopback_interface_and_an_unconfined_one_does(namespace, distro):
    if installed(ROOT, distro):
        pytest.skip(installed(ROOT, distro))
    with Ros2Environment(ROOT, distro, slot=0) as ros:
        replies, confined = sniffed(namespace, ros.env)
        assert (replies["code"], replies["goal"], replies["phases"]) == ("ok", "ok", ["running"])
        assert confined["rtps"] == 0, f"ROS 2 traffic on a non-loopback interface: {confined}"
        # Fast DDS's defaults: no profile, and the range that leaves discovery to the middleware
        unconfined_env = {**{k: v for k, v in ros.env.items() if k not in PROFILES},
                          "ROS_AUTOMATIC_DISCOVERY_RANGE": "SUBNET"}
        replies, unconfined = sniffed(namespace, unconfined_env)
        assert replies["code"] == "ok"
        assert unconfined["rtps"] > 0, f"the sniffer saw no RTPS packet of an unconfined run: {unconfined}"


@pytest.mark.parametrize("distro", DISTROS)
def test_a_run_that_ends_leaves_no_shared_memory(distro):
    if installed(ROOT, distro):
        pytest.skip(installed(ROOT, distro))
    before = _fast_dds_files()
    with Ros2Environment(ROOT, distro, slot=0) as ros:
        assert exchange(ros.env)["code"] == "ok"
    assert not _left_in_shared_memory(before), f"left in /dev/shm: {_left_in_shared_memory(before)}"


def test_two_slots_never_see_each_others_nodes():
    with Ros2Environment(ROOT, DEFAULT_DISTRO, slot=0) as mine, Ros2Environment(ROOT, DEFAULT_DISTRO, slot=0) as theirs:
        assert mine.domain_id != theirs.domain_id
        server = subprocess.Popen([str(mine.python), str(PEER), "serve", "untimely_mine"], env=mine.env,
                                  stdout=subprocess.PIPE, text=True)
        try:
            assert server.stdout.readline().strip() == "ready"
            # the same slot's look ends once it sees the node (discovery on a busy machine may take
            # seconds); only then does the other slot look, for a while
            seen = {name: json.loads(subprocess.run([str(ros.python), str(PEER), "nodes", seconds, "untimely_mine"],
                                                    env=ros.env, capture_output=True, text=True,
                                                    timeout=TIMEOUT_S).stdout)
                    for name, ros, seconds in (("same slot", mine, "30"), ("other slot", theirs, "3"))}
        finally:
            server.terminate()
            server.wait(timeout=TIMEOUT_S)
    assert "untimely_mine" in seen["same slot"], seen
    assert "untimely_mine" not in seen["other slot"], seen


def _fast_dds_files() -> set[str]:
    return {p.name for p in Path("/dev/shm").iterdir() if FAST_DDS_FILE.fullmatch(p.name)}


def _held(name: str) -> bool:
    """Whether a living process owns the segment a Fast DDS file belongs to (it holds the flock of
    the segment's lock file): another test process's, not something this run left."""
    segment = FAST_DDS_FILE.fullmatch(name)
    base = Path("/dev/shm") / f"{segment.group(2)}_{segment.group(3)}"
    for lock in (base.with_name(base.name + "_el"), base.with_name(base.name + "_sl")):
        try:
            with open(lock) as f:
                fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            return True
        except FileNotFoundError:
            continue
    return False


def _left_in_shared_memory(before: set[str]) -> list[str]:
    """Fast DDS files (segments, ports, their locks and semaphores) new since `before` and owned by
    no living process."""
    return sorted(name for name in _fast_dds_files() - before if not _held(name))


def _living_children() -> set[int]:
    return {p.pid for p in psutil.Process().children(recursive=True) if p.status() != psutil.STATUS_ZOMBIE}


def test_a_killed_run_leaves_no_process_shared_memory_or_log_folder():
    earlier = _living_children()  # what earlier tests of the session still run is not this run's
    before = _fast_dds_files()
    with Ros2Environment(ROOT, DEFAULT_DISTRO, slot=0) as ros:
        server = subprocess.Popen([str(ros.python), str(PEER), "serve", "untimely_killed"], env=ros.env,
                                  stdout=subprocess.PIPE, text=True)
        assert server.stdout.readline().strip() == "ready"
        client = subprocess.Popen([str(ros.python), str(PEER), "call"], env=ros.env, stdout=subprocess.PIPE, text=True)
        client.stdout.readline()  # the exchange is over, both processes still up
        for process in (server, client):
            process.kill()
            process.wait(timeout=TIMEOUT_S)
        log_dir = ros.log_dir
        assert any(log_dir.iterdir()), "the nodes logged nothing in their log folder"
    assert not log_dir.exists()
    assert not _living_children() - earlier
    assert not _left_in_shared_memory(before), f"left in /dev/shm: {_left_in_shared_memory(before)}"
