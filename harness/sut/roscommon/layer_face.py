"""What the ROS 1 and the ROS 2 Dala node share (harness/sut/ros/dala_node.py,
harness/sut/ros2/dala_node.py): the simulated layer's requests and replies, its world events and its
failure, each stamped on the wall clock.

A node mixes LayerFace in and gives it `host` (a LayerHost), `time_scale`, `ids` (request ids),
`open` (request id -> its ending, whose `reply(kind, code)` answers the ROS side), `world_pub` and
`internal_pub` (None where the mapping names no such topic), and two methods of its distro's client
library: `_publish_json(publisher, payload)` and `_shut_down(reason)`. An ending whose `id` is None
is no request of the bench's: it has no ground truth. No ROS import here.
"""
from __future__ import annotations

import json
import sys
import time


class LayerFace:
    def _start_host(self) -> None:
        self.host.start()
        self.origin = time.time() - self.host.env.clock() / self.time_scale  # wall-clock epoch of the host's t = 0

    def _stamp(self, t: float) -> float:
        """The wall-clock epoch of host time t (mission seconds)."""
        return self.origin + t / self.time_scale

    # -- goals and calls -> layer requests (the client library's threads) --------------------------
    def _request(self, qualified: str, args: dict, ending) -> None:
        rqst_id = next(self.ids)
        self.open[rqst_id] = ending
        # The layer reads argument values as text, whatever their type (as the simulator adapter).
        self.host.request(rqst_id, qualified, {k: str(v) for k, v in args.items()}, self._reply)

    # -- layer replies -> goal statuses or responses (the host's thread) ---------------------------
    def _reply(self, rqst_id: int, kind: str, code: str | None, t: float) -> None:
        ending = self.open.get(rqst_id)
        if ending is None:  # ended by a reset meanwhile
            return
        if self.internal_pub and ending.id is not None:
            self._publish_json(self.internal_pub, {"goal_id": ending.id, "kind": kind, "code": code,
                                                   "stamp": self._stamp(t)})
        if kind == "final":
            del self.open[rqst_id]
        ending.reply(kind, code)

    def _world(self, t: float, kind: str, detail: str) -> None:
        if self.world_pub:
            self._publish_json(self.world_pub, {"stamp": self._stamp(t), "kind": kind, "detail": json.loads(detail)})

    def _failed(self, message: str) -> None:
        self.failure = message
        print(f"dala_node: the simulated layer failed: {message}", file=sys.stderr, flush=True)
        self._shut_down(message)
