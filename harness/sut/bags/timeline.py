"""One bag's requests and replies as the rows of one trace, whatever order the bag holds them in.

A bag stores each topic's messages as they were received, so a goal's result may precede its
feedback, or an introspection event its request. The rules are the live adapter's (replies.py):
a request gets at most one intermediate reply, only before its final, and at most one final; a
reply to a request the bag never saw (recording started late) is left out and counted. Feedback
and result travel on separate topics, so a recorder may receive a goal's feedback after its
result, or a reply before its goal (kept as the goal's, at its instant, with a note); where
the SUT stamped both (ROS 1 headers), its own clock says which came first, and an intermediate
reply it sent first is kept, no later than the final.
Requests are numbered in the order their clients sent them (the client's own stamp), as the
bench numbers a script's requests.

The SUT's own stamps (ROS 1 headers; ROS 2 the server's introspection events and goals' accept
stamps, ros2.py) give the same requests on the SUT's clock, for `internal_events` (sut_rows): a
request at the first stamp showing that the server held the goal or call (ROS 1: a status list
naming it, its feedback or its result; ROS 2: its receipt or acceptance, else its response), its
first feedback at that feedback's stamp, its final at its result's (or terminal status's) stamp.
A request the SUT never stamped is left out of them, and so is a reply it did not stamp.
"""
from __future__ import annotations

import json
from dataclasses import dataclass

from harness.errors import UntimelyError


@dataclass
class BagRequest:
    """A request the bag holds, with the replies and the SUT's own stamps found for it so far."""
    order: tuple  # the client's send stamp, then the receive time: the request's number
    t: float
    qualified: str
    args: dict | None
    intermediate: float | None = None
    intermediate_stamp: float | None = None  # the SUT's own send stamp, where it gives one
    final: tuple[float, str] | None = None
    final_stamp: float | None = None
    status_final: tuple[float, str] | None = None  # a terminal status, for a goal whose result is not in the bag
    status_stamp: float | None = None  # that status list's stamp
    held_stamp: float | None = None  # the SUT's earliest stamp showing it held the goal (status list, receipt)

    def settle(self) -> None:
        """A goal whose result the bag lacks ends with its terminal status."""
        if self.final is None and self.status_final is not None:
            self.final, self.final_stamp = self.status_final, self.status_stamp


class BagTimeline:
    """The requests of one bag, numbered in their clients' order, as they are read."""

    def __init__(self, origin_s: float):
        self.origin_s = origin_s  # the bag's first receive stamp: t = 0
        self.requests: dict[object, BagRequest] = {}
        self.orphans = 0  # replies to goals whose request the bag does not hold
        # replies received before their goal (a recorder's order of its topics), until finish()
        self.early: list[tuple[str, tuple]] = []

    def goal(self, key, received_s: float, qualified: str, args: dict | None, sent_s: float) -> None:
        """A goal a client sent: its id must be new, as its replies name only the id."""
        if key in self.requests:
            raise UntimelyError(f"two goals carry the id {_shown(key)} (received {self.requests[key].t:.3f} s and "
                                f"{received_s - self.origin_s:.3f} s into the bag): their replies cannot be told "
                                "apart; a client must give each goal a new id")
        self.request(key, received_s, qualified, args, sent_s)

    def request(self, key, received_s: float, qualified: str, args: dict | None, sent_s: float | None = None) -> None:
        if key not in self.requests:
            t = received_s - self.origin_s
            self.requests[key] = BagRequest((sent_s if sent_s is not None else received_s, received_s), t, qualified, args)

    def intermediate(self, key, received_s: float, stamp_s: float | None = None) -> None:
        request = self.requests.get(key)
        if request is None:
            self.early.append(("intermediate", (key, received_s, stamp_s)))
        elif request.intermediate is None:
            request.intermediate, request.intermediate_stamp = received_s - self.origin_s, stamp_s

    def final(self, key, received_s: float, code: str | None, stamp_s: float | None = None) -> None:
        request = self.requests.get(key)
        if request is None:
            self.early.append(("final", (key, received_s, code, stamp_s)))
        elif request.final is None and code is not None:
            request.final, request.final_stamp = (received_s - self.origin_s, code), stamp_s

    def finish(self) -> list[str]:
        """Once every message is read: the replies received before their goal are its replies,
        no earlier than it (notes say so); those to goals the bag lacks are orphans."""
        notes, early, self.early = [], self.early, []
        for kind, args in early:
            key, received_s = args[:2]
            if key not in self.requests:
                self.orphans += 1
                continue
            getattr(self, kind)(*args)
            ahead_ms = (self.requests[key].t + self.origin_s - received_s) * 1e3
            notes.append(f"the {'feedback' if kind == 'intermediate' else 'result'} of goal {_shown(key)} was received "
                         f"{ahead_ms:.1f} ms before the goal (the recorder's order of its topics); kept as its reply, "
                         "at the goal's instant")
        return notes

    def status_final(self, key, received_s: float, code: str | None, stamp_s: float | None = None) -> None:
        """A terminal status seen in a status list: the final only if the bag holds no result."""
        request = self.requests.get(key)
        if request is not None and request.status_final is None and code is not None:
            request.status_final, request.status_stamp = (received_s - self.origin_s, code), stamp_s

    def held(self, key, stamp_s: float | None) -> None:
        """The SUT stamped `stamp_s` on something showing it held the goal (a status list naming it,
        its receipt or acceptance)."""
        request = self.requests.get(key)
        if request is not None and stamp_s is not None:
            request.held_stamp = stamp_s if request.held_stamp is None else min(stamp_s, request.held_stamp)

    def _numbered(self):
        for number, request in enumerate(sorted(self.requests.values(), key=lambda r: r.order), 1):
            request.settle()
            yield number, request, *request.qualified.split(".")

    def rows(self, label: str) -> list[dict]:
        """The events of the trace `label`, in time order (a request before its replies)."""
        events = []
        for number, request, module, service in self._numbered():
            args = json.dumps(request.args) if request.args is not None else None
            events.append((request.t, 0, number, "request", module, service, args, None))
            final_t = request.final[0] if request.final else None
            if request.intermediate is not None and (final_t is None or request.intermediate <= final_t
                                                     or _sent_before(request.intermediate_stamp, request.final_stamp)):
                t = request.intermediate if final_t is None else min(request.intermediate, final_t)
                events.append((max(t, request.t), 1, number, "intermediate", module, service, None, None))
            if request.final:
                events.append((max(final_t, request.t), 2, number, "final", module, service, None, request.final[1]))
        return _trace(label, events)

    def sut_rows(self, label: str) -> list[dict]:
        """The events of the trace `label` on the SUT's own clock (module doc), from the same origin."""
        events = []
        for number, request, module, service in self._numbered():
            stamps = [s for s in (request.held_stamp, request.intermediate_stamp, request.final_stamp) if s is not None]
            if not stamps:
                continue
            args = json.dumps(request.args) if request.args is not None else None
            events.append((min(stamps) - self.origin_s, 0, number, "request", module, service, args, None))
            if request.intermediate_stamp is not None and (request.final_stamp is None or _sent_before(
                    request.intermediate_stamp, request.final_stamp)):
                events.append((request.intermediate_stamp - self.origin_s, 1, number, "intermediate", module,
                               service, None, None))
            if request.final is not None and request.final_stamp is not None:
                events.append((request.final_stamp - self.origin_s, 2, number, "final", module, service, None,
                               request.final[1]))
        return _trace(label, events)


def _trace(label: str, events: list[tuple]) -> list[dict]:
    """Rows of (t, order in the request, number, kind, module, service, args, reply), in time order."""
    events.sort(key=lambda e: (e[0], e[2], e[1]))
    return [{"trace_id": label, "seq": seq, "t": round(t, 9), "kind": kind, "rqst_id": number, "module": module,
             "service": service, "args": args, "reply": reply}
            for seq, (t, _, number, kind, module, service, args, reply) in enumerate(events, 1)]


def _shown(key) -> str:
    """A goal id as its bag spells it (ROS 2: a UUID's bytes)."""
    return key.hex() if isinstance(key, bytes) else repr(key)


def _sent_before(first: float | None, second: float | None) -> bool:
    return first is not None and second is not None and first <= second


def seconds(stamp) -> float:
    """A message's time stamp (sec, nanosec) in seconds."""
    return stamp.sec + stamp.nanosec * 1e-9


def stamped(stamp) -> float | None:
    """A stamp the SUT gave, in seconds; None if it left it zero (no instant)."""
    return seconds(stamp) if stamp.sec or stamp.nanosec else None
