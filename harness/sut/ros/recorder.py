"""A run's bag, recorded with Debian's `rosbag record` on the run's own master (docs/ros.md).

`run`/`campaign --rosbag DIR` put DIR in $UNTIMELY_ROSBAG; the launcher then records every topic
the mapping names (each action's goal, cancel, status, feedback and result, and the JSON topics)
to DIR/trace-ID.bag, ID being the trace id the bench's hello gives as `run`, so `import DIR`
judges what the middleware carried. The hello is answered only once every publisher of every
recorded topic (the adapter's goals, the node's statuses, results...) has the recorder among its
connections, as `rostopic info` would show it: a publisher sends only to the subscribers it has
accepted, so no goal can precede the recorder. It is stopped first, with SIGINT, on which it closes
the bag.
It is `rosbag record`'s own program (the `rosbag` command forks it and exits on SIGINT before it
has closed the bag), in a process group of its own, as the bench kills the launcher's group
two seconds after `bye`, and it gets SIGINT, not SIGKILL, when the launcher dies: the bag is
closed whatever happens to the launcher, and the recorder exits then. ROS 1 services are not
topics: a bag cannot hold their calls.
"""
from __future__ import annotations

import signal
import subprocess
import time
import xmlrpc.client
from pathlib import Path

from harness.sut.roscommon.mapping import Mapping
from harness.errors import ChildError
from harness.sut.processes import Child

ACTION_TOPICS = ("goal", "cancel", "status", "feedback", "result")
RECORDER_NODE = "untimely_record"  # its node name; the master and the publishers say "/untimely_record"
CALLER = "/untimely"  # our caller id in XML-RPC calls to the master and the nodes
DRAIN_S = 0.3  # the last result reached the adapter; the recorder, another subscriber, gets it as soon


def recorded_topics(mapping: Mapping, services: list[tuple[str, str]]) -> list[str]:
    actions = sorted({route.name for route in mapping.routes(services).values() if route.kind == "action"})
    topics = [f"{action}/{leaf}" for action in actions for leaf in ACTION_TOPICS]
    return topics + [t for t in (mapping.world_topic, mapping.internal_topic, mapping.ping_topic,
                                 mapping.pong_topic) if t]


class RosbagRecorder(Child):
    def __init__(self, path: Path, argv: list[str], env: dict[str, str]):
        super().__init__("rosbag", argv, env, death_signal=signal.SIGINT, own_group=True)
        self.path = path


def start_recorder(folder: str, run: int, topics: list[str], env: dict[str, str]) -> RosbagRecorder:
    """`rosbag record` of `topics` into folder/trace-RUN.bag; it records once wait_connected says so."""
    import roslib.packages  # ROS's own lookup, as the rosbag command does

    found = roslib.packages.find_node("rosbag", "record")
    if not found:
        raise ChildError("--rosbag records with Debian's rosbag, which is not installed: apt-get install python3-rosbag")
    path = Path(folder) / f"trace-{run}.bag"
    return RosbagRecorder(path, [found[0], "--quiet", "-O", str(path), f"__name:={RECORDER_NODE}", *topics], env)


def unconnected(topics: list[str], master) -> list[str]:
    """"TOPIC from NODE" for each publisher of a recorded topic that has not accepted the recorder's
    connection yet, and "TOPIC (no publisher)" for a topic nobody publishes, from the master's
    system state and each publishing node's bus info (as `rostopic info` reads them)."""
    publishers = dict(master.getSystemState(CALLER)[2][0])
    buses: dict[str, list] = {}
    missing = []
    for topic in topics:
        nodes = publishers.get(topic, [])
        if not nodes:
            missing.append(f"{topic} (no publisher)")
        for node in nodes:
            if node not in buses:
                buses[node] = xmlrpc.client.ServerProxy(master.lookupNode(CALLER, node)[2]).getBusInfo(CALLER)[2]
            # getBusInfo rows: connection id, the subscriber's node, direction ("o": we publish), transport, topic...
            if not any(row[1] == f"/{RECORDER_NODE}" and row[2] == "o" and row[4] == topic for row in buses[node]):
                missing.append(f"{topic} from {node}")
    return missing


def wait_connected(recorder: RosbagRecorder, topics: list[str], env: dict[str, str], timeout_s: float) -> None:
    """Block until every publisher of every topic has accepted the recorder, so that the first goal
    is in the bag; called once the node and the adapter have all their publishers up."""
    master = xmlrpc.client.ServerProxy(env["ROS_MASTER_URI"])
    deadline = time.monotonic() + timeout_s
    while missing := unconnected(topics, master):
        problem = recorder.failure()
        if problem or time.monotonic() > deadline:  # the launcher's teardown stops the recorder
            raise ChildError(problem or
                             f"rosbag record was not connected within {timeout_s:g} s to {', '.join(missing)}; "
                             "the machine may be overloaded: run fewer --jobs, or raise the launcher's "
                             "--startup-timeout in the SUT's command (suts.toml)")
        time.sleep(0.05)


def stop_recorder(recorder: RosbagRecorder, timeout_s: float = 10.0) -> None:
    """SIGINT, as Ctrl-C: the recorder closes the bag (BAG.active becomes BAG) and exits."""
    time.sleep(DRAIN_S)
    if recorder.process.poll() is None:
        recorder.process.send_signal(signal.SIGINT)
    try:
        recorder.process.wait(timeout_s)
    except subprocess.TimeoutExpired:
        recorder.stop()
