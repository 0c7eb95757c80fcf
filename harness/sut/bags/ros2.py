"""A ROS 2 rosbag2 bag (MCAP or SQLite3) as one trace, read raw (ros2_types.py says why).

Per action NAME of the mapping: NAME/_action/status (a goal's first appearance is its request
when introspection is off; a terminal status is its final when no result was recorded),
NAME/_action/feedback (the first before the final is the intermediate reply) and, where
recorded, the introspection of its services: NAME/_action/send_goal/_service_event (the request,
its goal's fields as arguments; a response `accepted = false` is a REJECTED final) and
NAME/_action/get_result/_service_event (the final: status and result mapped to a catalogue code
as the live adapter does). Per ROS service NAME: NAME/_service_event, whose response gives the
final reply (Route.response_code). Events of one call are paired by the client GID's prefix (_participant) and sequence
number; the client's side (request sent, response received) is the observed one when recorded,
else the server's.

The SUT's own clock (timeline.sut_rows) comes from what the server stamps: a request at the earlier of
its REQUEST_RECEIVED event's stamp and its goal's accept stamp (goal_info.stamp in a status
list); a final at its RESPONSE_SENT event's stamp (send_goal's for a rejected goal, get_result's or
the call's otherwise). Status arrays and feedback messages carry no stamp of their own, so neither
a terminal status nor a feedback has an instant on the SUT's clock.
"""
from __future__ import annotations

from typing import NamedTuple

from rosbags.rosbag2 import Reader

from harness.sut.bags.ros2_types import register, typestore
from harness.errors import UntimelyError
from harness.sut.bags.routes import Routes, check_type
from harness.sut.bags.timeline import BagTimeline, seconds, stamped

STATUS = {4: "SUCCEEDED", 5: "PREEMPTED", 6: "ABORTED"}  # action_msgs/GoalStatus terminal codes
REQUEST_SENT, REQUEST_RECEIVED, RESPONSE_SENT, RESPONSE_RECEIVED = range(4)
INTROSPECTION = ("ros2 service introspection is off: turn it on in the client or server "
                 "(configure_introspection, ServiceIntrospectionState.CONTENTS) and record the "
                 "_service_event topics too")


def _topics(routes: Routes) -> dict[str, tuple[str, str]]:
    """Topic -> (what it carries, the action's or service's name)."""
    topics = {}
    for name in routes.named("action"):
        for leaf, what in (("_action/status", "status"), ("_action/feedback", "feedback"),
                           ("_action/send_goal/_service_event", "send_goal"),
                           ("_action/get_result/_service_event", "get_result")):
            topics[f"{name}/{leaf}"] = (what, name)
    for name in routes.named("service"):
        topics[f"{name}/_service_event"] = ("call", name)
    return topics


def _key(uuid) -> bytes:
    return bytes(bytearray(uuid.uuid))


class CallEvents(NamedTuple):
    """One call's events: the observed instants (the client's when recorded, else the server's), and
    the server's own stamps (the SUT's clock) where its side was recorded."""
    key: tuple  # the client's participant (GID prefix), sequence number
    sent: float  # receive time of the request event
    request: object
    answered: float | None  # receive time of the response event
    response: object | None
    sent_s: float  # the request event's stamp: numbers the requests
    received_stamp: float | None  # REQUEST_RECEIVED's stamp: the server got the request
    answer_stamp: float | None  # RESPONSE_SENT's stamp: the server sent its response


def _participant(gid) -> bytes:
    """The GUID prefix of a client's GID: its participant. Jazzy's rmw_fastrtps stamps a client's own
    events with one entity of the client and the server's with another (its request writer), so
    only the prefix and the sequence number pair them; Kilted stamps both with the writer."""
    return bytes(bytearray(gid))[:12]


def _calls(events: list) -> list[CallEvents]:
    """Each call, its events paired by the client's participant and sequence number."""
    calls: dict[tuple, dict[int, tuple]] = {}
    for received, event in events:
        pair = calls.setdefault((_participant(event.info.client_gid), event.info.sequence_number), {})
        pair.setdefault(event.info.event_type, (received, event))
    paired = []
    for key, pair in calls.items():
        sent = pair.get(REQUEST_SENT) or pair.get(REQUEST_RECEIVED)
        answered = pair.get(RESPONSE_RECEIVED) or pair.get(RESPONSE_SENT)
        if sent and sent[1].request:
            server = {kind: stamped(pair[kind][1].info.stamp)
                      for kind in (REQUEST_RECEIVED, RESPONSE_SENT) if kind in pair}
            paired.append(CallEvents(key, sent[0], sent[1].request[0], answered[0] if answered else None,
                               answered[1].response[0] if answered and answered[1].response else None,
                               seconds(sent[1].info.stamp), server.get(REQUEST_RECEIVED), server.get(RESPONSE_SENT)))
    return paired


def _send_goals(timeline: BagTimeline, routes: Routes, carried, events) -> None:
    route = carried[0][1]
    for call in _calls(events):
        target = routes.target(carried, call.request.goal)
        if target is not None:
            key = _key(call.request.goal_id)
            timeline.goal(key, call.sent, *target, sent_s=call.sent_s)
            timeline.held(key, call.received_stamp)
            if call.response is not None and not call.response.accepted:
                timeline.final(key, call.answered, routes.final_code(route, "REJECTED", None, ""), call.answer_stamp)


def _service_calls(timeline: BagTimeline, routes: Routes, carried, events) -> None:
    for call in _calls(events):
        key = (carried[0][1].name, *call.key)  # one client may call several services, each counting from 1
        timeline.request(key, call.sent, *routes.target(carried, call.request), sent_s=call.sent_s)
        timeline.held(key, call.received_stamp)
        if call.response is not None:
            timeline.final(key, call.answered, carried[0][1].response_code(call.response, routes.catalogue),
                           call.answer_stamp)


def _statuses(timeline: BagTimeline, routes: Routes, carried, events) -> None:
    route = carried[0][1]
    for received, message in events:
        for status in message.status_list:
            key, accepted = _key(status.goal_info.goal_id), stamped(status.goal_info.stamp)
            if not route.generic:  # a generic goal's service is in its goal only
                timeline.request(key, received, carried[0][0], None, sent_s=seconds(status.goal_info.stamp))
            timeline.held(key, accepted)  # the server's accept instant
            if status.status in STATUS:  # a status array has no stamp: no SUT instant for the change
                timeline.status_final(key, received, routes.final_code(route, STATUS[status.status], None, ""))


def _results(timeline: BagTimeline, routes: Routes, carried, events) -> None:
    for call in _calls(events):
        response = call.response
        if response is not None and response.status in STATUS:
            timeline.final(_key(call.request.goal_id), call.answered,
                           routes.final_code(carried[0][1], STATUS[response.status], response.result, ""),
                           call.answer_stamp)


def _feedback(timeline: BagTimeline, routes: Routes, carried, events) -> None:
    for received, message in events:  # a FeedbackMessage has no stamp: no SUT instant
        timeline.intermediate(_key(message.goal_id), received)


# What each kind of topic carries: a type name's end, or the full type name.
TYPES = {"status": "action_msgs/msg/GoalStatusArray", "feedback": "_FeedbackMessage", "send_goal": "_SendGoal_Event",
         "get_result": "_GetResult_Event", "call": "_Event"}
# In this order: requests before what refers to them.
HANDLERS = {"send_goal": _send_goals, "call": _service_calls, "status": _statuses, "get_result": _results,
            "feedback": _feedback}


def read_ros2(folder, routes: Routes) -> tuple[BagTimeline, list[str]]:
    topics, store = _topics(routes), typestore()
    by_kind: dict[tuple[str, str], list] = {}
    with Reader(folder) as reader:
        wanted = [c for c in reader.connections if c.topic in topics]
        if not wanted:
            raise UntimelyError(f"no topic of the mapping {routes.mapping.path} in this bag; it records "
                                f"{', '.join(sorted({c.topic for c in reader.connections})) or 'nothing'}")
        for connection in wanted:
            what = topics[connection.topic][0]
            check_type(connection, TYPES[what], f"a {what} message")
            register(store, connection.msgtype, connection.msgdef.data)
        timeline = BagTimeline(reader.start_time * 1e-9)
        for connection, received_ns, raw in reader.messages(connections=wanted):
            by_kind.setdefault(topics[connection.topic], []).append(
                (received_ns * 1e-9, store.deserialize_cdr(raw, connection.msgtype)))
    named = {**routes.named("action"), **routes.named("service")}
    for (what, name), events in sorted(by_kind.items(), key=lambda item: list(HANDLERS).index(item[0][0])):
        HANDLERS[what](timeline, routes, named[name], events)
    return timeline, _lacking(routes, {what for what, _ in by_kind})


def _lacking(routes: Routes, recorded: set[str]) -> list[str]:
    """Notes on what the bag lacks of the mapping."""
    notes = []
    if routes.named("action") and "send_goal" not in recorded:
        notes.append("no goal introspection: requests come from the status topic, without arguments, and "
                     f"rejected goals are missing ({INTROSPECTION})")
    services = routes.named("service")
    if services and "call" not in recorded:
        notes.append(f"no call of the ROS services {', '.join(sorted(services))}: {INTROSPECTION}")
    return notes
