"""Campaigns against external SUTs: the simulator through the protocol judges like the simulator
in process, slots run side by side with their own numbers, and a SIGKILLed real-time campaign
resumes with nothing lost or doubled."""
import os
import re
import shutil
import signal
import subprocess
import sys

import pytest

from harness import DEFAULT_MISSION_DIR, ROOT, store
from harness.cli import main as cli
from tests.support.external import FAULTY, assert_judges_like_in_process, campaign

pytestmark = pytest.mark.slow


def test_the_simulator_through_the_protocol_judges_like_the_simulator_in_process(tmp_path, capsys):
    """Golden + 20 mutants on `reference` in process and on `sim-reference` (missions/dala/suts.toml:
    the same layer out of process, 10x real time) on 8 slots."""
    db = tmp_path / "c.duckdb"
    assert campaign(db, "--mutants", "20", "--sut", "reference,sim-reference", "--jobs", "8") == 0
    con = assert_judges_like_in_process(db, capsys.readouterr().out, "sim-reference", 10)
    runs = con.execute("select count(*) from traces where sut = 'sim-reference'").fetchone()[0]
    provenance = con.execute("select count(*), min(pings), count(distinct host) from trace_runs").fetchone()
    assert provenance[0] == runs and provenance[1] >= 1 and provenance[2] == 1


def test_slots_run_side_by_side_each_with_its_own_number(tmp_path):
    db = tmp_path / "c.duckdb"
    sut = f"f=cmd:{{python}} {FAULTY}"
    assert campaign(db, "--mutants", "8", "--sut", sut, "--time-scale", "2", "--jobs", "3") == 0
    con = store.connect(db, read_only=True)
    infos = [r[0] for r in con.execute("select sut_info from trace_runs order by trace_id").fetchall()]
    assert {int(i.rsplit(" ", 1)[1]) for i in infos} == {0, 1, 2}, infos
    # Runs of a few wall seconds each (the adapter ends every request at once, the golden
    # mission's sleeps remain): at some instant all three slots were running one.
    most = con.execute("""
        with spans as (
            select started_at as instant, 1 as change from trace_runs
            union all
            select started_at + to_microseconds((wall_s * 1e6)::bigint), -1 from trace_runs join traces using (trace_id)
        )
        select max(running) from (select sum(change) over (order by instant, change) as running from spans)""")
    assert most.fetchone()[0] == 3


def test_a_sigkilled_realtime_campaign_resumes_with_nothing_lost_or_doubled(tmp_path):
    mission = tmp_path / "dala"
    shutil.copytree(DEFAULT_MISSION_DIR, mission)
    db = tmp_path / "c.duckdb"
    argv = ["campaign", "--db", str(db), "--seed", "5", "--mission", str(mission), "--mutants", "8",
            "--sut", f"f=cmd:{{python}} {FAULTY}", "--time-scale", "40", "--jobs", "2"]
    child = subprocess.Popen([sys.executable, "-m", "harness", *argv], cwd=ROOT, start_new_session=True,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    progress = ""
    while child.poll() is None and not re.search(r"\b[3-9]/\d+ runs", progress):
        progress += child.stderr.read(1)
    os.killpg(child.pid, signal.SIGKILL)
    child.wait()
    assert cli(argv) == 0
    con = store.connect(db, read_only=True)
    valid = con.execute("select script_id from scripts where valid order by script_id").fetchall()
    traces = con.execute("select trace_id from traces order by trace_id").fetchall()
    assert traces == valid  # one SUT: a script's trace id is its script id
    doubled = con.execute("select count(*) from (select trace_id, seq from events group by all having count(*) > 1)")
    assert doubled.fetchone()[0] == 0
    assert con.execute("select count(*) from trace_runs").fetchone()[0] == len(valid)
    assert con.execute("select count(*) from traces where outcome <> 'completed'").fetchone()[0] == 0
