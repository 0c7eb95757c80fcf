"""Cancels: a request of a service that the mapping's [cancels] table names is no goal of its own
but a cancel request (action_msgs/srv/CancelGoal) of the latest goal this run sent for the service
it names, whether that goal runs, waits for its goal response, or has ended (docs/ros2.md).

The cancel's response is the request's final reply: its return code (ERROR_NONE: the goal is
canceling; ERROR_REJECTED, ERROR_UNKNOWN_GOAL_ID, ERROR_GOAL_TERMINATED: refused) through the
mapping's cancel_codes. The cancelled goal's own ending comes, as any goal's, with its result (a
CANCELED status gives the result's code, else the mapping's CANCELED code). A cancel before any goal
of the service names a goal id no server knows, so the server answers it (ERROR_UNKNOWN_GOAL_ID):
no reply is invented. `taken` (Kilted): the server's introspection event of the cancel request.
"""
from __future__ import annotations

import os

from action_msgs.srv import CancelGoal
from rclpy.action.client import ClientGoalHandle
from service_msgs.msg import ServiceEventInfo
from unique_identifier_msgs.msg import UUID

from harness.sut.ros.replies import Replies
from harness.errors import UntimelyError

RESPONSES = {getattr(CancelGoal.Response, name): name for name in
             ("ERROR_NONE", "ERROR_REJECTED", "ERROR_UNKNOWN_GOAL_ID", "ERROR_GOAL_TERMINATED")}


def cancel_targets(mapping, routes: dict) -> dict[str, str]:
    """"module.Service" cancelled -> its action's name, checking that each is an action route of
    the interface."""
    targets = {}
    for canceller, target in mapping.cancels.items():
        route = routes.get(target)
        if canceller not in routes or route is None or route.kind != "action":
            raise UntimelyError(f"{mapping.path}: cancels: {canceller} = {target}: both must be services of the "
                                "interface, the second mapped to an action; fix the [cancels] table")
        targets[target] = route.name
    return targets


def send_cancel(adapter, rqst_id: int, target: str) -> None:
    """The cancel of `target`'s latest goal of this run, its response relayed as the final reply."""
    client = adapter.clients[adapter.routes[target].name]
    with adapter.lock:
        replies = adapter.replies
        goal_id = adapter.latest.get(target) or UUID(uuid=list(os.urandom(16)))
        adapter.cancelling.setdefault(bytes(goal_id.uuid).hex(), []).append(rqst_id)
        future = ClientGoalHandle(client, goal_id, None).cancel_goal_async()
    future.add_done_callback(lambda f: _answered(adapter.mapping, replies, rqst_id, f))


def _answered(mapping, replies: Replies, rqst_id: int, future) -> None:
    if future.exception() is not None:
        replies.ended(rqst_id, f"a failed cancel ({future.exception()})", None)
        return
    name = RESPONSES.get(future.result().return_code, f"return code {future.result().return_code}")
    replies.ended(rqst_id, name, mapping.cancel_codes.get(name))


def cancel_taken(adapter, event) -> None:
    """The server's record of a cancel request it received (Kilted's action introspection)."""
    if event.info.event_type == ServiceEventInfo.REQUEST_RECEIVED and event.request:
        with adapter.lock:
            waiting = adapter.cancelling.get(bytes(event.request[0].goal_info.goal_id.uuid).hex())
            rqst_id, replies = (waiting.pop(0) if waiting else None), adapter.replies
        if rqst_id is not None:
            replies.taken(rqst_id)
