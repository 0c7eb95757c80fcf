"""The report: numbers equal the store's views, timelines show every request, output is self-contained."""
from __future__ import annotations

import csv
import json
import shutil
import re
from collections import Counter
from html.parser import HTMLParser
from pathlib import Path
from types import SimpleNamespace

import pytest

from harness import DEFAULT_MISSION_DIR
from harness.analysis.analyzer import materialise
from harness.errors import StoreError
from harness.target.interface import load_interface, load_properties
from harness.report import build as report
from harness.store.database import add_campaign, add_reply_codes, connect, insert_trace
from harness.store.record import CampaignRecord
from harness.trace import Trace

GOLDEN = """send rflex.Init as ri
send ndd.Init as ni
wait all
send rflex.SetMode mode=velocity as mode
send ndd.SetParams speed=0.6 as nav
wait all
send rflex.TrackSpeedStart as track
send ndd.GotoPosition x=9 y=4 as site
wait site
send ndd.Stop as ns
send rflex.Stop as rs
wait all
"""
SWAPPED = GOLDEN.replace("send ndd.SetParams speed=0.6 as nav\nwait all\n", "wait all\n").replace(
    "wait site\n", "wait site\nsend ndd.SetParams speed=0.6 as nav\n")
REINIT = GOLDEN.replace("wait site\n", "send rflex.Init as ri2\nwait site\n")

# (module, service, args, requested at, final reply at or None, reply)
BASE = [("rflex", "Init", None, 0.0, 0.5, "ok"), ("ndd", "Init", None, 0.0, 0.4, "ok"),
        ("rflex", "SetMode", {"mode": "velocity"}, 0.6, 0.6, "ok"),
        ("ndd", "SetParams", {"speed": 0.6}, 0.6, 0.6, "ok")]
DRIVE = [("rflex", "TrackSpeedStart", None, 1.0, 12.0, "interrupted"),
         ("ndd", "GotoPosition", {"x": 9, "y": 4}, 1.0, 11.0, "ok"),
         ("ndd", "Stop", None, 11.5, 11.6, "ok"), ("rflex", "Stop", None, 11.999, 12.05, "ok")]
TRACES = {  # trace_id: (sut, outcome, script_id, requests, world events)
    1: ("genom", "completed", 1, BASE + DRIVE, []),
    2: ("genom", "completed", 2,  # the Stop or the Init, 1-2 ms apart, interrupted TrackSpeedStart: suspicious
        BASE[:3] + DRIVE + [("ndd", "SetParams", {"speed": 0.6}, 11.2, 11.2, "ok"),
                            ("rflex", "Init", None, 11.998, 12.5, "ok")],
        [(6.5, "collision", {"with": "rock"})]),
    3: ("genom", "completed", 3,  # genom's quirk: Init interrupts the running TrackSpeedStart
        BASE + [("rflex", "TrackSpeedStart", None, 1.0, 5.01, "interrupted")] + DRIVE[1:3]
        + [("rflex", "Init", None, 5.0, 5.5, "ok"), ("rflex", "Stop", None, 11.999, 12.05, "ok")], []),
    4: ("bip-a", "completed", 1, BASE + DRIVE, []),
    5: ("bip-a", "hung", 2, BASE[:3] + [("rflex", "TrackSpeedStart", None, 1.0, None, None),
                                          ("ndd", "GotoPosition", {"x": 9, "y": 4}, 1.0, 1.0, "disallowed"),
                                          ("antenna", "Communication", {"duration": 10}, 2.0, None, None)],
        [(3.0, "link_lost", {})]),
    6: ("reference", "completed", None, BASE, []),  # imported, only Init and control: no verdict
    7: ("bip-a", "completed", 3, BASE + DRIVE, []),  # good, but inverted on the internal timeline
}
# The layer took ndd.SetParams only after ndd.GotoPosition: PRE(ndd.GotoPosition) is TN observed, FN inside.
INTERNAL = {7: BASE[:3] + [("ndd", "SetParams", {"speed": 0.6}, 1.001, 1.001, "ok")] + DRIVE}


def _events(requests) -> list[tuple]:
    """Event rows (seq, t, kind, rqst_id, module, service, args, reply) from request tuples."""
    raw = []
    for rqst_id, (module, service, args, t0, t1, reply) in enumerate(requests, start=1):
        text = json.dumps(args) if args else None
        raw.append((t0, 0, "request", rqst_id, module, service, text, None))
        if t1 is not None:
            raw.append((t1, 1, "final", rqst_id, module, service, text, reply))
    raw.sort(key=lambda e: (e[0], e[1], e[3]))
    return [(seq, t, kind, r, m, s, a, reply) for seq, (t, _, kind, r, m, s, a, reply) in enumerate(raw)]


def make_store(path) -> None:
    """A small campaign: a golden script, two mutants and an invalid one, five traces on two variants
    (an FN, an FP, a hang, suspicious TPs, world events) and an imported trace without verdicts."""
    con = connect(path)
    add_campaign(con, 1, "missions/dala", 7, CampaignRecord(mission="missions/dala", sut=["genom", "bip-a"], mutants=3,
                                                             seed=7, ops_per_mutant=1))
    add_reply_codes(con, load_interface(DEFAULT_MISSION_DIR / "interface.toml"))
    scripts = [(1, "golden", None, [], GOLDEN, True, None),
               (2, "mutant", 1, [{"op": "swap", "lines": [5, 9]}], SWAPPED, True, None),
               (3, "mutant", 1, [{"op": "insert", "line": 9}], REINIT, True, None),
               (4, "mutant", 1, [{"op": "delete", "line": 1}], GOLDEN[22:], False,
                "line 2: unknown handle 'ri'; send it before waiting on it")]
    for sid, kind, parent, ops, body, valid, reason in scripts:
        con.execute("insert into scripts (script_id, campaign_id, kind, parent, mutations, body, valid, "
                    "invalid_reason) values (?, 1, ?, ?, ?, ?, ?, ?)",
                    [sid, kind, parent, json.dumps(ops), body, valid, reason])
    for trace_id, (sut, outcome, script_id, requests, world) in TRACES.items():
        trace = Trace(sut, seed=trace_id if script_id else None, outcome=outcome,
                      sim_s=12.1 if outcome == "completed" else 30.0, wall_s=0.0011 if outcome == "hung" else 0.01,
                      events=_events(requests), internal_events=_events(INTERNAL.get(trace_id, [])),
                      world_events=[(t, kind, json.dumps(d)) for t, kind, d in world])
        insert_trace(con, trace_id, 1, script_id, trace, label=None if script_id else "robot-log")
    con.close()


def analysed_store(path, epsilon: float = 0.01, mission: Path = DEFAULT_MISSION_DIR):
    """make_store, judged by the analyzer with the properties of `mission` (Dala's)."""
    make_store(path)
    interface = load_interface(mission / "interface.toml")
    con = connect(path)
    materialise(con, load_properties(mission / "properties.toml", interface), epsilon, interface,
                mission / "properties.toml")
    con.close()
    return path


def write_report(db, out, traces=()) -> Path:
    """The whole report, or with `traces` only their pages (on demand)."""
    report.main(SimpleNamespace(db=str(db), out=str(out), trace=list(traces)))
    return Path(out)


class Page(HTMLParser):
    """An HTML page as the tests read it: its elements, and each table's rows of (text, href) cells."""

    def __init__(self, text: str):
        super().__init__()
        self.elements: list[tuple[str, dict]] = []
        self.tables: dict[str, list[list[tuple[str, str | None]]]] = {}
        self._rows = self._cell = None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        self.elements.append((tag, attrs))
        if tag == "table":
            self._rows = self.tables.setdefault(attrs.get("id"), [])
        elif tag == "tr" and self._rows is not None:
            self._rows.append([])
        elif tag in ("td", "th") and self._rows is not None:
            self._cell = ["", None]
        elif tag == "a" and self._cell is not None:
            self._cell[1] = attrs.get("href")

    def handle_data(self, data):
        if self._cell is not None:
            self._cell[0] += data

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self._rows[-1].append((self._cell[0].strip(), self._cell[1]))
            self._cell = None
        elif tag == "table":
            self._rows = None

    def with_class(self, css: str) -> list[dict]:
        return [attrs for _, attrs in self.elements if css in (attrs.get("class") or "").split()]

    def texts(self, table: str) -> list[list[str]]:
        return [[text for text, _ in row] for row in self.tables[table]]


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
