"""Which servers publish their introspection, found in the graph once the node is up, and their
events of receiving a request relayed as `taken` replies (docs/ros2.md, "taken replies").

A server publishes introspection only when its node turned it on (rclpy's configure_introspection,
services from Jazzy on, actions from Kilted on; off by default, so a node written as the tutorials
write it publishes none). A route's event topic counts as the server's when a publisher of it
belongs to a node that offers the server's service (an action: its send_goal or cancel_goal):
the adapter's own clients publish on the same topic when a bag is recorded, and a client's events
say only that it sent. Only the events of those topics are relayed, so a `taken` reply always
comes from the server's own record of that request, and the hello names the services it may
come for (`taken_services`). Events name their request: a call by its sequence number, a goal by
its id (the event's contents), a cancel by the goal it cancels (cancels.py).
"""
from __future__ import annotations

import time

from rclpy.action import ActionServer
from service_msgs.msg import ServiceEventInfo

from harness.sut.ros2.cancels import goal_key

# Service introspection came with Jazzy (rclpy 7), action introspection with Kilted (rclpy 9).
ACTION_INTROSPECTION = hasattr(ActionServer, "configure_introspection")
SETTLE_S = 0.5  # discovery of the servers' event publishers, after their services are up
POLL_S = 0.05


def call_topic(name: str) -> str:
    return f"{name}/_service_event"


def goal_topic(name: str) -> str:
    return f"{name}/_action/send_goal/_service_event"


def cancel_topic(name: str) -> str:
    return f"{name}/_action/cancel_goal/_service_event"


def served_by(topic: str) -> str:
    """The service whose server publishes `topic`."""
    return topic.removesuffix("/_service_event")


def event_topics(adapter) -> dict[str, str]:
    """"module.Service" -> the topic of its server's events, where the distro has them."""
    topics = {qualified: call_topic(route.name) if route.kind == "service" else goal_topic(route.name)
              for qualified, route in adapter.routes.items() if route.kind == "service" or ACTION_INTROSPECTION}
    topics.update({qualified: cancel_topic(name) for qualified, name in adapter.cancelled.items()
                   if ACTION_INTROSPECTION})
    return topics


def subscribe(adapter, qos, group) -> None:
    """The servers' events of every route, as the distro has them; relayed only once their
    servers are found publishing them (`find`)."""
    handled = {}
    for qualified, topic in event_topics(adapter).items():
        handled.setdefault(topic, _handling(adapter, qualified))
    for topic, (event_class, handler) in handled.items():
        adapter.node.create_subscription(event_class, topic, handler, qos, callback_group=group)


def _handling(adapter, qualified: str):
    """The event class of a service's server's topic, and what relays its events."""
    if qualified in adapter.cancelled:
        action = adapter.cancelled[qualified]
        return adapter.types[action].Impl.CancelGoalService.Event, lambda event: cancel_taken(adapter, action, event)
    route = adapter.routes[qualified]
    kind = adapter.types[route.name]
    if route.kind == "service":
        return kind.Event, lambda event: call_taken(adapter, route.name, event)
    return kind.Impl.SendGoalService.Event, lambda event: goal_taken(adapter, route.name, event)


def find(adapter) -> list[str]:
    """Which servers publish their events (the node is up: a lifecycle node may turn them on when
    configured), relayed from now on; the "module.Service" whose requests may get a `taken`."""
    topics = event_topics(adapter)
    found = published(adapter.node, sorted(set(topics.values())))
    with adapter.lock:
        adapter.introspected = found
    return [qualified for qualified, topic in topics.items() if topic in found]


def published(node, topics: list[str], settle_s: float = SETTLE_S) -> set[str]:
    """Those of `topics` that a node offering their service publishes, looked for until all are
    found or `settle_s` has passed (a publisher is discovered apart from the services)."""
    deadline, found = time.monotonic() + settle_s, set()
    while True:
        found = {topic for topic in topics if _published_by_server(node, topic)}
        if found == set(topics) or time.monotonic() > deadline:
            return found
        time.sleep(POLL_S)


def _published_by_server(node, topic: str) -> bool:
    publishers = {_full(info.node_namespace, info.node_name) for info in node.get_publishers_info_by_topic(topic)}
    service = served_by(topic)
    return any(service in (name for name, _types in node.get_service_names_and_types_by_node(name, namespace))
               for name, namespace in node.get_node_names_and_namespaces()
               if _full(namespace, name) in publishers)


def _full(namespace: str, name: str) -> str:
    return f"{namespace.rstrip('/')}/{name}"


def call_taken(adapter, service: str, event) -> None:
    """The server's record of a call it received, named by its sequence number."""
    _relayed(adapter, call_topic(service), event,
             lambda: adapter.calls.pop((service, event.info.sequence_number), None))


def goal_taken(adapter, action: str, event) -> None:
    """The server's record of a goal request it received, with its contents: the goal id."""
    _relayed(adapter, goal_topic(action), event,
             lambda: adapter.goal_ids.get(goal_key(event.request[0].goal_id)) if event.request else None)


def cancel_taken(adapter, action: str, event) -> None:
    """The server's record of a cancel request it received, named by the goal it cancels."""
    def first_waiting() -> int | None:
        waiting = adapter.cancelling.get(goal_key(event.request[0].goal_info.goal_id)) if event.request else None
        return waiting.pop(0) if waiting else None
    _relayed(adapter, cancel_topic(action), event, first_waiting)


def _relayed(adapter, topic: str, event, request_named) -> None:
    """A `taken` reply for the request `request_named()` finds (under the adapter's lock; None: none
    of this run's), when the event is a server's receipt of it and its server publishes `topic`."""
    if event.info.event_type != ServiceEventInfo.REQUEST_RECEIVED or topic not in adapter.introspected:
        return
    with adapter.lock:
        rqst_id, replies = request_named(), adapter.replies
    if rqst_id is not None:
        replies.taken(rqst_id)
