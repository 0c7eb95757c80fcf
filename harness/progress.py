"""A plain-text progress bar on stderr: done/total, runs/s and ETA over this session's runs.

On a terminal the bar is redrawn in place (at most every REDRAW_S); in a log file it is a
line every 1/LOG_STEPS of the work, so a redirected campaign does not write megabytes of bars.
"""
from __future__ import annotations

import sys
import time

WIDTH = 30
REDRAW_S = 0.2
LOG_STEPS = 10


def _clock(seconds: float) -> str:
    minutes, s = divmod(int(seconds + 0.5), 60)
    return f"{minutes // 60}:{minutes % 60:02d}:{s:02d}" if minutes >= 60 else f"{minutes}:{s:02d}"


class Progress:
    def __init__(self, total: int, done: int = 0, stream=None, unit: str = "runs"):
        self.total, self.done, self.unit = total, done, unit
        self.stream = stream or sys.stderr
        self.tty = self.stream.isatty()
        self.start = time.monotonic()
        self.session = 0  # runs finished since start: the rate ignores resumed work
        self.drawn_at, self.logged_step = 0.0, self._step()

    def _step(self) -> int:
        return self.done * LOG_STEPS // self.total if self.total else 0

    def line(self) -> str:
        elapsed = time.monotonic() - self.start
        rate = self.session / elapsed if elapsed > 0 else 0.0
        left = self.total - self.done
        eta = _clock(left / rate) if rate else "?"
        fraction = self.done / self.total if self.total else 1.0
        bar = "#" * int(WIDTH * fraction)
        return (f"{self.done:>{len(str(self.total))}}/{self.total} {self.unit} [{bar:<{WIDTH}}] "
                f"{fraction:4.0%}  {rate:5.1f} {self.unit}/s  ETA {eta}")

    def advance(self, n: int = 1) -> None:
        self.done += n
        self.session += n
        now = time.monotonic()
        if self.tty:
            if now - self.drawn_at >= REDRAW_S or self.done == self.total:
                self.drawn_at = now
                self.stream.write("\r" + self.line())
                self.stream.flush()
        else:
            step = self._step()
            if step > self.logged_step or self.done == self.total:
                self.logged_step = step
                self.stream.write(self.line() + "\n")
                self.stream.flush()

    def close(self) -> None:
        if self.tty:
            self.stream.write("\r" + self.line() + "\n")
            self.stream.flush()
