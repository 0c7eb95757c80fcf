"""What a user gets wrong reaches them as a message and exit status 2, never as a traceback."""
from __future__ import annotations

import resource
import shutil
import signal
import subprocess
import sys

import pytest

from harness import DEFAULT_MISSION_DIR, ROOT
from harness.cli import main
from tests.support.traces import HERE, judged_store, load

INTERFACE = str(DEFAULT_MISSION_DIR / "interface.toml")


def _fails(capsys, *argv) -> str:
    """Run the CLI, expect exit status 2 and no traceback; the message it printed."""
    assert main([str(a) for a in argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and "Traceback" not in err
    return err


def _mission_copy(tmp_path):
    mission = tmp_path / "mission"
    shutil.copytree(DEFAULT_MISSION_DIR, mission)
    return mission


def test_a_script_that_is_not_utf8_names_its_line(tmp_path, capsys):
    script = tmp_path / "latin1.mission"
    script.write_bytes("send rflex.Init as ri\nwait ri  # d\xe9j\xe0 vu\n".encode("latin-1"))
    err = _fails(capsys, "run", script, "--sut", "reference", "--interface", INTERFACE, "--db", tmp_path / "s.duckdb")
    assert f"{script}:2: not UTF-8 (byte 0xe9)" in err


def test_a_golden_mission_or_interface_that_is_not_utf8_stops_a_campaign(tmp_path, capsys):
    mission = _mission_copy(tmp_path)
    golden = mission / "golden.mission"
    golden.write_bytes(golden.read_bytes() + b"# \xff\n")
    lines = golden.read_bytes().count(b"\n")
    err = _fails(capsys, "campaign", "--mission", mission, "--mutants", 1, "--db", tmp_path / "c.duckdb")
    assert f"{golden}:{lines}: not UTF-8 (byte 0xff)" in err
    (mission / "interface.toml").write_bytes(b"# caf\xe9\n")
    err = _fails(capsys, "campaign", "--mission", mission, "--mutants", 1, "--db", tmp_path / "c.duckdb")
    assert f"{mission / 'interface.toml'}:1: not UTF-8" in err


@pytest.mark.parametrize("suffix, text", [
    (".csv", "trace_id,seq,t,kind,rqst_id,module,service,args,reply\nr\xe9,1,0,request,1,rflex,Init,,\n"),
    (".jsonl", '{"trace_id": "a", "seq": 1, "t": 0, "kind": "request", "rqst_id": 1, "module": "rflex",'
               ' "service": "Init"}\n{"trace_id": "r\xe9"}\n'),
])
def test_an_import_file_that_is_not_utf8_names_its_line(tmp_path, capsys, suffix, text):
    log = tmp_path / f"log{suffix}"
    log.write_bytes(text.encode("latin-1"))
    err = _fails(capsys, "import", log, "--interface", INTERFACE, "--db", tmp_path / "s.duckdb")
    assert f"{log}:2: not UTF-8 (byte 0xe9)" in err


@pytest.mark.slow
def test_a_store_or_report_folder_that_cannot_be_created_is_refused(tmp_path, capsys):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    err = _fails(capsys, "run", DEFAULT_MISSION_DIR / "golden.mission", "--sut", "reference",
                 "--db", blocker / "store.duckdb")
    assert f"cannot create the folder {str(blocker)!r} for the store: " in err and "pass a writable place" in err
    db = tmp_path / "judged.duckdb"
    judged_store(load(HERE / "tables.trace"), 0.01, db).close()
    err = _fails(capsys, "report", "--db", db, "--out", blocker / "report")
    assert f"cannot create the folder {str(blocker / 'report')!r} for the report" in err


HOLD_THE_STORE = """
import sys, time, duckdb
con = duckdb.connect(sys.argv[1])
print("holding", flush=True)
time.sleep(120)
"""


def test_a_store_another_process_writes_is_named_with_what_to_do(tmp_path, capsys):
    db = tmp_path / "busy.duckdb"
    judged_store(load(HERE / "tables.trace"), 0.01, db).close()
    holder = subprocess.Popen([sys.executable, "-c", HOLD_THE_STORE, str(db)], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline() == "holding\n"
        for argv in (["sql", "select 1"], ["report", "--out", tmp_path / "out"], ["analyze"]):
            err = _fails(capsys, *argv, "--db", db)
            assert f"{str(db)!r} is being written by another process" in err and f"PID {holder.pid}" in err
            assert "wait for it to finish" in err
    finally:
        holder.kill()
        holder.wait()


@pytest.mark.slow
def test_a_full_disk_during_a_campaign_is_a_message_and_the_campaign_resumes(tmp_path):
    """RLIMIT_FSIZE makes every write past 100 kB fail as a full disk would (EFBIG instead of ENOSPC)."""
    db = tmp_path / "full.duckdb"
    argv = [sys.executable, "-m", "harness", "campaign", "--mutants", "20", "--sut", "genom",
            "--jobs", "1", "--db", str(db)]

    def small_disk():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (100_000, 100_000))
    full = subprocess.run(argv, cwd=ROOT, capture_output=True, text=True, timeout=600, preexec_fn=small_disk)
    assert full.returncode == 2, full.stderr
    assert "Traceback" not in full.stderr
    assert "error: could not write the store" in full.stderr and "rerun the same command" in full.stderr
    resumed = subprocess.run(argv, cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert resumed.returncode == 0, resumed.stderr
    assert "genom     19 runs: 19 completed" in resumed.stdout and "Table II" in resumed.stdout


def test_sql_prints_timestamps_with_time_zone_and_refuses_an_empty_query(tmp_path, capsys):
    db = tmp_path / "judged.duckdb"
    judged_store(load(HERE / "tables.trace"), 0.01, db).close()
    assert main(["sql", "--db", str(db), "select timestamptz '2026-01-02 03:04:05+00' as at"]) == 0
    assert "2026-01-02 03:04:05+00:00" in capsys.readouterr().out
    for query in ("", "-- only a comment", " ; "):
        err = _fails(capsys, "sql", "--db", db, query)
        assert f"no statement in {query!r}; give a query" in err


def test_cli_errors_have_no_traceback_end_to_end(tmp_path):
    """The same path as a user's shell: `python -m harness` in a subprocess."""
    script = tmp_path / "bad.mission"
    script.write_bytes(b"\xff\xfe")
    done = subprocess.run([sys.executable, "-m", "harness", "run", str(script), "--sut", "reference",
                           "--interface", INTERFACE, "--db", str(tmp_path / "s.duckdb")],
                          cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and done.stderr == f"error: {script}:1: not UTF-8 (byte 0xff); save the file as UTF-8\n"


@pytest.mark.slow
@pytest.mark.parametrize("setup_error", ["--sut nonexistent", "bad world.toml", "bad import file"])
def test_a_setup_error_leaves_no_new_store_behind(tmp_path, capsys, setup_error):
    mission, db = _mission_copy(tmp_path), tmp_path / "new" / "store.duckdb"
    argv = ["campaign", "--mission", mission, "--mutants", 1, "--db", db]
    if setup_error == "--sut nonexistent":
        argv += ["--sut", "nonexistent"]
    elif setup_error == "bad world.toml":
        (mission / "world.toml").write_text("[bounds]\nx = 1\n")
    else:
        (tmp_path / "log.csv").write_text("trace_id,seq,t,kind,rqst_id,module,service\na,1,0,request,1,rflx,Init\n")
        argv = ["import", tmp_path / "log.csv", "--interface", INTERFACE, "--db", db]
    _fails(capsys, *argv)
    assert not db.exists() and not db.with_name("store.duckdb.wal").exists()


def test_a_setup_error_keeps_an_existing_store(tmp_path, capsys):
    db = tmp_path / "judged.duckdb"
    judged_store(load(HERE / "tables.trace"), 0.01, db).close()
    before = db.read_bytes()
    _fails(capsys, "run", DEFAULT_MISSION_DIR / "golden.mission", "--sut", "nonexistent", "--db", db)
    assert db.read_bytes() == before


@pytest.mark.slow
def test_analyze_says_which_interface_the_properties_need(tmp_path, capsys):
    db = tmp_path / "judged.duckdb"
    judged_store(load(HERE / "tables.trace"), 0.01, db).close()
    properties = tmp_path / "mine.toml"
    properties.write_text((DEFAULT_MISSION_DIR / "properties.toml").read_text())
    err = _fails(capsys, "analyze", "--db", db, "--properties", properties)
    assert f"{tmp_path / 'interface.toml'}: file not found; the properties {properties} name services" in err
    assert "pass --interface FILE" in err
    assert main(["analyze", "--db", str(db), "--properties", str(properties), "--interface", INTERFACE]) == 0
    assert "against 25 properties" in capsys.readouterr().out


def test_a_huge_mutant_count_is_refused_at_once(tmp_path, capsys):
    err = _fails(capsys, "campaign", "--mutants", 100000000000, "--db", tmp_path / "c.duckdb")
    assert "--mutants 100000000000: give a number of mutants from 0 to 100,000" in err
    assert not (tmp_path / "c.duckdb").exists()


def test_a_long_mutant_generation_shows_its_progress(monkeypatch, capsys):
    from harness.campaign import campaign
    from harness.campaign.context import CampaignContext
    from harness.store.record import CampaignRecord
    from harness.target.mission import load_mission
    target = load_mission(DEFAULT_MISSION_DIR)
    config = CampaignRecord(mission=str(DEFAULT_MISSION_DIR), mutants=20, sut=["genom"], seed=1, ops_per_mutant=1)
    ctx = CampaignContext(con=None, db="", target=target, golden=target.golden(), golden_text="", properties=[], config=config,
                          setup=None, executor=None, jobs=1)
    monkeypatch.setattr(campaign, "SHOW_GENERATION", 10)
    assert len(campaign._generate(ctx, 1)) == 20
    assert "20/20 mutants" in capsys.readouterr().err
    monkeypatch.setattr(campaign, "SHOW_GENERATION", 21)
    campaign._generate(ctx, 1)
    assert capsys.readouterr().err == ""


def test_help_names_every_kind_of_system_under_test(capsys):
    assert main(["--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "simulated layer" in text and "untimely/1" in text and "NAME=cmd:COMMAND" in text and "ROS 1" in text


INTERRUPTED_ANALYSIS = """
import os, signal, sys, threading
from harness import cli
from harness.analysis import analyzer

def endless(con, *args, **kwargs):  # an analysis query that runs until Ctrl-C stops it in DuckDB
    threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT)).start()
    con.execute("select count(*) from range(100000000000)").fetchall()

analyzer.materialise = endless
sys.exit(cli.main(["analyze", *sys.argv[1:]]))
"""


@pytest.mark.slow
def test_ctrl_c_during_an_analysis_query_stops_it_clearly(tmp_path):
    """Issue 19: DuckDB ends a query that Ctrl-C interrupts with `RuntimeError: Query interrupted`."""
    db = tmp_path / "judged.duckdb"
    judged_store(load(HERE / "tables.trace"), 0.01, db).close()
    done = subprocess.run([sys.executable, "-c", INTERRUPTED_ANALYSIS, "--db", str(db), "--interface",
                           str(DEFAULT_MISSION_DIR / "interface.toml")], cwd=ROOT, capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 130, done.stderr
    assert done.stderr == "stopped (Ctrl-C); the store keeps every finished transaction\n"


def test_a_bench_name_that_names_no_bench_is_refused_rather_than_running_nothing():
    """`python bench/run.py cluster_bench` ran no bench and exited 0: a bench is named without `_bench`."""
    ran = subprocess.run([sys.executable, "bench/run.py", "cluster_bench"], cwd=ROOT, capture_output=True, text=True,
                         timeout=60)
    assert ran.returncode == 2 and "==" not in ran.stdout
    assert "no bench named 'cluster_bench'; name some of: analyzer, analyzer_memory," in ran.stderr
    assert ", cluster, " in ran.stderr


@pytest.mark.parametrize("flag", ["--world", "--interface"])
def test_a_missing_file_given_to_run_is_refused_naming_that_file(tmp_path, capsys, flag):
    """Issue 48: `run --interface X --world MISSING` answered `layer.toml: file not found`."""
    missing = tmp_path / "elsewhere" / "missing.toml"
    other = ["--interface", INTERFACE] if flag == "--world" else []
    err = _fails(capsys, "run", DEFAULT_MISSION_DIR / "golden.mission", "--sut", "genom", *other, flag, missing,
                 "--db", tmp_path / "r.duckdb")
    assert err.startswith(f"error: {missing}: ") and "layer.toml: file not found" not in err, err
