"""The golden mission end to end through `python -m harness run` (issue 2's acceptance)."""
import json

import pytest

from harness import DEFAULT_MISSION_DIR, store
from harness.cli import main

GOLDEN = str(DEFAULT_MISSION_DIR / "golden.mission")


@pytest.fixture(scope="module")
def db(tmp_path_factory):
    path = tmp_path_factory.mktemp("golden") / "runs.duckdb"
    for seed in (7, 7, 8):
        assert main(["run", GOLDEN, "--sut", "reference", "--seed", str(seed), "--db", str(path)]) == 0
    con = store.connect(path, read_only=True)
    yield con
    con.close()


def finals(con, trace_id):
    return con.execute("""
        select r.service, f.module, f.reply from events f
        join events r on r.trace_id = f.trace_id and r.rqst_id = f.rqst_id and r.kind = 'request'
        where f.trace_id = ? and f.kind = 'final' order by f.seq""", [trace_id]).fetchall()


def test_golden_on_reference_ends_every_request_ok_or_stopped(db):
    rows = finals(db, 1)
    requests = db.execute("select count(*) from events where trace_id = 1 and kind = 'request'").fetchone()[0]
    assert len(rows) == requests  # every request got its final reply
    interrupted = {(m, s) for s, m, reply in rows if reply != "ok"}
    assert {reply for _, _, reply in rows} <= {"ok", "interrupted"}
    # only the activities that run until stopped end interrupted, by the mission's Stops
    assert interrupted == {("rflex", "TrackSpeedStart"), ("sick", "ContinuousShot"), ("aspect", "Fuse")}
    assert {m for _, m, _ in rows} == {"rflex", "sick", "aspect", "ndd", "antenna"}
    assert db.execute("select outcome from traces where trace_id = 1").fetchone() == ("completed",)


def test_golden_on_reference_is_collision_free(db):
    kinds = [k for (k,) in db.execute("select kind from world_events where trace_id = 1").fetchall()]
    assert "collision" not in kinds


def test_same_seed_same_events_other_seed_other_delays(db):
    def events(trace_id):
        return db.execute("select seq, t, kind, rqst_id, module, service, args, reply from events "
                          "where trace_id = ? order by seq", [trace_id]).fetchall()
    assert events(1) == events(2)
    other = events(3)
    assert [e[2:] for e in other] != [] and [e[1] for e in other] != [e[1] for e in events(1)]
    seeds = db.execute("select seed from traces order by trace_id").fetchall()
    assert seeds == [(7,), (7,), (8,)]


def test_each_run_is_its_own_campaign_with_its_config(db):
    rows = db.execute("select campaign_id, seed, config from campaigns order by campaign_id").fetchall()
    assert [r[0] for r in rows] == [1, 2, 3]
    assert json.loads(rows[0][2]) == {"kind": "run", "sut": "reference", "max_delay": 0.003,
                                      "target": str(DEFAULT_MISSION_DIR.resolve())}


def test_unknown_variant_is_refused_with_the_known_ones(tmp_path, capsys):
    code = main(["run", GOLDEN, "--sut", "bip-c", "--db", str(tmp_path / "x.duckdb")])
    err = capsys.readouterr().err
    assert code != 0 and "bip-c" in err and "reference" in err
