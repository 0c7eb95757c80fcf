"""The `taken` reply (untimely/1's optional interface extension, issue 23): the simulator adapter
with --taken replies it when its control task takes each request, the bench stores it in
taken_events, and the oracles place the request there. A real adapter process, a short script."""
import pytest

from harness import DEFAULT_MISSION_DIR, store
from harness.cli import main as cli
from harness.target.suts import ExternalSut
from harness.sut.external.runner import run_external
from harness.target.script import parse

SHORT = """send rflex.Init as ri
send sick.Init as si
wait all
send rflex.SetMode mode=velocity as m
send sick.SetParams fov=180 range=8 as p
send rflex.TrackSpeedStart as track
sleep 5
send rflex.Stop as stop
send sick.Stop as sstop
wait all
"""
COMMAND = f"{{python}} -m harness.sut.simulated --variant reference --mission {DEFAULT_MISSION_DIR} --taken"


def test_each_request_gets_one_taken_reply_between_its_sending_and_its_final(interface):
    sut = ExternalSut("sim-taken", command=COMMAND, time_scale=10.0)
    trace = run_external(parse(SHORT, "short"), sut, 7, interface)
    assert trace.outcome == "completed", trace.error
    sent = {e[3]: (e[1], e[0]) for e in trace.events if e[2] == "request"}
    final = {e[3]: (e[1], e[0]) for e in trace.events if e[2] == "final"}
    taken = {rqst_id: (t, seq) for seq, t, rqst_id in trace.taken_events}
    assert sorted(taken) == sorted(sent) == list(range(1, 8)) and len(trace.taken_events) == 7
    assert all(sent[r] < taken[r] < final[r] for r in sent)
    assert not {seq for seq, *_ in trace.taken_events} & {e[0] for e in trace.events}


@pytest.mark.slow
def test_the_oracles_place_requests_at_their_taken_replies_and_see_the_layers_order(tmp_path):
    db, mission = str(tmp_path / "t.duckdb"), tmp_path / "short.mission"
    mission.write_text(SHORT)
    for name in ("interface.toml", "world.toml", "properties.toml"):
        (tmp_path / name).write_bytes((DEFAULT_MISSION_DIR / name).read_bytes())
    assert cli(["run", str(mission), "--sut", f"sim-taken=cmd:{COMMAND}", "--db", db]) == 0
    assert cli(["analyze", "--db", db, "--properties", str(tmp_path / "properties.toml")]) == 0
    con = store.connect(db, read_only=True)
    placed = con.execute("""select count(*), count(*) filter (where r.t = k.t and r.seq = k.seq)
                            from requests r join taken_events k using (trace_id, rqst_id)""").fetchone()
    assert placed == (7, 7)
    # every instant an oracle reads now comes down the adapter's one channel, in the layer's order
    assert con.execute("select count(*) from verdicts").fetchone()[0] > 0
    assert con.execute("select count(*) from inversions").fetchone()[0] == 0
