"""The SVG timeline of one trace, drawn from the analyzer's requests view."""
from __future__ import annotations

from xml.etree import ElementTree as ET

import pytest

from harness.report.queries import trace_rows
from harness.report.timeline import LEFT, PLOT_W, timeline
from harness.report.trace_pages import traces
from harness.store.database import connect
from tests.support.report import TRACES, analysed_store

MODULES = ["rflex", "sick", "aspect", "ndd", "antenna"]


@pytest.fixture(scope="module")
def details(tmp_path_factory):
    con = connect(analysed_store(tmp_path_factory.mktemp("store") / "store.duckdb"), read_only=True)
    found = {t["trace_id"]: t for batch in trace_rows(con, list(TRACES)) for t in traces(batch)}
    con.close()
    return found


def _draw(trace: dict, verdicts=None) -> ET.Element:
    markup = timeline(MODULES, trace["requests"], trace["verdicts"] if verdicts is None else verdicts,
                      trace["world"], 30.0, trace["outcome"])
    root = ET.fromstring(str(markup))
    for element in root.iter():  # drop the SVG namespace so that find("title") reads naturally
        element.tag = element.tag.split("}")[-1]
    return root


def _find(root, css: str) -> list[ET.Element]:
    return [e for e in root.iter() if css in e.get("class", "").split()]


def _request(root, rqst_id: int) -> ET.Element:
    return next(g for g in _find(root, "request") if g.get("data-rqst") == str(rqst_id))


@pytest.mark.slow
def test_a_lane_per_module_in_interface_order_and_a_bar_per_request(details):
    root = _draw(details[5])
    lanes = _find(root, "lane")
    assert [lane.get("data-module") for lane in lanes] == ["rflex", "ndd", "antenna"]
    for lane in lanes:
        assert len(_find(lane, "bar")) == sum(1 for r in TRACES[5][3] if r[0] == lane.get("data-module"))
    assert len(_find(root, "open")) == 2  # TrackSpeedStart and Communication never replied
    assert len(_find(root, "reply-R")) == 1  # the disallowed GotoPosition
    assert len(_find(root, "world-event")) == 1


def test_a_bar_spans_request_to_final_reply(details):
    bar = _find(_request(_draw(details[1]), 6), "bar")[0]
    scale = PLOT_W / 30.0
    assert float(bar.get("x")) == pytest.approx(LEFT + 1.0 * scale, abs=0.01)
    assert float(bar.get("width")) == pytest.approx(10.0 * scale, abs=0.01)
    title = bar.find("title").text
    assert "ndd.GotoPosition x=9 y=4" in title and "final reply 'ok' (class T) at 11.000 s" in title


def test_an_open_bar_runs_to_the_end_of_the_trace(details):
    bar = _find(_request(_draw(details[5]), 6), "bar")[0]
    assert float(bar.get("x")) + float(bar.get("width")) == pytest.approx(LEFT + PLOT_W, abs=0.01)
    assert "no final reply" in bar.find("title").text


def test_overlapping_requests_of_a_module_stack_in_rows(details):
    # rflex.Stop is sent while TrackSpeedStart still runs: they cannot share a row
    root = _draw(details[1])
    top = {i: float(_find(_request(root, i), "bar")[0].get("y")) for i in (1, 5, 8)}
    assert top[5] != top[8]
    assert top[1] == top[5]  # Init ended long before TrackSpeedStart began: same row


def test_fn_fp_tp_are_marked_and_other_verdicts_stay_in_tooltips(details):
    trace = details[2]
    verdicts = trace["verdicts"] + [dict(trace["verdicts"][0], property_id="PEX(ndd)", rqst_id=5, verdict="TN",
                                         suspicious=False)]
    root = _draw(trace, verdicts)
    marks = {(m.get("data-property"), m.get("class")) for m in _find(root, "verdict")}
    assert marks == {("PRE(ndd.GotoPosition)", "verdict verdict-FN"),
                     ("AIB(rflex.TrackSpeedStart)", "verdict verdict-TP suspicious")}
    suspicious = _find(root, "suspicious")[0]
    assert "SUSPICIOUS" in suspicious.find("rect/title").text
    assert "TN PEX(ndd)" in _find(_request(root, 5), "bar")[0].find("title").text


def test_a_short_bar_is_labelled_after_it_when_there_is_room(details):
    root = _draw(details[1])
    stop = _request(root, 8)  # rflex.Stop: 50 ms, a few pixels wide, nothing after it in its row
    bar = _find(stop, "bar")[0]
    assert float(bar.get("width")) < 6 * len("Stop")
    label = _find(stop, "bar-label")[0]
    assert label.text == "Stop" and float(label.get("x")) >= float(bar.get("x")) + float(bar.get("width"))
    # rflex.SetMode, an instant, has TrackSpeedStart 0.4 s after it in its row: no room, no label
    assert not _find(_request(root, 3), "bar-label")
