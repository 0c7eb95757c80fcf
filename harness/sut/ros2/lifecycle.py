"""The adapter's side of a lifecycle node (rclpy.lifecycle): its transitions, driven through
NODE/change_state, each awaited (docs/ros2.md, "Run after run").

rmw_fastrtps drops a service's response when the server has not yet matched the client's response
reader within 100 ms ("failed to send response (timeout): client will not receive response"),
which a loaded machine makes likely right after discovery: measured once in a focused campaign at
load 20, a node's first `configure` went unanswered and its slot waited 60 s. A transition is not
idempotent (one sent twice is an invalid transition, which kills the executor of Jazzy's rclpy,
rclpy#1209), so an unanswered one is not simply sent again: NODE/get_state (idempotent, asked
until answered) says whether it happened, and it is sent again only from its starting state (a
transition still under way is waited for).
"""
from __future__ import annotations

import threading
import time

from lifecycle_msgs.msg import State, Transition
from lifecycle_msgs.srv import ChangeState, GetState

from harness.errors import UntimelyError

BRING_UP = (Transition.TRANSITION_CONFIGURE, Transition.TRANSITION_ACTIVATE)
RESET = (Transition.TRANSITION_DEACTIVATE, Transition.TRANSITION_CLEANUP) + BRING_UP
# The state each transition starts from, and the one it ends in when it succeeds.
STATES = {Transition.TRANSITION_CONFIGURE: (State.PRIMARY_STATE_UNCONFIGURED, State.PRIMARY_STATE_INACTIVE),
          Transition.TRANSITION_ACTIVATE: (State.PRIMARY_STATE_INACTIVE, State.PRIMARY_STATE_ACTIVE),
          Transition.TRANSITION_DEACTIVATE: (State.PRIMARY_STATE_ACTIVE, State.PRIMARY_STATE_INACTIVE),
          Transition.TRANSITION_CLEANUP: (State.PRIMARY_STATE_INACTIVE, State.PRIMARY_STATE_UNCONFIGURED)}
# The transitions that take a node in each primary state back to unconfigured, the state a fresh
# node starts in (a mission that drives the lifecycle itself begins there).
TO_UNCONFIGURED = {State.PRIMARY_STATE_UNCONFIGURED: (),
                   State.PRIMARY_STATE_INACTIVE: (Transition.TRANSITION_CLEANUP,),
                   State.PRIMARY_STATE_ACTIVE: (Transition.TRANSITION_DEACTIVATE, Transition.TRANSITION_CLEANUP)}
ANSWER_S = 5.0  # a response later than this is taken as lost (a resent transition must not overtake a slow one)


class Lifecycle:
    def __init__(self, node, name: str, group):
        self.name = name
        self.change = node.create_client(ChangeState, f"{name}/change_state", callback_group=group)
        self.state = node.create_client(GetState, f"{name}/get_state", callback_group=group)

    def clients(self) -> list:
        return [self.change, self.state]

    def transition(self, transitions: tuple[int, ...], timeout_s: float, answer_s: float = ANSWER_S) -> None:
        """Drive the node through `transitions`, each done before the next."""
        deadline = time.monotonic() + timeout_s
        for transition in transitions:
            while True:
                answer = _call(self.change, ChangeState.Request(transition=Transition(id=transition)), answer_s)
                if answer is not None and not answer.success:
                    raise UntimelyError(f"the node {self.name} refused lifecycle transition {transition}")
                if answer is not None or self._done(transition, deadline, timeout_s, answer_s):
                    break

    def unconfigure(self, timeout_s: float) -> str | None:
        """Take the node back to unconfigured from the primary state a run left it in, each call
        answered within `timeout_s` (a node that answers later, e.g. its executor busy with a goal,
        is not worth the wait: a fresh one starts sooner); why it cannot be (finalized, a transition
        refused, no state said), or None once it is there."""
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            answer = _call(self.state, GetState.Request(), timeout_s)
            state = answer.current_state if answer is not None else None
            if state is not None and state.id in TO_UNCONFIGURED:
                try:
                    self.transition(TO_UNCONFIGURED[state.id], timeout_s, answer_s=timeout_s)
                except UntimelyError as e:
                    return str(e)
                return None
            if state is not None and state.id == State.PRIMARY_STATE_FINALIZED:
                return f"the node {self.name} is finalized (shut down)"
            time.sleep(0.05)  # unanswered, or a transition still under way
        return f"the node {self.name} said no primary state within {timeout_s:g} s"

    def _done(self, transition: int, deadline: float, timeout_s: float, answer_s: float) -> bool:
        """Whether an unanswered transition happened (the node is in its end state) or not (in its
        start state: send it again), asking NODE/get_state until it says one or the other."""
        start, end = STATES[transition]
        while time.monotonic() < deadline:
            answer = _call(self.state, GetState.Request(), answer_s)
            state = answer.current_state.id if answer is not None else None
            if state in (start, end):
                return state == end
            time.sleep(0.05)  # unanswered, or a transition still under way
        raise UntimelyError(f"the node {self.name} did not complete lifecycle transition {transition} "
                            f"within {timeout_s:g} s")


def _call(client, request, timeout_s: float):
    """The response of one call, or None if none came within `timeout_s`."""
    future = client.call_async(request)
    done = threading.Event()
    future.add_done_callback(lambda _f: done.set())
    if not done.wait(timeout_s):
        client.remove_pending_request(future)
        return None
    return future.result()
