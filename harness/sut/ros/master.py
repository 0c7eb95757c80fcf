"""The rosmaster of one run, on a free loopback port, with a folder and an environment of its own.

It is a `Child` (harness/sut/processes.py): it dies with the launcher even when the launcher is
killed outright, and a normal teardown ends it with SIGTERM, then SIGKILL after a grace period.
"""
from __future__ import annotations

import os
import shutil
import socket
import tempfile
import time
import xmlrpc.client

from harness.errors import ChildError
from harness.sut.processes import Child


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
