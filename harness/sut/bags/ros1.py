"""A ROS 1 .bag as one trace: the actionlib topics of every action the mapping names.

Per action namespace NS: NS/goal (the request; the goal's goal_id.stamp is the client's send
instant, which numbers the requests), NS/feedback (the first the server sent before the result,
by their header stamps, is the intermediate reply), NS/result (the final: GoalStatus and the
result's text mapped to a catalogue code as the live adapter does), NS/status (the final of a
goal whose result the bag lost). Goals are paired by goal_id.id; NS/cancel changes nothing by
itself (the preempted goal's result says how it ended). The server's header stamps on status,
feedback and result give the SUT's own clock (timeline.sut_rows). ROS 1 services are not topics: a bag
cannot hold them.
"""
from __future__ import annotations

from pathlib import Path

from rosbags.highlevel import AnyReader

from harness.errors import UntimelyError
from harness.sut.bags.routes import Routes, check_type
from harness.sut.bags.timeline import BagTimeline, seconds, stamped

STATUS = ("PENDING", "ACTIVE", "PREEMPTED", "SUCCEEDED", "ABORTED", "REJECTED", "PREEMPTING", "RECALLING",
          "RECALLED", "LOST")
# What each topic of an action namespace carries: a type name's end, or the full type name.
TYPES = {"goal": "ActionGoal", "feedback": "ActionFeedback", "result": "ActionResult",
         "status": "actionlib_msgs/msg/GoalStatusArray"}
TERMINAL = {"PREEMPTED", "SUCCEEDED", "ABORTED", "REJECTED", "RECALLED"}


def read_ros1(path: Path, routes: Routes) -> tuple[BagTimeline, list[str]]:
    """The bag's timeline, and notes on what it cannot hold."""
    actions = routes.named("action")
    with AnyReader([path]) as reader:
        topics = {}
        for connection in reader.connections:
            namespace, _, leaf = connection.topic.rpartition("/")
            if namespace in actions and leaf in ("goal", "feedback", "result", "status"):
                topics.setdefault(connection.topic, []).append(connection)
        if not topics:
            raise UntimelyError(f"no actionlib topic of the mapping {routes.mapping.path} in this bag; it records "
                             f"{', '.join(sorted({c.topic for c in reader.connections})) or 'nothing'}")
        timeline = BagTimeline(reader.start_time * 1e-9)
        wanted = [c for connections in topics.values() for c in connections]
        for connection in wanted:
            leaf = connection.topic.rpartition("/")[2]
            check_type(connection, TYPES[leaf], f"an actionlib {leaf}")
        for connection, received_ns, raw in reader.messages(connections=wanted):
            namespace, _, leaf = connection.topic.rpartition("/")
            message, received = reader.deserialize(raw, connection.msgtype), received_ns * 1e-9
            carried = actions[namespace]
            if leaf == "goal":
                target = routes.target(carried, message.goal)
                if target is not None:
                    timeline.goal(message.goal_id.id, received, *target, sent_s=seconds(message.goal_id.stamp))
            elif leaf == "feedback":
                timeline.intermediate(message.status.goal_id.id, received, _stamp(message))
            elif leaf == "result":
                status = message.status
                route = carried[0][1]
                code = routes.final_code(route, _status(status, connection.topic), message.result, status.text)
                timeline.final(status.goal_id.id, received, code, _stamp(message))
            else:
                for status in message.status_list:
                    timeline.held(status.goal_id.id, _stamp(message))
                    name = _status(status, connection.topic)
                    if name in TERMINAL:
                        code = routes.final_code(carried[0][1], name, None, status.text)
                        timeline.status_final(status.goal_id.id, received, code, _stamp(message))
    services = routes.named("service")
    notes = [f"ROS 1 services are no topics, so a bag holds no call of {', '.join(sorted(services))}"] if services else []
    return timeline, notes


def _status(status, topic: str) -> str:
    """The name of an actionlib GoalStatus code."""
    if not 0 <= status.status < len(STATUS):
        raise UntimelyError(f"topic {topic}: goal {status.goal_id.id!r} has status {status.status}, which is no "
                            f"actionlib GoalStatus (0 to {len(STATUS) - 1}, {', '.join(STATUS)}); the bag is not "
                            "actionlib's")
    return STATUS[status.status]


def _stamp(message) -> float | None:
    """The header stamp the server (the SUT) gave a message, in seconds; None if it left it zero."""
    return stamped(message.header.stamp)
