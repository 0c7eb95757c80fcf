"""A tiny untimely/1 adapter in the standard library alone, for the value-domain tests: it logs
the `args` of every request as it received them (one JSON line each, to --log) and, with --check,
refuses a request whose arguments break the domains of --interface (an interface.toml, read
as the adapter's own documentation) with bad_params; otherwise every request ends ok after 0.1
mission seconds. How values travel: docs/protocol.md (nan and infinities as "nan", "inf", "-inf").
"""
import argparse
import json
import math
import re
import sys
import threading
import time
import tomllib

p = argparse.ArgumentParser()
p.add_argument("--interface", required=True)
p.add_argument("--log", required=True)
p.add_argument("--check", action="store_true")
args = p.parse_args()
with open(args.interface, "rb") as f:
    MODULES = tomllib.load(f)["modules"]
lock, scale = threading.Lock(), [1.0]


def send(**fields) -> None:
    with lock:
        sys.stdout.write(json.dumps(fields) + "\n")
        sys.stdout.flush()


def legal(spec: dict, value) -> bool:
    if spec["type"] == "float":
        return (isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
                and spec.get("min", -math.inf) <= value <= spec.get("max", math.inf))
    return (isinstance(value, str) and (not spec.get("choices") or value in spec["choices"])
            and (spec.get("pattern") is None or re.fullmatch(spec["pattern"], value) is not None))


def in_domain(module: str, service: str, given: dict) -> bool:
    declared = MODULES[module]["services"][service].get("args", {})
    return all(legal(spec, given[name]) if name in given else not spec.get("required", True)
               for name, spec in declared.items())


def finish(rqst_id: int, code: str) -> None:
    time.sleep(0.1 / scale[0])
    send(op="reply", id=rqst_id, kind="final", code=code)


with open(args.log, "a") as log:
    for line in sys.stdin:
        msg = json.loads(line)
        if msg["op"] == "hello":
            scale[0] = msg["time_scale"]
            send(op="hello", proto="untimely/1", caps=[], sut="domains test adapter" + (" (checks)" if args.check else ""))
        elif msg["op"] == "request":
            log.write(json.dumps({"id": msg["id"], "args": msg["args"]}) + "\n")
            log.flush()
            ok = not args.check or in_domain(msg["module"], msg["service"], msg["args"])
            threading.Thread(target=finish, args=(msg["id"], "ok" if ok else "bad_params"), daemon=True).start()
        elif msg["op"] == "ping":
            send(op="pong", id=msg["id"])
        elif msg["op"] == "bye":
            break
