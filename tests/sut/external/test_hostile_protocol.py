"""A hostile corpus for the protocol, over stdio and TCP: every case ends in the right trace
outcome with its reason in the trace's error (never a traceback, a hang or unbounded memory).
The adapters are real processes (tests/adapters/hostile.py) or sockets served here."""
import re
import resource
import select
import socket
import struct
import threading
import time

import pytest

from harness.sut.external.channel import MAX_LINE_BYTES, STDERR_KEEP_BYTES, Channel, TcpChannel
from harness.target.suts import ExternalSut
from harness.sut.external.runner import run_external
from harness.target.script import parse

from tests.support.external import SHORT

HOSTILE = "{python} tests/adapters/hostile.py --case "


def hostile(case: str, **options) -> ExternalSut:
    settings = dict(time_scale=10.0, probe_timeout_s=1.0, startup_s=10.0) | options
    return ExternalSut("hostile", command=HOSTILE + case, **settings)


def run(sut: ExternalSut, interface, body: str = SHORT):
    return run_external(parse(body, "short"), sut, 7, interface)


@pytest.mark.slow
@pytest.mark.parametrize("case, outcome, says", [
    ("error-hello", "crashed", r"^the SUT sent an error instead of hello: interface catalogue lacks code 'stalled'"),
    ("nested-hello", "crashed", r"^JSON nested too deeply to read; the SUT's line: '\[\[\[.*\.\.\. \(200000 characters\)"),
    ("nested-later", "crashed", r"^JSON nested too deeply to read; the SUT's line: '\{\"a\":"),
    ("never-pong", "hung", r"^ping 1 got no pong within the probe timeout \(\d+\.\d s unanswered when the run "
                           r"ended\); the last line read from the SUT, \d+\.\d s before, was '\{\"op\": \"reply\""),
    ("held-back", "crashed", r"^a pong's held_s must be seconds >= 0, got -1; the SUT's line: '\{\"op\": \"pong\""),
    ("endless-line", "crashed", rf"^the SUT ended before answering hello \(the SUT sent a line of more than "
                                rf"{MAX_LINE_BYTES:,} bytes without a newline \(it starts 'xxxx"),
])
def test_a_hostile_stdio_adapter_ends_its_trace_with_the_reason(interface, case, outcome, says):
    trace = run(hostile(case), interface)
    assert trace.outcome == outcome, trace.error
    assert re.search(says, trace.error), trace.error


@pytest.mark.slow
def test_an_endless_line_does_not_grow_the_bench(interface):
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    trace = run(hostile("endless-line"), interface)
    assert trace.outcome == "crashed"
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before < 100_000  # KB: well under 100 MB


def test_stderr_is_kept_bounded_with_its_last_words(interface):
    trace = run(hostile("stderr-flood"), interface)
    assert trace.outcome == "crashed" and "exit status 3" in trace.error
    tail = trace.error.split("last lines of the SUT's stderr:\n", 1)[1]
    assert tail.startswith("[") and "earlier bytes not kept]" in tail and tail.endswith("the last words")
    assert len(tail) <= STDERR_KEEP_BYTES + 100


@pytest.mark.slow
def test_a_flood_of_world_events_does_not_starve_the_pongs(interface):
    trace = run(hostile("flood"), interface)
    assert trace.outcome == "completed", trace.error
    assert sum(kind == "noise" for _, kind, _ in trace.world_events) == 1_000_000


@pytest.mark.slow
def test_an_adapter_that_stops_reading_ends_hung_saying_so(interface):
    body = "send rflex.Init\n" * 3000  # more than a pipe holds, written at once
    trace = run(hostile("deaf"), interface, body)
    assert trace.outcome == "hung"
    assert re.search(r"^the SUT took no input for 1 s: \d+ bytes of the line '\{\"op\":\"request\".* could not "
                     r"be written; the last line read from the SUT, \d+\.\d s before, was '\{\"op\": \"hello\"",
                     trace.error), trace.error


class Server:
    """A TCP 'adapter' served from this process by `behave(connection)`, once per connection."""

    def __init__(self, behave):
        self.listener = socket.create_server(("127.0.0.1", 0))
        self.address = "127.0.0.1:%d" % self.listener.getsockname()[1]
        self.behave = behave
        threading.Thread(target=self._serve, daemon=True).start()

    def _serve(self):
        while True:
            try:
                connection, _ = self.listener.accept()
            except OSError:
                return
            threading.Thread(target=self.behave, args=(connection,), daemon=True).start()

    def sut(self, **options) -> ExternalSut:
        return ExternalSut("tcp", address=self.address, **dict(probe_timeout_s=1.0, startup_s=10.0) | options)

    def close(self):
        self.listener.close()


def reset(connection):
    connection.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
    connection.close()


def nested_hello(connection):
    connection.recv(1 << 16)
    connection.sendall(b"[" * 100_000 + b"]" * 100_000 + b"\n")
    threading.Event().wait(30)


def hello_then_nothing(connection):
    connection.recv(1 << 16)
    connection.sendall(b'{"op": "hello", "proto": "untimely/1", "sut": "slowloris", "caps": []}\n')
    threading.Event().wait(30)  # never reads, never answers


@pytest.mark.slow
@pytest.mark.parametrize("behave, outcome, says", [
    (reset, "crashed", r"^the SUT ended before answering hello \(the (connection failed \(Connection reset by peer\)|"
                       r"SUT reset the connection as it accepted it)\)"),
    (nested_hello, "crashed", r"^JSON nested too deeply to read"),
    (hello_then_nothing, "hung", r"^ping 1 got no pong within the probe timeout .*; the last line read from the SUT, "
                                 r"\d+\.\d s before, was '\{\"op\": \"hello\""),
])
def test_a_hostile_tcp_adapter_ends_its_trace_with_the_reason(interface, behave, outcome, says):
    server = Server(behave)
    try:
        trace = run(server.sut(), interface)
    finally:
        server.close()
    assert trace.outcome == outcome, trace.error
    assert re.search(says, trace.error), trace.error
    assert trace.wall_s < 8  # not the start-up bound: the reason is known at once


@pytest.mark.slow
def test_a_campaign_whose_runs_all_crash_says_why_grouped_and_so_does_the_report(tmp_path, capsys):
    from harness.cli import main as cli
    db = tmp_path / "c.duckdb"
    boom = "boom=cmd:{python} tests/adapters/faulty.py --fault crash --after 0"
    assert cli(["campaign", "--sut", boom, "--mutants", "2", "--jobs", "1", "--time-scale", "10",
                "--db", str(db)]) == 0
    out = capsys.readouterr().out
    assert re.search(r"boom +3 runs: 0 completed, 0 hung, 3 crashed", out), out
    assert "crashed   3 run(s) on boom: the SUT closed its output before bye (exit status 3)" in out
    assert cli(["report", "--db", str(db), "--out", str(tmp_path / "report")]) == 0
    page = (tmp_path / "report" / "index.html").read_text()
    assert "why runs crashed" in page and "the SUT closed its output before bye (exit status 3)" in page


def test_a_reset_taken_by_a_write_is_the_reason_the_reader_reports(monkeypatch):
    """The kernel reports a reset once, to a write or to the reader: a reader that meets the end
    while the write that took the reset has not yet recorded it waits for that record."""
    told, was_reset = threading.Event(), threading.Event()
    server = Server(lambda connection: told.wait(30) and (reset(connection), was_reset.set()))
    channel, ends = TcpChannel(server.sut(), slot=0), []
    record = Channel._failed

    def record_late(self, error):  # the reader starts, and meets the end, before the reset is recorded
        self.start(lambda lines: ends.append(self.why_ended()))
        time.sleep(0.5)
        record(self, error)

    monkeypatch.setattr(Channel, "_failed", record_late)
    try:
        told.set()
        assert was_reset.wait(10)
        select.select([channel.socket], [], [], 10)  # the reset has arrived (it makes the socket readable): the write takes it
        channel.write('{"op": "hello"}\n')
        channel.reader.join(5)
    finally:
        channel.close()
        server.close()
    assert ends == ["the connection failed (Connection reset by peer)"]
