"""The kernel in wall-clock time: the same events and processes, paced by a monotonic clock.

`now` is mission seconds: wall seconds since the environment started, times `time_scale`
(1 = real time, 10 = ten times faster). An event is processed when the clock reaches its time,
never before; a late one runs as soon as it can, at its own time. Other threads (the reader of
a SUT's output, a ROS callback) hand work in with `post`: the callback runs on the kernel's
thread, before any due event, at the clock's reading (or the kernel's time if it is late), so
the event log stays ordered and single-threaded.
"""
from __future__ import annotations

import queue
import time
from typing import Callable

from harness.sut.simulated.kernel import Environment, Event


class RealtimeEnvironment(Environment):
    def __init__(self, time_scale: float = 1.0) -> None:
        if not time_scale > 0:
            raise ValueError(f"time_scale {time_scale!r}: give a factor > 0 (1 = real time)")
        super().__init__()
        self.time_scale = time_scale
        self._start = time.monotonic()
        self._posted: queue.SimpleQueue[Callable[[], None]] = queue.SimpleQueue()

    def restart_clock(self, origin: float | None = None) -> None:
        """Start the clock anew (after a start-up or a handshake) at the monotonic instant `origin`
        (default: now), before any event is processed: what is scheduled keeps its mission time,
        counted from the new start."""
        if self.now:
            raise RuntimeError(f"{self!r}: the clock can only restart before any event is processed")
        self._start = time.monotonic() if origin is None else origin

    def clock(self) -> float:
        """The wall clock in mission seconds since start."""
        return (time.monotonic() - self._start) * self.time_scale

    def lag(self) -> float:
        """Mission seconds the kernel is behind the wall clock (busy with a flood of messages)."""
        return max(0.0, self.clock() - self.now)

    def post(self, callback: Callable[[], None]) -> None:
        """Thread-safe: run `callback` on the kernel's thread as soon as it is free."""
        self._posted.put(callback)

    def _run_posted(self, wait_s: float) -> bool:
        """Run one posted callback, waiting at most `wait_s` wall seconds for one; False if none.
        It runs at the clock's reading or, when the kernel is late (an event is already due), at
        the kernel's own time: a late kernel still takes messages in (a busy machine must not
        starve a SUT's pings), and time never goes back."""
        try:
            callback = self._posted.get(timeout=wait_s) if wait_s > 0 else self._posted.get_nowait()
        except queue.Empty:
            return False
        self.now = max(self.now, min(self.clock(), self.peek()))
        callback()
        return True

    def run(self, until: float | Event | None = None) -> None:
        """Process events as the clock reaches them, until an event is processed or a time is
        reached (`None`: until nothing is scheduled or posted)."""
        limit = until if isinstance(until, (int, float)) else float("inf")
        while not (isinstance(until, Event) and until.processed):
            if self._run_posted(0):
                continue
            clock = self.clock()
            if self.peek() <= min(limit, clock):
                self.step()
            elif self.peek() > limit and limit <= clock:
                self.now = max(self.now, limit)
                return
            elif until is None and self.peek() == float("inf"):
                return
            else:
                self._run_posted(min((min(self.peek(), limit) - clock) / self.time_scale, 1.0))

    def __repr__(self) -> str:
        return (f"<RealtimeEnvironment t={self.now:.6f} x{self.time_scale:g} "
                f"clock={self.clock():.6f} pending={len(self._heap)}>")
