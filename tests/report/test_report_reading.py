"""The report reads well: what each list shows and in which order, every link leads somewhere,
charts do not overlap, a killed report leaves the previous one whole, and Tables II-IV count
only judged traces of one kind (no ad-hoc run folded into a campaign's rows)."""
from __future__ import annotations

import json
import re
from pathlib import Path
from xml.etree import ElementTree as ET

import pytest

from harness import DEFAULT_MISSION_DIR
from harness.analysis.analyzer import materialise
from harness.analysis.summary import analysis_summary
from harness.target.interface import load_interface, load_properties
from harness.report import charts, html, trace_pages
from harness.store.database import add_campaign, add_reply_codes, connect, insert_trace
from harness.store.record import RunRecord
from harness.trace import Trace
from tests.support.report import TRACES, Page, _events, analysed_store, copied_store, make_store, write_report


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    root = tmp_path_factory.mktemp("reading")
    # epsilon 11 s: trace 2's FN (margin 10.2 s) is suspicious, like the TPs; trace 3's FP (7 s) is sure:
    # the only other request that could have interrupted its TrackSpeedStart, a Stop, was sent after
    # the interruption was observed
    return write_report(analysed_store(root / "store.duckdb", epsilon=11.0), root / "out")


def _page(path: Path) -> Page:
    return Page(path.read_text())


@pytest.mark.slow
def test_the_suspicious_list_shows_fn_and_fp_first(out):
    rows = _page(out / "index.html").tables["suspicious"]
    verdicts = [row[rows[0].index(("verdict", None))][0] for row in rows[1:]]
    assert verdicts[:1] == ["FN"] and len(verdicts) > 1
    assert not {"FN", "FP"} & set(verdicts[1:])
    assert rows[1][0] == ("2", "traces/trace-2.html")


def test_inversion_trace_ids_link_to_their_pages(out):
    rows = _page(out / "index.html").tables["inversions"]
    column = rows[0].index(("trace_id", None))
    assert [row[column] for row in rows[1:]] == [("7", "traces/trace-7.html")]
    assert (out / "traces" / "trace-7.html").exists()


def test_list_pages_name_the_properties_and_mutation_behind_each_trace(out):
    page = _page(out / html.list_href("genom", "PRE"))
    assert page.texts("traces")[1] == ["2", "completed", "1", "0", "0", "1", "PRE(ndd.GotoPosition)",
                                       "swap lines 5, 9"]
    aib = _page(out / html.list_href("genom", "AIB"))
    assert [row[0] for row in aib.texts("traces")[1:]] == ["3"]  # the FP
    tp_only = aib.texts("tp-only")
    assert [row[0] for row in tp_only[1:]] == ["1", "2"]
    assert tp_only[1][-2:] == ["AIB(rflex.TrackSpeedStart)", ""]  # the golden script: no mutation


def test_a_trace_without_a_page_names_the_command_that_writes_it(out):
    text = (out / html.list_href("genom", "All")).read_text()
    assert 'title="no page yet: python -m harness report --trace' not in text  # every genom trace has one
    assert html.mutation(json.dumps([{"op": "insert_request", "position": 8, "step": "send aspect.Stop"}])) == \
        "insert_request position 8: send aspect.Stop"


def test_trace_pages_say_yes_or_no_and_a_short_wall_time(out):
    fp = _page(out / "traces" / "trace-3.html")
    assert {row[2] for row in fp.texts("verdicts")[1:]} <= {"yes", "no", ""}
    assert "True" not in (out / "traces" / "trace-3.html").read_text()
    hung = (out / "traces" / "trace-5.html").read_text()
    assert "1.1 ms of wall time" in hung and "observation seed 5" in hung


def test_every_link_of_the_report_leads_to_a_file(out):
    pages_seen = 0
    for path in out.rglob("*.html"):
        pages_seen += 1
        base = out if path.parent != out else path.parent  # subpages say <base href="../">
        for href in re.findall(r'href="([^"#]+)"', path.read_text()):
            if href != "../":
                assert (base / href).exists(), f"{path.name} links to missing {href}"
    assert pages_seen > 10


@pytest.mark.slow
def test_a_report_killed_while_writing_leaves_the_previous_one_whole(tmp_path, monkeypatch):
    db = analysed_store(tmp_path / "store.duckdb")
    out = write_report(db, tmp_path / "out")
    before = {p.relative_to(out): p.read_bytes() for p in out.rglob("*") if p.is_file()}
    (out / ".report-writing" / "traces").mkdir(parents=True)  # a killed report's leftovers

    def killed(folder, batch, *context):
        html.render("trace.html.j2", folder / "traces" / "half.html", t={**trace_pages.traces(batch)[0], "shrunk": []},
                     timeline="", verdicts=[],
                     counts={}, events="", explained=[])
        raise KeyboardInterrupt
    monkeypatch.setattr(trace_pages, "write_traces", killed)
    with pytest.raises(KeyboardInterrupt):
        write_report(db, out)
    after = {p.relative_to(out): p.read_bytes() for p in out.rglob("*") if p.is_file()}
    assert after == before


def _svg_texts(markup) -> list[tuple[float, float, float, float, str]]:
    """The boxes (left, top, right, bottom) the chart's texts take, at CHAR_W per character."""
    root = ET.fromstring(str(markup))
    boxes = []
    for e in root.iter():
        if e.tag.endswith("text") and e.text:
            x, y, w = float(e.get("x")), float(e.get("y")), charts.CHAR_W * len(e.text)
            left = {"end": x - w, "middle": x - w / 2}.get(e.get("text-anchor"), x)
            boxes.append((left, y - 11, left + w, y + 2, e.text))
    return boxes


def _overlaps(a, b) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


@pytest.mark.parametrize("chart", range(4))
def test_no_chart_label_overlaps_another(chart):
    suts, families = ["genom", "bip-a", "bip-b"], ["PEX", "AIB", "PRE", "EXC", "All"]
    rates = {(f, s): 0.5 for f in families for s in suts}
    drawn = [charts.grouped_bars("T", ["T_ROB"], suts, {("T_ROB", s): 0.7 for s in suts}),
             charts.grouped_bars("TP", families, suts, rates),
             charts.grouped_bars("FP", families, suts, rates, full_scale=False),
             charts.stacked_bars("mix", suts, ["TP", "FN", "FP", "TN", "op", "na", "omega"],
                                 {(s, v): n for s in suts for v, n in zip(["TP", "FN", "FP", "TN"], [900, 1, 2, 5000])})]
    boxes = _svg_texts(drawn[chart])
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not _overlaps(a, b), (a, b)


def test_the_verdict_mix_has_a_scale_and_shows_a_single_fn():
    root = ET.fromstring(str(charts.stacked_bars("mix", ["genom"], ["TP", "FN", "TN"],
                                                 {("genom", "TP"): 3000, ("genom", "FN"): 1, ("genom", "TN"): 9000})))
    ticks = [e.text for e in root.iter() if e.tag.endswith("text")]
    assert ["0%", "25%", "50%", "75%", "100%"] == [t for t in ticks if t.endswith("%")]
    widths = {e.get("class"): float(e.get("width")) for e in root.iter()
              if e.tag.endswith("rect") and e.get("y") == "26"}
    assert widths["v-FN"] >= charts.MIN_PART_W
    assert sum(widths.values()) == pytest.approx(560)


def _add_trace(con, trace_id, campaign_id, requests, sut="genom"):
    insert_trace(con, trace_id, campaign_id, None, Trace(sut, seed=0, sim_s=12.1, events=_events(requests)))


@pytest.mark.slow
def test_tables_count_judged_traces_and_keep_ad_hoc_runs_apart(tmp_path):
    db = tmp_path / "store.duckdb"
    make_store(db)
    con = connect(db)
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    properties = load_properties(DEFAULT_MISSION_DIR / "properties.toml", interface)
    materialise(con, properties, 0.01, interface)
    before = con.execute("select * from trace_robustness order by sut").fetchall()
    add_campaign(con, 2, "golden.mission", 0, RunRecord(sut="genom"))
    _add_trace(con, 20, 2, TRACES[2][3])  # an ad-hoc run with an FN, on a campaign's variant
    materialise(con, properties, 0.01, interface)
    assert con.execute("select count(*) from verdicts where trace_id = 20 and verdict = 'FN'").fetchone()[0] == 1
    assert con.execute("select * from trace_robustness order by sut").fetchall() == before
    _add_trace(con, 21, 1, TRACES[2][3])  # stored after the analysis: no verdicts yet
    assert con.execute("select * from trace_robustness order by sut").fetchall() == before
    assert con.execute("select trace_id, left_out from trace_scope where not counted order by 1").fetchall() == [
        (20, "ad-hoc run beside a campaign or import"), (21, "stored after the last analysis: run analyze")]
    assert "Not counted in Tables II-IV (view trace_scope): 1 trace: ad-hoc run beside a campaign or import; " \
           "1 trace: stored after the last analysis: run analyze." in analysis_summary(con, 0.01)
    con.close()
    out = write_report(db, tmp_path / "out")
    outcomes = _page(out / "index.html").texts("trace_outcomes")
    assert outcomes[0][-2:] == ["not_counted", "left_out_because"]
    assert ["2", "genom", "1", "1", "0", "0", "1", "ad-hoc run beside a campaign or import"] in outcomes


@pytest.mark.slow
def test_a_store_of_ad_hoc_runs_alone_counts_them(tmp_path):
    con = connect(tmp_path / "runs.duckdb")
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    add_campaign(con, 1, "golden.mission", 0, RunRecord(sut="genom"))
    add_reply_codes(con, interface)
    _add_trace(con, 1, 1, TRACES[2][3])
    materialise(con, load_properties(DEFAULT_MISSION_DIR / "properties.toml", interface), 0.01, interface)
    assert con.execute("select sut, total, with_fn, t_rob from trace_robustness").fetchall() == [("genom", 1, 1, 0.0)]
    con.close()


@pytest.mark.slow
def test_pages_written_by_worker_processes_equal_those_written_in_one(tmp_path, monkeypatch):
    from harness.report import build as report
    db = analysed_store(tmp_path / "store.duckdb")
    serial = write_report(db, tmp_path / "serial")
    monkeypatch.setattr(report, "PARALLEL_FROM", 1)
    monkeypatch.setattr(report.os, "sched_getaffinity", lambda pid: {0, 1})
    parallel = write_report(db, tmp_path / "parallel")
    assert len(_files(serial)) > 20 and _files(parallel) == _files(serial)


@pytest.mark.slow
def test_the_report_goes_beside_its_store_wherever_it_is_run_from(tmp_path, monkeypatch, capsys):
    from harness.cli import main
    db = analysed_store(tmp_path / "store" / "campaign.duckdb")
    monkeypatch.chdir(tmp_path)
    assert main(["report", "--db", str(db)]) == 0
    assert (tmp_path / "store" / "index.html").exists() and not (tmp_path / "reports").exists()
    assert f"wrote {tmp_path / 'store' / 'index.html'}" in capsys.readouterr().out


@pytest.mark.slow
def test_a_store_beyond_the_memory_limit_is_reported_all_the_same(tmp_path, monkeypatch, capsys):
    from harness.report import build as report
    db = analysed_store(tmp_path / "store.duckdb")
    within = write_report(db, tmp_path / "within")
    monkeypatch.setattr(report, "memory_limit_mb", lambda traces: 1)
    beyond = write_report(db, tmp_path / "beyond")
    assert "needs more than 1 MB of DuckDB memory for this store; writing it again" in capsys.readouterr().err
    assert _files(beyond) == _files(within)


@pytest.mark.slow
def test_a_store_of_a_default_campaign_s_size_is_reported_once_within_its_limit(tmp_path, monkeypatch, capsys):
    """1,057 traces (the hand-made store's, copied): 48 MB, the limit set for far larger stores
    before it was chosen from the store's size, was not enough and the report was written twice."""
    from harness.report import build as report
    db = tmp_path / "store.duckdb"
    copied_store(db, copies=150)
    real_write, writes = report.write_report, []
    monkeypatch.setattr(report, "write_report", lambda con, out: writes.append(out) or real_write(con, out))
    write_report(db, tmp_path / "out")
    assert len(writes) == 1 and "writing it again" not in capsys.readouterr().err


def _files(out: Path) -> dict[Path, bytes]:
    return {p.relative_to(out): p.read_bytes() for p in out.rglob("*") if p.is_file()}
