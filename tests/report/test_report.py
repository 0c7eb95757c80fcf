"""The report: numbers equal the store's views, timelines show every request, output is self-contained."""
from __future__ import annotations

import csv
import shutil
import re
from collections import Counter
from pathlib import Path

import pytest

from harness import DEFAULT_MISSION_DIR
from harness.analysis.analyzer import materialise
from harness.errors import StoreError
from harness.target.interface import load_interface, load_properties
from harness.store.database import connect
from tests.support.report import Page, analysed_store, make_store, write_report


def shown(value, rate: bool = False) -> str:
    """How the report writes a store value, restated independently of harness.report.tables."""
    if rate:
        return "-" if value is None else f"{100 * value:.1f}"
    return "" if value is None else ("yes" if value is True else "no" if value is False else str(value))


def _query(db, sql):
    con = connect(db, read_only=True)
    cursor = con.execute(sql)
    names = [d[0] for d in cursor.description]
    found = [dict(zip(names, row)) for row in cursor.fetchall()]
    con.close()
    return names, found


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    root = tmp_path_factory.mktemp("report")
    db = analysed_store(root / "campaign.duckdb")
    write_report(db, root / "out")
    return db, write_report(db, root / "out", [6])


def _page(path: Path) -> Page:
    return Page(path.read_text())


@pytest.mark.slow
def test_table2_equals_the_trace_robustness_view(site):
    db, out = site
    names, found = _query(db, "select * from trace_robustness")
    rows = _page(out / "index.html").texts("trace_robustness")
    assert rows[0] == names
    assert sorted(rows[1:]) == sorted([shown(r[c], c.startswith("t_rob")) for c in names] for r in found)
    assert [r[0] for r in rows[1:]] == ["genom", "bip-a", "reference"]  # the order they were run


@pytest.mark.parametrize("table, view, rate", [("table3", "tp_rates", "tp_rate"), ("table4", "fp_rates", "fp_rate")])
def test_tables_3_and_4_equal_the_rate_views(site, table, view, rate):
    db, out = site
    _, found = _query(db, f"select * from {view}")
    rows = _page(out / "index.html").texts(table)
    suts = rows[0][1:]
    cells = {(row[0], sut): text for row in rows[1:] for sut, text in zip(suts, row[1:])}

    def with_interval(r):  # the rate, its 95% interval, n, then its interval over the orders of events
        orders = f" o=[{shown(r[rate + '_min'], rate=True)}, {shown(r[rate + '_max'], rate=True)}]"
        if not r["n"]:
            return "- n=0" + orders
        return (f"{shown(r[rate], rate=True)} [{shown(r[rate + '_low'], rate=True)}, "
                f"{shown(r[rate + '_high'], rate=True)}] n={r['n']}{orders}")
    expected = {(r["family"], r["sut"]): with_interval(r) for r in found}
    assert cells == {key: expected.get(key, "- n=0 o=[-, -]") for key in cells}  # a variant without such verdicts: no case
    assert set(expected) <= set(cells)
    assert table == "table4" or "- n=0 o=[-, -]" in cells.values()  # a family without a case says so
    assert [row[0] for row in rows[1:]] == ["PEX", "AIB", "PRE", "EXC", "VAL", "All"]


def test_the_property_table_equals_the_coverage_view(site):
    db, out = site
    names, found = _query(db, "select * from coverage")
    rows = _page(out / "index.html").texts("coverage")
    assert rows[0] == names
    rates = [c for c in names if "rate" in c]
    assert Counter(map(tuple, rows[1:])) == Counter(tuple(shown(r[c], c in rates) for c in names) for r in found)


def test_csv_files_equal_the_views(site):
    db, out = site
    for view in ("trace_robustness", "tp_rates", "fp_rates", "coverage", "inversions"):
        names, found = _query(db, f"select * from {view}")
        with open(out / f"{view}.csv", newline="") as f:
            written = list(csv.reader(f))
        extra = [c for c in written[0] if c not in names]  # e.g. the variant beside a trace id
        assert [c for c in written[0] if c not in extra] == names
        keep = [written[0].index(c) for c in names]
        assert Counter(tuple(row[i] for i in keep) for row in written[1:]) == \
            Counter(tuple("" if r[c] is None else str(r[c]) for c in names) for r in found), view


def test_the_bad_trace_verdicts_csv_holds_every_fn_and_fp(site):
    db, out = site
    _, found = _query(db, "select trace_id, property_id, rqst_id, verdict from verdicts "
                          "where verdict in ('FN', 'FP')")
    with open(out / "bad_trace_verdicts.csv", newline="") as f:
        written = list(csv.DictReader(f))
    assert sorted((int(r["trace_id"]), r["property_id"], int(r["rqst_id"]), r["verdict"]) for r in written) == \
        sorted(tuple(r.values()) for r in found) == [(2, "PRE(ndd.GotoPosition)", 5, "FN"),
                                                     (3, "AIB(rflex.TrackSpeedStart)", 5, "FP")]


def test_every_trace_page_has_a_lane_per_module_and_a_bar_per_request(site):
    db, out = site
    _, found = _query(db, "select trace_id, module, count(*) as n from requests group by all")
    pages = sorted(out.glob("traces/trace-*.html"))
    # golden runs 1 and 4, bad traces 2, 3, 5, inverted 7, and 6 asked for on demand
    assert [p.name for p in pages] == [f"trace-{i}.html" for i in (1, 2, 3, 4, 5, 6, 7)]
    for path in pages:
        trace_id = int(re.search(r"\d+", path.name).group())
        page = _page(path)
        expected = {r["module"]: r["n"] for r in found if r["trace_id"] == trace_id}
        lanes = [lane["data-module"] for lane in page.with_class("lane")]
        assert sorted(lanes) == sorted(expected)
        assert len(page.with_class("bar")) == sum(expected.values())


def test_a_hung_trace_page_shows_open_bars_world_events_and_the_mutation(site):
    _, out = site
    text = (out / "traces" / "trace-5.html").read_text()
    page = Page(text)
    assert [lane["data-module"] for lane in page.with_class("lane")] == ["rflex", "ndd", "antenna"]
    assert len(page.with_class("open")) == 2 and len(page.with_class("reply-R")) == 1
    assert len(page.with_class("world-event")) == 1 and "link_lost" in text
    assert "hung at 30 s" in text
    assert "<span class=\"del\">-send ndd.SetParams speed=0.6 as nav</span>" in text
    assert "<span class=\"add\">+send ndd.SetParams speed=0.6 as nav</span>" in text


def test_verdict_marks_on_the_fn_fp_and_suspicious_tp(site):
    _, out = site
    fn = _page(out / "traces" / "trace-2.html")
    assert [m["data-property"] for m in fn.with_class("verdict-FN")] == ["PRE(ndd.GotoPosition)"]
    assert [m["data-property"] for m in fn.with_class("suspicious")] == ["AIB(rflex.TrackSpeedStart)"]
    fp = _page(out / "traces" / "trace-3.html")
    assert [m["data-property"] for m in fp.with_class("verdict-FP")] == ["AIB(rflex.TrackSpeedStart)"]


def test_table3_cells_reach_trace_pages_in_two_clicks(site):
    db, out = site
    _, found = _query(db, """select t.sut, coalesce(v.family, 'All') as family, count(distinct trace_id) as n
                             from verdicts v join traces t using (trace_id) where v.verdict in ('TP', 'FN', 'FP')
                             group by grouping sets ((t.sut, v.family), (t.sut))""")
    listed = {(r["sut"], r["family"]): r["n"] for r in found}
    _, rates = _query(db, "select * from tp_rates")
    rows = _page(out / "index.html").tables["table3"]
    suts = [text for text, _ in rows[0][1:]]
    for row in rows[1:]:
        for sut, (_, href) in zip(suts, row[1:]):
            cell_page = _page(out / href)
            rows_shown = [r for table in ("traces", "tp-only") for r in cell_page.tables.get(table, [])[1:]]
            assert len(rows_shown) == listed.get((sut, row[0][0]), 0), (sut, row[0][0])
            links = [r[0][1] for r in rows_shown if r[0][1]]
            assert len(links) == len(rows_shown) and all((out / link).exists() for link in links)
            cell = next((r for r in rates if (r["sut"], r["family"]) == (sut, row[0][0])), None)
            if cell is None:  # the variant has no verdict of the family: its cell says "- n=0", lists none
                assert row[suts.index(sut) + 1][0] == "- n=0 o=[-, -]" and rows_shown == []
                continue
            interval = (f"{shown(cell['tp_rate'], rate=True)} [{shown(cell['tp_rate_low'], rate=True)}, "
                        f"{shown(cell['tp_rate_high'], rate=True)}] n={cell['n']}" if cell["n"] else "- n=0")
            interval += f" o=[{shown(cell['tp_rate_min'], rate=True)}, {shown(cell['tp_rate_max'], rate=True)}]"
            assert f"TP {cell['tp']}, FN {cell['fn']}: TP rate (%, 95% interval, n)\n{interval}." in \
                (out / href).read_text()


def test_every_bad_trace_is_listed_under_its_variant(site):
    db, out = site
    _, found = _query(db, """select t.trace_id, t.sut from traces t where t.outcome <> 'completed'
                             or exists (select 1 from verdicts v where v.trace_id = t.trace_id
                                        and v.verdict in ('FN', 'FP'))""")
    assert sorted(r["trace_id"] for r in found) == [2, 3, 5]
    for r in found:
        page = _page(out / "traces" / f"bad-{r['sut']}.html")
        assert f"traces/trace-{r['trace_id']}.html" in [row[0][1] for row in page.tables["traces"][1:]]


def test_the_bad_traces_csv_and_table_ii_read_the_one_rule_of_a_bad_trace(site):
    db, out = site
    _, bad = _query(db, "select trace_id, sut from trace_badness where bad")
    _, table2 = _query(db, "select sut, bad from trace_robustness")
    with open(out / "bad_traces.csv", newline="") as f:
        written = [(int(r["trace_id"]), r["sut"]) for r in csv.DictReader(f)]
    assert written == sorted((r["trace_id"], r["sut"]) for r in bad) == [(2, "genom"), (3, "genom"), (5, "bip-a")]
    assert Counter(sut for _, sut in written) == {r["sut"]: r["bad"] for r in table2 if r["bad"]}


def test_the_index_names_the_campaign_and_the_invalid_mutant(site):
    _, out = site
    index = _page(out / "index.html")
    text = (out / "index.html").read_text()
    assert "mission <code>missions/dala</code>, seed 7" in text and "3 mutants of which 1 invalid" in text
    assert index.texts("invalid_mutants")[1][3] == "line 2: unknown handle 'ri'; send it before waiting on it"
    assert "epsilon = 0.01 s" in text
    assert len(index.with_class("chart")) == 4


def test_output_is_self_contained(site):
    _, out = site
    for path in out.rglob("*.html"):
        text = path.read_text()
        assert not re.search(r"""(src|href)\s*=\s*["']?\s*(https?:)?//""", text, re.I), path
        assert "<script" not in text and "<link" not in text and "@import" not in text, path


@pytest.mark.slow
def test_a_trace_asked_for_gets_a_page_on_demand_and_stale_pages_go(site, tmp_path):
    db, _ = site
    out = write_report(db, tmp_path / "out")
    index = (out / "index.html").stat().st_mtime_ns
    assert not (out / "traces" / "trace-6.html").exists()
    write_report(db, out, [6])
    page = (out / "traces" / "trace-6.html").read_text()
    assert "Imported trace <code>robot-log</code>" in page and "observation seed" not in page
    assert (out / "index.html").stat().st_mtime_ns == index  # only the page was written
    write_report(db, out)
    assert not (out / "traces" / "trace-6.html").exists()


def test_an_unknown_trace_id_is_refused(site, tmp_path):
    db, _ = site
    with pytest.raises(StoreError, match=r"no trace \[99\] in the store"):
        write_report(db, tmp_path / "out", [99])


def test_report_of_an_unanalysed_store_says_to_run_analyze(tmp_path):
    make_store(tmp_path / "raw.duckdb")
    with pytest.raises(StoreError, match=r"has no verdicts yet .*run python -m harness analyze"):
        write_report(tmp_path / "raw.duckdb", tmp_path / "out")
    assert not (tmp_path / "out" / "index.html").exists()


def test_report_of_a_missing_store_names_it(tmp_path):
    with pytest.raises(StoreError, match="nowhere.duckdb"):
        write_report(tmp_path / "nowhere.duckdb", tmp_path / "out")


def test_trace_pages_explain_their_fn_fp_and_suspicious_verdicts(site):
    _, out = site
    texts = [text for text in (out / "traces" / "trace-2.html").read_text().split('<pre class="explain">')[1:]]
    heads = [text.splitlines()[0] for text in texts]
    assert heads == ["AIB(rflex.TrackSpeedStart) on request 4 of trace 2: TP",
                     "PRE(ndd.GotoPosition) on request 5 of trace 2: FN"]
    assert "C is false; margin 0.001000 s; suspicious (epsilon 0.01 s)" in texts[0]
    assert "y rflex.Stop #7" in texts[0]
    assert "explain" not in (out / "traces" / "trace-1.html").read_text().split("Event log")[0].split("Why")[1]


@pytest.mark.slow
def test_the_index_shows_the_files_of_the_verdicts_and_warns_when_they_changed(tmp_path):
    mission = tmp_path / "mission"
    shutil.copytree(DEFAULT_MISSION_DIR, mission)
    db = analysed_store(tmp_path / "campaign.duckdb", mission=mission)
    index = (write_report(db, tmp_path / "out") / "index.html").read_text()
    assert str(mission / "properties.toml") in index and 'id="stale"' not in index
    with open(mission / "properties.toml", "a") as f:
        f.write("# refined\n")
    index = (write_report(db, tmp_path / "out") / "index.html").read_text()
    stale = index.split('id="stale"')[1].split("</p>")[0]
    assert f"properties <code>{mission / 'properties.toml'}</code>" in stale


@pytest.mark.slow
def test_the_index_shows_what_the_last_analysis_changed(tmp_path):
    db = analysed_store(tmp_path / "campaign.duckdb")
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    properties = load_properties(DEFAULT_MISSION_DIR / "properties.toml", interface)
    con = connect(db)
    materialise(con, [p for p in properties if p.family != "PRE"], 0.01, interface)
    con.close()
    page = _page(write_report(db, tmp_path / "out") / "index.html")
    transitions = page.texts("verdict_transitions")
    assert transitions[0] == ["sut", "property_id", "family", "previous", "current", "verdicts"]
    assert ["genom", "PRE(ndd.GotoPosition)", "PRE", "FN", "", "1"] in transitions
    assert ["genom", "PRE", "III", "tp_rate", "0", ""] in page.texts("table_changes")


def test_after_a_first_analysis_changes_say_so_and_list_nothing(site):
    """Issue 19, item 7: the Changes section listed every verdict as a change from nothing."""
    db, out = site
    index = (out / "index.html").read_text()
    assert "This is the first analysis of the store: there is nothing to compare it with." in index
    assert 'id="verdict_transitions"' not in index


def test_every_trace_id_in_the_suspicious_table_is_a_link(site):
    db, out = site
    rows = _page(out / "index.html").tables["suspicious"][1:]
    _, suspicious = _query(db, "select distinct trace_id from verdicts where suspicious")
    assert rows and {int(row[0][0]) for row in rows} == {r["trace_id"] for r in suspicious}
    for (text, href), *_ in rows:
        assert href and (out / href).is_file(), text
