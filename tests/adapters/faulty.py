"""A tiny untimely/1 adapter for the bench's fault tests: a layer that ends every request `ok`
after 0.2 mission seconds, answers pings, and misbehaves as `--fault` says once it has taken
`--after` requests. It names its slot (UNTIMELY_SLOT) in its hello and on stderr.

Faults: none, crash (exits 3), silent (stops answering anything), garbage (a non-JSON line),
two-finals (a second final to the same request), unknown-code, unknown-op, error (an error
message), no-hello (never answers hello), stray-reply (a reply to an id never sent).
With `--reuse answer` it offers `reuse`, answers bye and takes the next hello (its faults count
the requests of each run); `--reuse mute` offers it but never answers bye. Its hello counts runs.
"""
import argparse
import json
import os
import sys
import threading
import time

p = argparse.ArgumentParser()
p.add_argument("--fault", default="none")
p.add_argument("--after", type=int, default=3)
p.add_argument("--reuse", choices=["no", "answer", "mute"], default="no")
args = p.parse_args()
lock = threading.Lock()
state = {"taken": 0, "silent": False, "scale": 1.0, "runs": 0}
print(f"faulty adapter on slot {os.environ.get('UNTIMELY_SLOT')}", file=sys.stderr, flush=True)


def send(line: str) -> None:
    with lock:
        if not state["silent"]:
            sys.stdout.write(line + "\n")
            sys.stdout.flush()


def message(**fields) -> str:
    return json.dumps(fields)


def finish(rqst_id: int) -> None:
    time.sleep(0.2 / state["scale"])
    send(message(op="reply", id=rqst_id, kind="final", code="ok"))
    if args.fault == "two-finals" and state["taken"] > args.after:
        send(message(op="reply", id=rqst_id, kind="final", code="ok"))


def misbehave(rqst_id: int) -> None:
    fault = args.fault
    if fault == "crash":
        print("adapter: simulated crash, exiting 3", file=sys.stderr, flush=True)
        os._exit(3)
    state["silent"] = fault == "silent"
    lines = {"garbage": "this is not json", "unknown-code": message(op="reply", id=rqst_id, kind="final", code="kaput"),
             "unknown-op": message(op="dance", id=rqst_id), "error": message(op="error", message="motor driver lost"),
             "stray-reply": message(op="reply", id=99999, kind="final", code="ok")}
    if fault in lines:
        send(lines[fault])


for line in sys.stdin:
    msg = json.loads(line)
    if msg["op"] == "hello":
        state.update(scale=msg["time_scale"], taken=0, runs=state["runs"] + 1)
        runs = f", run {state['runs']}" if args.reuse != "no" else ""
        if args.fault != "no-hello":
            send(message(op="hello", proto="untimely/1", caps=["reuse"] if args.reuse != "no" else [],
                         sut=f"faulty test adapter on slot {os.environ.get('UNTIMELY_SLOT')}{runs}"))
    elif msg["op"] == "request":
        state["taken"] += 1
        if state["taken"] > args.after:
            misbehave(msg["id"])
        threading.Thread(target=finish, args=(msg["id"],), daemon=True).start()
    elif msg["op"] == "ping":
        send(message(op="pong", id=msg["id"]))
    elif msg["op"] == "bye" and args.reuse == "no":
        break
    elif msg["op"] == "bye" and args.reuse == "answer":
        send(message(op="bye"))
