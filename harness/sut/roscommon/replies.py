"""Which `reply` lines a request's ROS events give, whatever order ROS delivers them in.

Feedback, status and result travel on separate topics, each read by its own thread, so a goal's
feedback may arrive after its result, and its result twice (once from the result topic, once
through the status that carries it). A request gets at most one intermediate reply, only before
its final, and at most one final; a goal that ends with no final code (LOST) gets none.

A `taken` reply relays the server's own record of receiving the request (ROS 2 introspection),
only when that record is the request's first news: it travels on a topic of its own, so it may
arrive after the feedback or response it preceded, and the bench stamps a line when it reads it,
so a late record cannot be placed honestly; it is dropped, and the request keeps its sending and
receiving instants (with their epsilon). A `taken` reply is never made up from other replies.
No ROS import: the rules are checked without a master.
"""
from __future__ import annotations

import sys
import threading
from typing import Callable


class Replies:
    def __init__(self, write: Callable[[dict], None]):
        self.write = write
        self.lock = threading.Lock()
        self.given: dict[int, str] = {}  # request id -> its last reply: "taken", "intermediate" or "final"

    def feedback(self, rqst_id: int) -> None:
        with self.lock:
            if self.given.get(rqst_id, "taken") == "taken":
                self.given[rqst_id] = "intermediate"
                self.write({"op": "reply", "id": rqst_id, "kind": "intermediate"})

    def taken(self, rqst_id: int) -> None:
        """The server's record of receiving the request: a `taken` reply if nothing of the request
        came before it, else none (a late record)."""
        with self.lock:
            if rqst_id in self.given:
                return
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
            self.given[rqst_id] = "final"
            self.write({"op": "reply", "id": rqst_id, "kind": "final", "code": code})
