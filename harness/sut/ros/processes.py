"""The child processes of one run: a rosmaster on a free loopback port, and the SUT's node.

Children die with the launcher even when it is killed outright (PR_SET_PDEATHSIG), and a
normal teardown ends them with SIGTERM, then SIGKILL after a grace period: no orphans.
"""
from __future__ import annotations

import collections
import ctypes
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import xmlrpc.client

from harness.errors import UntimelyError

PR_SET_PDEATHSIG = 1
_libc = ctypes.CDLL(None, use_errno=True)  # loaded before any fork: the child only calls into it


def _dying_with_parent(death_signal: int):
    return lambda: _libc.prctl(PR_SET_PDEATHSIG, death_signal)


class ChildError(UntimelyError):
    """A child process could not start or died during start-up (the launcher reports it as `error`)."""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


HOME_PREFIX = "untimely-ros-"


def ros_home() -> str:
    """A fresh folder for a run's ROS logs, named after this process; folders left behind by
    launchers that were killed before their teardown are removed."""
    tmp = tempfile.gettempdir()
    for name in os.listdir(tmp):
        owner = name[len(HOME_PREFIX):].split("-")[0]
        if name.startswith(HOME_PREFIX) and owner.isdigit() and not os.path.exists(f"/proc/{owner}"):
            shutil.rmtree(os.path.join(tmp, name), ignore_errors=True)
    return tempfile.mkdtemp(prefix=f"{HOME_PREFIX}{os.getpid()}-")


def ros_environment(master_port: int, home: str) -> dict[str, str]:
    """The environment of every ROS process of a run: its own master, loopback only, logs in `home`."""
    return {**os.environ, "ROS_MASTER_URI": f"http://127.0.0.1:{master_port}", "ROS_HOSTNAME": "127.0.0.1",
            "ROS_HOME": home, "ROS_LOG_DIR": os.path.join(home, "log")}


class Child:
    """A process whose stderr is forwarded to ours, keeping its last lines for error messages."""

    def __init__(self, name: str, argv: list[str], env: dict[str, str], death_signal: int = signal.SIGKILL,
                 own_group: bool = False):
        """`death_signal` reaches the child when the launcher dies; `own_group` keeps it out of the
        launcher's process group, which the bench kills after its grace period."""
        self.name, self.argv = name, argv
        try:
            self.process = subprocess.Popen(argv, env=env, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                                            stderr=subprocess.PIPE, text=True, errors="replace",
                                            preexec_fn=_dying_with_parent(death_signal), start_new_session=own_group)
        except OSError as e:
            raise ChildError(f"cannot start the {name} ({' '.join(argv)!r}): {e}; check the command") from None
        self.last_lines: collections.deque[str] = collections.deque(maxlen=20)
        threading.Thread(target=self._forward, name=f"{name} stderr", daemon=True).start()

    def _forward(self) -> None:
        for line in self.process.stderr:
            self.last_lines.append(line.rstrip("\n"))
            print(f"[{self.name}] {line}", end="", file=sys.stderr, flush=True)

    def failure(self) -> str | None:
        """Why the child is no longer running, with its last stderr lines; None while it runs."""
        status = self.process.poll()
        if status is None:
            return None
        return f"the {self.name} exited with status {status}; its last lines: " + " | ".join(self.last_lines)

    def stop(self, grace_s: float = 5.0) -> None:
        stop_all([self], grace_s)


def stop_all(children: list[Child], grace_s: float = 5.0) -> None:
    """SIGTERM to all at once (their shutdowns overlap), SIGKILL to whoever outlives the grace period."""
    for child in children:
        if child.process.poll() is None:
            child.process.terminate()
    deadline = time.monotonic() + grace_s
    for child in children:
        try:
            child.process.wait(max(0.0, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            child.process.kill()
            child.process.wait()


PORT_ATTEMPTS = 5


def start_master(home: str, timeout_s: float) -> tuple[Child, dict[str, str]]:
    """A rosmaster of our own and the environment that reaches it. The free port may be taken by
    someone else before the master binds it, and a master that cannot bind does not exit: it says
    so and stays, while the port's owner (maybe another run's master) answers in its place. So the
    answer must come from our master's pid, or we try another port."""
    for _ in range(PORT_ATTEMPTS):
        port = free_port()
        env = ros_environment(port, home)
        master = Child("rosmaster", ["rosmaster", "--core", "-p", str(port)], env)
        if _answers(master, xmlrpc.client.ServerProxy(env["ROS_MASTER_URI"]), timeout_s):
            return master, env
        exited = master.failure()  # by itself, before we stop it
        master.stop()
        if exited and "already in use" not in exited:
            raise ChildError(exited)
    raise ChildError(f"no free port for a rosmaster after {PORT_ATTEMPTS} attempts; the last: "
                     f"{' | '.join(master.last_lines)}")


def _answers(master: Child, proxy, timeout_s: float) -> bool:
    """Whether `master` itself answers within `timeout_s`; False as soon as it cannot bind."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline and master.process.poll() is None:
        if any("already in use" in line for line in master.last_lines):
            return False
        try:
            return proxy.getPid("/untimely")[2] == master.process.pid
        except (OSError, xmlrpc.client.Error):
            time.sleep(0.05)
    if master.process.poll() is None:
        raise ChildError(f"the rosmaster did not answer within {timeout_s:g} s; the machine may be overloaded")
    return False
