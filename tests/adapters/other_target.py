"""An untimely/1 adapter made for another target than Dala: it answers hello, then gives up on the
first request, naming what it does not know (tests/campaign/test_recorded_target.py)."""
import json
import sys

hello = json.loads(sys.stdin.readline())
print(json.dumps({"op": "hello", "proto": "untimely/1", "sut": "quadcopter 0.1", "caps": []}), flush=True)
for line in sys.stdin:
    message = json.loads(line)
    if message["op"] == "ping":
        print(json.dumps({"op": "pong", "id": message["id"]}), flush=True)
    elif message["op"] == "request":
        print(json.dumps({"op": "error", "message": f"no module {message['module']} on this quadcopter"}), flush=True)
        break
