"""Cancels: a request of a service that the mapping's [cancels] table names is no goal of its own
but a cancel request (action_msgs/srv/CancelGoal), sent to the cancel_goal service of the action
serving the service it names; the cancel service needs no route (docs/ros2.md, "Cancels").

Which goal: the one its `goal` argument names (the request id, in this run, of a goal of that
service: the mission language's `cancel HANDLE` sends it), else the latest goal of that service,
whether that goal runs, waits for its goal response, or has ended. The cancel's response is the
request's final reply: its return code (ERROR_NONE: the goal is canceling; ERROR_REJECTED,
ERROR_UNKNOWN_GOAL_ID, ERROR_GOAL_TERMINATED: refused) through the mapping's cancel_codes. The
cancelled goal's own ending comes, as any goal's, with its result (a CANCELED status gives the
result's code, else the mapping's CANCELED code). A cancel before any goal of the service names a
goal id no server knows, so the server answers it (ERROR_UNKNOWN_GOAL_ID): no reply is invented.
`taken`: the server's introspection event of the cancel request, where it publishes one
(introspection.cancel_taken).
"""
from __future__ import annotations

import os

from action_msgs.srv import CancelGoal
from rclpy.action.client import ClientGoalHandle
from unique_identifier_msgs.msg import UUID

from harness.sut.roscommon.replies import Replies
from harness.errors import UntimelyError

RESPONSES = {getattr(CancelGoal.Response, name): name for name in
             ("ERROR_NONE", "ERROR_REJECTED", "ERROR_UNKNOWN_GOAL_ID", "ERROR_GOAL_TERMINATED")}


def send_cancel(adapter, rqst_id: int, canceller: str, args: dict) -> None:
    """The cancel of the goal `args` names (else the latest of the service `canceller` cancels),
    its response relayed as the final reply."""
    target = adapter.mapping.cancels[canceller]
    client = adapter.clients[adapter.routes[target].name]
    with adapter.lock:
        replies = adapter.replies
        goal_id = named_goal(adapter.sent_goals, rqst_id, canceller, target, args) if "goal" in args else \
            adapter.latest.get(target) or UUID(uuid=list(os.urandom(16)))
        adapter.cancelling.setdefault(goal_key(goal_id), []).append(rqst_id)
        future = ClientGoalHandle(client, goal_id, None).cancel_goal_async()
    future.add_done_callback(lambda f: _answered(adapter.mapping, replies, rqst_id, f))


def goal_key(goal_id) -> str:
    """How the adapter keys a goal id (unique_identifier_msgs/UUID) in its tables."""
    return bytes(goal_id.uuid).hex()


def named_goal(sent_goals: dict[int, tuple[str, object]], rqst_id: int, canceller: str, target: str, args: dict):
    """The goal id of the request `args["goal"]` names, a goal of `target` sent in this run."""
    goal = args["goal"]
    # a request id, which a script's argument of type float carries as 7.0
    whole = isinstance(goal, (int, float)) and not isinstance(goal, bool) and float(goal).is_integer()
    sent = sent_goals.get(int(goal)) if whole else None
    if sent is None or sent[0] != target:
        raise UntimelyError(f"request {rqst_id} ({canceller}) cancels goal = {goal!r}, which is no request of "
                            f"{target} sent in this run; name the request id of a goal of {target}")
    return sent[1]


def _answered(mapping, replies: Replies, rqst_id: int, future) -> None:
    if future.exception() is not None:
        replies.ended(rqst_id, f"a failed cancel ({future.exception()})", None)
        return
    name = RESPONSES.get(future.result().return_code, f"return code {future.result().return_code}")
    replies.ended(rqst_id, name, mapping.cancel_codes.get(name))

