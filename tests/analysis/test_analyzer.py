"""The analyze command: materialisation in one transaction, ground-truth inversions, printed tables."""
import json
import re
import shutil
import tomllib

import jinja2
import pytest

from harness import DEFAULT_MISSION_DIR, SQL_DIR
from harness.analysis import analyzer
from harness.store import sql as oracles

from harness.analysis.analyzer import materialise
from harness.analysis.summary import analysis_summary, flag_accuracy
from harness.cli import main
from harness.errors import PropertyError, StoreError
from harness.target.interface import Property
from harness.trace import Trace
from tests.support.traces import HERE, PROPERTIES, judged_store, judged_traces, load

EPSILON = 0.01
PEX = PROPERTIES["PEX(rflex)"]


def _row(seq, t, kind, rqst_id, service, reply=None):
    module, name = service.split(".")
    return (seq, t, kind, rqst_id, module, name, None, reply)


def _store_with_truth():
    """Two traces whose internal timeline inverts the observed order of the request and Init's ok
    (the request sent before the ok came, but slow to reach the layer; the other way round cannot
    be: a reply observed before a request was sent came before it).

    Trace 1: request observed 2 ms before the ok (FN, suspicious); internally taken after it (TN).
    Trace 2: request observed 0.5 s before (FN, not suspicious); internally after (TN) - missed by the flag.
    """
    traces = []
    for gap in (0.002, 0.5):
        trace = Trace(sut="genom", seed=0)
        trace.events = [_row(1, 0.0, "request", 1, "rflex.Init"),
                        _row(2, 1.0 - gap, "request", 2, "rflex.TrackSpeedStart"),
                        _row(3, 1.0, "final", 1, "rflex.Init", "ok"),
                        _row(4, 2.0, "final", 2, "rflex.TrackSpeedStart", "ok")]
        trace.internal_events = [_row(1, 0.0, "request", 1, "rflex.Init"),
                                 _row(2, 0.999, "final", 1, "rflex.Init", "ok"),
                                 _row(3, 1.0, "request", 2, "rflex.TrackSpeedStart"),
                                 _row(4, 2.0, "final", 2, "rflex.TrackSpeedStart", "ok")]
        traces.append((trace, None))
    return judged_traces("test", traces, [PEX], EPSILON)


def test_the_same_oracles_judge_the_internal_timeline():
    con = _store_with_truth()
    assert con.execute("select trace_id, verdict, suspicious from verdicts order by 1").fetchall() == [
        (1, "FN", True), (2, "FN", False)]
    assert con.execute("select trace_id, verdict, c_holds from verdicts_internal order by 1").fetchall() == [
        (1, "TN", True), (2, "TN", True)]


def test_inversions_count_differing_verdicts_and_what_the_flag_caught():
    con = _store_with_truth()
    assert con.execute("""select trace_id, property_id, rqst_id, observed, internal, observed_c, internal_c,
                                 suspicious from inversions order by trace_id""").fetchall() == [
        (1, "PEX(rflex)", 2, "FN", "TN", False, True, True),
        (2, "PEX(rflex)", 2, "FN", "TN", False, True, False)]
    assert "Ground truth: 2 of 2 observed verdicts differ" in analysis_summary(con, EPSILON)
    assert ("caught 1 of them (recall 50.0%) and is raised on 1 verdict in all (precision 100.0%)"
            in analysis_summary(con, EPSILON))


def test_a_request_the_layer_never_took_is_no_inversion():
    """A hung layer never takes the last request: it is judged (omega) on the observed side only,
    which no reordering could change, so neither the view nor the flag's recall counts it."""
    trace = Trace(sut="bip-a", seed=0, outcome="hung")
    trace.events = [_row(1, 0.0, "request", 1, "rflex.Init"), _row(2, 1.0, "final", 1, "rflex.Init", "ok"),
                    _row(3, 1.5, "request", 2, "rflex.TrackSpeedStart")]
    trace.internal_events = trace.events[:2]
    con = judged_traces("test", [(trace, None)], [PEX], EPSILON)
    assert con.execute("select rqst_id, verdict from verdicts").fetchall() == [(2, "omega")]
    assert con.execute("select count(*) from verdicts_internal").fetchone()[0] == 0
    assert con.execute("select count(*) from inversions").fetchone()[0] == 0
    assert flag_accuracy(con) == (0, 0, 0, 0)


def test_traces_without_ground_truth_have_no_inversions():
    con = judged_store(load(HERE / "tables.trace"), EPSILON)
    assert con.execute("select count(*) from inversions").fetchone()[0] == 0
    assert "Ground truth" not in analysis_summary(con, EPSILON)


def test_analysing_again_replaces_the_verdicts():
    con = judged_store(load(HERE / "tables.trace"), EPSILON)
    before = con.execute("select * from verdicts order by all").fetchall()
    materialise(con, load(HERE / "tables.trace").properties, EPSILON)
    assert con.execute("select * from verdicts order by all").fetchall() == before
    pex = "select trace_id, rqst_id, verdict, certain, suspicious from verdicts where property_id = 'PEX(rflex)' order by all"
    pex_before = con.execute(pex).fetchall()
    materialise(con, [PEX], 1.0)
    assert con.execute("select distinct property_id from verdicts").fetchall() == [("PEX(rflex)",)]
    # Init's ok observed 0.5 s before the request was sent came before it, however wide epsilon is
    assert con.execute(pex).fetchall() == pex_before and all(row[3] for row in pex_before)
    assert con.execute("select epsilon, properties from analysis").fetchall() == [(1.0, 1)]


def test_a_property_that_cannot_be_rendered_leaves_the_verdicts_alone():
    con = judged_store(load(HERE / "tables.trace"), EPSILON)
    before = con.execute("select count(*) from verdicts").fetchone()[0]
    broken = Property(id="ES(broken)", family="ES", type="ES", x=("ndd.GotoPosition",), r_p="disallowed")
    with pytest.raises(PropertyError, match=r"ES\(broken\)"):
        materialise(con, [PEX, broken], EPSILON)
    assert con.execute("select count(*) from verdicts").fetchone()[0] == before


def test_a_store_the_oracles_cannot_read_rolls_everything_back():
    con = judged_store(load(HERE / "tables.trace"), EPSILON)
    before = con.execute("select * from verdicts order by all").fetchall()
    con.execute("alter table reply_codes rename to reply_catalogue")  # neither oracles nor views can bind
    with pytest.raises(StoreError) as failed:
        materialise(con, [PEX], 0.5)
    assert str(failed.value).startswith("the oracle queries failed on this store: Catalog Error: Table with "
                                        "name reply_codes does not exist!")
    assert str(failed.value).endswith("the previous verdicts are kept")
    assert con.execute("select * from verdicts order by all").fetchall() == before
    assert con.execute("select epsilon from analysis").fetchall() == [(EPSILON,)]


def _two_properties(tmp_path):
    """The fixture's two properties in a properties file, with the interface beside it."""
    chosen = [e for e in tomllib.loads((DEFAULT_MISSION_DIR / "properties.toml").read_text())["property"]
              if e["id"] in ("PEX(rflex)", "AIB(ndd.GotoPosition)")]
    lines = ['[[property]]\n' + "".join(f"{k} = {json.dumps(v)}\n" for k, v in e.items()) for e in chosen]
    shutil.copy(DEFAULT_MISSION_DIR / "interface.toml", tmp_path / "interface.toml")
    (tmp_path / "properties.toml").write_text("\n".join(lines))
    return tmp_path / "properties.toml"


def test_analyze_command_prints_tables_ii_to_iv(tmp_path, capsys):
    db = tmp_path / "store.duckdb"
    judged_store(load(HERE / "tables.trace"), EPSILON, db).close()
    assert main(["analyze", "--db", str(db), "--properties", str(_two_properties(tmp_path))]) == 0
    out = capsys.readouterr().out
    assert "Judged 22 events of 6 traces against 2 properties" in out
    table2, table3, table4 = (_cells(out, a, b) for a, b in (("Table II -", "Table III"),
                                                            ("Table III", "Table IV"), ("Table IV", "Epsilon (view")))
    assert table2 == [["sut", "total", "hung", "crashed", "with_fn", "with_fp", "bad", "unknown", "t_rob", "with_fn_min",
                       "with_fn_max", "with_fp_min", "with_fp_max", "bad_min", "bad_max", "unknown_min", "unknown_max",
                       "t_rob_min", "t_rob_max"],
                      ["A", "4", "1", "0", "1", "1", "3", "0", "25.0%", "1", "1", "1", "1", "3", "3", "0", "0", "25.0%",
                       "25.0%"],
                      ["B", "2", "0", "1", "0", "0", "1", "0", "50.0%", "0", "0", "0", "0", "1", "1", "0", "0", "50.0%",
                       "50.0%"]]
    # each rate with its 95% Wilson interval (textbook values: 1/2 -> 9.5-90.5, 1/1 -> 20.7-100) and n,
    # then o= its interval over the orders of events closer than epsilon (a point: all are certain here)
    assert table3 == [["family", "A", "B"], ["PEX", "50.0 [9.5, 90.5] n=2 o=[50.0, 50.0]", "100.0 [20.7, 100.0] n=1 o=[100.0, 100.0]"],
                      ["AIB", "100.0 [20.7, 100.0] n=1 o=[100.0, 100.0]", "- n=0 o=[-, -]"],
                      ["All", "66.7 [20.8, 93.9] n=3 o=[66.7, 66.7]", "100.0 [20.7, 100.0] n=1 o=[100.0, 100.0]"]]
    assert table4 == [["family", "A", "B"], ["PEX", "50.0 [9.5, 90.5] n=2 o=[50.0, 50.0]", "- n=0 o=[-, -]"],
                      ["AIB", "0.0 [0.0, 79.3] n=1 o=[0.0, 0.0]", "0.0 [0.0, 79.3] n=1 o=[0.0, 0.0]"],
                      ["All", "33.3 [6.1, 79.2] n=3 o=[33.3, 33.3]", "0.0 [0.0, 79.3] n=1 o=[0.0, 0.0]"]]
    # the two properties, fewest C-false requests first, on their worst variant
    assert "view coverage): AIB(ndd.GotoPosition) 0 (B), PEX(rflex) 1 (B)." in out


def _cells(out: str, start: str, end: str) -> list[list[str]]:
    """The cells of the printed table between two titles, without its title and rule."""
    lines = out.split(start)[1].split(end)[0].splitlines()[1:]
    return [re.split(r"\s{2,}", line.strip()) for line in lines if line.strip() and set(line) - {"-", " "}]


def test_analyze_refuses_a_missing_store_and_a_bad_epsilon(tmp_path, capsys):
    assert main(["analyze", "--db", str(tmp_path / "none.duckdb")]) == 2
    assert "no store at" in capsys.readouterr().err
    db = tmp_path / "store.duckdb"
    judged_store(load(HERE / "tables.trace"), EPSILON, db).close()
    assert main(["analyze", "--db", str(db), "--epsilon", "-1"]) == 2
    assert "argument --epsilon: '-1': give a number of seconds >= 0" in capsys.readouterr().err


def test_a_typo_in_a_template_names_the_property_the_template_and_the_rendered_line(tmp_path, monkeypatch):
    sql = tmp_path / "sql"
    shutil.copytree(SQL_DIR, sql)
    ee = sql / "oracles" / "ee.sql"
    ee.write_text(ee.read_text().replace("y_class is not distinct from 'R' as conflict_rejected",
                                         "y_klass is not distinct from 'R' as conflict_rejected"))
    con = judged_store(load(HERE / "tables.trace"), EPSILON)
    before = con.execute("select * from verdicts where property_id = 'PEX(rflex)' order by all").fetchall()
    monkeypatch.setattr(oracles.ENV, "loader", jinja2.FileSystemLoader(sql))
    monkeypatch.setattr(analyzer, "SQL_DIR", sql)
    aib = PROPERTIES["AIB(ndd.GotoPosition)"]
    materialise(con, [PEX, aib], EPSILON)
    # a one-pass query that fails is replaced by its properties' own: the failure is in one of those
    alone = [a for o in analyzer.render_oracles([PEX, aib], EPSILON).oracles
             for a in (o.alone if isinstance(o, analyzer.OnePass) else [o])]
    ran = next(o.sql for o in alone if o.prop == aib)
    query = ran.split("\n", 1)[1]  # the statement less its first line, `insert into`
    line = next(n for n, text in enumerate(query.splitlines(), 1) if "y_klass" in text)
    failures = con.execute("select analysis_id, property_id, source, template, error from oracle_failures "
                           "order by source").fetchall()
    # the store holds no internal events: no oracle ran on them, so none failed there
    assert [f[:4] for f in failures] == [(2, "AIB(ndd.GotoPosition)", "events", "sql/oracles/ee.sql")]
    assert failures[0][4].startswith('Binder Error: Referenced column "y_klass" not found')
    assert failures[0][4].endswith(f", line {line} of the rendered query: "
                                   "\"y_klass is not distinct from 'R' as conflict_rejected\"")
    assert con.execute("select * from verdicts where property_id = 'PEX(rflex)' order by all").fetchall() == before
    # one unknown row per request the property judges (its x requests), the same as a normal analysis gives
    assert con.execute("select distinct verdict, c_holds, margin_s, suspicious from verdicts "
                       "where property_id = 'AIB(ndd.GotoPosition)'").fetchall() == [("unknown", None, None, False)]
    assert con.execute("select count(*) from verdicts where property_id = 'AIB(ndd.GotoPosition)'").fetchone()[0] \
        == con.execute("select count(*) from events where kind = 'request' and service = 'GotoPosition'").fetchone()[0]
    shown = analyzer.failed_oracles(con)
    assert len(shown) == 1 and shown[0].startswith(
        "The oracle of property 'AIB(ndd.GotoPosition)' on events failed: Binder Error: "
        'Referenced column "y_klass" not found')
    assert "[template sql/oracles/ee.sql]; its 3 verdicts are 'unknown' (table oracle_failures)" in shown[0]


def test_a_real_time_trace_is_judged_with_the_epsilon_its_pings_measured():
    """The same request 5 ms before Init's ok: unsure at the analysis's 10 ms, sure in a real-time
    run whose slowest ping round trip was 2 ms (wall) at time scale 1."""
    traces = []
    for _ in range(2):
        trace = Trace(sut="genom", seed=0)
        trace.events = [_row(1, 0.0, "request", 1, "rflex.Init"), _row(2, 0.995, "request", 2, "rflex.TrackSpeedStart"),
                        _row(3, 1.0, "final", 1, "rflex.Init", "ok"),
                        _row(4, 2.0, "final", 2, "rflex.TrackSpeedStart", "ok")]
        traces.append((trace, None))
    con = judged_traces("test", traces, [PEX], EPSILON)
    con.execute("""insert into trace_runs (trace_id, host, started_at, time_scale, pings, rtt_p50_s, rtt_p95_s,
                   rtt_max_s) values (2, 'local', now(), 1, 12, 0.001, 0.0015, 0.0019)""")
    materialise(con, [PEX], EPSILON)
    assert con.execute("select trace_id, epsilon_s, source from trace_epsilon order by 1").fetchall() == [
        (1, EPSILON, "analysis"), (2, 0.0019, "pings")]
    assert con.execute("select trace_id, verdict, suspicious from verdicts order by 1").fetchall() == [
        (1, "FN", True), (2, "FN", False)]
    assert ("Epsilon (view trace_epsilon): 0.01 s for 1 trace (the analysis's --epsilon); 0.0019 s for 1 trace "
            "(measured by the pings of each real-time run)." in analysis_summary(con, EPSILON))
