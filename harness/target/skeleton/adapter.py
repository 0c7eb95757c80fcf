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

What this stand-in layer does: the rules of standin.toml beside it (written by `untimely init`
with the properties), on the interface the bench sends in its hello:
- a request of a service some [[requires]] entry names in x is rejected with its reply until
  every service of its q has ended ok once;
- an accepted control request ends `ok` at once; an accepted init or exec request runs INIT_S or
  ACTIVITY_S mission seconds, then ends `ok`;
- an accepted request of a service some [[interrupts]] entry names as `by` interrupts the running
  activities of that entry's x first, which end with its reply;
- a request of a service some [[validates]] entry names in x, once the [[requires]] rules let it
  through, is rejected with its reply when an argument breaks its domain in interface.toml (beside
  this file): missing though required, of the wrong JSON type, outside min..max, not one of the
  choices, not matching the pattern. Other services' arguments are not checked.
"""
import json
import os
import re
import sys
import threading
import tomllib

INIT_S = 0.3       # mission seconds an init service takes
ACTIVITY_S = 1.0   # mission seconds an exec activity runs
RULES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "standin.toml")
INTERFACE = os.path.join(os.path.dirname(RULES), "interface.toml")


def domains() -> dict:
    """"module.Service" -> argument -> its spec, from interface.toml beside this file."""
    if not os.path.exists(INTERFACE):
        return {}
    with open(INTERFACE, "rb") as f:
        modules = tomllib.load(f).get("modules", {})
    return {f"{m}.{s}": spec.get("args", {}) for m, services in modules.items()
            for s, spec in services.get("services", {}).items()}


def legal(value, spec: dict) -> bool:
    """Whether a request's JSON value (None: absent) lies in the argument's domain."""
    if value is None:
        return not spec.get("required", True)
    if spec["type"] == "float":
        number = isinstance(value, (int, float)) and not isinstance(value, bool)
        return number and spec.get("min", value) <= value <= spec.get("max", value)
    return isinstance(value, str) and value in spec.get("choices", [value]) and \
        re.fullmatch(spec.get("pattern", ".*"), value, re.S) is not None


class Layer:
    def __init__(self, hello: dict, rules: dict):
        self.kinds = hello["interface"]["modules"]          # module -> service -> kind
        self.scale = float(hello.get("time_scale", 1.0))    # mission seconds per wall second
        self.requires = rules.get("requires", [])           # [{x, q, reply}]
        self.interrupts = rules.get("interrupts", [])       # [{by, x, reply}]
        self.validates = rules.get("validates", [])         # [{x, reply}]
        self.domains = domains()                            # "module.Service" -> argument -> spec
        self.done: set[str] = set()                         # "module.Service" that ended ok once
        self.running: dict[int, tuple[str, threading.Event, list]] = {}  # id -> service, cut, reply
        self.lock = threading.Lock()
        self.over = False  # the bench said bye: nothing of this run may be sent any more

    def rejection(self, service: str, args: dict) -> str | None:
        for rule in self.requires:
            if service in rule["x"] and not set(rule["q"]) <= self.done:
                return rule["reply"]
        for rule in self.validates:
            spec = self.domains.get(service, {})
            if service in rule["x"] and not all(legal(args.get(name), spec[name]) for name in spec):
                return rule["reply"]
        return None

    def take(self, rqst_id: int, module: str, service: str, args: dict) -> None:
        """A request crosses the interface: decide, then reply (here, in a thread of its own)."""
        name, kind = f"{module}.{service}", self.kinds[module][service]
        with self.lock:
            rejected = self.rejection(name, args)
            if rejected:
                return final(rqst_id, rejected)
            for rule in self.interrupts:
                if rule["by"] == name:
                    for other, other_cut, reply in self.running.values():
                        if other in rule["x"] and not other_cut.is_set():
                            reply.append(rule["reply"])
                            other_cut.set()
            if kind == "control":
                self.done.add(name)
                return final(rqst_id, "ok")
            cut = threading.Event()
            self.running[rqst_id] = (name, cut, [])
        threading.Thread(target=self.activity, args=(rqst_id, kind, cut), daemon=True).start()

    def activity(self, rqst_id: int, kind: str, cut: threading.Event) -> None:
        interrupted = cut.wait((INIT_S if kind == "init" else ACTIVITY_S) / self.scale)
        with self.lock:
            name, _, reply = self.running.pop(rqst_id)
            if self.over:
                return
            if not interrupted:
                self.done.add(name)
            final(rqst_id, reply[0] if interrupted else "ok")

    def end(self) -> None:
        """The run is over: its activities stop, and none of them replies after this returns."""
        with self.lock:
            self.over = True
            for _, cut, _ in self.running.values():
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
    with open(RULES, "rb") as f:
        rules = tomllib.load(f)
    for line in sys.stdin:  # ends when the bench closes our input: it keeps us no longer
        message = json.loads(line)
        op = message["op"]
        if op == "hello":
            layer, runs = Layer(message, rules), runs + 1  # a fresh layer: nothing of the last run is left
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
