"""Runs against an external SUT over `untimely/1` (docs/reference/protocol.md), in wall-clock time.

The same Executive plays the script, with the same watchdog and drain rules, on a kernel paced
by the monotonic clock; its layer is a ProtocolLayer that turns requests and pings into lines
and the SUT's lines back into replies. Every line is stamped when the bench writes it, or when
its kernel takes it from the reader thread (within microseconds of reading): that observed
timeline is `events`. The trace clock starts when the SUT has answered hello.

Real-time runs are not reproducible, so each trace records where, when and how fast the
interface answered (`trace_runs`): the ping round trips give the latency from which a tester
sets epsilon. A run takes its channel from the adapters kept between runs when one is (kept.py),
and leaves it there when it ended well on an adapter that offered `reuse`.
"""
from __future__ import annotations

import itertools
import json
import random
import socket
import statistics
import threading
import time
from datetime import datetime, timezone

from harness.sut.external import kept
from harness.sut.external.channel import GRACE_S, Channel, Unresponsive, open_channel, quoted
from harness.sut.executive import Executive, LayerMisbehaved, Probe, trace_of
from harness.target.interface import Interface
from harness.target.script import Script
from harness.sut.protocol import (INTERNAL_KINDS, PROTO, REPLY_KINDS, REUSE, SUT_FAREWELL,
                                           ProtocolViolation, decode, encode, has_type)
from harness.sut.simulated.realtime import RealtimeEnvironment
from harness.target.suts import ExternalSut
from harness.trace import Trace

PROBE_PERIOD_WALL_S = 1.0
# Reads (of up to 64 KB) not yet handled by the kernel: beyond, the reader waits (and the SUT
# with it), so a flood of messages cannot grow the bench's memory.
MAX_QUEUED_READS = 64


class ProtocolLayer:
    """The Executive's layer when the SUT is a process or a socket away."""

    def __init__(self, env: RealtimeEnvironment, interface: Interface):
        self.env, self.interface = env, interface
        self.connection: Channel | None = None
        self.requests: dict[int, tuple] = {}  # id -> (service, args JSON)
        self.on_reply = None
        self.pings: dict[int, tuple] = {}  # id -> (answer, monotonic time sent), until its pong
        self.ping_ids = itertools.count(1)
        self.round_trips: list[float] = []  # wall seconds
        self.transport_trips: list[float] = []  # the same, less what the SUT says it held each pong
        self.internal: list[tuple] = []
        self.world_events: list[tuple] = []
        self.hello: dict | None = None
        self.hello_at = 0.0  # monotonic instant the hello answer was read: mission time 0
        self.greeted = threading.Event()
        self.problem: str | None = None  # a violation before the hello answer
        self.closing = False
        self.farewell = threading.Event()  # the SUT answered bye: its channel may serve the next run
        self.room = threading.BoundedSemaphore(MAX_QUEUED_READS)

    # Reader thread: the hello is handled here; every later line goes to the kernel's thread.
    def deliver(self, lines: list[str] | None) -> None:
        if not self.greeted.is_set():
            self._greet(lines[0] if lines else None)
            lines = lines[1:] if lines else None
            if lines == []:
                return
        while not self.closing and not self.room.acquire(timeout=0.25):
            pass
        if self.closing:  # the run is over: only the SUT's bye still counts
            self._farewell(lines)
            return
        self.env.post(lambda: self.handle(lines))

    def _farewell(self, lines: list[str] | None) -> None:
        for line in lines or ():
            try:
                decode(line, SUT_FAREWELL)
                self.farewell.set()
            except ProtocolViolation:
                pass

    def reusable(self, outcome: str) -> bool:
        """Whether the channel may serve the next run: a run that ended well, on a SUT that offered
        reuse and said its bye within the grace period."""
        caps = (self.hello or {}).get("caps")
        return outcome == "completed" and isinstance(caps, list) and REUSE in caps and self.farewell.wait(GRACE_S)

    def _greet(self, line: str | None) -> None:
        if line is None:
            self.problem = f"the SUT ended before answering hello ({self.connection.why_ended()})"
        else:
            try:
                message = decode(line)
                if message["op"] == "error":
                    raise ProtocolViolation(f"the SUT sent an error instead of hello: {message['message']}")
                if message["op"] != "hello" or message["proto"] != PROTO:
                    raise ProtocolViolation(f"expected a hello with proto {PROTO!r} first")
                self.hello, self.hello_at = message, time.monotonic()
            except ProtocolViolation as e:
                self.problem = f"{e}; the SUT's line: {quoted(line)}"
        self.greeted.set()

    def receive(self, rqst_id: int, service: str, args: dict[str, str], reply) -> None:
        spec = self.interface.services[service]
        self.on_reply = reply
        self.requests[rqst_id] = (spec, json.dumps(spec.typed(args)))
        self.connection.write(encode("request", id=rqst_id, module=spec.module, service=spec.name,
                                     args=spec.typed(args)))

    def ping(self, answer) -> None:
        ping_id = next(self.ping_ids)
        self.pings[ping_id] = (answer, time.monotonic())
        self.connection.write(encode("ping", id=ping_id))

    def handle(self, lines: list[str] | None) -> None:
        if lines is None:
            if not self.closing:
                raise LayerMisbehaved(f"the SUT closed its output before bye ({self.connection.why_ended()})")
            return
        self.room.release()
        for line in lines:
            try:
                self._dispatch(decode(line))
            except (ProtocolViolation, LayerMisbehaved) as e:
                raise LayerMisbehaved(f"{e}; the SUT's line: {quoted(line)}") from None

    def unanswered(self) -> str:
        """Why a trace is hung: its oldest ping without a pong, and what the SUT last wrote."""
        if not self.pings:
            return "the SUT stopped answering" + self.connection.last_read_text()
        ping_id, (_, sent) = min(self.pings.items())
        return (f"ping {ping_id} got no pong within the probe timeout ({time.monotonic() - sent:.1f} s "
                f"unanswered when the run ended){self.connection.last_read_text()}")

    def _request(self, message: dict) -> tuple:
        if message["id"] not in self.requests:
            raise ProtocolViolation(f"{message['op']} for request {message['id']}, which was never sent")
        return self.requests[message["id"]]

    def _dispatch(self, message: dict) -> None:
        op = message["op"]
        if op == "reply":
            if message["kind"] not in REPLY_KINDS:
                raise ProtocolViolation(f"reply kind {message['kind']!r}; expected one of {', '.join(REPLY_KINDS)}")
            self._request(message)
            code = message.get("code")
            if not (isinstance(code, str) or code is None and message["kind"] != "final"):
                raise ProtocolViolation(f"a {message['kind']} reply needs a text code, got {code!r}")
            self.on_reply(message["id"], message["kind"], code)
        elif op == "pong":
            if message["id"] not in self.pings:
                raise ProtocolViolation(f"pong {message['id']} answers no ping waiting for one")
            held = message.get("held_s", 0.0)
            if not (has_type(held, float) and held >= 0):
                raise ProtocolViolation(f"a pong's held_s must be seconds >= 0, got {held!r}")
            answer, sent = self.pings.pop(message["id"])
            trip = time.monotonic() - sent
            self.round_trips.append(trip)
            self.transport_trips.append(max(trip - held, 0.0))
            answer()
        elif op == "internal":
            if message["kind"] not in INTERNAL_KINDS:
                raise ProtocolViolation(f"internal kind {message['kind']!r}; "
                                        f"expected one of {', '.join(INTERNAL_KINDS)}")
            service, args = self._request(message)
            kind = message["kind"]
            code = message.get("code") if kind != "request" else None
            self.internal.append((len(self.internal) + 1, message["t"], kind, message["id"],
                                  service.module, service.name, args if kind == "request" else None, code))
        elif op == "world":
            self.world_events.append((message["t"], message["kind"], json.dumps(message["detail"])))
        elif op == "error":
            raise LayerMisbehaved(f"the SUT gave up with an error: {message['message']}")
        else:  # a second hello
            raise ProtocolViolation("a second hello")

    def provenance(self, started_at: datetime) -> dict:
        trips = sorted(self.round_trips)

        def percentile(q: float):
            return trips[min(len(trips) - 1, int(q * len(trips)))] if trips else None
        return {"host": socket.gethostname(), "started_at": started_at, "time_scale": self.env.time_scale,
                "sut_info": str((self.hello or {}).get("sut", "")), "pings": len(trips),
                "rtt_p50_s": statistics.median(trips) if trips else None, "rtt_p95_s": percentile(0.95),
                "rtt_max_s": trips[-1] if trips else None,
                "transport_max_s": max(self.transport_trips) if self.transport_trips else None}


def _session(sut: ExternalSut, seed: int, interface: Interface) -> tuple:
    """A run's clock, protocol layer and executive."""
    env = RealtimeEnvironment(sut.time_scale)
    layer = ProtocolLayer(env, interface)
    executive = Executive(env, layer, interface, random.Random(seed), max_delay=0.0,
                          probe=Probe(PROBE_PERIOD_WALL_S * sut.time_scale, sut.probe_timeout_s * sut.time_scale))
    return env, layer, executive


def _greet(layer: ProtocolLayer, hello: str, startup_s: float) -> None:
    """Send the hello on the layer's connection and wait for its answer (LayerMisbehaved if none)."""
    layer.connection.start(layer.deliver)
    try:
        layer.connection.write(hello, startup_s)
    except Unresponsive as e:
        raise LayerMisbehaved(f"no hello answer: {e}") from None
    if not layer.greeted.wait(startup_s):
        raise LayerMisbehaved(f"no hello answer within {startup_s:g} s of starting"
                              f"{layer.connection.last_read_text()}")
    if layer.problem:
        raise LayerMisbehaved(layer.problem)


def run_external(script: Script, sut: ExternalSut, seed: int, interface: Interface, slot: int = 0,
                 run: int = 0) -> Trace:
    """Run one script against an external SUT; a misbehaving SUT gives a crashed or hung trace,
    an adapter that cannot be started or reached is the user's error (UntimelyError)."""
    wall, started_at = time.perf_counter(), datetime.now(timezone.utc).replace(tzinfo=None)
    env, layer, executive = _session(sut, seed, interface)
    outcome, error, reused = "crashed", None, False
    hello = encode("hello", proto=PROTO, run=run, seed=seed, time_scale=sut.time_scale,
                   interface=interface.describe())
    taken = kept.take(sut, slot)
    layer.connection = taken or open_channel(sut, slot)
    try:  # from here on, however the run ends (a signal included), the SUT is closed
        try:
            _greet(layer, hello, sut.startup_s)
        except LayerMisbehaved:
            if taken is None:
                raise
            # a kept adapter that died while idle, its end not yet seen: replaced, never blamed, on a
            # fresh layer (what the dead one's reader still delivers reaches the old one)
            layer.connection.close()
            fresh = open_channel(sut, slot)
            env, layer, executive = _session(sut, seed, interface)
            layer.connection = fresh
            _greet(layer, hello, sut.startup_s)
        env.restart_clock(layer.hello_at)
        env.process(executive.play(script), "executive")
        env.process(executive.probe(), "liveness probe")
        env.run(until=executive.done)
        outcome = executive.done.value
        error = layer.unanswered() if outcome == "hung" else None
        layer.closing = True
        try:
            layer.connection.write(encode("bye"))
            reused = (error is None and kept.keeping() and layer.reusable(outcome)
                      and kept.keep(layer.connection, sut, slot))
        except Unresponsive:
            pass  # the run is over; closing the channel ends the SUT
    except LayerMisbehaved as e:
        error = str(e)
    except Unresponsive as e:  # a SUT that stops reading stops answering: hung, like a missing pong
        outcome, error = "hung", str(e)
    finally:
        layer.closing = True
        if not reused:
            layer.connection.close()
    if error and layer.connection.stderr:
        error += "\nlast lines of the SUT's stderr:\n" + layer.connection.stderr_tail()
    trace = trace_of(executive, env, Trace(sut=sut.name, seed=seed, outcome=outcome, error=error), wall,
                     layer.internal, layer.world_events)
    trace.provenance = layer.provenance(started_at)
    return trace
