"""What the ROS 1 and ROS 2 adapters share once their middleware has delivered a message: the run
being served, its reply lines, and the topics of JSON strings beside the servers (docs/ros.md).

- each hello starts a run (a generation); whatever the middleware delivers of an earlier run, or
  between runs, is dropped, so a line of an ended run never follows the bye that ended it;
- `internal` and `world` events carry the SUT's wall-clock stamps, told in mission seconds since
  the hello was answered;
- a ping is answered once the SUT has echoed it on the mapping's pong topic (if it has one) and
  while the middleware's own evidence of life holds (`alive`, each adapter's own); its pong says
  how long it was held after the echo (`held_s`), so the bench tells the transport's round trip
  from the waits for the SUT's executor.

No middleware import: a message is anything with a `data` string.
"""
from __future__ import annotations

import json
import threading
import time
from typing import Callable

from harness.sut.roscommon.mapping import Mapping
from harness.sut.roscommon.replies import Replies

ECHO_WAIT_S = 0.1  # a start-up ping's echo, before it is published again
ECHO_POLL_S = 0.005


class Bridge:
    def __init__(self, mapping: Mapping, interface: dict, time_scale: float, write: Callable[[dict], None]):
        self.mapping, self.time_scale = mapping, time_scale
        self._write = write
        # Held around each line written: a line of an ended run can never follow the bye that ended it.
        self.out_lock = threading.Lock()
        self.generation, self.live = 0, False  # the run being served (one per hello), and whether it is on
        self.catalogue: dict[str, str] = dict(interface.get("replies") or {})
        self.lock = threading.Lock()  # guards the state below
        # ping id -> when it was echoed through the middleware (when it came, without a ping topic); None: not yet
        self.pending_pings: dict[int, float | None] = {}
        self.goal_ids: dict[str, int] = {}  # the middleware's goal or call id -> request id
        self.replies = Replies(self._writer(0))
        self.hello_epoch = time.time()  # reset when the hello is answered: the SUT's clock starts there

    def hello(self, proto: str, sut: str, caps: list[str], taken_services: list[str] | None = None) -> None:
        """Answer the bench's hello, starting a run; `internal` and `world` times count from here.
        `taken_services` ("module.Service"), where given, are those whose requests may get a `taken`
        reply (docs/reference/protocol.md)."""
        caps = [cap for cap, topic in (("internal", self.mapping.internal_topic),
                                       ("world", self.mapping.world_topic)) if topic] + caps
        told = {} if taken_services is None else {"taken_services": sorted(taken_services)}
        with self.lock, self.out_lock:
            self.generation += 1
            self.live = True  # the goals and pings of the last run were forgotten at its end
            self.replies = Replies(self._writer(self.generation))
            self.hello_epoch = time.time()
            self._write({"op": "hello", "proto": proto, "sut": sut, "caps": caps, **told})

    def end_run(self) -> None:
        """The bench's bye: this run's goals are forgotten, and bye is answered (nothing of the run
        follows it)."""
        with self.lock, self.out_lock:
            self.live = False
            self.forget()
            self.goal_ids, self.pending_pings = {}, {}
            self._write({"op": "bye"})

    def forget(self) -> None:
        """Drop the ended run's goal handles (an adapter that keeps any overrides this)."""

    def _writer(self, generation: int) -> Callable[[dict], None]:
        """What writes a line of run `generation`: nothing once that run is over."""
        def write(message: dict) -> None:
            with self.out_lock:
                if self.live and self.generation == generation:
                    self._write(message)
        return write

    def write(self, message: dict) -> None:
        """A line of the current run, if one is on."""
        with self.out_lock:
            if self.live:
                self._write(message)

    # -- pings ---------------------------------------------------------------------------------
    def ping(self, message: dict) -> None:
        with self.lock:
            self.pending_pings[message["id"]] = None if self.mapping.ping_topic else time.monotonic()
            if self.mapping.ping_topic:
                self.publish_ping(json.dumps({"id": message["id"]}))
            self._answer_pings()

    def publish_ping(self, data: str) -> None:
        raise NotImplementedError

    def ping_done(self, ping_id: int) -> bool:
        """Whatever else a ping waits for besides its echo (an adapter's own round trip)."""
        return True

    def alive(self) -> bool:
        """The middleware's evidence that the SUT still serves (each adapter's own)."""
        raise NotImplementedError

    def _pong(self, message) -> None:
        ping_id = json.loads(message.data)["id"]
        with self.lock:
            if ping_id in self.pending_pings:
                self.pending_pings[ping_id] = time.monotonic()
                self._answer_pings()

    def _answer_pings(self) -> None:
        """Pong the pings echoed (if there is a ping topic), while the SUT is alive; the start-up
        ping (id 0) is the launcher's, never the bench's."""
        if self.alive():
            for ping_id in [p for p, echoed in self.pending_pings.items()
                            if echoed is not None and p != 0 and self.ping_done(p)]:
                held = time.monotonic() - self.pending_pings.pop(ping_id)
                self.write({"op": "pong", "id": ping_id, "held_s": round(held, 6)})

    def echoed(self) -> bool:
        """One start-up ping (id 0; the bench's count from 1) through the SUT and back within
        ECHO_WAIT_S; looked at every ECHO_POLL_S, as a hello waits for it (once per run)."""
        with self.lock:
            self.pending_pings[0] = None
            self.publish_ping(json.dumps({"id": 0}))
        deadline = time.monotonic() + ECHO_WAIT_S
        while True:
            time.sleep(ECHO_POLL_S)
            with self.lock:
                if self.pending_pings[0] is not None or time.monotonic() > deadline:
                    return self.pending_pings.pop(0) is not None

    # -- ground truth and virtual damage ---------------------------------------------------------
    def _t(self, stamp: float) -> float:
        """Seconds on the SUT's clock since hello, in mission seconds."""
        return round((stamp - self.hello_epoch) * self.time_scale, 6)

    def _internal(self, message) -> None:
        data = json.loads(message.data)
        with self.lock:
            rqst_id = self.goal_ids.get(data["goal_id"])
            if rqst_id is not None:
                self.write({"op": "internal", "id": rqst_id, "kind": data["kind"], "t": self._t(data["stamp"]),
                            **({"code": data["code"]} if data.get("code") else {})})

    def _world(self, message) -> None:
        data = json.loads(message.data)
        with self.lock:
            self.write({"op": "world", "t": self._t(data["stamp"]), "kind": data["kind"], "detail": data["detail"]})
