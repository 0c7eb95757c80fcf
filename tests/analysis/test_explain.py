"""`explain TRACE_ID PROPERTY [RQST_ID]`: the events that decided a verdict."""
import shutil
import signal

import duckdb
import pytest

from harness import DEFAULT_MISSION_DIR
from harness.analysis import explain
from harness.analysis.analyzer import materialise
from harness.analysis.explain import Explainer, judged_properties
from harness.cli import main
from harness.errors import StoreError
from harness.sut import processes
from harness.store.database import add_campaign, add_reply_codes, connect, insert_trace
from harness.store.record import RunRecord
from harness.target.interface import load_properties
from harness.trace import Trace
from harness.target.property_types import property_types
from tests.support.traces import HERE, INTERFACE, all_fixtures, load, judged_store

EPSILON = 0.01


def _store(tmp_path, name: str):
    """A fixture file's traces judged from a copy of the Dala mission's files."""
    mission = tmp_path / "mission"
    shutil.copytree(DEFAULT_MISSION_DIR, mission, dirs_exist_ok=True)
    fixture = load(HERE / name)
    db = tmp_path / "store.duckdb"
    judged_store(fixture, EPSILON, db).close()
    con = connect(db)
    materialise(con, fixture.properties, EPSILON, INTERFACE, mission / "properties.toml")
    con.close()
    return db, {case.label: n for n, case in enumerate(fixture.cases, 1)}


@pytest.mark.slow
def test_a_pc_verdict_shows_the_ok_replies_that_set_c(tmp_path, capsys):
    db, ids = _store(tmp_path, "pc.trace")
    trace = ids["pc_tie_request_first"]
    assert main(["explain", str(trace), "PEX(rflex)", "--db", str(db)]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[:3] == [
        f"PEX(rflex) on request 2 of trace {trace}: FN",
        "  x(i) rflex.TrackSpeedStart sent at 1.000000 s; final reply ok (class T) at 2.000000 s",
        "  C is false; margin 0.000000 s; suspicious (epsilon 0.01 s)"]
    assert "q rflex.Init  ok at 1.000000" in out and "yes            no" in out


def test_an_ee_verdict_shows_the_y_requests_and_that_causality_settles_it(tmp_path, capsys):
    db, ids = _store(tmp_path, "flag.trace")
    trace = ids["flag_control_is_no_cause"]
    assert main(["explain", str(trace), "AIB(ndd.GotoPosition)", "1", "--db", str(db)]) == 0
    out = capsys.readouterr().out
    assert f"AIB(ndd.GotoPosition) on request 1 of trace {trace}: TP" in out
    assert "C is false; margin 0.002000 s; not suspicious" in out
    assert "y ndd.Stop #3  sent 1.000000, ok (T) at 1.100000" in out
    assert "one of them came before the end whatever the observed order, so C cannot hold" in out


def test_explain_refuses_an_unknown_property_or_request(tmp_path, capsys):
    db, ids = _store(tmp_path, "pc.trace")
    assert main(["explain", "1", "PEX(nosuch)", "--db", str(db)]) == 2
    assert "no property 'PEX(nosuch)'" in capsys.readouterr().err
    assert main(["explain", "1", "PEX(rflex)", "9", "--db", str(db)]) == 2
    assert "trace 1 has no verdict of PEX(rflex) on request 9; it has verdicts on requests [2]" in \
        capsys.readouterr().err


def test_a_value_domain_verdict_shows_the_arguments_their_values_and_domains(tmp_path, capsys):
    db, ids = _store(tmp_path, "val.trace")
    trace = ids["val_false_rp"]
    assert main(["explain", str(trace), "VAL(ndd)", "2", "--db", str(db)]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[:3] == [
        f"VAL(ndd) on request 2 of trace {trace}: TP",
        '  x(i) ndd.GotoPosition {"x": "nan", "y": 4.0} sent at 0.200000 s; final reply bad_params (class R) '
        'at 0.300000 s',
        "  C is false; margin - s; not suspicious (epsilon 0.01 s)"]
    assert 'argument x  "nan"; domain float 0..20  yes' in out and "argument y  4.0; domain float 0..20    no" in out
    assert main(["explain", str(ids["val_false_rp"]), "VAL(ndd)", "5", "--db", str(db)]) == 0
    assert "argument y  missing; domain float 0..20" in capsys.readouterr().out


def test_a_property_whose_oracle_fails_is_not_explained_and_the_others_are(tmp_path, monkeypatch):
    db, ids = _store(tmp_path, "flag.trace")
    con = connect(db, read_only=True)
    explainer = Explainer(con, *judged_properties(con))
    keys = [tuple(k) for k in con.execute("select trace_id, property_id, rqst_id from verdicts "
                                          "order by all").fetchall()]
    assert len({p for _, p, _ in keys}) >= 2
    normal = explainer.explain(keys)
    broken = keys[0][1]
    original = explain.render_property
    monkeypatch.setattr(explain, "render_property", lambda prop, *args, **kwargs: (
        "select no_such_column from verdicts" if prop.id == broken else original(prop, *args, **kwargs)))
    texts = explainer.explain(keys)
    assert {k: t for k, t in texts.items() if k[1] != broken} == {k: t for k, t in normal.items() if k[1] != broken}
    failed = [t for k, t in texts.items() if k[1] == broken]
    assert failed and all(t.splitlines()[1] == '  not explained: the property\'s oracle failed (Binder Error: '
                          'Referenced column "no_such_column" not found in FROM clause!); fix its template, then '
                          'analyze again' for t in failed)


SELF_INTERRUPTING = """component selfish {
  activity X() { interrupts X; };
  activity Y();
};
"""


def test_explain_report_and_junit_never_crash_on_an_ee_verdict_without_a_y_request(tmp_path, capsys):
    """An activity that interrupts itself, requested twice, and one that only genom3's kill
    interrupts (no request of it in the trace): every verdict is explained, reported and written
    as JUnit (explain crashed on the verdict no y request decided)."""
    gen = tmp_path / "selfish.gen"
    gen.write_text(SELF_INTERRUPTING)
    folder, db = tmp_path / "selfish", tmp_path / "s.duckdb"
    assert main(["init", str(folder), "--from-genom", str(gen)]) == 0
    script = folder / "trace.mission"  # beside the target's interface and suts.toml
    script.write_text("send selfish.Y as y\nsleep 0.2\nsend selfish.X as a\nsleep 0.2\nsend selfish.X as b\nwait all\n")
    assert main(["run", str(script), "--sut", "adapter", "--db", str(db)]) == 0
    assert main(["analyze", "--db", str(db), "--properties", str(folder / "properties.toml"),
                 "--junit", str(tmp_path / "j.xml")]) == 0
    con = connect(db, read_only=True)
    verdicts = con.execute("select trace_id, property_id, rqst_id, verdict from verdicts").fetchall()
    con.close()
    assert {v[1] for v in verdicts} == {"AIB(selfish.X)", "AIB(selfish.Y)"}, verdicts
    capsys.readouterr()
    for trace_id, property_id, rqst_id, _ in verdicts:
        assert main(["explain", str(trace_id), property_id, str(rqst_id), "--db", str(db)]) == 0
    out = capsys.readouterr()
    assert "Traceback" not in out.err and "AIB(selfish.X)" in out.out
    assert main(["report", "--db", str(db), "--out", str(tmp_path / "report")]) == 0
    assert (tmp_path / "j.xml").read_text().startswith("<?xml")


def test_a_crash_exits_with_its_own_status_not_the_finding_status(tmp_path, capsys, monkeypatch):
    def broken(*args):
        raise AttributeError("'NoneType' object has no attribute 'startswith'")
    monkeypatch.setattr(explain, "main", broken)
    assert main(["explain", "1", "P", "--db", str(tmp_path / "none.duckdb")]) == 3
    err = capsys.readouterr().err
    assert "crashed (a bug, not a finding)" in err and "AttributeError" in err


@pytest.mark.slow
def test_every_verdict_of_every_fixture_is_explained(tmp_path):
    """The hand-made traces cover every verdict cell of every type: each verdict row gets an
    explanation naming its property and verdict, none a traceback."""
    explained = set()
    for n, fixture in enumerate(all_fixtures()):
        con = judged_store(fixture, EPSILON, tmp_path / f"{n}.duckdb")
        rows = con.execute("select trace_id, property_id, rqst_id, verdict from verdicts").fetchall()
        texts = Explainer(con, fixture.interface, {p.id: p for p in fixture.properties}).explain(
            [(t, p, r) for t, p, r, _ in rows])
        con.close()
        types = {p.id: p.type for p in fixture.properties}
        for trace_id, property_id, rqst_id, verdict in rows:
            assert texts[(trace_id, property_id, rqst_id)].startswith(
                f"{property_id} on request {rqst_id} of trace {trace_id}: {verdict}"), fixture.path
            explained.add((types[property_id], verdict))
    assert {t for t, _ in explained} == set(property_types())  # every type a template declares
    assert {v for _, v in explained} >= {"TN", "TP", "FN", "FP"}


def test_a_request_placed_at_its_taken_reply_is_said_sent_then_taken(tmp_path, capsys):
    """The oracles place a request the SUT replied `taken` to at that reply (issue 48: explain called
    that instant "sent at"): explain gives both instants, for x(i) and for each y request."""
    db = tmp_path / "store.duckdb"
    con = connect(db)
    add_campaign(con, 1, "missions/dala", 1, RunRecord(mission=str(DEFAULT_MISSION_DIR), sut="genom", target=str(DEFAULT_MISSION_DIR)))
    add_reply_codes(con, INTERFACE)
    events = [(0, 0.0, "request", 1, "rflex", "Init", None, None), (1, 0.5, "final", 1, "rflex", "Init", None, "ok"),
              (2, 1.0, "request", 2, "rflex", "TrackSpeedStart", None, None),
              (3, 2.0, "final", 2, "rflex", "TrackSpeedStart", None, "ok")]
    insert_trace(con, 1, 1, None, Trace("genom", 1, sim_s=3.0, events=events, taken_events=[(4, 1.25, 2)]))
    properties = DEFAULT_MISSION_DIR / "properties.toml"
    materialise(con, load_properties(properties, INTERFACE), EPSILON, INTERFACE, properties)
    con.close()
    assert main(["explain", "1", "PEX(rflex)", "2", "--db", str(db)]) == 0
    out = capsys.readouterr().out
    assert "x(i) rflex.TrackSpeedStart sent at 1.000000 s, taken at 1.250000 s; final reply ok" in out, out


def test_a_real_time_trace_is_explained_with_the_epsilon_its_pings_measured(tmp_path, capsys):
    """A verdict is judged with its trace's own epsilon (view trace_epsilon); explain once printed the
    analysis's beside it (an arm run: 'margin 0.500000 s; suspicious (epsilon 0.01 s)', judged with
    the 0.6026 s its pings measured). Here 5 ms before Init's ok: unsure at 10 ms, sure at 1.9 ms."""
    db = tmp_path / "store.duckdb"
    con = connect(db)
    add_campaign(con, 1, "missions/dala", 1, RunRecord(mission=str(DEFAULT_MISSION_DIR), sut="genom", target=str(DEFAULT_MISSION_DIR)))
    add_reply_codes(con, INTERFACE)
    events = [(0, 0.0, "request", 1, "rflex", "Init", None, None), (1, 1.0, "final", 1, "rflex", "Init", None, "ok"),
              (2, 0.995, "request", 2, "rflex", "TrackSpeedStart", None, None),
              (3, 2.0, "final", 2, "rflex", "TrackSpeedStart", None, "ok")]
    for trace_id in (1, 2):
        insert_trace(con, trace_id, 1, None, Trace("genom", 1, sim_s=3.0, events=events))
    con.execute("""insert into trace_runs (trace_id, host, started_at, time_scale, pings, rtt_p50_s, rtt_p95_s,
                   rtt_max_s) values (2, 'local', now(), 1, 12, 0.001, 0.0015, 0.0019)""")
    properties = DEFAULT_MISSION_DIR / "properties.toml"
    materialise(con, load_properties(properties, INTERFACE), EPSILON, INTERFACE, properties)
    assert con.execute("select trace_id, suspicious from verdicts where property_id = 'PEX(rflex)' and rqst_id = 2 "
                       "order by 1").fetchall() == [(1, True), (2, False)]
    con.close()
    said = {}
    for trace_id in (1, 2):
        assert main(["explain", str(trace_id), "PEX(rflex)", "2", "--db", str(db)]) == 0
        said[trace_id] = capsys.readouterr().out
    assert "C is false; margin 0.005000 s; suspicious (epsilon 0.01 s)" in said[1], said[1]
    assert "C is false; margin 0.005000 s; not suspicious (epsilon 0.0019 s, measured by the trace's pings)" \
        in said[2], said[2]
    assert "q rflex.Init  ok at 1.000000" in said[2] and said[1].splitlines()[-2].endswith("yes") \
        and said[2].splitlines()[-2].endswith("no"), said


@pytest.mark.parametrize("became", [duckdb.CatalogException("Table with name given does not exist!"),
                                    StoreError("could not write the store: ...")])
def test_an_error_that_a_stop_signal_became_reads_as_the_stop_not_a_crash(tmp_path, capsys, monkeypatch, became):
    # measured: a Ctrl-C arriving while DuckDB reads a Python object (a replacement scan) comes out
    # of the query as a CatalogException, or through a transaction as the store's write problem
    def stopped_mid_query(*args):
        try:
            processes._raise_stopped(signal.SIGINT, None)
        except KeyboardInterrupt:
            raise became from None
    monkeypatch.setattr(processes, "_STOPPING", [])
    monkeypatch.setattr(explain, "main", stopped_mid_query)
    try:
        assert main(["explain", "1", "P", "--db", str(tmp_path / "none.duckdb")]) == 130
    finally:
        processes.stop_on_signals()  # the handlers that the first stop replaced, back for the next tests
    err = capsys.readouterr().err
    assert "stopped (Ctrl-C)" in err and "crashed" not in err and "Traceback" not in err
