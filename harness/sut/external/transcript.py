"""The transcript of the lines that cross the channels to external SUTs: with
UNTIMELY_PROTOCOL_LOG=FILE in the environment, every line is appended to FILE with its channel,
direction and monotonic time (for adapter authors; docs/protocol.md shows one)."""
from __future__ import annotations

import threading
import time


class Transcript:
    """The lines of one channel, appended to a file shared by all channels (or nowhere)."""
    lock = threading.Lock()

    def __init__(self, path: str | None, label: str):
        self.path, self.label, self.start = path, label, time.monotonic()

    def add(self, direction: str, line: str) -> None:
        if self.path:
            with self.lock, open(self.path, "a", encoding="utf-8") as f:
                f.write(f"{time.monotonic() - self.start:10.6f} {self.label} {direction} {line.rstrip()}\n")
