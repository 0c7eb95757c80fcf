"""A small untimely/1 adapter (stdlib only) for the toy pump-and-valve target of
tests/test_focused.py: Init takes 0.2 mission s; an exec request of a module not initialised is
refused `not_ready`; pump.Run runs until a Halt of its module (`stopped`); valve.Open runs 1 s;
Halt stops its module's activities and ends `ok` after 0.05 s. `--careless`: pump.Run is not
refused while valve.Open runs (the DRY protection missing)."""
import json
import sys
import threading

careless = "--careless" in sys.argv
lock = threading.Lock()
scale = [1.0]
ready, running = set(), {}  # running: request id -> (module, timer or None)


def send(**fields) -> None:
    with lock:
        sys.stdout.write(json.dumps(fields) + "\n")
        sys.stdout.flush()


def final(rqst_id: int, code: str) -> None:
    with lock:
        if running.pop(rqst_id, None) is None:
            return  # already ended by a Halt
    send(op="reply", id=rqst_id, kind="final", code=code)


def later(seconds: float, rqst_id: int, module: str, code: str = "ok", then=None) -> None:
    def end():
        if then:
            then()
        final(rqst_id, code)
    timer = threading.Timer(seconds / scale[0], end)
    with lock:
        running[rqst_id] = (module, timer)
    timer.start()


def request(rqst_id: int, module: str, service: str) -> None:
    if service == "Init":
        return later(0.2, rqst_id, module, then=lambda: ready.add(module))
    if module not in ready:
        return send(op="reply", id=rqst_id, kind="final", code="not_ready")
    if service == "Halt":
        with lock:
            stopped = [i for i, (m, _) in running.items() if m == module]
        for i in stopped:
            final(i, "stopped")
        return later(0.05, rqst_id, module)
    if service == "Run":
        with lock:
            opening = any(m == "valve" for m, _ in running.values())
        if opening and not careless:
            return send(op="reply", id=rqst_id, kind="final", code="refused")
        with lock:
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
