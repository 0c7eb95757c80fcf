"""`python -m harness.sut.simulated --variant NAME`: the simulated layer as an external SUT.

It speaks `untimely/1` on stdio (the bench starts it, and keeps it for run after run: it offers
`reuse`) or, with `--listen HOST:PORT`, to every bench that connects (runs one after another on
a connection, several connections at once). The layer
runs in wall-clock time scaled by the hello's `time_scale`, so the same scripts can be run in
process and through the protocol and their traces compared. It reports the layer's internal
instants (`internal`) and its virtual damage (`world`); with `--taken`, it also replies `taken`
at the instant its control task takes each request (the paper's interface extension).
"""
from __future__ import annotations

import argparse
import json
import socketserver
import sys
import threading
import time
from pathlib import Path

from harness import DEFAULT_MISSION_DIR
from harness.errors import UntimelyError
from harness.target.interface import load_interface
from harness.sut.protocol import BENCH_MESSAGES, PROTO, REUSE, ProtocolViolation, decode, encode
from harness.sut.simulated.host import LayerHost
from harness.target.mission import INTERFACE_FILE, WORLD_FILE


class Session:
    """One run: the bench's lines in, the layer's replies out."""

    def __init__(self, variant: str, mission: Path, output, taken: bool = False):
        self.variant, self.mission, self.output, self.taken = variant, mission, output, taken
        self.lock = threading.Lock()
        self.host: LayerHost | None = None
        self.runs = 0

    def send(self, op: str, **fields) -> None:
        with self.lock:
            self.output.write(encode(op, **fields))
            self.output.flush()

    def on_reply(self, rqst_id: int, kind: str, code: str | None, t: float) -> None:
        # the ground truth first: a run that ends at a reply (the bench sends bye once it has the
        # last final) has the reply's internal line too
        self.send("internal", id=rqst_id, kind=kind, t=t, **({"code": code} if code else {}))
        if kind != "request":
            self.send("reply", id=rqst_id, kind=kind, **({"code": code} if code else {}))
        elif self.taken:
            self.send("reply", id=rqst_id, kind="taken")

    def start(self, hello: dict) -> None:
        interface = load_interface(self.mission / INTERFACE_FILE)
        self.host = LayerHost(self.variant, interface, self.mission / WORLD_FILE, hello["time_scale"],
                              on_world=lambda t, kind, detail: self.send("world", t=t, kind=kind,
                                                                         detail=json.loads(detail)),
                              on_error=lambda message: self.send("error", message=message))
        answered = time.monotonic()  # internal times count from the hello answer
        self.runs += 1
        self.send("hello", proto=PROTO, sut=f"untimely simulated layer, variant {self.variant}, run {self.runs} "
                  "of this adapter", caps=["internal", "world", REUSE, *(["taken"] if self.taken else [])])
        self.host.start(answered)

    def end_run(self) -> None:
        """The bench's bye: the layer stops (its thread joined, so nothing of the run follows), and
        the adapter answers bye, ready for the next run's hello."""
        self.host.stop()
        self.host = None
        self.send("bye")

    def serve(self, lines) -> int:
        try:
            for line in lines:
                message = decode(line, BENCH_MESSAGES)
                op = message["op"]
                if op == "hello" and self.host is not None:
                    raise ProtocolViolation("a second hello before bye")
                if op == "hello":
                    self.start(message)
                elif self.host is None:
                    raise ProtocolViolation(f"{op!r} before hello")
                elif op == "request":
                    args = {k: str(v) for k, v in message["args"].items()}
                    self.host.request(message["id"], f"{message['module']}.{message['service']}", args,
                                      self.on_reply)
                elif op == "ping":
                    self.host.ping(lambda ping_id=message["id"]: self.send("pong", id=ping_id))
                else:  # bye
                    self.end_run()
        except (ProtocolViolation, UntimelyError) as e:
            self.send("error", message=str(e))
            return 1
        finally:
            if self.host:
                self.host.stop()
        return 0


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m harness.sut.simulated", description=__doc__.split("\n\n")[0])
    p.add_argument("--variant", required=True, help="implementation variant of the simulated layer")
    p.add_argument("--mission", default=str(DEFAULT_MISSION_DIR), help="mission folder (default: %(default)s)")
    p.add_argument("--listen", metavar="HOST:PORT", help="serve benches over TCP instead of stdio")
    p.add_argument("--taken", action="store_true",
                   help="reply `taken` when the layer takes each request (an interface extension)")
    args = p.parse_args(argv)
    mission = Path(args.mission)
    if not args.listen:
        return Session(args.variant, mission, sys.stdout, args.taken).serve(sys.stdin)

    class Handler(socketserver.StreamRequestHandler):
        def handle(self):
            writer = self.connection.makefile("w", encoding="utf-8")
            Session(args.variant, mission, writer, args.taken).serve(self.connection.makefile("r", encoding="utf-8"))

    host, port = args.listen.rsplit(":", 1)
    with socketserver.ThreadingTCPServer((host, int(port)), Handler) as server:
        server.daemon_threads = True
        print(f"listening on {host}:{server.server_address[1]}", file=sys.stderr, flush=True)
        server.serve_forever()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
