"""Campaigns: what is stored, resume after SIGKILL, refusal of changed arguments, worker failures.

Runs use the real executive against a small fake layer (every request ends `ok` after half a
second), so a campaign of a few mutants takes a fraction of a second once its workers are up.
"""
import io
import json
import os
import signal
import subprocess
import sys
import time
from dataclasses import asdict

import pytest

from harness import ROOT, cli, store
from harness.campaign import campaign, runs
from harness.dispatch import transport, workers
from harness.dispatch.description import Task
from harness.errors import InputFileError, StoreError, UntimelyError
from harness.progress import Progress
from harness.trace import Trace
from tests.support.campaigns import MARKER, arguments, dump, failing_runner, fake_layer_mission, fake_runner


def user_error_runner(script, sut, seed, interface, world_file, max_delay):
    if sut == "nosuch":
        raise InputFileError(world_file, "[rover]", "unknown variant 'nosuch'; use genom or bip-a")
    return fake_runner(script, sut, seed, interface, world_file, max_delay)


@pytest.fixture
def mission(tmp_path):
    return fake_layer_mission(tmp_path / "mission")


@pytest.mark.slow
def test_campaign_stores_scripts_and_every_run_with_deterministic_ids(mission, tmp_path, capsys):
    db = tmp_path / "c.duckdb"
    assert campaign.main(arguments(mission, db, mutants=8), runner=fake_runner) == 0
    out = capsys.readouterr().out
    con = store.connect(db, read_only=True)
    scripts = con.execute("select script_id, kind, parent, mutations, body, valid, invalid_reason "
                          "from scripts order by script_id").fetchall()
    assert scripts[0][:4] == (1, "golden", None, "[]")
    assert scripts[0][4] == (mission / "golden.mission").read_text()
    assert len(scripts) == 9 and all(s[1] == "mutant" and s[2] == 1 for s in scripts[1:])
    for script_id, _, _, mutations, _, valid, reason in scripts[1:]:
        assert len(json.loads(mutations)) == 1
        assert valid == (reason is None)
        assert valid or reason.startswith(f"script {script_id}:")
    assert not all(s[5] for s in scripts), "seed 11 draws an invalid mutant among 8"
    valid_ids = [s[0] for s in scripts if s[5]]
    traces = con.execute("select trace_id, script_id, sut, seed, outcome from traces order by trace_id").fetchall()
    expected = [((sid - 1) * 2 + v + 1, sid, sut, runs.run_seed(11, sid - 1, sut), "completed")
                for sid in valid_ids for v, sut in enumerate(["genom", "bip-a"])]
    assert traces == expected
    per_trace = con.execute("select count(distinct trace_id) from events").fetchone()[0]
    assert per_trace == len(traces)
    config = json.loads(con.execute("select config from campaigns").fetchone()[0])
    assert config["mutants"] == 8 and config["sut"] == ["genom", "bip-a"]
    assert set(config["files"]) == {"golden.mission", "interface.toml", "layer.toml", "world.toml"}
    invalid = len(scripts) - len(valid_ids)
    assert f"{len(valid_ids) - 1} valid, {invalid} invalid" in out
    assert f"genom     {len(valid_ids)} runs: {len(valid_ids)} completed, 0 hung, 0 crashed" in out
    judged = con.execute("select count(distinct trace_id) from verdicts").fetchone()[0]
    assert judged == len(traces) and "Table II - per trace results" in out


@pytest.mark.slow
def test_results_do_not_depend_on_jobs_and_a_finished_campaign_does_nothing(mission, tmp_path, capsys):
    one, two = tmp_path / "one.duckdb", tmp_path / "two.duckdb"
    campaign.main(arguments(mission, one, jobs=1), runner=fake_runner)
    campaign.main(arguments(mission, two, jobs=2), runner=fake_runner)
    first = dump(two)
    capsys.readouterr()
    campaign.main(arguments(mission, two, jobs=2), runner=fake_runner)
    out = capsys.readouterr().out
    assert f"campaign 1 in {two} is complete ({len(first['traces'])} runs stored); nothing to run" in out
    assert "this run" not in out
    assert dump(two) == first
    for name in ("scripts", "traces", "events", "world_events"):
        assert dump(one)[name] == first[name]


def kill_when_script4_starts(args, tmp_path, setup: str = "") -> None:
    """Run a campaign (stalling_runner) in a child process and SIGKILL it once script 4 has started."""
    marker = tmp_path / "script4-started"
    program = (f"from harness.campaign.request import CampaignRequest; from tests.support import campaigns as t; "
               f"from harness.campaign import campaign; {setup}"
               f"campaign.main(CampaignRequest(**{asdict(args)!r}), runner=t.stalling_runner)")
    env = dict(os.environ, PYTHONPATH=str(ROOT), **{MARKER: str(marker)})
    child = subprocess.Popen([sys.executable, "-c", program], env=env, cwd=tmp_path, start_new_session=True,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 60
    while not marker.exists() and child.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    os.killpg(child.pid, signal.SIGKILL)
    stderr = child.communicate()[1].decode()
    assert marker.exists(), stderr


@pytest.mark.slow
def test_resume_after_sigkill_equals_an_uninterrupted_campaign(mission, tmp_path, capsys):
    killed, whole = tmp_path / "killed.duckdb", tmp_path / "whole.duckdb"
    kill_when_script4_starts(arguments(mission, killed), tmp_path)
    capsys.readouterr()
    campaign.main(arguments(mission, killed), runner=fake_runner)
    resumed = capsys.readouterr().err
    assert "resuming campaign 1" in resumed
    stored, total = (int(n) for n in resumed.split(": ")[1].split(" runs")[0].split(" of "))
    assert 0 < stored < total
    campaign.main(arguments(mission, whole), runner=fake_runner)
    assert dump(killed) == dump(whole)


@pytest.mark.slow
def test_a_killed_campaign_loses_at_most_the_batch_it_had_not_committed(mission, tmp_path, capsys):
    """One worker runs the scripts in order; with batches of 3 runs, those before script 4 are
    stored but for the last, incomplete batch, which the resumed campaign runs again."""
    killed, whole = tmp_path / "killed.duckdb", tmp_path / "whole.duckdb"
    kill_when_script4_starts(arguments(mission, killed, jobs=1), tmp_path,
                             setup="from harness.campaign import runs; runs.BATCH_RUNS, runs.BATCH_S = 3, 3600.0; ")
    con = store.connect(killed, read_only=True)
    valid = [r[0] for r in con.execute("select script_id from scripts where valid and script_id < 4").fetchall()]
    stored = [r[0] for r in con.execute("select trace_id from traces order by trace_id").fetchall()]
    con.close()
    done = [(script_id - 1) * 2 + v + 1 for script_id in valid for v in range(2)]  # golden first, committed alone
    assert len(done) > 2 + 3, "seed 11 must give the two mutants before script 4 whole batches to commit"
    assert stored == done[:2 + (len(done) - 2) // 3 * 3]
    capsys.readouterr()
    campaign.main(arguments(mission, killed, jobs=1), runner=fake_runner)
    assert f"{len(stored)} of " in capsys.readouterr().err
    campaign.main(arguments(mission, whole, jobs=1), runner=fake_runner)
    assert dump(killed) == dump(whole)


@pytest.mark.slow
def test_changed_arguments_are_refused_naming_the_argument(mission, tmp_path):
    db = tmp_path / "c.duckdb"
    campaign.main(arguments(mission, db, mutants=2), runner=fake_runner)
    with pytest.raises(StoreError, match=r"holds campaign 1, made with --mutants 2, not 3; rerun with its "
                                         r"arguments to resume it, or pass another --db"):
        campaign.main(arguments(mission, db, mutants=3), runner=fake_runner)
    with pytest.raises(StoreError, match="made with --sut genom,bip-a, not bip-a,genom"):
        campaign.main(arguments(mission, db, mutants=2, sut="bip-a,genom"), runner=fake_runner)
    with pytest.raises(StoreError, match="made with --time-mutations False, not True"):
        campaign.main(arguments(mission, db, mutants=2, time_mutations=True), runner=fake_runner)
    (mission / "world.toml").write_text("# another world\n")
    with pytest.raises(StoreError, match=r"had other contents: world.toml differ"):
        campaign.main(arguments(mission, db, mutants=2), runner=fake_runner)


def test_bad_arguments_are_refused_before_anything_runs(mission, tmp_path):
    db = tmp_path / "c.duckdb"
    with pytest.raises(UntimelyError, match=r"--sut 'genom,,bip-a': '' is not a new SUT name; give distinct"):
        campaign.main(arguments(mission, db, sut="genom,,bip-a"), runner=fake_runner)
    with pytest.raises(UntimelyError, match=r"--sut 'genom,genom': 'genom' is not a new SUT name"):
        campaign.main(arguments(mission, db, sut="genom,genom"), runner=fake_runner)
    with pytest.raises(UntimelyError, match=r"--ops-per-mutant 0: give at least 1"):
        campaign.main(arguments(mission, db, ops_per_mutant=0), runner=fake_runner)
    (mission / "golden.mission").unlink()
    with pytest.raises(UntimelyError, match=r"golden.mission: file not found; a mission folder holds"):
        campaign.main(arguments(mission, db), runner=fake_runner)
    assert not db.exists()


@pytest.mark.slow
def test_a_failing_run_or_dead_worker_is_a_crashed_trace_and_the_rest_completes(mission, tmp_path):
    db = tmp_path / "c.duckdb"
    campaign.main(arguments(mission, db, mutants=4, seed=3), runner=failing_runner)
    con = store.connect(db, read_only=True)
    rows = con.execute("select script_id, sut, outcome, error from traces order by trace_id").fetchall()
    valid = con.execute("select count(*) from scripts where valid").fetchone()[0]
    assert len(rows) == 2 * valid
    crashed = {(sid, sut): error for sid, sut, outcome, error in rows if outcome == "crashed"}
    assert set(crashed) == {(2, "genom"), (3, "genom")}
    assert "ZeroDivisionError: codel divided by zero" in crashed[(2, "genom")]
    assert crashed[(3, "genom")] == "the worker process died (exit code 3) during this run"
    assert all(outcome == "completed" for sid, sut, outcome, _ in rows if (sid, sut) not in crashed)


@pytest.mark.slow
def test_a_variant_that_cannot_be_built_stores_nothing(mission, tmp_path):
    db = tmp_path / "c.duckdb"
    with pytest.raises(UntimelyError, match=r"world.toml:\[rover\]: unknown variant 'nosuch'; use genom"):
        campaign.main(arguments(mission, db, sut="genom,nosuch"), runner=user_error_runner)
    campaign.main(arguments(mission, db, mutants=1, sut="genom"), runner=user_error_runner)
    con = store.connect(db, read_only=True)
    assert con.execute("select count(*), min(config->>'sut') from campaigns").fetchone() == (1, '["genom"]')


def sleepy_runner(script, sut, seed, interface, world_file, max_delay):
    if sut == "slow":
        time.sleep(600)
    return fake_runner(script, sut, seed, interface, world_file, max_delay)


def test_a_run_past_the_wall_clock_watchdog_is_killed_and_recorded(mission):
    tasks = [Task(n, 1, sut, 0, (mission / "golden.mission").read_text())
             for n, sut in enumerate(["slow", "genom", "bip-a"], 1)]
    setup = transport.setup(sleepy_runner, mission / "interface.toml", mission / "world.toml", 0.003, watchdog_s=1.0)
    results = {}
    workers.run_all(tasks, setup, 2, lambda task, trace: results.update({task.sut: trace}))
    assert results["slow"].outcome == "crashed"
    assert results["slow"].error == "no result after 1 s of wall time; the worker was killed"
    assert results["genom"].outcome == results["bip-a"].outcome == "completed"


class SlowToStartRunner:
    """Unpickled in the spawned worker before it reports ready, like a slow import on a loaded machine."""

    def __getstate__(self):
        return {"start_up_s": 2.0}  # a non-empty state, so that unpickling calls __setstate__

    def __setstate__(self, state):
        time.sleep(state["start_up_s"])

    def __call__(self, script, sut, seed, interface, world_file, max_delay):
        time.sleep(0.5)
        return fake_runner(script, sut, seed, interface, world_file, max_delay)


@pytest.mark.slow
def test_the_watchdog_counts_from_when_the_worker_is_ready_not_from_its_slow_start(mission):
    tasks = [Task(1, 1, "genom", 0, (mission / "golden.mission").read_text())]
    setup = transport.setup(SlowToStartRunner(), mission / "interface.toml", mission / "world.toml", 0.003,
                          watchdog_s=1.5)
    results = []
    workers.run_all(tasks, setup, 1, lambda task, trace: results.append(trace))
    assert [t.outcome for t in results] == ["completed"], results[0].error


def test_progress_logs_a_line_every_tenth_when_not_on_a_terminal():
    stream = io.StringIO()
    bar = Progress(20, stream=stream)
    for _ in range(20):
        bar.advance()
    lines = stream.getvalue().splitlines()
    assert [line.split()[0] for line in lines] == [f"{n}/20" for n in range(2, 21, 2)]
    assert "[##############################] 100%" in lines[-1] and "runs/s  ETA 0:00" in lines[-1]


def test_progress_of_a_resumed_campaign_counts_only_this_session():
    stream = io.StringIO()
    bar = Progress(100, done=90, stream=stream)
    bar.advance()
    assert bar.session == 1 and bar.line().startswith(" 91/100 runs [###########################   ]  91%")
    assert stream.getvalue() == ""  # still within the tenth reached before the resume


@pytest.mark.slow
def test_a_finished_campaign_without_verdicts_gets_them_without_running_anything(mission, tmp_path, capsys):
    db = tmp_path / "c.duckdb"
    campaign.main(arguments(mission, db, mutants=2, sut="genom"), runner=fake_runner)
    before = dump(db)
    con = store.connect(db)
    con.execute("drop table verdicts")  # as if the campaign was killed while judging
    con.close()
    capsys.readouterr()
    campaign.main(arguments(mission, db, mutants=2, sut="genom"), runner=fake_runner)
    out = capsys.readouterr().out
    assert "nothing to run" in out and "verdicts  materialised" in out
    assert dump(db) == before


@pytest.mark.slow
def test_a_finished_campaign_judges_traces_added_after_its_verdicts(mission, tmp_path, capsys):
    db = tmp_path / "c.duckdb"
    campaign.main(arguments(mission, db, mutants=2, sut="genom"), runner=fake_runner)
    con = store.connect(db)
    extra = con.execute("select max(trace_id) + 100 from traces").fetchone()[0]
    con.execute("insert into traces by name select * replace (? as trace_id) from traces where trace_id = 1", [extra])
    con.execute("insert into events by name select * replace (? as trace_id) from events where trace_id = 1", [extra])
    con.close()
    capsys.readouterr()
    campaign.main(arguments(mission, db, mutants=2, sut="genom"), runner=fake_runner)
    out = capsys.readouterr().out
    assert "nothing to run" in out and "verdicts  materialised" in out
    con = store.connect(db, read_only=True)
    assert con.execute("select count(*) from verdicts where trace_id = ?", [extra]).fetchone()[0] > 0


@pytest.mark.slow
def test_a_finished_and_judged_campaign_is_left_as_it_is(mission, tmp_path, capsys):
    db = tmp_path / "c.duckdb"
    campaign.main(arguments(mission, db, mutants=2, sut="genom"), runner=fake_runner)
    capsys.readouterr()
    campaign.main(arguments(mission, db, mutants=2, sut="genom"), runner=fake_runner)
    out = capsys.readouterr().out
    assert "nothing to run" in out and "verdicts  materialised" not in out


@pytest.mark.slow
def test_a_resumed_campaign_judges_with_the_epsilon_of_the_last_analysis(mission, tmp_path, capsys):
    db = tmp_path / "c.duckdb"
    campaign.main(arguments(mission, db, mutants=2, sut="genom"), runner=fake_runner)
    assert cli.main(["analyze", "--db", str(db), "--epsilon", "0.05"]) == 0
    con = store.connect(db)
    con.execute("drop table verdicts")  # as if the campaign was killed while judging
    con.close()
    capsys.readouterr()
    campaign.main(arguments(mission, db, mutants=2, sut="genom"), runner=fake_runner)
    assert "verdicts  materialised for every trace of" in capsys.readouterr().out
    con = store.connect(db, read_only=True)
    assert con.execute("select epsilon from analyses order by analysis_id").fetchall() == [(0.01,), (0.05,), (0.05,)]


def test_progress_past_its_total_shows_it_full_with_no_negative_eta():
    bar = Progress(8, stream=io.StringIO())
    for _ in range(12):  # a total that turned out short: the bar stops at it
        bar.advance()
    assert bar.line().startswith("8/8 runs [##############################] 100%") and "ETA 0:00" in bar.line()


def test_progress_in_mission_seconds_counts_each_trace_s_simulated_time():
    stream = io.StringIO()
    bar = Progress(4000, done=1000, stream=stream, unit="mission s", mission_time=True)
    bar.ran(Trace("genom", 1, sim_s=1500.0))
    assert bar.line().startswith("2,500/4,000 mission s [##################            ]  62%")


def test_progress_without_a_total_shows_the_work_done_and_its_rate_only():
    bar = Progress(None, stream=io.StringIO())
    for _ in range(3):
        bar.advance()
    assert bar.line().startswith("3 runs ") and "ETA" not in bar.line() and "%" not in bar.line()
