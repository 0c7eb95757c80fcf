"""A plain-text progress bar on stderr: done/total, rate and ETA over this session's work.

The work is counted in runs (one a trace), or in mission seconds (`mission_time`: each trace
counts its simulated seconds, the measure of a focused campaign's budget). A total of None is
work whose end is not known in advance (a focused campaign without a budget stops by its rule):
the bar shows what was done and its rate, no fraction or ETA. Neither goes past the total.

On a terminal the bar is redrawn in place (at most every REDRAW_S); in a log file it is a
line every 1/LOG_STEPS of the work (every LOG_EVERY_S without a total), so a redirected
campaign does not write megabytes of bars.
"""
from __future__ import annotations

import sys
import time

WIDTH = 30
REDRAW_S = 0.2
LOG_STEPS = 10
LOG_EVERY_S = 30.0


def _clock(seconds: float) -> str:
    minutes, s = divmod(int(seconds + 0.5), 60)
    return f"{minutes // 60}:{minutes % 60:02d}:{s:02d}" if minutes >= 60 else f"{minutes}:{s:02d}"


def _amount(amount: float) -> str:
    return f"{amount:,.0f}"


class Progress:
    def __init__(self, total: float | None, done: float = 0, stream=None, unit: str = "runs",
                 mission_time: bool = False):
        self.total, self.done, self.unit, self.mission_time = total, done, unit, mission_time
        self.stream = stream or sys.stderr
        self.tty = self.stream.isatty()
        self.start = time.monotonic()
        self.session = 0  # work finished since start: the rate ignores resumed work
        self.drawn_at, self.logged_step = 0.0, self._step()

    def _step(self) -> int:
        if self.total is None:
            return int((time.monotonic() - self.start) // LOG_EVERY_S)
        return min(int(self.done * LOG_STEPS // self.total), LOG_STEPS) if self.total else 0

    def line(self) -> str:
        elapsed = time.monotonic() - self.start
        rate = self.session / elapsed if elapsed > 0 else 0.0
        if self.total is None:
            return f"{_amount(self.done)} {self.unit}  {rate:5.1f} {self.unit}/s"
        left = max(self.total - self.done, 0)
        eta = _clock(left / rate) if rate else "?"
        fraction = min(self.done / self.total, 1.0) if self.total else 1.0
        bar = "#" * int(WIDTH * fraction)
        total = _amount(self.total)
        return (f"{_amount(min(self.done, self.total)):>{len(total)}}/{total} {self.unit} "
                f"[{bar:<{WIDTH}}] {fraction:4.0%}  {rate:5.1f} {self.unit}/s  ETA {eta}")

    def ran(self, trace) -> None:
        """One run's trace came back: a run, or its mission seconds."""
        self.advance(trace.sim_s if self.mission_time else 1)

    def spent(self, mission_s: float) -> None:
        """Mission seconds spent outside the runs counted (a shrink's): counted on a bar of mission seconds."""
        if self.mission_time:
            self.advance(mission_s)

    def advance(self, n: float = 1) -> None:
        self.done += n
        self.session += n
        now = time.monotonic()
        if self.tty:
            if now - self.drawn_at >= REDRAW_S or (self.total is not None and self.done >= self.total):
                self.drawn_at = now
                self.stream.write("\r" + self.line())
                self.stream.flush()
        else:
            step = self._step()
            if step > self.logged_step:
                self.logged_step = step
                self.stream.write(self.line() + "\n")
                self.stream.flush()

    def close(self) -> None:
        if self.tty:
            self.stream.write("\r" + self.line() + "\n")
            self.stream.flush()
