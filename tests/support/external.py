"""External SUTs for the tests: the faulty adapter, a short script, a yes-man adapter, and a campaign
against an external SUT compared with the same campaign in process."""
import re

from harness import store
from harness.cli import main as cli
from tests.support.paths import ADAPTERS

FAULTY = ADAPTERS / "faulty.py"


SHORT = """send rflex.Init as ri
send sick.Init as si
wait all
send rflex.SetMode mode=velocity as m
send sick.SetParams fov=180 range=8 as p
wait all
send rflex.TrackSpeedStart as track
sleep 20
send rflex.Stop as stop
wait all
"""


def campaign(db, *options):
    return cli(["campaign", "--db", str(db), "--seed", "5", *options])


def assert_judges_like_in_process(db, out: str, there: str, time_scale: int, min_runs: int = 16):
    """A campaign of `reference` in process and `there` on the same scripts: the latency line is
    printed, every run completed on both, every verdict that differs is suspicious on one side,
    and Table III is the same row for row when none differs. Returns the open store."""
    assert re.search(rf"{there} +\d+ +\d+ +{time_scale} +[\d.e-]+ +[\d.e-]+ +[\d.e-]+ +[\d.e-]+", out), out
    con = store.connect(db, read_only=True)
    outcomes = con.execute("select sut, outcome, count(*) from traces group by all order by all").fetchall()
    runs = outcomes[0][2]
    assert outcomes == [("reference", "completed", runs), (there, "completed", runs)] and runs >= min_runs
    pairs, differ, unflagged = con.execute("""
        with judged as (
            select t.sut, t.script_id, v.property_id, v.rqst_id, v.verdict, v.suspicious
            from verdicts v join traces t using (trace_id)
        ),
        paired as (
            select i.verdict as here, o.verdict as there, i.suspicious or o.suspicious as suspicious
            from judged i join judged o using (script_id, property_id, rqst_id)
            where i.sut = 'reference' and o.sut = $there
        )
        select count(*), count(*) filter (where here <> there),
               count(*) filter (where here <> there and not suspicious)
        from paired""", {"there": there}).fetchone()
    assert pairs > 25 * runs and unflagged == 0, f"{differ} of {pairs} verdicts differ, {unflagged} not suspicious"
    if differ == 0:
        table = "select * exclude (sut) from tp_rates where sut = ? order by all"
        assert con.execute(table, [there]).fetchall() == con.execute(table, ["reference"]).fetchall()
    return con


# An adapter that accepts everything at once: TrackSpeedStart before Init is not refused (an FN on PEX).
ADAPTER = '''import json, sys
for line in sys.stdin:
    msg = json.loads(line)
    if msg["op"] == "hello":
        print(json.dumps({"op": "hello", "proto": "untimely/1", "sut": "yes-man", "caps": []}), flush=True)
    elif msg["op"] == "request":
        print(json.dumps({"op": "reply", "id": msg["id"], "kind": "final", "code": "ok"}), flush=True)
    elif msg["op"] == "ping":
        print(json.dumps({"op": "pong", "id": msg["id"]}), flush=True)
    elif msg["op"] == "bye":
        break
'''
