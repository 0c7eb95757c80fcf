"""The Node.js example adapter (examples/node/adapter.js), driven directly over stdio with
untimely/1 lines (docs/reference/protocol.md). Timeouts are generous: the machine may be loaded."""
from __future__ import annotations

import queue
import shlex
import shutil
import subprocess
import threading

import pytest

from harness import DEFAULT_MISSION_DIR, store
from harness.cli import main
from harness.sut.protocol import PROTO, decode, encode

from tests.support.paths import ROOT
ADAPTER = ROOT / "examples" / "node" / "adapter.js"
NODE = shutil.which("node")
TIME_SCALE = 10  # mission seconds per wall second: Init (0.5 s) takes 50 ms
PATIENCE_S = 15.0

pytestmark = pytest.mark.skipif(NODE is None, reason="node is not installed (.ci/run installs Debian's nodejs)")


def hello_fields(interface, time_scale=TIME_SCALE) -> dict:
    return {"proto": PROTO, "run": 1, "seed": 7, "time_scale": time_scale,
            "interface": interface.describe()}


class Adapter:
    """The adapter as a child process: lines in, parsed lines out (read by a thread)."""

    def __init__(self):
        self.process = subprocess.Popen([NODE, str(ADAPTER)], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                        stderr=subprocess.PIPE, text=True)
        self.lines: queue.Queue = queue.Queue()
        self.seen: list[dict] = []
        threading.Thread(target=self._read, daemon=True).start()
        self.next_id = 0

    def _read(self):
        for line in self.process.stdout:
            self.lines.put(decode(line))  # the bench's own check of every line
        self.lines.put(None)

    def send(self, op: str, **fields):
        self.process.stdin.write(encode(op, **fields))
        self.process.stdin.flush()

    def request(self, service: str, **args) -> int:
        self.next_id += 1
        module, name = service.split(".")
        self.send("request", id=self.next_id, module=module, service=name, args=args)
        return self.next_id

    def expect(self, **fields) -> dict:
        """The next line that has these fields (earlier lines are kept in `seen`)."""
        while True:
            message = self.lines.get(timeout=PATIENCE_S)
            assert message is not None, f"the adapter closed stdout while {fields} was awaited; seen {self.seen}"
            self.seen.append(message)
            if all(message.get(k) == v for k, v in fields.items()):
                return message

    def final(self, rqst_id: int) -> str:
        return self.expect(op="reply", id=rqst_id, kind="final")["code"]

    def replies(self, rqst_id: int) -> list[tuple[str, str | None]]:
        return [(m["kind"], m.get("code")) for m in self.seen if m["op"] == "reply" and m["id"] == rqst_id]

    def init(self, *modules: str) -> None:
        for module in modules:
            assert self.final(self.request(f"{module}.Init")) == "ok"

    def close(self):
        if self.process.poll() is None:
            self.process.kill()
        self.process.wait()
        for stream in (self.process.stdin, self.process.stdout, self.process.stderr):
            stream.close()


@pytest.fixture
def adapter(interface):
    a = Adapter()
    a.send("hello", **hello_fields(interface))
    yield a
    a.close()


def test_answers_hello_with_proto_sut_and_caps(adapter):
    answer = adapter.expect(op="hello")
    assert answer["proto"] == "untimely/1"
    assert "node" in answer["sut"]
    assert set(answer["caps"]) == {"internal", "world"}


def test_exec_request_gets_intermediate_then_ok_with_internal_ground_truth(adapter, interface):
    adapter.init("antenna")
    point = adapter.request("antenna.Point", az=135.0)
    assert adapter.final(point) == "ok"
    assert adapter.replies(point) == [("intermediate", None), ("final", "ok")]
    intermediate = next(m for m in adapter.seen if m["op"] == "reply" and m["kind"] == "intermediate")
    assert "code" not in intermediate
    truth = [(m["kind"], m["t"], m.get("code")) for m in adapter.seen if m["op"] == "internal" and m["id"] == point]
    assert [(kind, code) for kind, _, code in truth] == [("request", None), ("intermediate", None), ("final", "ok")]
    # Point slews for 2 mission seconds; internal t is in mission seconds (wall x time_scale)
    assert 1.9 <= truth[-1][1] - truth[0][1] <= 2 + PATIENCE_S * TIME_SCALE
    codes = [m["code"] for m in adapter.seen if m["op"] == "reply" and m["kind"] == "final"]
    assert set(codes) <= set(interface.replies)


def test_control_request_replies_ok_at_once_without_intermediate(adapter):
    params = adapter.request("ndd.SetParams", speed=0.6)
    assert adapter.final(params) == "ok"
    assert adapter.replies(params) == [("final", "ok")]


def test_ping_gets_its_pong(adapter):
    adapter.send("ping", id=41)
    assert adapter.expect(op="pong")["id"] == 41


def test_exec_before_init_is_rejected_wait_init(adapter):
    early = adapter.request("sick.OneShot")
    assert adapter.final(early) == "wait_init"
    assert adapter.replies(early) == [("final", "wait_init")]
    adapter.init("sick")
    assert adapter.final(adapter.request("sick.OneShot")) == "ok"


def test_stop_interrupts_the_modules_running_activities_only(adapter):
    adapter.init("sick", "aspect")
    laser = adapter.request("sick.ContinuousShot")
    fuse = adapter.request("aspect.Fuse")
    adapter.expect(op="reply", id=fuse, kind="intermediate")
    stop = adapter.request("sick.Stop")
    assert adapter.final(laser) == "interrupted"
    assert adapter.final(stop) == "ok"
    assert adapter.replies(fuse) == [("intermediate", None)]  # aspect's Fuse still runs
    assert adapter.final(adapter.request("aspect.Stop")) == "ok"
    assert adapter.replies(fuse) == [("intermediate", None), ("final", "interrupted")]


def test_a_new_request_interrupts_the_running_one_of_the_same_service(adapter):
    adapter.init("ndd")
    first = adapter.request("ndd.GotoPosition", x=9.0, y=4.0)
    second = adapter.request("ndd.GotoPosition", x=2.0, y=2.0)
    assert adapter.final(first) == "interrupted"
    assert adapter.final(second) == "ok"


def test_moving_during_communication_loses_the_link_and_reports_world_damage(adapter):
    adapter.init("antenna", "ndd")
    talk = adapter.request("antenna.Communication", duration=30.0)
    adapter.expect(op="reply", id=talk, kind="intermediate")
    goto = adapter.request("ndd.GotoPosition", x=9.0, y=4.0)
    assert adapter.final(talk) == "link_lost"
    damage = next(m for m in adapter.seen if m["op"] == "world")
    assert damage["kind"] == "moved_while_linked" and damage["detail"] == {"request": goto}
    assert adapter.final(goto) == "ok"


def test_bye_ends_the_adapter_with_status_0(adapter):
    adapter.expect(op="hello")
    adapter.send("bye")
    assert adapter.process.wait(timeout=PATIENCE_S) == 0


def test_stdin_eof_ends_the_adapter(adapter):
    adapter.init("rflex")
    adapter.request("rflex.TrackSpeedStart")  # a running activity does not keep it alive
    adapter.process.stdin.close()
    assert adapter.process.wait(timeout=PATIENCE_S) == 0


def test_a_catalogue_without_its_codes_is_refused_with_an_error(interface):
    a = Adapter()
    try:
        hello = hello_fields(interface)
        hello["interface"]["replies"] = {"ok": "T", "interrupted": "Z"}
        a.send("hello", **hello)
        assert a.expect(op="error")["message"] == ("the reply catalogue lacks wait_init, link_lost, "
                                                   "which this layer replies")
        assert a.process.wait(timeout=PATIENCE_S) == 1
    finally:
        a.close()


@pytest.mark.slow
def test_golden_mission_through_the_bench_completes_with_every_final_in_the_catalogue(interface, tmp_path):
    db = tmp_path / "node.duckdb"
    command = f"{shlex.quote(NODE)} {shlex.quote(str(ADAPTER))}"
    assert main(["run", str(DEFAULT_MISSION_DIR / "golden.mission"), "--sut", f"toy=cmd:{command}",
                 "--time-scale", str(TIME_SCALE), "--db", str(db)]) == 0
    con = store.connect(db, read_only=True)
    assert con.execute("select sut, outcome, error from traces").fetchall() == [("toy", "completed", None)]
    finals = con.execute("""
        select r.module, r.service, f.reply from events r
        left join events f on f.rqst_id = r.rqst_id and f.kind = 'final'
        where r.kind = 'request' order by r.seq""").fetchall()
    assert len(finals) == 23 and all(reply in interface.replies for _, _, reply in finals)
    # the activities that run until stopped are interrupted by the mission's Stops, the rest end ok
    assert {(m, s) for m, s, reply in finals if reply != "ok"} == {
        ("rflex", "TrackSpeedStart"), ("sick", "ContinuousShot"), ("aspect", "Fuse")}
    assert {reply for _, _, reply in finals} == {"ok", "interrupted"}
    # the adapter's ground truth (internal) is stored beside the observed timeline
    assert con.execute("select count(*) from internal_events where kind = 'final'").fetchone() == (23,)
    pings, p50, sut_info = con.execute("select pings, rtt_p50_s, sut_info from trace_runs").fetchone()
    assert pings >= 1 and 0 < p50 < PATIENCE_S and "node" in sut_info
    con.close()
