"""Runs against external SUTs over untimely/1: a well-behaved adapter, every fault of docs/reference/protocol.md,
the TCP path, and the command line. The adapters are real processes (tests/adapters/faulty.py,
the simulator adapter); timing bounds are generous for a loaded machine."""
import re
import subprocess
import sys

import pytest

from harness import DEFAULT_MISSION_DIR, ROOT, store
from harness.cli import main as cli
from harness.errors import UntimelyError
from harness.sut.external.runner import run_external
from harness.target.script import parse
from harness.sut.definitions import resolve
from harness.target.suts import ExternalSut
from tests.support.external import FAULTY, SHORT


def faulty(fault: str, after: int = 3, **options) -> ExternalSut:
    settings = dict(time_scale=10.0, probe_timeout_s=1.0, startup_s=10.0) | options
    return ExternalSut("faulty", command=f"{{python}} {FAULTY} --fault {fault} --after {after}", **settings)


def run(sut: ExternalSut, interface, body: str = SHORT):
    return run_external(parse(body, "short"), sut, 7, interface, slot=2)


@pytest.mark.slow
def test_a_well_behaved_adapter_gives_a_completed_trace_with_its_latency(interface):
    trace = run(faulty("none"), interface)
    assert trace.outcome == "completed", trace.error
    finals = [e for e in trace.events if e[2] == "final"]
    assert [e[3] for e in trace.events if e[2] == "request"] == list(range(1, 7))
    assert sorted(e[3] for e in finals) == list(range(1, 7)) and {e[7] for e in finals} == {"ok"}
    assert all(a[1] <= b[1] for a, b in zip(trace.events, trace.events[1:])), "observed times go back"
    assert 20 < trace.sim_s < 40 and trace.wall_s < trace.sim_s / 2
    p = trace.provenance
    assert p["sut_info"] == "faulty test adapter on slot 2" and p["time_scale"] == 10.0 and p["pings"] >= 1
    assert 0 < p["rtt_p50_s"] <= p["rtt_p95_s"] <= p["rtt_max_s"] < 1.0


@pytest.mark.slow
@pytest.mark.parametrize("fault, outcome, says", [
    ("crash", "crashed", r"the SUT closed its output before bye \(exit status 3\)"
                         r"[\s\S]*last lines of the SUT's stderr:\n.*slot 2\nadapter: simulated crash, exiting 3"),
    ("garbage", "crashed", r"not a JSON line .*; the SUT's line: 'this is not json'"),
    ("two-finals", "crashed", r"after its final reply 'ok'; the SUT's line: '\{\"op\": \"reply\", \"id\": \d, "
                              r"\"kind\": \"final\", \"code\": \"ok\"\}'"),
    ("unknown-code", "crashed", r"replied 'kaput' to request 4 \(sick.SetParams\); the interface catalogue "
                                r"has no such code; the SUT's line"),
    ("unknown-op", "crashed", r"unknown op 'dance'; expected one of hello, reply"),
    ("error", "crashed", r"the SUT gave up with an error: motor driver lost"),
    ("stray-reply", "crashed", r"reply for request 99999, which was never sent"),
    ("silent", "hung", None),
])
def test_a_misbehaving_adapter_ends_its_trace_with_the_right_outcome(interface, fault, outcome, says):
    trace = run(faulty(fault), interface)
    assert trace.outcome == outcome, trace.error
    if says:
        assert re.search(says, trace.error), trace.error
    # What was observed before the fault (at the 4th request) is kept.
    assert sum(e[2] == "final" for e in trace.events) >= 2


@pytest.mark.slow
def test_a_silent_adapter_is_hung_and_its_pending_requests_keep_no_final(interface):
    trace = run(faulty("silent"), interface)
    assert trace.outcome == "hung"
    assert any(kind == "probe_unanswered" for _, kind, _ in trace.world_events)
    requested = {e[3] for e in trace.events if e[2] == "request"}
    answered = {e[3] for e in trace.events if e[2] == "final"}
    assert answered < requested  # nothing invented for the requests it never answered


def test_an_adapter_that_never_says_hello_is_crashed(interface):
    trace = run(faulty("no-hello", startup_s=1.0), interface)
    assert trace.outcome == "crashed" and trace.error.startswith("no hello answer within 1 s of starting")
    assert trace.events == []


def test_an_adapter_that_cannot_be_started_is_the_users_error(interface):
    sut = ExternalSut("ghost", command="/nonexistent/adapter --flag")
    with pytest.raises(UntimelyError, match=r"--sut ghost: cannot start '/nonexistent/adapter --flag': .*No such file"):
        run(sut, interface)


@pytest.mark.slow
def test_the_simulator_adapter_over_tcp(interface):
    server = subprocess.Popen([sys.executable, "-m", "harness.sut.simulated", "--variant", "reference",
                               "--listen", "127.0.0.1:0"], stderr=subprocess.PIPE, text=True, cwd=ROOT)
    try:
        port = re.search(r"listening on 127.0.0.1:(\d+)", server.stderr.readline()).group(1)
        trace = run(ExternalSut("sim", address=f"127.0.0.1:{port}", time_scale=10.0), interface)
    finally:
        server.kill()
        server.wait()
    assert trace.outcome == "completed", trace.error
    finals = {e[3]: e[7] for e in trace.events if e[2] == "final"}
    assert finals == {1: "ok", 2: "ok", 3: "ok", 4: "ok", 5: "interrupted", 6: "ok"}
    # The simulator reports its internal instants: every request taken and answered.
    assert sorted(e[3] for e in trace.internal_events if e[2] == "request") == list(range(1, 7))


def test_an_unreachable_tcp_sut_is_the_users_error(interface):
    with pytest.raises(UntimelyError, match=r"--sut sim: cannot reach tcp://127.0.0.1:1 \(.*\); start the adapter"):
        run(ExternalSut("sim", address="127.0.0.1:1", startup_s=2.0), interface)


def test_sut_entries_are_checked_naming_the_entry(tmp_path):
    names, external = resolve("genom,toy=cmd:node adapter.js,far=tcp://10.0.0.1:7400", tmp_path, 4.0)
    assert names == ["genom", "toy", "far"]
    assert external["toy"].argv() == ["node", "adapter.js"] and external["far"].address == "10.0.0.1:7400"
    assert external["toy"].time_scale == external["far"].time_scale == 4.0
    with pytest.raises(UntimelyError, match=r"--sut 'far=tcp://nowhere': address = 'nowhere'; give HOST:PORT"):
        resolve("far=tcp://nowhere", tmp_path)
    with pytest.raises(UntimelyError, match=r"--sut 'toy=cmd:node \"adapter': command = 'node \"adapter': "
                                            r"No closing quotation; close the quote"):
        resolve('toy=cmd:node "adapter', tmp_path)
    with pytest.raises(UntimelyError, match=r"--sut 'x=ssh:robot': write NAME=cmd:COMMAND or NAME=tcp://HOST:PORT"):
        resolve("x=ssh:robot", tmp_path)
    # --time-scale 0 is refused by the command line's parser, its one check (tests/project/test_commands.py)


def test_suts_file_entries_are_checked_naming_file_and_key(tmp_path):
    (tmp_path / "suts.toml").write_text('[ros]\ncommand = "launch"\nslots = 8\ntime_scale = 2\n'
                                        '[bad]\ncommand = "x"\nslots = "many"\n')
    with pytest.raises(UntimelyError, match=r"suts.toml:7: bad.slots = 'many'; give a whole number > 0"):
        resolve("ros", tmp_path)
    (tmp_path / "suts.toml").write_text('[ros]\ncomand = "launch"\n')
    with pytest.raises(UntimelyError, match=r"suts.toml:2: unknown key 'comand'; a SUT takes command,"):
        resolve("ros", tmp_path)
    for table, message in [('ros = 5', r"suts.toml:1: 'ros': a SUT is a table named by"),
                           ('[ros]\ncommand = "x"\nenv = ["A=1"]', r"suts.toml:3: ros.env = \['A=1'\]; give a table"),
                           ('[ros]\ncommand = "x"\nstartup_s = inf', r"suts.toml:3: ros.startup_s = inf; give a number")]:
        (tmp_path / "suts.toml").write_text(table + "\n")
        with pytest.raises(UntimelyError, match=message):
            resolve("ros", tmp_path)
    (tmp_path / "suts.toml").write_text('[ros]\ncommand = "launch"\nslots = 8\ntime_scale = 2\n')
    names, external = resolve("ros", tmp_path)
    # a command of a suts.toml starts in its folder, so it may name the adapter relative to it
    assert external["ros"] == ExternalSut("ros", command="launch", slots=8, time_scale=2.0, cwd=str(tmp_path.resolve()))


def test_an_external_sut_is_a_suts_table_with_a_name_and_round_trips_through_the_store(tmp_path):
    from harness.store.record import RunRecord, record_of, stored_json
    from harness.target.suts import KEYS, SutTable
    sut = ExternalSut("toy", command="adapter")
    # one home for the fields and their defaults: a table with no key but its transport gives them
    assert {key: getattr(sut, key) for key in KEYS} == SutTable(command="adapter").model_dump()
    # campaigns.config stores every field of a SUT that --sut or suts.toml defines, cwd only when set
    (tmp_path / "suts.toml").write_text('[kept]\ncommand = "adapter"\nslots = 3\n')
    (_, given), (_, defined) = resolve("toy=cmd:adapter", tmp_path), resolve("kept", tmp_path)
    for defined_sut, keys in [(given["toy"], {"name", *KEYS}), (defined["kept"], {"name", *KEYS, "cwd"})]:
        record = RunRecord(sut=defined_sut.name, external={defined_sut.name: defined_sut})
        assert set(record.stored()["external"][defined_sut.name]) == keys
        assert record_of(stored_json(record)) == record and stored_json(record_of(stored_json(record))) == stored_json(record)
    with pytest.raises(ValueError, match="give exactly one of command"):
        ExternalSut("both", command="adapter", address="127.0.0.1:7400")


@pytest.mark.slow
def test_run_on_the_command_line_stores_where_and_how_fast_it_ran(tmp_path, capsys):
    db = tmp_path / "r.duckdb"
    mission = tmp_path / "short.mission"
    mission.write_text(SHORT)
    (tmp_path / "interface.toml").write_bytes((DEFAULT_MISSION_DIR / "interface.toml").read_bytes())
    (tmp_path / "world.toml").write_bytes((DEFAULT_MISSION_DIR / "world.toml").read_bytes())
    sut = f"sim=cmd:{{python}} -m harness.sut.simulated --variant bare --mission {DEFAULT_MISSION_DIR}"
    assert cli(["run", str(mission), "--sut", sut, "--time-scale", "10", "--db", str(db)]) == 0
    out = capsys.readouterr().out
    assert "outcome    completed" in out and re.search(r"interface  \d+ pings on .*, round trip p50", out)
    con = store.connect(db, read_only=True)
    sut_name, time_scale, pings = con.execute("select sut, time_scale, pings from traces join trace_runs "
                                              "using (trace_id)").fetchone()
    assert (sut_name, time_scale) == ("sim", 10.0) and pings >= 1
