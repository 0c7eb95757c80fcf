"""The line channel to an external SUT: an adapter process on stdio, or a TCP connection.

A reader thread hands every line the SUT writes to `deliver(line)`, and `None` when its output
ends. A started adapter gets a process group of its own (it may start a ROS master and nodes),
so closing the channel ends all of it. Its standard error is kept: the last lines go into the
error of a crashed trace. With UNTIMELY_PROTOCOL_LOG=FILE in the environment, every line that
crosses the channel is appended to FILE with its direction and monotonic time (a transcript for
adapter authors; docs/protocol.md shows one).
"""
from __future__ import annotations

import os
import signal
import socket
import subprocess
import threading
import time
from collections import deque
from typing import Callable

from harness.errors import UntimelyError
from harness.run.external.definitions import ExternalSut

STDERR_LINES = 20
GRACE_S = 2.0  # after bye, how long an adapter has to exit by itself


class Connection:
    def __init__(self, sut: ExternalSut, slot: int, deliver: Callable[[str | None], None]):
        self.sut, self.deliver = sut, deliver
        self.transcript = _Transcript(os.environ.get("UNTIMELY_PROTOCOL_LOG"), f"{sut.name}@{slot}")
        self.stderr: deque[str] = deque(maxlen=STDERR_LINES)
        self.process: subprocess.Popen | None = None
        if sut.command:
            self._start(slot)
        else:
            host, port = sut.address.rsplit(":", 1)
            try:
                self.socket = socket.create_connection((host, int(port)), timeout=sut.startup_s)
            except OSError as e:
                raise UntimelyError(f"--sut {sut.name}: cannot reach tcp://{sut.address} ({e}); "
                                    "start the adapter first, or check the address") from None
            self.socket.settimeout(None)
            self.output, self.input = self.socket.makefile("r", encoding="utf-8", errors="replace"), \
                self.socket.makefile("w", encoding="utf-8")
        threading.Thread(target=self._read, name=f"{sut.name} output", daemon=True).start()

    def _start(self, slot: int) -> None:
        env = {**os.environ, **self.sut.env, "UNTIMELY_SLOT": str(slot)}
        try:
            self.process = subprocess.Popen(self.sut.argv(), stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                            stderr=subprocess.PIPE, env=env, text=True, encoding="utf-8",
                                            errors="replace", bufsize=1, start_new_session=True)
        except OSError as e:
            raise UntimelyError(f"--sut {self.sut.name}: cannot start {self.sut.command!r}: {e}; "
                                "check the command (a path relative to the current folder?)") from None
        self.output, self.input = self.process.stdout, self.process.stdin
        self._stderr_reader = threading.Thread(target=self._keep_stderr, name=f"{self.sut.name} stderr", daemon=True)
        self._stderr_reader.start()

    def _read(self) -> None:
        try:
            for line in self.output:
                self.transcript.add("<", line)
                self.deliver(line)
        except (OSError, ValueError):
            pass
        if self.process:  # an adapter closing its output is usually exiting: let its status be known
            try:
                self.process.wait(GRACE_S)
            except subprocess.TimeoutExpired:
                pass
        self.deliver(None)

    def _keep_stderr(self) -> None:
        for line in self.process.stderr:
            self.stderr.append(line.rstrip("\n"))

    def write(self, line: str) -> None:
        self.transcript.add(">", line)
        try:
            self.input.write(line)
            self.input.flush()
        except (OSError, ValueError):
            pass  # the reader sees the end of the output and reports it

    def exit_status(self) -> str:
        if self.process is None:
            return "the connection was closed"
        code = self.process.poll()
        if code is None:
            return "still running"
        return f"killed by signal {signal.Signals(-code).name}" if code < 0 else f"exit status {code}"

    def close(self) -> None:
        """End the channel; a started adapter gets GRACE_S to exit, then its group is killed."""
        try:
            self.input.close()
        except OSError:
            pass
        if self.process is None:
            self.socket.close()
            return
        try:
            self.process.wait(GRACE_S)
        except subprocess.TimeoutExpired:
            pass
        try:
            os.killpg(self.process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        self.process.wait()
        self._stderr_reader.join(GRACE_S)  # its last lines, for the error of a crashed trace

    def stderr_tail(self) -> str:
        return "\n".join(self.stderr)


class _Transcript:
    """The lines of one channel, appended to a file shared by all channels (or nowhere)."""
    lock = threading.Lock()

    def __init__(self, path: str | None, label: str):
        self.path, self.label, self.start = path, label, time.monotonic()

    def add(self, direction: str, line: str) -> None:
        if self.path:
            with self.lock, open(self.path, "a", encoding="utf-8") as f:
                f.write(f"{time.monotonic() - self.start:10.6f} {self.label} {direction} {line.rstrip()}\n")
