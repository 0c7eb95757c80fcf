"""A small untimely/1 adapter (stdlib only) for the toy pump-and-valve target of
tests/campaign/test_focused.py: Init takes 0.2 mission s; an exec request of a module not initialised is
refused `not_ready`; pump.Run runs until a Halt of its module (`stopped`); valve.Open runs 1 s;
Halt stops its module's activities and ends `ok` after 0.05 s. `--careless`: pump.Run is not
refused while valve.Open runs (the DRY protection missing)."""
import json
import sys
import threading

careless = "--careless" in sys.argv
lock = threading.RLock()
scale = [1.0]
ready, running = set(), {}  # running: request id -> (module, timer or None)


def send(**fields) -> None:
    with lock:
        sys.stdout.write(json.dumps(fields) + "\n")
        sys.stdout.flush()


def final(rqst_id: int, code: str, then=lambda: None) -> None:
    """The final reply and what it changes, at once: no request is taken in between."""
    with lock:
        if running.pop(rqst_id, None) is None:
            return  # already ended by a Halt
        then()
        send(op="reply", id=rqst_id, kind="final", code=code)


def later(seconds: float, rqst_id: int, module: str, code: str = "ok", then=lambda: None) -> None:
    def end():
        final(rqst_id, code, then)
    timer = threading.Timer(seconds / scale[0], end)
    running[rqst_id] = (module, timer)
    timer.start()


def request(rqst_id: int, module: str, service: str) -> None:
    with lock:
        answer(rqst_id, module, service)


def answer(rqst_id: int, module: str, service: str) -> None:
    if service == "Init":
        return later(0.2, rqst_id, module, then=lambda: ready.add(module))
    if module not in ready:
        return send(op="reply", id=rqst_id, kind="final", code="not_ready")
    if service == "Halt":
        for i in [i for i, (m, _) in running.items() if m == module]:
            final(i, "stopped")
        return later(0.05, rqst_id, module)
    if service == "Run":
        if any(m == "valve" for m, _ in running.values()) and not careless:
            return send(op="reply", id=rqst_id, kind="final", code="refused")
        running[rqst_id] = (module, None)
        return
    later(1.0, rqst_id, module)  # valve.Open


for line in sys.stdin:
    msg = json.loads(line)
    if msg["op"] == "hello":
        scale[0] = msg["time_scale"]
        send(op="hello", proto="untimely/1", caps=[], sut="toy pump adapter" + (" (careless)" if careless else ""))
    elif msg["op"] == "request":
        request(msg["id"], msg["module"], msg["service"])
    elif msg["op"] == "ping":
        send(op="pong", id=msg["id"])
    elif msg["op"] == "bye":
        break
