"""Focused campaigns (issue 21): short tests made from any target folder, a budget that bounds
every run's mission time, a stopping rule, findings with shrunk reproducers."""
import sys
import threading
from pathlib import Path

import pytest

from harness import DEFAULT_MISSION_DIR, ROOT, store
from harness.cli import main as cli
from harness.campaign import shrink
from harness.campaign.budget import Budget, MeteredOriginal, parse_duration
from harness.errors import BudgetSpent
from harness.mutator.focused import Plan
from harness.mutator.script_time import bound_s
from harness.mutator.timeline import ScriptTimeline
from harness.sut.executive import run_script
from harness.target.mission import load_mission
from tests.support.toy_target import GOLDEN, INTERFACE, LAYER, PROPERTIES

sys.path.insert(0, str(ROOT / "bench"))
from defects import expected, exposed  # noqa: E402  (bench/defects.py: what each defect must show)
from tests.support.paths import ADAPTERS

PUMP = ADAPTERS / "pump.py"


def spent(db) -> tuple[float, str, float | None]:
    """(mission seconds of every run, shrink runs included: every stored trace; why it stopped; its budget)."""
    con = store.connect(db, read_only=True)
    traces = con.execute("select sum(sim_s) from traces").fetchone()[0]
    stopped, budget = con.execute("select stopped, budget_s from campaign_budgets").fetchone()
    return traces, stopped, budget


def assert_every_defect_exposed(db, mission: Path, suts: list[str]) -> None:
    target = load_mission(mission)
    con = store.connect(db, read_only=True)
    found = exposed(con, expected(mission, target.properties(), suts))
    missing = [f"{e.sut}: {e.what} ({e.kind})" for e, reproducer in found.items() if reproducer is None]
    assert not missing, f"not exposed with a reproducer of at most 10 steps: {missing}"


@pytest.mark.slow
@pytest.mark.parametrize("mission, suts", [(DEFAULT_MISSION_DIR, "genom,bip-a,bip-b"),
                                           (ROOT / "missions" / "manipulator", "safe,careless,quirky,stuck")])
def test_a_focused_campaign_stops_by_itself_within_its_budget_and_exposes_every_defect(tmp_path, capsys,
                                                                                        mission, suts):
    db = tmp_path / "f.duckdb"
    assert cli(["campaign", "--mission", str(mission), "--strategy", "focused", "--budget", "4000s", "--shrink",
                "--sut", suts, "--db", str(db)]) == 0
    out = capsys.readouterr().out
    total, stopped, budget = spent(db)
    assert stopped == "rule" and budget == 4000 and total <= 4000, out
    assert "stopped   (rule)" in out and "findings (view findings):" in out
    assert_every_defect_exposed(db, mission, suts.split(","))


@pytest.mark.slow
def test_the_budget_bounds_every_run_and_says_it_stopped_the_campaign(tmp_path, capsys):
    db = tmp_path / "b.duckdb"
    assert cli(["campaign", "--strategy", "focused", "--budget", "6m", "--shrink", "--sut", "genom",
                "--db", str(db)]) == 0
    total, stopped, budget = spent(db)
    assert stopped == "budget" and budget == 360 and 300 < total <= 360
    out, err = capsys.readouterr()
    assert "stopped   (budget) the next test does not fit in the budget" in out
    # the bar counts the budget's mission seconds, never past it, never a negative ETA
    bars = [line.split() for line in err.splitlines() if "/360 mission s [" in line]
    assert len(bars) >= 3 and all(0 < float(bar[0].split("/")[0]) <= 360 for bar in bars), err
    assert not any("ETA -" in line or "runs [" in line and "/1 runs" not in line for line in err.splitlines()), err
    # every shrink run is a stored trace of a shrink of one of the campaign's traces, out of the tables
    con = store.connect(db, read_only=True)
    shrink_s, runs, originals, counted, found = con.execute("""
        select sum(t.sim_s), count(*), count(distinct r.original) filter (where o.campaign_id = 1),
               count(*) filter (where s.counted),
               count(*) filter (where r.trace_id in (select trace_id from trace_findings))
        from shrink_runs r join traces t using (trace_id) join traces o on o.trace_id = r.original
        join trace_scope s on s.trace_id = r.trace_id""").fetchone()
    assert runs > 10 and originals >= 1 and counted == 0 and found == 0
    assert con.execute("select shrink_s from campaign_budgets").fetchone()[0] == pytest.approx(shrink_s)
    campaign_s = con.execute("select sum(sim_s) from traces where campaign_id = 1").fetchone()[0]
    assert campaign_s + shrink_s == pytest.approx(total) and total <= 360
    tables = con.execute("select sum(total) from trace_robustness").fetchone()[0]
    assert tables == con.execute("select count(*) from traces where campaign_id = 1").fetchone()[0]
    assert con.execute("select max(traces) from findings").fetchone()[0] <= tables
    con.close()
    # run again: nothing fits, nothing runs, the same reason
    assert cli(["campaign", "--strategy", "focused", "--budget", "6m", "--shrink", "--sut", "genom",
                "--db", str(db)]) == 0
    assert spent(db) == (total, "budget", 360)


@pytest.mark.slow
def test_a_resumed_focused_campaign_runs_only_what_is_missing_and_ends_the_same(tmp_path):
    args = ["campaign", "--strategy", "focused", "--mutants", "24", "--sut", "genom,bip-a", "--seed", "3"]
    whole, cut = tmp_path / "whole.duckdb", tmp_path / "cut.duckdb"
    assert cli(args + ["--db", str(whole)]) == 0
    assert cli(args + ["--db", str(cut)]) == 0
    con = store.connect(cut)
    con.execute("delete from traces where trace_id > (select max(trace_id) - 7 from traces)")
    con.execute("update campaign_budgets set stopped = null")
    con.close()
    assert cli(args + ["--db", str(cut)]) == 0
    rows = "select trace_id, sut, outcome, sim_s from traces order by trace_id"
    findings = "select * exclude (first_trace) from findings"
    a, b = store.connect(whole, read_only=True), store.connect(cut, read_only=True)
    assert a.execute(rows).fetchall() == b.execute(rows).fetchall()
    assert a.execute(findings).fetchall() == b.execute(findings).fetchall()
    assert b.execute("select stopped, tests from campaign_budgets").fetchone() == ("tests", 24)


def test_every_test_is_valid_and_ends_within_its_bound():
    target = load_mission(DEFAULT_MISSION_DIR)
    golden, interface = target.golden(), target.interface
    trace = run_script(golden, "reference", 1, interface, target.world_file)
    plan = Plan(golden, ScriptTimeline(golden, trace, interface.replies), interface, target.properties(), 7)
    assert len(plan.aims) > 100 and all(a.properties for a in plan.aims)
    for n in range(0, len(plan.aims) + 20, 5):
        test = plan.test(n, f"test {n}")
        assert test.valid, test.invalid_reason
        assert len(test.script.steps) <= 14 and "golden" not in test.body
        run = run_script(test.script, "reference", n, interface, target.world_file)
        assert run.outcome == "completed" and run.sim_s <= bound_s(test.script), (n, test.body)


@pytest.mark.parametrize("text, seconds", [("4000s", 4000), ("40m", 2400), ("1.5h", 5400)])
def test_durations(text, seconds):
    assert parse_duration(text) == seconds


@pytest.mark.parametrize("argv, message", [
    (["--strategy", "focused", "--budget", "40 minutes"],
     "--budget '40 minutes': give mission time as a positive number followed by s, m or h (4000s, 40m, 1h)"),
    (["--strategy", "focused", "--budget", "0s"], "--budget '0s': give mission time as a positive number"),
    (["--budget", "40m"], "--budget 40m applies to --strategy focused, whose tests are made as the campaign "
                          "goes; a random campaign runs its --mutants"),
    (["--strategy", "focused", "--time-mutations"], "--time-mutations applies to --strategy random only; "
                                                    "focused mutants choose their own sleeps"),
])
def test_bad_budget_arguments_are_refused_with_a_message(tmp_path, capsys, argv, message):
    assert cli(["campaign", "--db", str(tmp_path / "x.duckdb"), *argv]) != 0
    assert message in capsys.readouterr().err
    assert not (tmp_path / "x.duckdb").exists()


@pytest.mark.slow
def test_a_target_folder_outside_the_repository_with_an_external_adapter(tmp_path, capsys):
    """The toy pump-and-valve target (tests/target/test_toy_target.py), its layer a stdlib adapter run over
    untimely/1 at 5x: the careless pump's missing DRY protection is found and shrunk."""
    toy = tmp_path / "toy"
    toy.mkdir()
    for name, text in (("interface.toml", INTERFACE), ("properties.toml", PROPERTIES), ("golden.mission", GOLDEN)):
        (toy / name).write_text(text)
    (toy / "suts.toml").write_text(
        f'[pump]\ncommand = "{{python}} {PUMP}"\nslots = 4\ntime_scale = 5.0\n\n'
        f'[careless]\ncommand = "{{python}} {PUMP} --careless"\nslots = 4\ntime_scale = 5.0\n')
    db = tmp_path / "toy.duckdb"
    assert cli(["campaign", "--mission", str(toy), "--strategy", "focused", "--budget", "20m", "--shrink",
                "--sut", "pump,careless", "--db", str(db)]) == 0
    out = capsys.readouterr().out
    con = store.connect(db, read_only=True)
    found = con.execute("select sut, property_id, kind, reproducer_steps from findings").fetchall()
    assert ("careless", "DRY(pump.Run)", "FN") in [f[:3] for f in found], out
    assert all(steps is not None and steps <= 10 for *_, steps in found), found
    assert not [f for f in found if f[0] == "pump"], found
    total, stopped, _ = spent(db)
    assert stopped == "rule" and total <= 1200
    assert cli(["report", "--db", str(db), "--out", str(tmp_path / "report")]) == 0
    index = (tmp_path / "report" / "index.html").read_text()
    assert index.index('<h2 id="findings">') < index.index('<h2 id="campaign">')
    assert "DRY(pump.Run)" in index.split('<h2 id="campaign">')[0]
    assert (tmp_path / "report" / "findings.csv").read_text().count("\n") == len(found) + 1


@pytest.mark.slow
def test_a_campaign_stopped_during_a_shrink_stores_its_runs_and_shrinks_again_when_resumed(tmp_path, monkeypatch):
    """Ctrl-C (or SIGTERM, the same KeyboardInterrupt) in the midst of a shrink: the runs it made are
    stored, marked interrupted, and counted when the campaign resumes, which shrinks that finding again."""
    from harness.dispatch.description import Setup
    args = ["campaign", "--strategy", "focused", "--budget", "8m", "--shrink", "--sut", "genom",
            "--db", str(tmp_path / "s.duckdb")]
    real, calls = Setup.run, []

    def stopped_on_the_fifth_shrink_run(setup, task, interface, slot):
        calls.append(task.trace_id)  # in this process, only shrinks run (the tests run in workers)
        if len(calls) == 5:
            raise KeyboardInterrupt
        return real(setup, task, interface, slot)
    monkeypatch.setattr(Setup, "run", stopped_on_the_fifth_shrink_run)
    assert cli(args) == 130  # as after Ctrl-C
    monkeypatch.undo()
    con = store.connect(tmp_path / "s.duckdb", read_only=True)
    (config, runs, runs_s), = con.execute("""select any_value(c.config), count(*), sum(t.sim_s) from campaigns c
        join traces t using (campaign_id) join shrink_runs using (trace_id) group by campaign_id""").fetchall()
    con.close()
    assert '"interrupted": true' in config and runs == 4 and runs_s > 0
    assert cli(args) == 0
    con = store.connect(tmp_path / "s.duckdb", read_only=True)
    shrinks = con.execute("""select config->>'trace', config->>'property', (config->>'interrupted') is not null
                             from campaigns where config->>'kind' = 'shrink' order by campaign_id""").fetchall()
    assert shrinks[0][2] and (shrinks[0][0], shrinks[0][1], False) in shrinks[1:]
    assert con.execute("select shrink_s from campaign_budgets").fetchone()[0] >= runs_s


# The toy's golden with its pump started while the valve opens: the leaky layer (no DRY) accepts it.
GOLDEN_SHOWING_DRY = """send pump.Init as p
send valve.Init as v
wait all
send valve.Open as open
send pump.Run as run
sleep 2
send pump.Halt as halt
wait all
"""


def test_a_finding_the_golden_run_shows_is_shrunk_like_any_other(tmp_path, capsys):
    """Before, only a test's finding was shrunk: one the golden showed (and no test did) never was."""
    toy = tmp_path / "toy"
    toy.mkdir()
    for name, text in (("interface.toml", INTERFACE), ("layer.toml", LAYER), ("properties.toml", PROPERTIES),
                       ("golden.mission", GOLDEN_SHOWING_DRY)):
        (toy / name).write_text(text)
    db = tmp_path / "g.duckdb"
    args = ["campaign", "--mission", str(toy), "--strategy", "focused", "--mutants", "0", "--shrink",
            "--sut", "good,leaky", "--max-delay", "0", "--jobs", "1", "--db", str(db)]
    assert cli(args) == 0  # no test at all: what is found and shrunk is the golden's
    out = capsys.readouterr().out
    con = store.connect(db, read_only=True)
    (golden_trace,) = con.execute("""select trace_id from traces join scripts using (script_id)
                                     where kind = 'golden' and sut = 'leaky'""").fetchone()
    assert f"found     leaky: FN on DRY(pump.Run) (trace {golden_trace}," in out
    found = con.execute("select sut, property_id, kind, first_trace, reproducer_steps from findings").fetchall()
    assert found == [("leaky", "DRY(pump.Run)", "FN", golden_trace, found[0][4])] and found[0][4] is not None
    shrunk = con.execute("""select s.body from scripts s join campaigns c using (campaign_id)
                            where s.kind = 'shrunk' and c.config->>'trace' = ?""", [str(golden_trace)]).fetchall()
    assert len(shrunk) == 1 and found[0][4] < GOLDEN_SHOWING_DRY.count("\n")
    assert "send valve.Open" in shrunk[0][0] and "send pump.Run" in shrunk[0][0]
    con.close()
    assert cli(args) == 0  # resumed: nothing shrunk again
    assert "shrunk in" not in capsys.readouterr().out


class Took:
    sim_s = 3.0


def metered(budget, monkeypatch):
    """A shrink's original whose runs take 3 mission s (no SUT: the budget's account is the test)."""
    monkeypatch.setattr(shrink.Original, "run", lambda self, body: Took())
    return MeteredOriginal(1, 1, "genom", 0, "FN", "body", ROOT, 0.0, {}, budget=budget, bound=10.0)


def test_a_shrink_run_that_does_not_fit_waits_for_the_runs_in_flight_then_takes_what_they_left(monkeypatch):
    budget = Budget(20.0)
    budget.reserve(10.0)  # a test's run in flight at its bound: 10 of 20 spent
    budget.spent_s += 5.0  # and 5 spent before
    original = metered(budget, monkeypatch)
    done = threading.Event()
    threading.Thread(target=lambda: (original.run("body"), done.set()), daemon=True).start()
    assert not done.wait(0.3), "a shrink run started with 15 of 20 s spent and a bound of 10 s"
    with budget.account:
        budget.settle(10.0, 2.0)  # the run came back having taken 2 s: 7 of 20 spent
    assert done.wait(10), "the shrink run never started once the budget had room"
    assert budget.spent_s == pytest.approx(10.0) and budget.in_flight == 0


def test_a_shrink_run_that_does_not_fit_with_nothing_in_flight_finds_the_budget_spent(monkeypatch):
    budget = Budget(20.0, spent_s=15.0)
    with pytest.raises(BudgetSpent):
        metered(budget, monkeypatch).run("body")
    assert budget.spent_s == 15.0 and budget.in_flight == 0
