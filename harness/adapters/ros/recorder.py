"""A run's bag, recorded with Debian's `rosbag record` on the run's own master (docs/ros.md).

`run`/`campaign --rosbag DIR` put DIR in $UNTIMELY_ROSBAG; the launcher then records every topic
the mapping names (each action's goal, cancel, status, feedback and result, and the JSON topics)
to DIR/trace-ID.bag, ID being the trace id the bench's hello gives as `run`, so `import DIR`
judges what the middleware carried. The recorder is subscribed to every topic before the hello
is answered (no goal can precede it) and stopped first, with SIGINT, on which it closes the bag.
It is `rosbag record`'s own program (the `rosbag` command forks it and exits on SIGINT before it
has closed the bag), in a process group of its own, as the bench kills the launcher's group
two seconds after `bye`, and it gets SIGINT, not SIGKILL, when the launcher dies: the bag is
closed whatever happens to the launcher, and the recorder exits then. ROS 1 services are not
topics: a bag cannot hold their calls.
"""
from __future__ import annotations

import os
import signal
import subprocess
import time
import xmlrpc.client
from pathlib import Path

from harness.adapters.ros.mapping import Mapping
from harness.adapters.ros.processes import Child, ChildError

ROSBAG_ENV = "UNTIMELY_ROSBAG"
ACTION_TOPICS = ("goal", "cancel", "status", "feedback", "result")
DRAIN_S = 0.3  # the last result reached the adapter; the recorder, another subscriber, gets it as soon


def recorded_topics(mapping: Mapping, services: list[tuple[str, str]]) -> list[str]:
    actions = sorted({route.name for route in mapping.routes(services).values() if route.kind == "action"})
    topics = [f"{action}/{leaf}" for action in actions for leaf in ACTION_TOPICS]
    return topics + [t for t in (mapping.world_topic, mapping.internal_topic, mapping.ping_topic,
                                 mapping.pong_topic) if t]


class Recorder(Child):
    def __init__(self, path: Path, argv: list[str], env: dict[str, str]):
        super().__init__("rosbag", argv, env, death_signal=signal.SIGINT, own_group=True)
        self.path = path


def start_recorder(folder: str, run: int, topics: list[str], env: dict[str, str], timeout_s: float) -> Recorder:
    """`rosbag record` of `topics` into folder/trace-RUN.bag, once the master lists it on every topic."""
    import roslib.packages  # ROS's own lookup, as the rosbag command does

    found = roslib.packages.find_node("rosbag", "record")
    if not found:
        raise ChildError("--rosbag records with Debian's rosbag, which is not installed: apt-get install python3-rosbag")
    path = Path(folder) / f"trace-{run}.bag"
    recorder = Recorder(path, [found[0], "--quiet", "-O", str(path), "__name:=untimely_record", *topics], env)
    master = xmlrpc.client.ServerProxy(env["ROS_MASTER_URI"])
    deadline = time.monotonic() + timeout_s
    while True:
        subscribers = {topic: nodes for topic, nodes in master.getSystemState("/untimely")[2][1]}
        if all("/untimely_record" in subscribers.get(topic, []) for topic in topics):
            return recorder
        problem = recorder.failure()
        if problem or time.monotonic() > deadline:
            recorder.stop()
            raise ChildError(problem or f"rosbag record did not subscribe within {timeout_s:g} s")
        time.sleep(0.1)


def stop_recorder(recorder: Recorder, timeout_s: float = 10.0) -> None:
    """SIGINT, as Ctrl-C: the recorder closes the bag (BAG.active becomes BAG) and exits."""
    time.sleep(DRAIN_S)
    if recorder.process.poll() is None:
        recorder.process.send_signal(signal.SIGINT)
    try:
        recorder.process.wait(timeout_s)
    except subprocess.TimeoutExpired:
        recorder.stop()


def recording_folder() -> str | None:
    return os.environ.get(ROSBAG_ENV) or None
