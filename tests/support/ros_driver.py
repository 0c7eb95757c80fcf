"""Drives the ROS launcher over stdio with `untimely/1` lines, as the bench would, for the ROS tests.

The launcher runs in .venv-ros (Debian's ROS 1 under /usr/bin/python3); `make ros` builds it.
Where /usr/bin/python3 cannot import rospy the tests skip, saying so (.ci/run installs ROS).
"""
from __future__ import annotations

import json
import queue
import subprocess
import threading
import time
from pathlib import Path

import pytest

from harness import DEFAULT_MISSION_DIR, ROOT
from harness.sut.ros2.environment import installed
from harness.target.interface import load_interface

ROS_PYTHON = "/usr/bin/python3"
VENV_PYTHON = ROOT / ".venv-ros" / "bin" / "python"
MAPPING = DEFAULT_MISSION_DIR / "ros.toml"
LAUNCHER, NODE = "harness.sut.ros", "harness.sut.ros.dala_node"


def requires(modules: str, packages: str, what: str):
    """A mark that skips a test, saying what to install, where /usr/bin/python3 cannot import `modules`."""
    probe = subprocess.run([ROS_PYTHON, "-c", f"import {modules}"], capture_output=True)
    return pytest.mark.skipif(probe.returncode != 0,
                              reason=f"{ROS_PYTHON} cannot import {what} (apt-get install {packages})")


requires_ros = requires("rospy, actionlib, genpy, rosmaster", "python3-rospy python3-actionlib",
                        "Debian's ROS 1 packages")
# The message packages of the typed routes (ros-typed.toml, ros-cpp.toml).
requires_typed = requires("move_base_msgs.msg, std_srvs.srv", "python3-move-base-msgs python3-std-srvs",
                          "move_base_msgs and std_srvs")


def ensure_ros_venv() -> Path:
    """.venv-ros, built by `make ros` if a test run starts without it."""
    if not VENV_PYTHON.exists():
        subprocess.run(["make", "--no-print-directory", "ros"], cwd=ROOT, check=True, capture_output=True)
    return VENV_PYTHON


def launcher_command(variant: str, mapping: Path = MAPPING, node: list[str] | None = None) -> list[str]:
    """The launcher serving `node` (by default the Python Dala node of `variant`)."""
    python = str(ensure_ros_venv())
    return [python, "-m", LAUNCHER, "--mapping", str(mapping), "--",
            *(node or [python, "-m", NODE, "--variant", variant, "--mapping", str(mapping)])]


def hello(time_scale: float) -> dict:
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    return {"op": "hello", "proto": "untimely/1", "run": 1, "seed": 1, "time_scale": time_scale,
            "interface": interface.describe()}


def descendants(pid: int) -> set[int]:
    """Every living process below `pid` (zombies are dead)."""
    children: dict[int, list[int]] = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if fields[0] != "Z":
                children.setdefault(int(fields[1]), []).append(int(entry.name))
    found, todo = set(), [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            found.add(child)
            todo.append(child)
    return found


def command_line(pid: int) -> list[str]:
    """The arguments process `pid` runs with ([] once it has gone)."""
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().decode().split("\0")
    except OSError:
        return []


def running_module(pid: int) -> str | None:
    """The module a `python -m MODULE ...` process runs, if it is one."""
    argv = command_line(pid)
    return argv[2] if len(argv) > 2 and argv[1] == "-m" else None


def alive(pids: set[int]) -> set[int]:
    living = set()
    for pid in pids:
        try:
            state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except OSError:
            continue
        if state != "Z":
            living.add(pid)
    return living


class Launcher:
    """One launcher process; `lines` collects what it writes, each with its monotonic arrival time."""

    def __init__(self, variant: str = "reference", mapping: Path = MAPPING, node: list[str] | None = None,
                 command: list[str] | None = None):
        """The ROS 1 launcher of `variant`, or `command` (a ROS 2 launcher: ros2_driver.py)."""
        command = command or launcher_command(variant, mapping, node)
        self.node_command = command[command.index("--") + 1:]
        self.process = subprocess.Popen(command, cwd=ROOT, stdin=subprocess.PIPE,
                                        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.started = time.monotonic()
        self.lines: list[tuple[float, dict]] = []
        self._inbox: queue.Queue = queue.Queue()
        self.stderr: list[str] = []
        threading.Thread(target=self._read, daemon=True).start()
        threading.Thread(target=lambda: self.stderr.extend(self.process.stderr), daemon=True).start()

    def _read(self) -> None:
        for line in self.process.stdout:
            self._inbox.put((time.monotonic(), json.loads(line)))
        self._inbox.put(None)

    def send(self, message: dict) -> float:
        self.process.stdin.write(json.dumps(message) + "\n")
        self.process.stdin.flush()
        return time.monotonic()

    def expect(self, predicate, timeout: float = 60.0) -> dict:
        """The first new line matching `predicate`, waiting at most `timeout` seconds."""
        found = self.wait(predicate, timeout)
        if found is None:
            raise AssertionError(f"no matching line within {timeout} s; got {[m for _, m in self.lines]}\n"
                                 f"stderr: {''.join(self.stderr[-20:])}")
        return found

    def wait(self, predicate, timeout: float) -> dict | None:
        """Like expect, but None when nothing matches in time (or the output ends)."""
        for _, message in self.lines:
            if predicate(message):
                return message
        deadline = time.monotonic() + timeout
        while (left := deadline - time.monotonic()) > 0:
            try:
                item = self._inbox.get(timeout=left)
            except queue.Empty:
                return None
            if item is None:
                return None
            self.lines.append(item)
            if predicate(item[1]):
                return item[1]
        return None

    def start(self, time_scale: float = 1.0) -> dict:
        self.send(hello(time_scale))
        return self.expect(lambda m: m["op"] in ("hello", "error"))

    def final(self, rqst_id: int, timeout: float = 60.0) -> str:
        return self.expect(lambda m: m["op"] == "reply" and m["id"] == rqst_id and m["kind"] == "final",
                           timeout)["code"]

    def internal(self, wanted: set[tuple[int, str]], timeout: float = 60.0) -> dict[tuple[int, str], float]:
        """The ground-truth lines read, (id, kind) -> t, once each of `wanted` has come (or `timeout`
        seconds passed): the node sends them on a topic of its own, which may lag the replies."""
        for rqst_id, kind in sorted(wanted):
            self.wait(lambda m: m["op"] == "internal" and m["id"] == rqst_id and m["kind"] == kind, timeout)
        return {(m["id"], m["kind"]): m["t"] for _, m in self.lines if m["op"] == "internal"}

    def replies(self, rqst_id: int) -> list[dict]:
        return [m for _, m in self.lines if m["op"] == "reply" and m["id"] == rqst_id]

    def node_pid(self) -> int:
        """The node's process: the one below the launcher that runs the node's command."""
        for pid in descendants(self.process.pid):
            if command_line(pid)[:3] == self.node_command[:3]:
                return pid
        raise AssertionError(f"no process of {' '.join(self.node_command[:3])} below the launcher")

    def bye(self, timeout: float = 60.0) -> int:
        """bye, then end of input (as the bench: a launcher that offers reuse waits for a next hello)."""
        self.send({"op": "bye"})
        self.process.stdin.close()
        return self.process.wait(timeout)

    def kill(self) -> None:
        if self.process.poll() is None:
            self.process.kill()
            self.process.wait()


def request(rqst_id: int, qualified: str, **args) -> dict:
    module, service = qualified.split(".")
    return {"op": "request", "id": rqst_id, "module": module, "service": service,
            "args": args}


def wait_gone(pids: set[int], timeout: float = 30.0) -> set[int]:
    """The pids still alive after waiting up to `timeout` seconds for them to end."""
    deadline = time.monotonic() + timeout
    while alive(pids) and time.monotonic() < deadline:
        time.sleep(0.1)
    return alive(pids)


def requires_ros2(distro: str):
    return pytest.mark.skipif(installed(ROOT, distro) is not None, reason=str(installed(ROOT, distro)))


def finished(launcher: Launcher) -> set[int]:
    """bye, then the launcher's former children that are still alive."""
    children = descendants(launcher.process.pid)
    assert launcher.bye() == 0, "".join(launcher.stderr[-20:])
    return wait_gone(children, timeout=10)


def assert_run_after_run(launcher: Launcher) -> None:
    """With the mapping's reset_service: bye is answered, the next hello is served by the same node,
    reset (a TrackSpeedStart before rflex.Init is refused again), and nothing of the first run (its
    request 2, left running at bye) reaches the second."""
    try:
        first = launcher.start(time_scale=1.0)
        assert "reuse" in first["caps"] and first["sut"].endswith("run 1 of this master)"), first
        node = launcher.node_pid()
        launcher.send(request(1, "rflex.Init"))
        launcher.send(request(3, "rflex.SetMode", mode="velocity"))
        assert (launcher.final(1), launcher.final(3)) == ("ok", "ok")
        launcher.send(request(2, "rflex.TrackSpeedStart"))
        launcher.expect(lambda m: m["op"] == "reply" and m["id"] == 2 and m["kind"] == "intermediate")
        launcher.send({"op": "bye"})
        launcher.expect(lambda m: m == {"op": "bye"})
        second_run = len(launcher.lines)
        launcher.send(hello(1.0))
        second = launcher.expect(lambda m: m["op"] in ("hello", "error") and m is not first)
        assert second["sut"].endswith("run 2 of this master)") and launcher.node_pid() == node, second
        launcher.send(request(2, "rflex.TrackSpeedStart"))
        assert launcher.final(2) == "wait_init"
        launcher.send({"op": "ping", "id": 1})
        launcher.expect(lambda m: m["op"] == "pong" and m["id"] == 1 and m["held_s"] >= 0, timeout=30)
        assert [m for _, m in launcher.lines[second_run:] if m["op"] == "reply"] == [
            {"op": "reply", "id": 2, "kind": "final", "code": "wait_init"}]
        assert finished(launcher) == set()
    finally:
        launcher.kill()
