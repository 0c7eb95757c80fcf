"""Shrinking: ddmin itself, then one shrunk reproducer per variant's defect (replayed with `run`),
its stored script, the report's link to it, and the refusals."""
import json
import os
import re
import shlex
import subprocess
import sys
from pathlib import Path
from types import SimpleNamespace

import duckdb
import pytest

from harness import DEFAULT_MISSION_DIR, store
from harness.cli import main
from harness.errors import BudgetSpent, StoreError
from harness.mutator.ddmin import ddmin
from harness.target.script import parse
from harness.campaign.context import CampaignContext
from harness.campaign.representatives import representatives
from harness.campaign import shrink as shrink_module
from harness.campaign.shrink import MIN_SLEEP_S, Behaviour, Original, replay_command, shorter_sleeps, store_shrink
from harness.sut.executive import run_script
from harness.target.suts import ExternalSut
from harness.dispatch import transport
from harness.target.mission import load_mission
from harness.store.sql import render_query

MAX_STEPS = 10


def test_ddmin_finds_a_one_minimal_sublist_keeping_the_order():
    calls = []

    def needs_3_and_7(items):
        calls.append(items)
        return 3 in items and 7 in items
    assert ddmin(list(range(20)), needs_3_and_7) == [3, 7]
    assert ddmin([5, 1], lambda items: items == [5, 1]) == [5, 1]  # nothing can go
    assert len(calls) < 60


def test_sleeps_are_halved_while_the_behaviour_stays():
    steps = list(parse("send a.B\nsleep 8\nsend a.C\nsleep 1\n").steps)
    # the behaviour needs the first sleep to last at least 1.5 s; the second does not matter
    shorter = shorter_sleeps(steps, lambda s: s[1].seconds >= 1.5)
    assert [s.seconds for s in shorter if s.op == "sleep"] == [2.0, 0.0156]
    assert 0.0156 / 2 < MIN_SLEEP_S


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    db = tmp_path_factory.mktemp("shrink") / "c.duckdb"
    assert main(["campaign", "--strategy", "targeted", "--mutants", "60", "--sut", "genom,bip-a,bip-b,bare",
                 "--db", str(db), "--jobs", "2"]) == 0
    return db


def _shrunk(db_or_con) -> list[dict]:
    """Every shrunk reproducer, as the report reads them (sql/report/shrunk_reproducers.sql)."""
    con = db_or_con if isinstance(db_or_con, duckdb.DuckDBPyConnection) else store.connect(db_or_con, read_only=True)
    try:
        cursor = con.execute(render_query("shrunk_reproducers"))
        names = [d[0] for d in cursor.description]
        return [dict(zip(names, row)) for row in cursor.fetchall()]
    finally:
        if con is not db_or_con:
            con.close()


def _query(db, sql, params=()):
    con = store.connect(db, read_only=True)
    try:
        return con.execute(sql, list(params)).fetchall()
    finally:
        con.close()


# One behaviour per variant, each the mark of one defect or missing protection (missions/dala/layer.toml).
DEFECTS = {
    "genom": ("FP", "AIB(%"),  # init_interrupts: an Init interrupts the module's running activities
    "bip-a": ("hung", None),  # deadlock_on_dominated_start
    "bip-b": ("hung", None),  # deadlock_on_excluded_start
    "bare": ("FN", "PRE(%"),  # no protection: the missing PRE connector lets x run before Q
}


@pytest.mark.slow
@pytest.mark.parametrize("sut", DEFECTS)
def test_each_variants_defect_shrinks_to_a_replayable_reproducer(campaign, tmp_path, capsys, sut):
    verdict, like = DEFECTS[sut]
    found = _query(campaign, "select property_id, representative from bad_behaviours where sut = ? and verdict = ? "
                             "and coalesce(property_id like ?, true) order by traces desc limit 1",
                   [sut, verdict, like])
    assert found, f"the campaign shows no {verdict} {like or ''} on {sut}"
    prop, trace_id = found[0]
    capsys.readouterr()
    assert main(["shrink", str(trace_id), "--db", str(campaign), "--out", str(tmp_path)]
                + (["--property", prop, "--verdict", verdict] if prop else [])) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"{verdict} on {prop} on {sut}: " if prop else f"hang on {sut}: ")
    path = tmp_path / re.search(r"(script-\d+\.mission)", out).group(1)
    script_id, parent, kind, mutations, body = _query(
        campaign, "select script_id, parent, kind, mutations, body from scripts order by script_id desc limit 1")[0]
    assert kind == "shrunk" and path.name == f"script-{script_id}.mission" and json.loads(mutations) == []
    assert parent == _query(campaign, "select script_id from traces where trace_id = ?", [trace_id])[0][0]
    # what was shrunk: the shrink's record (campaigns.config), read by the report's query
    (record,) = [r for r in _shrunk(campaign) if r["script_id"] == script_id]
    assert (record["trace_id"], record["sut"], record["verdict"], record["property_id"]) == (trace_id, sut, verdict, prop)
    assert len(parse(body).steps) == record["steps_after"] <= MAX_STEPS < record["steps_before"]
    # every run it made (the re-run that named the behaviour, then the shrink's) is a stored trace of the
    # shrink's campaign, linked to the trace, left out of Tables II-IV and the findings
    runs, originals, counted, findings = _query(campaign, """
        select count(*), count(distinct r.original), count(*) filter (where s.counted),
               count(*) filter (where r.trace_id in (select trace_id from trace_findings))
        from traces t join shrink_runs r using (trace_id) left join trace_scope s using (trace_id)
        where t.campaign_id = (select campaign_id from scripts where script_id = ?)""", [script_id])[0]
    assert (runs, originals, counted, findings) == (record["runs"] + 1, 1, 0, 0)
    assert _query(campaign, "select original from shrink_runs r join traces t using (trace_id) "
                            "where t.campaign_id = (select campaign_id from scripts where script_id = ?) limit 1",
                  [script_id]) == [(trace_id,)]
    # the file replays with the command its header gives, as written, from another folder, and shows
    # the same behaviour
    replay = path.read_text().splitlines()[1].split("# Replay: ")[1]
    replay_db, elsewhere = tmp_path / "replay.duckdb", tmp_path / "elsewhere"
    assert replay.startswith("untimely run /") and f"--sut {sut}" in replay and "world" not in replay
    elsewhere.mkdir()
    subprocess.run(f"{replay} --db {shlex.quote(str(replay_db))}", shell=True, cwd=elsewhere, timeout=300,
                   env={**os.environ, "PATH": f"{Path(sys.executable).parent}:{os.environ['PATH']}"})
    assert main(["analyze", "--db", str(replay_db)]) == 0
    if verdict == "hung":
        assert _query(replay_db, "select outcome from traces") == [("hung",)]
    else:
        assert _query(replay_db, "select count(*) from verdicts where property_id = ? and verdict = ?",
                      [prop, verdict])[0][0] >= 1


@pytest.mark.slow
def test_the_trace_page_links_the_minimal_reproducer(campaign, tmp_path):
    trace_id = _query(campaign, "select representative from bad_behaviours "
                                "where sut = 'bip-a' and verdict = 'hung'")[0][0]
    assert main(["shrink", str(trace_id), "--db", str(campaign), "--out", str(tmp_path / "s")]) == 0
    script_id = _query(campaign, "select max(script_id) from scripts where kind = 'shrunk'")[0][0]
    assert main(["report", "--db", str(campaign), "--out", str(tmp_path / "r")]) == 0  # a hung trace has a page
    page = (tmp_path / "r" / "traces" / f"trace-{trace_id}.html").read_text()
    assert f'href="../shrunk/script-{script_id}.mission"' in page
    written = (tmp_path / "r" / "shrunk" / f"script-{script_id}.mission").read_text()
    assert written.endswith(_query(campaign, "select body from scripts where script_id = ?", [script_id])[0][0])


@pytest.mark.slow
def test_a_trace_without_the_behaviour_is_refused_naming_it(campaign, capsys):
    good = _query(campaign, "select min(trace_id) from traces where sut = 'bip-b' and outcome = 'completed' and "
                            "trace_id not in (select trace_id from verdicts where verdict in ('FN', 'FP'))")[0][0]
    assert main(["shrink", str(good), "--db", str(campaign)]) == 2
    assert f"trace {good} (bip-b) shows no bad behaviour when re-run" in capsys.readouterr().err
    assert main(["shrink", "99999", "--db", str(campaign)]) == 2
    assert "no trace 99999 in the store" in capsys.readouterr().err
    bad = _query(campaign, "select representative from bad_behaviours "
                           "where sut = 'bare' and verdict = 'FN' limit 1")[0][0]
    assert main(["shrink", str(bad), "--db", str(campaign), "--property", "NOPE"]) == 2
    assert f"trace {bad} has no FN or FP on 'NOPE' when re-run; it has: FN on " in capsys.readouterr().err
    assert main(["shrink", str(bad), "--db", str(campaign), "--verdict", "FP"]) == 2
    assert "--verdict FP needs --property" in capsys.readouterr().err


@pytest.mark.slow
def test_campaign_shrink_does_every_distinct_behaviour_once(tmp_path, capsys):
    db = tmp_path / "c.duckdb"
    args = ["campaign", "--strategy", "targeted", "--mutants", "6", "--sut", "bip-a", "--db", str(db), "--jobs", "2",
            "--shrink"]
    assert main(args) == 0
    out = capsys.readouterr().out
    behaviours = _query(db, "select sut, verdict, property_id from bad_behaviours order by all")
    shrunk = [(r["sut"], r["verdict"], r["property_id"]) for r in _shrunk(db)]
    assert behaviours and sorted(shrunk, key=str) == sorted(behaviours, key=str)
    assert out.count(" shrunk from ") == len(behaviours)
    assert all((tmp_path / "shrunk" / f"script-{i}.mission").exists()
               for (i,) in _query(db, "select script_id from scripts where kind = 'shrunk'"))
    assert main(args) == 0  # again: every behaviour has its reproducer, nothing is shrunk twice
    assert " shrunk from " not in capsys.readouterr().out
    assert len(_query(db, "select 1 from scripts where kind = 'shrunk'")) == len(behaviours)


def _runner_broken_on_genom(script, sut, *args, **kwargs):
    """The simulator, broken on purpose for one variant (runs in the shrink's worker processes)."""
    if sut == "genom":
        raise RuntimeError("the genom simulator broke on purpose")
    return run_script(script, sut, *args, **kwargs)


@pytest.mark.slow
def test_a_shrink_that_fails_is_recorded_and_shown_and_the_others_go_on(tmp_path):
    db = tmp_path / "c.duckdb"
    assert main(["campaign", "--strategy", "targeted", "--mutants", "6", "--sut", "genom,bip-a", "--db", str(db),
                 "--jobs", "2"]) == 0
    con = store.connect(db)
    behaviours = con.execute("select sut, verdict, property_id from bad_behaviours order by all").fetchall()
    assert {sut for sut, *_ in behaviours} == {"genom", "bip-a"}
    target = load_mission(DEFAULT_MISSION_DIR)
    setup = transport.setup(_runner_broken_on_genom, target.interface_file, target.world_file, 0.003)
    ctx = CampaignContext(con=con, db=str(db), target=target, golden=target.golden(), golden_text="", properties=target.properties(),
                          config={}, setup=setup, executor=None, jobs=2, shrink_to=tmp_path / "shrunk")
    lines = []
    representatives(ctx, lines.append)
    assert len(lines) == len(behaviours)
    failed = [line for line in lines if "not shrunk" in line]
    # the broken runs crash, so the script no longer shows its behaviour: the worker's UntimelyError says so
    assert failed and all(re.fullmatch(r".* on genom: not shrunk \(table shrink_failures\): trace \d+'s script does "
                                       r"not show the .* again when re-run with seed \d+; it cannot be shrunk", line)
                          for line in failed)
    assert len(failed) == sum(sut == "genom" for sut, *_ in behaviours)
    assert con.execute("select sut, verdict, property_id from shrink_failures order by all").fetchall() == [
        b for b in behaviours if b[0] == "genom"]
    shrunk = [(r["sut"], r["verdict"], r["property_id"]) for r in _shrunk(con)]
    assert sorted(shrunk, key=str) == sorted((b for b in behaviours if b[0] == "bip-a"), key=str)


def test_a_store_older_than_shrunk_scripts_is_refused_and_left_as_it_was(tmp_path):
    con = store.connect()
    con.execute("drop table scripts")  # as a store made before shrunk scripts had it
    con.execute("""create table scripts (script_id integer primary key, campaign_id integer not null,
                   kind varchar not null check (kind in ('golden', 'mutant')), parent integer,
                   mutations json not null, body varchar not null, valid boolean not null, invalid_reason varchar)""")
    orig = Original(1, 1, "genom", 7, "hung", "send rflex.Init\n", Path("missions/dala"), 0.003, {})
    with pytest.raises(StoreError, match="this store predates shrunk scripts"):
        store_shrink(con, orig, Behaviour("genom", "hung"), parse("send rflex.Init\n"), 3)
    assert con.execute("select count(*) from campaigns").fetchone() == (0,)


def test_a_replay_line_names_the_installed_command_absolute_paths_and_no_missing_world(tmp_path):
    """Issue 48: the line named a bare `python` (a checkout's) and a world.toml the target lacked."""
    target = tmp_path / "target"
    target.mkdir()
    (target / "interface.toml").write_text("")
    orig = Original(7, 3, "ros2-node", 42, "completed", "", target, 0.003, {"ros2-node": ExternalSut("ros2-node", command="adapter", time_scale=2.0)})
    words = shlex.split(replay_command(orig, Path("shrunk") / "script-9.mission"))
    assert words == ["untimely", "run", str(Path("shrunk/script-9.mission").resolve()), "--sut", "ros2-node",
                     "--seed", "42", "--max-delay", "0.003", "--interface", str(target / "interface.toml"),
                     "--time-scale", "2"]


class Spending(Original):
    """A shrink's original on no SUT: a run hangs while its script sends rflex.Init (the behaviour),
    and the budget is spent after `runs` runs."""
    runs = 4

    def run(self, body):
        if len(self.made) == self.runs:
            raise BudgetSpent()
        trace = SimpleNamespace(outcome="hung" if "rflex.Init" in body else "completed")
        self.made.append((body, trace))
        return trace


def test_a_shrink_the_budget_cuts_short_keeps_the_smallest_script_a_run_showed_it_with(monkeypatch):
    monkeypatch.setattr(shrink_module, "Judge", lambda *args: SimpleNamespace(verdicts=lambda traces: [[]]))
    body = "".join(f"send {service}\nsleep 1\n" for service in ("sick.Init", "rflex.Init", "ndd.Init", "aspect.Init"))
    orig = Spending(1, 1, "genom", 0, "hung", body, DEFAULT_MISSION_DIR, 0.003, {})
    result = shrink_module.shrunk(orig, Behaviour("genom", "hung"), [])
    assert result.error is None and not result.whole and result.runs == 4
    shown = [len(parse(b).steps) for b, trace in orig.made if trace.outcome == "hung"]
    assert len(result.script.steps) == min(shown) < 8 and "rflex.Init" in result.script.render()
    orig.made, orig.runs = [], 0  # spent before the script showed the hang again: nothing came out
    result = shrink_module.shrunk(orig, Behaviour("genom", "hung"), [])
    assert result.script is None and result.error == "the budget is spent"
