"""The simulated layer running in wall-clock (or scaled) time on a thread of its own.

Adapters that put the simulated layer behind a real boundary (the `untimely/1` simulator
adapter, the ROS nodes) host it here: they hand requests and pings in from their own threads
and get replies back on the host's thread, stamped on its clock.
"""
from __future__ import annotations

import threading
import traceback
from pathlib import Path
from typing import Callable

from harness.target.interface import Interface
from harness.sut.simulated.layer import FunctionalLayer
from harness.sut.simulated.realtime import RealtimeEnvironment

WORLD_POLL_S = 0.05  # mission seconds between two looks for new virtual damage

OnReply = Callable[[int, str, str | None, float], None]  # (rqst_id, kind, code, t)


class LayerHost:
    def __init__(self, variant: str, interface: Interface, world_file: Path, time_scale: float = 1.0,
                 on_world: Callable[[float, str, str], None] | None = None,
                 on_error: Callable[[str], None] | None = None):
        self.env = RealtimeEnvironment(time_scale)
        self.layer = FunctionalLayer(self.env, variant, interface, world_file)  # the user's error if bad
        self.on_world, self.on_error = on_world, on_error
        self._stopped = self.env.event()
        self._thread = threading.Thread(target=self._run, name=f"layer {variant}", daemon=True)
        self._world_sent = 0

    def start(self, origin: float | None = None) -> None:
        """Start the layer's thread, its clock at mission time 0 at the monotonic instant `origin`
        (default: now)."""
        self.env.restart_clock(origin)
        if self.on_world:
            self.env.process(self._forward_world(), "world events")
        self._thread.start()

    def _run(self) -> None:
        try:
            self.env.run(until=self._stopped)
        except Exception as e:  # noqa: BLE001 - a failure inside the layer is the adapter's to report
            if self.on_error:
                self.on_error("".join(traceback.format_exception_only(e)).strip())

    def _forward_world(self):
        while True:
            self._flush_world()
            yield self.env.timeout(WORLD_POLL_S)

    def _flush_world(self) -> None:
        events = self.layer.world_events
        for t, kind, detail in events[self._world_sent:]:
            self.on_world(t, kind, detail)
        self._world_sent = len(events)

    def request(self, rqst_id: int, service: str, args: dict[str, str], on_reply: OnReply) -> None:
        """Thread-safe; `on_reply(rqst_id, kind, code, t)` runs on the host's thread, with kind
        `request` (the layer's control task took it), `intermediate` or `final`."""
        def reply(rqst_id: int, kind: str, code: str | None) -> None:
            on_reply(rqst_id, kind, code, self.env.now)
        self.env.post(lambda: self.layer.receive(rqst_id, service, args, reply))

    def ping(self, on_pong: Callable[[], None]) -> None:
        """Thread-safe; `on_pong()` is never called while a module is deadlocked."""
        self.env.post(lambda: self.layer.ping(on_pong))

    def stop(self) -> None:
        """Stop the clock; virtual damage not yet forwarded is forwarded first."""
        def stop_now() -> None:
            if self.on_world:
                self._flush_world()
            if not self._stopped.triggered:
                self._stopped.succeed()
        self.env.post(stop_now)
        self._thread.join(timeout=5.0)

    def __repr__(self) -> str:
        return f"<LayerHost {self.layer!r} x{self.env.time_scale:g}>"
