"""Which `reply` lines a request's ROS events give, whatever order ROS delivers them in.

Feedback, status and result travel on separate topics, each read by its own thread, so a goal's
feedback may arrive after its result, and its result twice (once from the result topic, once
through the status that carries it). A request gets at most one intermediate reply, only before
its final, and at most one final; a goal that ends with no final code (LOST) gets none.

Where the adapter promised `taken` replies (ROS 2 introspection), the server's event of receiving a
request travels on a topic of its own, and may arrive after the response it preceded: a feedback
or a response then proves the request was taken, and its `taken` reply goes first, as the protocol
requires, at the instant the proof arrived (no later than the late event); the late event is
dropped. No ROS import: the rules are checked without a master.
"""
from __future__ import annotations

import sys
import threading
from typing import Callable


class Replies:
    def __init__(self, write: Callable[[dict], None], taken_promised: bool = False):
        self.write, self.taken_promised = write, taken_promised
        self.lock = threading.Lock()
        self.given: dict[int, str] = {}  # request id -> its last reply: "taken", "intermediate" or "final"

    def feedback(self, rqst_id: int) -> None:
        with self.lock:
            if self.given.get(rqst_id, "taken") == "taken":
                self._taken_first(rqst_id)
                self.given[rqst_id] = "intermediate"
                self.write({"op": "reply", "id": rqst_id, "kind": "intermediate"})

    def taken(self, rqst_id: int) -> None:
        """The server took the request (ROS 2 introspection): a `taken` reply, once, before any other,
        where the adapter promised them."""
        with self.lock:
            self._taken_first(rqst_id)

    def _taken_first(self, rqst_id: int) -> None:
        """The promised `taken` reply, unless the request has had a reply already."""
        if self.taken_promised and rqst_id not in self.given:
            self.given[rqst_id] = "taken"
            self.write({"op": "reply", "id": rqst_id, "kind": "taken"})

    def ended(self, rqst_id: int, status: str, code: str | None) -> None:
        """The goal is done with `status`; `code` is its final reply, None if it may have none."""
        with self.lock:
            if self.given.get(rqst_id) == "final":
                return
            if code is None:
                print(f"ros adapter: request {rqst_id} ended {status} without a result: no final reply",
                      file=sys.stderr, flush=True)
                return
            self._taken_first(rqst_id)
            self.given[rqst_id] = "final"
            self.write({"op": "reply", "id": rqst_id, "kind": "final", "code": code})
