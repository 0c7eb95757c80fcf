"""The launcher's side of `untimely/1` on stdio, shared by the ROS 1 and ROS 2 adapters: whole
lines out from any thread, the bench's messages in, and the hello that starts each run."""
from __future__ import annotations

import json
import os
import signal
import sys
import threading
from typing import Callable

from harness.errors import UntimelyError
from harness.sut.protocol import BENCH_MESSAGES, PROTO, ProtocolViolation, decode, encode


class LineWriter:
    """One message per line on stdout (the shared codec), whole lines only, whichever thread writes."""

    def __init__(self, stream):
        self.stream, self.lock = stream, threading.Lock()

    def write(self, message: dict) -> None:
        line = encode(**message)
        with self.lock:
            self.stream.write(line)
            self.stream.flush()


def read_message(stream) -> dict | None:
    """The bench's next message; None at end of input."""
    line = stream.readline()
    if not line:
        return None
    try:
        return decode(line, BENCH_MESSAGES)
    except ProtocolViolation as e:
        raise UntimelyError(f"the bench sent {line.strip()[:200]!r}: {e}") from None


def serve(adapter, stream) -> bool:
    """Requests and pings until `bye` (True) or end of input (False)."""
    handlers = {"request": adapter.request, "ping": adapter.ping}
    while (message := read_message(stream)) is not None and message["op"] != "bye":
        if message["op"] not in handlers:
            raise UntimelyError(f"the bench sent a second {message['op']!r}")
        handlers[message["op"]](message)
    return message is not None


def read_hello(stream, first: dict | None = None) -> dict | None:
    """The bench's hello (None at end of input); a later run's must keep the first's time scale and
    interface, which the node was started with."""
    hello = read_message(stream)
    if hello is None:
        return None
    if hello["op"] != "hello" or hello["proto"] != PROTO:
        raise UntimelyError(f"the bench's first line must be a hello of {PROTO}, got {json.dumps(hello)[:200]}")
    if first and (hello["time_scale"], hello["interface"]) != (first["time_scale"], first["interface"]):
        raise UntimelyError("the bench reused this adapter for another time scale or interface; start one for it")
    return hello


def serve_runs(adapter, first: dict, node, ready: Callable[[], None], greet: Callable[[int, list[str]], None],
               reset: Callable[[], bool] | None) -> None:
    """Run after run on one node, from the `first` hello on: `ready()` once the node can serve (its
    servers answer), `greet(n, offers)` answers the n-th run's hello (offering `reuse` where the node
    has a `reset`; None: it cannot be reused), requests until `bye`; then, with reuse and a node
    still alive, the run ends, `reset()` gives the node a fresh layer and the next hello starts the
    next run. A reset that cannot (False) ends the adapter: the bench replaces an idle one that
    ended, never blaming it."""
    reusable = reset is not None
    hello, runs, offers = first, 0, ["reuse"] if reusable else []
    while hello is not None:
        ready()
        runs += 1
        greet(runs, offers)
        if not (serve(adapter, sys.stdin) and reusable) or node.failure():
            return
        adapter.end_run()
        if not reset():
            return
        hello = read_hello(sys.stdin, first)


def protocol_stdout():
    """This process's stdout as the protocol's own stream, and file descriptor 1 sent to stderr: what
    a library writes there itself (Fast DDS logs its errors to std::cout) cannot break a line."""
    sys.stdout.flush()
    stream = os.fdopen(os.dup(1), "w", encoding="utf-8")
    os.dup2(2, 1)
    return stream


def run_main(run, args) -> int:
    """A launcher's life on stdio: `run(args, out)` until it returns or SIGTERM comes (torn down as on
    bye); its UntimelyError is an `error` line and exit status 2."""
    out = LineWriter(protocol_stdout())
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    try:
        run(args, out)
    except UntimelyError as e:
        out.write({"op": "error", "message": str(e)})
        return 2
    return 0
