"""The line channel to an external SUT: an adapter process on stdio (StdioChannel), or a TCP
connection (TcpChannel); `open_channel` opens the one a SUT's definition names.

A reader thread hands the lines the SUT writes to `deliver(lines)`, as many as one read brought
(a flood costs one hand-over per read, not per line), and `None` when its output ends
(`why_ended()` then says how). Nothing the SUT does grows the bench without bound: a line
longer than MAX_LINE_BYTES ends the output, and only the last STDERR_KEEP_BYTES of its standard
error are kept (for the error of a crashed trace). A write that the SUT does not take within its
timeout raises Unresponsive: an adapter that stops reading cannot block the bench.

A started adapter gets a process group of its own (it may start a ROS master and nodes);
closing the channel ends the group, then the daemons it detached (harness.sut.processes).
With UNTIMELY_PROTOCOL_LOG=FILE in the environment, every line that crosses the channel is
appended to FILE (transcript.py).
"""
from __future__ import annotations

import os
import select
import signal
import socket
import subprocess
import threading
import time
from typing import Callable

from harness.errors import InternalSignal, UntimelyError
from harness.sut import processes
from harness.target.suts import ExternalSut
from harness.sut.external.transcript import Transcript

MAX_LINE_BYTES = 1 << 20
STDERR_KEEP_BYTES = 8 << 10
QUOTE_CHARS = 200  # of a line quoted in a message
GRACE_S = 2.0  # after bye, how long an adapter has to exit by itself
POLL_S = 0.25  # how often a blocked reader or writer looks whether the channel was closed
_live: set[int] = set()  # the adapters of this process's open channels (a Dask worker runs several)
# Held from an adapter's start until it is in _live, and while a closing channel lists orphans: an
# adapter starting in another thread (a focused campaign's runs share one process) is no orphan.
_starting = threading.Lock()


class Unresponsive(InternalSignal):
    """The SUT did not take a line within the write timeout: it stopped reading."""


def quoted(text: str) -> str:
    text = text.rstrip("\n")
    return repr(text) if len(text) <= QUOTE_CHARS else f"{text[:QUOTE_CHARS]!r}... ({len(text)} characters)"


class Channel:
    """What both channels share: the reader thread, the bounded write, the transcript. A channel
    kind sets `out_fd` and `in_fd` (`out_fd` None: its output ended before it began)."""
    out_fd: int | None
    in_fd: int

    def __init__(self, sut: ExternalSut, slot: int):
        self.sut = sut
        self.transcript = Transcript(os.environ.get("UNTIMELY_PROTOCOL_LOG"), f"{sut.name}@{slot}")
        self.stderr = bytearray()
        self.stderr_cut = 0  # bytes of stderr dropped from the front
        self.ended: str | None = None  # why the output ended, when the bench ended it
        self.last_read: tuple[float, str] | None = None  # (monotonic time, line)
        self.closed = threading.Event()
        self.writing = threading.Lock()  # held while a write's outcome is not yet recorded
        self.reader = None
        self.deliver: Callable[[list[str] | None], None] | None = None

    def start(self, deliver: Callable[[list[str] | None], None]) -> None:
        """Hand the SUT's lines to `deliver` from now on: a kept channel's next run (kept.py) takes
        over the reader, and only this run's standard error is kept for its errors."""
        self.deliver = deliver
        if self.reader is None:
            self.reader = threading.Thread(target=self._read, name=f"{self.sut.name} output", daemon=True)
            self.reader.start()
        else:
            self.stderr.clear()
            self.stderr_cut = 0

    def gone(self) -> bool:
        """Whether the SUT's output has ended (a kept adapter that exited while idle)."""
        return self.out_fd is None or not self.reader.is_alive()

    def exited(self) -> bool:
        """Whether the SUT's process is known to have ended: its reader may not have seen the end of
        its output yet (a child that inherited the pipe keeps it open), and a run given a kept
        adapter that has would be blamed for its death. Only a started adapter's is known."""
        return False

    def _chunks(self, fd: int):
        """What arrives on `fd` until its end, or until nothing more comes once the channel is closed."""
        while fd is not None:
            if not select.select([fd], [], [], POLL_S)[0]:
                if self.closed.is_set():
                    return
                continue
            try:
                chunk = os.read(fd, 1 << 16)
            except BlockingIOError:
                continue
            except OSError as e:  # a TCP peer that resets the connection
                self._failed(e)
                return
            if not chunk:
                return
            yield chunk

    def _read(self) -> None:
        rest = b""
        try:
            for chunk in self._chunks(self.out_fd):
                *complete, rest = (rest + chunk).split(b"\n")
                if complete:
                    lines = [raw.decode("utf-8", errors="replace") + "\n" for raw in complete]
                    self.last_read = (time.monotonic(), lines[-1])
                    for line in lines:
                        self.transcript.add("<", line)
                    self.deliver(lines)
                if len(rest) > MAX_LINE_BYTES:
                    self.ended = (f"the SUT sent a line of more than {MAX_LINE_BYTES:,} bytes without a newline "
                                  f"(it starts {quoted(rest[:QUOTE_CHARS].decode('utf-8', 'replace'))}); "
                                  "the bench stopped reading it")
                    break
            if not self.ended:
                self._output_closed()
        except Exception as e:  # noqa: BLE001 - the run must learn that its SUT's output ended
            self.ended = self.ended or f"the bench could not read the SUT's output ({e!r})"
        with self.writing:  # a reset is reported once: a write that took it has said so in `ended`
            pass
        self.deliver(None)

    def _output_closed(self) -> None:
        """The SUT closed its output (nothing to wait for on a TCP connection)."""

    def write(self, line: str, timeout_s: float | None = None) -> None:
        """Write one line within `timeout_s` (default: the SUT's probe timeout), else Unresponsive.
        A SUT that has gone is not an error here: the reader sees the end of its output."""
        self.transcript.add(">", line)
        timeout_s = self.sut.probe_timeout_s if timeout_s is None else timeout_s
        data = memoryview(line.encode("utf-8"))
        deadline = time.monotonic() + timeout_s
        while data and not self.closed.is_set() and self.out_fd is not None:
            left = deadline - time.monotonic()
            if left <= 0:
                raise Unresponsive(f"the SUT took no input for {timeout_s:g} s: {len(data):,} bytes of the line "
                                   f"{quoted(line)} could not be written{self.last_read_text()}")
            if not select.select([], [self.in_fd], [], min(left, POLL_S))[1]:
                continue
            with self.writing:
                try:
                    data = data[os.write(self.in_fd, data):]
                except BlockingIOError:
                    continue
                except ConnectionResetError as e:  # the reset is reported once: to the write, or to the reader
                    self._failed(e)
                    return
                except OSError:
                    return

    def _failed(self, error: OSError) -> None:
        self.ended = self.ended or f"the connection failed ({error.strerror or error})"

    def last_read_text(self) -> str:
        """Where the SUT's output stood, for a message about a SUT that stopped answering."""
        if self.last_read is None:
            return "; nothing was read from the SUT"
        at, line = self.last_read
        return f"; the last line read from the SUT, {time.monotonic() - at:.1f} s before, was {quoted(line)}"

    @staticmethod
    def _join(thread: threading.Thread | None) -> None:
        if thread is not None and thread is not threading.current_thread():
            thread.join(GRACE_S)

    def stderr_tail(self) -> str:
        text = self.stderr.decode("utf-8", errors="replace")
        if self.stderr_cut:
            text = f"[{self.stderr_cut:,} earlier bytes not kept]\n" + text.split("\n", 1)[-1]
        return text.rstrip("\n")


class StdioChannel(Channel):
    """An adapter started for the run (`cmd:`), in a process group of its own, on its stdin/stdout;
    the last STDERR_KEEP_BYTES of its standard error are kept."""

    def __init__(self, sut: ExternalSut, slot: int):
        super().__init__(sut, slot)
        self.started = processes.uptime()
        self._stderr_reader = None
        self._start(slot)
        try:  # stopped (a signal) right after the start: the adapter must not be left behind
            self._stderr_reader = threading.Thread(target=self._keep_stderr, name=f"{sut.name} stderr", daemon=True)
            self._stderr_reader.start()
            self.out_fd, self.in_fd = self.process.stdout.fileno(), self.process.stdin.fileno()
            os.set_blocking(self.in_fd, False)  # a write waits in select, with a deadline
        except BaseException:
            self.close()
            raise

    def _start(self, slot: int) -> None:
        env = {**os.environ, **self.sut.env, "UNTIMELY_SLOT": str(slot)}
        with _starting:
            try:
                self.process = subprocess.Popen(self.sut.argv(), stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                                stderr=subprocess.PIPE, env=env, bufsize=0, cwd=self.sut.cwd,
                                                start_new_session=True)
            except OSError as e:
                raise UntimelyError(f"--sut {self.sut.name}: cannot start {self.sut.command!r}: {e}; "
                                    "check the command (a path relative to the current folder?)") from None
            _live.add(self.process.pid)

    def _keep_stderr(self) -> None:
        for chunk in self._chunks(self.process.stderr.fileno()):
            self.stderr += chunk
            if len(self.stderr) > STDERR_KEEP_BYTES:
                self.stderr_cut += len(self.stderr) - STDERR_KEEP_BYTES
                del self.stderr[:len(self.stderr) - STDERR_KEEP_BYTES]

    def exited(self) -> bool:
        return self.process.poll() is not None

    def _output_closed(self) -> None:
        try:  # an adapter closing its output is usually exiting
            self.process.wait(GRACE_S)
        except subprocess.TimeoutExpired:
            pass

    def why_ended(self) -> str:
        if self.ended:
            return self.ended
        code = self.process.poll()
        if code is None:
            return "its output was closed, the process still running"
        return f"killed by signal {signal.Signals(-code).name}" if code < 0 else f"exit status {code}"

    def close(self) -> None:
        """End the channel: the adapter gets GRACE_S to exit after end of input, then its group is
        ended (SIGTERM, then SIGKILL), then any daemon it detached."""
        self.closed.set()
        self.process.stdin.close()
        try:
            self.process.wait(GRACE_S)
        except subprocess.TimeoutExpired:
            pass
        processes.end([self.process], groups=True)
        with _starting:
            _live.discard(self.process.pid)
            processes.end_orphans(self.started, _live)
        self._join(self.reader)
        self._join(self._stderr_reader)  # its last lines, for the error of a crashed trace
        self.process.stdout.close()
        self.process.stderr.close()


class TcpChannel(Channel):
    """An adapter already listening (`tcp://HOST:PORT`), reached anew for the run."""

    def __init__(self, sut: ExternalSut, slot: int):
        super().__init__(sut, slot)
        host, port = sut.address.rsplit(":", 1)
        try:
            self.socket = socket.create_connection((host, int(port)), timeout=sut.startup_s)
        except ConnectionResetError:  # accepted, then reset: the SUT's doing, a crashed trace
            self.socket, self.ended, self.out_fd = None, "the SUT reset the connection as it accepted it", None
            return
        except OSError as e:
            raise UntimelyError(f"--sut {sut.name}: cannot reach tcp://{sut.address} ({e}); "
                                "start the adapter first, or check the address") from None
        self.out_fd = self.in_fd = self.socket.fileno()
        os.set_blocking(self.in_fd, False)

    def why_ended(self) -> str:
        return self.ended or "the connection was closed"

    def close(self) -> None:
        self.closed.set()
        if self.socket:
            try:
                self.socket.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass
            self._join(self.reader)
            self.socket.close()


def open_channel(sut: ExternalSut, slot: int) -> Channel:
    """The channel `sut`'s definition names: its command started on stdio, or its address over TCP."""
    return StdioChannel(sut, slot) if sut.command else TcpChannel(sut, slot)

