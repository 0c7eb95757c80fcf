"""A hostile untimely/1 adapter (standard library only) for the bench's robustness tests: a layer
that ends every request `ok` at once and answers pings, except as `--case` says.

Cases: error-hello (an error instead of hello), nested-hello (a hello nested 100,000 levels
deep), nested-later (such a line after the first request), flood (a million `world` events
while it keeps answering), stderr-flood (20 MB on stderr, then exit 3), endless-line (an
endless line without newline), never-pong (answers requests, never pings), held-back (says it held
each pong a negative time), deaf (stops reading
its input after hello, answers nothing), stubborn (ignores SIGTERM, forks a child that ignores
it too and a double-forked setsid daemon; writes their pids, one a line, to $HOSTILE_PIDS).
"""
import argparse
import json
import os
import signal
import sys
import threading
import time

p = argparse.ArgumentParser()
p.add_argument("--case", default="none")
case = p.parse_args().case
lock = threading.Lock()
out = sys.stdout.buffer


def send(text: str) -> None:
    with lock:
        out.write(text.encode() + b"\n")
        out.flush()


def hello() -> str:
    return json.dumps({"op": "hello", "proto": "untimely/1", "sut": f"hostile {case}", "caps": []})


def flood() -> None:
    line = json.dumps({"op": "world", "t": 0.0, "kind": "noise", "detail": {"n": 1}}).encode() + b"\n"
    for _ in range(1000):
        with lock:
            out.write(line * 1000)
            out.flush()


def sleep_forever() -> None:
    while True:
        time.sleep(60)


def stubborn() -> None:
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    pids = []
    child = os.fork()
    if child == 0:
        sleep_forever()  # inherits SIG_IGN for SIGTERM, stays in the adapter's group
    pids.append(child)
    reader, writer = os.pipe()
    if os.fork() == 0:
        os.setsid()
        daemon = os.fork()
        if daemon == 0:
            sleep_forever()
        os.write(writer, f"{daemon}\n".encode())
        os._exit(0)
    os.close(writer)
    pids.append(int(os.read(reader, 64).decode()))
    with open(os.environ["HOSTILE_PIDS"], "a") as f:
        f.write("".join(f"{pid}\n" for pid in [os.getpid()] + pids))


if case == "stubborn":
    stubborn()
for raw in sys.stdin:
    msg = json.loads(raw)
    op = msg["op"]
    if op == "hello":
        if case == "error-hello":
            send(json.dumps({"op": "error", "message": "interface catalogue lacks code 'stalled'"}))
            sys.exit(1)
        if case == "nested-hello":
            send("[" * 100_000 + "]" * 100_000)
            continue
        if case == "endless-line":
            while True:
                out.write(b"x" * 65536)
        if case == "stderr-flood":
            for _ in range(320):
                sys.stderr.write("noise " * 10_000 + "\n")
            sys.stderr.write("the last words\n")
            sys.stderr.flush()
            sys.exit(3)
        send(hello())
        if case == "flood":
            flooding = threading.Thread(target=flood, daemon=True)
            flooding.start()
        if case == "deaf":
            sleep_forever()
    elif op == "request":
        if case == "nested-later":
            send("{\"a\":" * 100_000 + "1" + "}" * 100_000)
        final = json.dumps({"op": "reply", "id": msg["id"], "kind": "final", "code": "ok"})
        if case == "flood":  # after the whole million, which the bench then reads before the run can end
            threading.Thread(target=lambda line=final: (flooding.join(), send(line)), daemon=True).start()
        else:
            send(final)
    elif op == "ping" and case != "never-pong":
        send(json.dumps({"op": "pong", "id": msg["id"], **({"held_s": -1} if case == "held-back" else {})}))
    elif op == "bye":
        break
