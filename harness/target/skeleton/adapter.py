#!/usr/bin/env python3
"""An untimely/1 adapter: the bench's side of your robot's functional layer (standard library only).

`untimely init` wrote it as a working example: it stands in for a layer by itself, so that the
golden run completes and a campaign runs before you connect anything. Replace `Layer.take` (and
what it calls) with calls to your robot's layer (ROS actions, GenoM requests, a serial line...).

The protocol (docs/reference/protocol.md), one JSON object per line on stdin/stdout:
  bench -> adapter: hello, request {id, module, service, args}, ping {id}, bye
  adapter -> bench: hello {proto, sut, caps}, reply {id, kind: intermediate|final, code}, pong {id},
                    bye (offered as the capability "reuse": the run is over, send the next hello)
Every request gets exactly one final reply whose code is in the interface's catalogue; never
invent a final reply the layer did not give. Write diagnostics to stderr, never to stdout.
A campaign keeps an adapter that offers "reuse" for its next run, saving a start per run: put
your layer back in its initial state before answering bye, or drop "reuse" from the caps.

What this stand-in layer does, from the interface the bench sends in its hello:
- an init service ends `ok` after INIT_S mission seconds and sets its module up;
- before that, any other exec request of the module is rejected `wait_init` (if catalogued;
  a module without an init service is set up from the start);
- a control service ends `ok` at once;
- an exec service runs ACTIVITY_S mission seconds, then ends `ok`; a new request of the same
  service, or of a service named Stop, interrupts the module's running activity of that service
  (all of them for Stop, which then ends after STOP_S) with `interrupted` (if catalogued).
It checks no other precondition: a campaign finds what such a layer lets through.
"""
import json
import os
import sys
import threading

INIT_S = 0.3       # mission seconds an init service takes
ACTIVITY_S = 1.0   # mission seconds an exec activity runs
STOP = "Stop"      # the service that interrupts every activity of its module...
STOP_S = 0.1       # ...and then ends, this many mission seconds later


class Layer:
    def __init__(self, hello: dict):
        self.kinds = hello["interface"]["modules"]          # module -> service -> kind
        self.codes = set(hello["interface"]["replies"])     # the reply catalogue
        self.scale = float(hello.get("time_scale", 1.0))    # mission seconds per wall second
        self.ready = {m for m, services in self.kinds.items()  # set up: a module without an init service,
                      if "init" not in services.values()}          # others once their init ends ok
        self.running: dict[int, tuple[str, str, threading.Event]] = {}  # id -> module, service, cut
        self.lock = threading.Lock()
        self.over = False  # the bench said bye: nothing of this run may be sent any more

    def code(self, wanted: str, otherwise: str = "ok") -> str:
        return wanted if wanted in self.codes else otherwise

    def take(self, rqst_id: int, module: str, service: str, args: dict) -> None:
        """A request crosses the interface: decide, then reply (here, in a thread of its own)."""
        kind = self.kinds[module][service]
        if kind == "control":
            return final(rqst_id, "ok")
        if kind == "exec" and module not in self.ready and "wait_init" in self.codes:
            return final(rqst_id, "wait_init")
        cut = threading.Event()
        with self.lock:
            for m, s, other_cut in list(self.running.values()):
                if m == module and (s == service or service == STOP and self.kinds[m][s] == "exec"):
                    other_cut.set()
            self.running[rqst_id] = (module, service, cut)
        threading.Thread(target=self.activity, args=(rqst_id, module, service, kind, cut), daemon=True).start()

    def activity(self, rqst_id: int, module: str, service: str, kind: str, cut: threading.Event) -> None:
        lasts = INIT_S if kind == "init" else STOP_S if service == STOP else ACTIVITY_S
        interrupted = cut.wait(lasts / self.scale)
        with self.lock:
            del self.running[rqst_id]
            if self.over:
                return
            if kind == "init" and not interrupted:
                self.ready.add(module)
            final(rqst_id, self.code("interrupted") if interrupted else "ok")

    def end(self) -> None:
        """The run is over: its activities stop, and none of them replies after this returns."""
        with self.lock:
            self.over = True
            for _, _, cut in self.running.values():
                cut.set()


_out = threading.Lock()


def send(**message) -> None:
    with _out:
        sys.stdout.write(json.dumps(message) + "\n")
        sys.stdout.flush()


def final(rqst_id: int, code: str) -> None:
    send(op="reply", id=rqst_id, kind="final", code=code)


def main() -> None:
    layer, runs = None, 0
    for line in sys.stdin:  # ends when the bench closes our input: it keeps us no longer
        message = json.loads(line)
        op = message["op"]
        if op == "hello":
            layer, runs = Layer(message), runs + 1  # a fresh layer: nothing of the last run is left
            send(op="hello", proto="untimely/1", caps=["reuse"],
                 sut=f"untimely init stand-in layer (slot {os.environ.get('UNTIMELY_SLOT', '0')}), run {runs}")
        elif op == "request":
            layer.take(message["id"], message["module"], message["service"], message.get("args", {}))
        elif op == "ping":
            send(op="pong", id=message["id"])
        elif op == "bye":
            layer.end()
            send(op="bye")


if __name__ == "__main__":
    main()
