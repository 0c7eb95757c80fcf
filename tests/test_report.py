"""The report: numbers equal the store's views, timelines show every request, output is self-contained."""
from __future__ import annotations

import json
from types import SimpleNamespace
from xml.etree import ElementTree as ET

import pytest

from harness import DEFAULT_MISSION_DIR, report
from harness.errors import StoreError
from harness.interface import load_interface
from harness.report.timeline import LEFT, PLOT_W, timeline
from harness.store import add_campaign, add_reply_codes, connect, insert_trace
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
    2: ("genom", "completed", 2, BASE[:3] + DRIVE + [("ndd", "SetParams", {"speed": 0.6}, 11.2, 11.2, "ok")],
        [(6.5, "collision", {"with": "rock"})]),
    3: ("genom", "completed", 3, BASE + DRIVE[:2] + [("rflex", "Init", None, 5.0, 5.5, "ok")] + DRIVE[2:],
        []),
    4: ("bip-a", "completed", 1, BASE + DRIVE, []),
    5: ("bip-a", "hung", 2, BASE[:3] + [("rflex", "TrackSpeedStart", None, 1.0, None, None),
                                          ("ndd", "GotoPosition", {"x": 9, "y": 4}, 1.0, 1.0, "disallowed"),
                                          ("antenna", "Communication", {"duration": 10}, 2.0, None, None)],
        [(3.0, "link_lost", {})]),
}


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
    """A small campaign: a golden script, two mutants and an invalid one, five traces on two variants."""
    con = connect(path)
    add_campaign(con, 1, "missions/dala", 7, {"sut": ["genom", "bip-a"], "mutants": 3})
    add_reply_codes(con, load_interface(DEFAULT_MISSION_DIR / "interface.toml"))
    scripts = [(1, "golden", None, [], GOLDEN, True, None),
               (2, "mutant", 1, [{"op": "swap", "lines": [5, 9]}], SWAPPED, True, None),
               (3, "mutant", 1, [{"op": "insert", "line": 9}], REINIT, True, None),
               (4, "mutant", 1, [{"op": "delete", "line": 1}], GOLDEN[22:], False,
                "line 2: unknown handle 'ri'; send it before waiting on it")]
    for sid, kind, parent, ops, body, valid, reason in scripts:
        con.execute("insert into scripts values (?, 1, ?, ?, ?, ?, ?, ?)",
                    [sid, kind, parent, json.dumps(ops), body, valid, reason])
    for trace_id, (sut, outcome, script_id, requests, world) in TRACES.items():
        trace = Trace(sut, seed=trace_id, outcome=outcome, sim_s=12.1 if outcome == "completed" else 30.0,
                      wall_s=0.01, events=_events(requests),
                      world_events=[(t, kind, json.dumps(d)) for t, kind, d in world])
        insert_trace(con, trace_id, 1, script_id, trace)
    con.close()


def _rows(con, sql):
    cursor = con.execute(sql)
    names = [d[0] for d in cursor.description]
    return [dict(zip(names, r)) for r in cursor.fetchall()]


def _svg(markup) -> ET.Element:
    root = ET.fromstring(str(markup))
    for element in root.iter():  # drop the SVG namespace so that find("title") reads naturally
        element.tag = element.tag.split("}")[-1]
    return root


def _classes(element) -> set[str]:
    return set(element.get("class", "").split())


def _find(root, css_class: str) -> list:
    return [e for e in root.iter() if css_class in _classes(e)]


@pytest.fixture(scope="module")
def raw_store(tmp_path_factory):
    path = tmp_path_factory.mktemp("store") / "raw.duckdb"
    make_store(path)
    return path


def _trace_timeline(path, trace_id, verdicts=()):
    con = connect(path, read_only=True)
    events = _rows(con, f"""select e.*, c.class from events e left join reply_codes c using (module, service, reply)
                            where trace_id = {trace_id} order by seq""")
    world = _rows(con, f"select * from world_events where trace_id = {trace_id} order by t")
    con.close()
    sut, outcome, *_ = TRACES[trace_id]
    return _svg(timeline(["rflex", "sick", "aspect", "ndd", "antenna"], events, list(verdicts), world,
                         30.0, outcome))


def test_timeline_has_a_lane_per_module_and_a_bar_per_request(raw_store):
    root = _trace_timeline(raw_store, 5)
    lanes = _find(root, "lane")
    assert [lane.get("data-module") for lane in lanes] == ["rflex", "ndd", "antenna"]
    requests = TRACES[5][3]
    for lane in lanes:
        bars = _find(lane, "bar")
        assert len(bars) == sum(1 for r in requests if r[0] == lane.get("data-module"))
    assert len(_find(root, "open")) == 2  # TrackSpeedStart and Communication never replied
    assert len(_find(root, "reply-R")) == 1  # the disallowed GotoPosition
    assert len(_find(root, "world-event")) == 1


def test_timeline_bars_span_request_to_final_reply(raw_store):
    root = _trace_timeline(raw_store, 1)
    goto = next(g for g in _find(root, "request") if g.get("data-rqst") == "6")
    bar = _find(goto, "bar")[0]
    scale = PLOT_W / 30.0
    assert float(bar.get("x")) == pytest.approx(LEFT + 1.0 * scale, abs=0.01)
    assert float(bar.get("width")) == pytest.approx(10.0 * scale, abs=0.01)
    assert "GotoPosition" in bar.find("title").text and "'ok'" in bar.find("title").text


def test_overlapping_requests_of_a_module_stack_in_rows(raw_store):
    # trace 1: rflex.Stop is sent while TrackSpeedStart still runs, so they share no row
    root = _trace_timeline(raw_store, 1)
    rflex = _find(root, "lane")[0]
    tops = {g.get("data-rqst"): float(_find(g, "bar")[0].get("y")) for g in _find(rflex, "request")}
    assert tops["5"] != tops["8"]
    assert tops["1"] == tops["5"]  # Init ended long before TrackSpeedStart: same row


def test_timeline_marks_fn_fp_tp_and_keeps_tn_in_tooltips(raw_store):
    verdicts = [dict(trace_id=2, property_id=p, family=p[:3], rqst_id=r, module="ndd", service="GotoPosition",
                     c_holds=c, verdict=v, margin_s=0.002, suspicious=s)
                for p, r, c, v, s in [("PRE(ndd.GotoPosition)", 5, False, "FN", True),
                                      ("PEX(ndd)", 5, True, "TN", False),
                                      ("AIB(rflex.TrackSpeedStart)", 4, False, "TP", False)]]
    root = _trace_timeline(raw_store, 2, verdicts)
    marks = _find(root, "verdict")
    assert sorted(m.get("data-property") for m in marks) == ["AIB(rflex.TrackSpeedStart)",
                                                             "PRE(ndd.GotoPosition)"]
    fn = _find(root, "verdict-FN")[0]
    assert "suspicious" in _classes(fn) and "SUSPICIOUS" in fn.find("rect/title").text
    goto = next(g for g in _find(root, "request") if g.get("data-rqst") == "5")
    assert "TN PEX(ndd)" in _find(goto, "bar")[0].find("title").text


def test_report_of_an_unanalysed_store_says_to_run_analyze(raw_store, tmp_path):
    args = SimpleNamespace(db=str(raw_store), out=str(tmp_path / "out"), trace=[])
    with pytest.raises(StoreError, match=r"has no verdicts yet .*run python -m harness analyze"):
        report.main(args)
    assert not (tmp_path / "out" / "index.html").exists()


def test_report_of_a_missing_store_names_it(tmp_path):
    args = SimpleNamespace(db=str(tmp_path / "nowhere.duckdb"), out=str(tmp_path / "out"), trace=[])
    with pytest.raises(StoreError, match="nowhere.duckdb"):
        report.main(args)
