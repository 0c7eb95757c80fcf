"""A ROS 2 run's traffic recorded to an MCAP bag: raw subscriptions (the CDR bytes as they came)
and `rosbags`' writer, no rosbag2 needed (docs/ros2.md, "Recording").

It runs in a distro's environment (environment.py), in the adapter's process or as one of its own:

    python -m harness.sut.ros2.recorder BAG --action /dala/goto=untimely_msgs/action/Request \\
        --service /dala/set=untimely_msgs/srv/Call [--wait 10]

records until SIGINT or SIGTERM, then until nothing has come for DRAIN_S, and closes the bag; it
prints "recording" once every topic that has publishers at all has one discovered. Per action NAME it records NAME/_action/status and
NAME/_action/feedback, and on Kilted (ROS_DISTRO), whose action servers and clients have
introspection, NAME/_action/{send_goal,get_result,cancel_goal}/_service_event; per service NAME,
NAME/_service_event. An introspection event is written at its own stamp (the instant the side
that published it sent or received the request or response), anything else at its arrival. Each
connection stores the definition rosbag2 would (a message's .msg text
with those it uses; a service's or action's .srv or .action text for its derived types), found
under AMENT_PREFIX_PATH, and the type hash its publisher announces, so the project's bag reader
(`untimely import`) and rosbag2 read it.
"""
from __future__ import annotations

import argparse
import importlib
import os
import re
import signal
import struct
import threading
import time
from functools import partial
from pathlib import Path

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosbags.rosbag2 import StoragePlugin, Writer

INTROSPECTED_ACTIONS = {"jazzy": False, "kilted": True}  # rclpy's action introspection came in Kilted
DERIVED = re.compile(r"(\w+)/(srv|action)/(\w+?)(_SendGoal|_GetResult|_CancelGoal)?(_Request|_Response|_Event|_Goal|_Result|_Feedback|_FeedbackMessage)?")
SEPARATOR = "=" * 80
# After a stop, the recorder writes on until nothing has come for this long: what the peers published
# just before the stop may still be on its way (measured: a loaded machine's bag lacked a whole run).
DRAIN_S = 0.5


def action_topics(name: str, action_type: str, distro: str | None = None) -> list[tuple[str, str]]:
    """(topic, type) of what an action carries; its services' introspection where the distro has it."""
    topics = [(f"{name}/_action/status", "action_msgs/msg/GoalStatusArray"),
              (f"{name}/_action/feedback", f"{action_type}_FeedbackMessage")]
    if INTROSPECTED_ACTIONS.get(distro or os.environ.get("ROS_DISTRO", ""), False):
        topics += [(f"{name}/_action/send_goal/_service_event", f"{action_type}_SendGoal_Event"),
                   (f"{name}/_action/get_result/_service_event", f"{action_type}_GetResult_Event"),
                   (f"{name}/_action/cancel_goal/_service_event", "action_msgs/srv/CancelGoal_Event")]
    return topics


def event_stamp_ns(raw: bytes) -> int:
    """The stamp of a service event from its CDR bytes: service_msgs/ServiceEventInfo is the event's
    first field, its `uint8 event_type` then `builtin_interfaces/Time stamp` (int32 sec, uint32
    nanosec, aligned to 4), after the 4-byte encapsulation header whose second byte says the
    endianness (1: little)."""
    sec, nanosec = struct.unpack_from("<iI" if raw[1] & 1 else ">iI", raw, 8)
    return sec * 1_000_000_000 + nanosec


def service_topics(name: str, service_type: str) -> list[tuple[str, str]]:
    return [(f"{name}/_service_event", f"{service_type}_Event")]


def message_class(msgtype: str):
    """The Python class of `pkg/kind/Name`; rosidl nests a service's or action's derived types in
    its class (Call.Event, Request.Impl.FeedbackMessage, Request.Impl.SendGoalService.Event)."""
    package, kind, name = msgtype.split("/")
    module = importlib.import_module(f"{package}.{kind}")
    if kind == "msg":
        return getattr(module, name)
    _, _, base, service, part = DERIVED.fullmatch(msgtype).groups()
    owner = getattr(module, base)
    if service:
        owner = getattr(owner.Impl, f"{service[1:]}Service")
    elif part == "_FeedbackMessage":
        owner = owner.Impl
    return getattr(owner, part[1:]) if part else owner


def _interface_file(package: str, kind: str, name: str) -> Path:
    for prefix in filter(None, os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep)):
        path = Path(prefix) / "share" / package / kind / f"{name}.{kind}"
        if path.is_file():
            return path
    raise FileNotFoundError(f"{package}/{kind}/{name}.{kind} is in no prefix of AMENT_PREFIX_PATH")


def definition(msgtype: str) -> str:
    """The definition rosbag2 stores for `msgtype`: the .srv/.action text of a derived type, else the
    .msg text followed by that of every message it uses, each under a `MSG: pkg/msg/Name` line."""
    package, kind, name = msgtype.split("/")
    if kind != "msg":
        base = DERIVED.fullmatch(msgtype).group(3)
        return _interface_file(package, kind, base).read_text()
    texts, todo = {}, [(package, name)]
    while todo:
        package, name = todo.pop()
        if f"{package}/msg/{name}" not in texts:
            text = _interface_file(package, "msg", name).read_text()
            texts[f"{package}/msg/{name}"] = text
            todo += _used(package, text)
    first, *rest = texts.items()
    return first[1] + "".join(f"\n{SEPARATOR}\nMSG: {used}\n{text}" for used, text in rest)


def _used(package: str, text: str) -> list[tuple[str, str]]:
    """(package, name) of each message a .msg text's fields use (a bare name is of its own package)."""
    kinds = [line.split()[0] for line in (raw.split("#")[0] for raw in text.splitlines())
             if line.strip() and "=" not in line]
    used = []
    for kind in kinds:
        kind = kind.split("[")[0].split("<")[0]
        if "/" in kind:
            used.append((kind.split("/")[0], kind.split("/")[-1]))
        elif kind[:1].isupper():
            used.append((package, kind))
    return used


class McapRecorder:
    """Records `topics` [(topic, type)] into the MCAP bag `path` from a node of its own, `node`,
    which the caller spins (or `spin()` does); `close()` ends the node and closes the bag."""

    def __init__(self, path: Path, topics: list[tuple[str, str]]):
        self.topics, self.lock = dict(topics), threading.Lock()
        self.writer = Writer(Path(path), version=9, storage_plugin=StoragePlugin.MCAP)
        self.writer.open()
        self.connections: dict[str, object] = {}
        self.written = 0
        self.node = rclpy.create_node("untimely_record")
        self.subscriptions = {}
        for topic, msgtype in self.topics.items():
            durable = DurabilityPolicy.TRANSIENT_LOCAL if topic.endswith("/_action/status") else DurabilityPolicy.VOLATILE
            qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE, durability=durable)
            self.subscriptions[topic] = self.node.create_subscription(
                message_class(msgtype), topic, partial(self._write, topic), qos, raw=True)

    def _write(self, topic: str, raw: bytes) -> None:
        # An introspection event's instant is its own stamp, not its arrival here: events of separate
        # topics arrive some milliseconds out of the order they happened in (docs/ros2.md, "Recording").
        instant_ns = event_stamp_ns(raw) if topic.endswith("/_service_event") else time.time_ns()
        with self.lock:
            if self.writer is None:
                return
            if topic not in self.connections:
                self.connections[topic] = self._connection(topic)
            self.writer.write(self.connections[topic], instant_ns, raw)
            self.written += 1

    def _connection(self, topic: str):
        """The topic's connection, typed by the hash its publisher announces."""
        msgtype = self.topics[topic]
        hashes = [str(info.topic_type_hash) for info in self.node.get_publishers_info_by_topic(topic)]
        return self.writer.add_connection(topic, msgtype, msgdef=definition(msgtype),
                                          rihs01=hashes[0] if hashes else "RIHS01_" + "0" * 64)

    def wait_for_publishers(self, timeout_s: float) -> list[str]:
        """Waits until every topic has a publisher in the graph and matched to its subscription (one
        in the graph may not be matched yet, and what it publishes until then is not received);
        returns the topics that still have none."""
        deadline = time.monotonic() + timeout_s
        while True:
            missing = [t for t, sub in self.subscriptions.items()
                       if not self.node.count_publishers(t) or not sub.get_publisher_count()]
            if not missing or time.monotonic() > deadline:
                return missing
            rclpy.spin_once(self.node, timeout_sec=0.05)

    def drain(self) -> None:
        """Spins until nothing has come for DRAIN_S."""
        written, quiet_since = self.written, time.monotonic()
        while time.monotonic() - quiet_since < DRAIN_S:
            rclpy.spin_once(self.node, timeout_sec=0.05)
            if self.written != written:
                written, quiet_since = self.written, time.monotonic()

    def close(self) -> None:
        with self.lock:
            writer, self.writer = self.writer, None
        if writer is not None:
            self.node.destroy_node()
            writer.close()


def _pairs(values: list[str], option: str) -> list[tuple[str, str]]:
    pairs = [value.partition("=")[::2] for value in values]
    for value, (name, kind) in zip(values, pairs):
        if not name.startswith("/") or kind.count("/") != 2:
            raise SystemExit(f"{option} {value!r}: give /NAME=package/kind/Type, "
                             f"e.g. {option} /dala/goto=untimely_msgs/{option[2:]}/Request")
    return pairs


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m harness.sut.ros2.recorder")
    parser.add_argument("bag", type=Path)
    parser.add_argument("--action", action="append", default=[], metavar="/NAME=pkg/action/Type")
    parser.add_argument("--service", action="append", default=[], metavar="/NAME=pkg/srv/Type")
    parser.add_argument("--wait", type=float, default=10.0, help="seconds to wait for publishers")
    args = parser.parse_args(argv)
    topics = ([t for name, kind in _pairs(args.action, "--action") for t in action_topics(name, kind)]
              + [t for name, kind in _pairs(args.service, "--service") for t in service_topics(name, kind)])
    rclpy.init()
    stop = threading.Event()
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda *_: stop.set())
    recorder = McapRecorder(args.bag, topics)
    try:
        recorder.wait_for_publishers(args.wait)
        print("recording", flush=True)
        while not stop.is_set():
            rclpy.spin_once(recorder.node, timeout_sec=0.05)
        recorder.drain()
    except ExternalShutdownException:
        pass
    finally:
        recorder.close()
        rclpy.try_shutdown()


if __name__ == "__main__":
    main()
