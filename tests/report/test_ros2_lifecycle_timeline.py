"""A trace's timeline names a managed ROS 2 node's lifecycle state at each request (view
lifecycle_states, sql/views/lifecycle_states.sql), derived from the transitions requested and
their replies: the hand-made traces of tests/traces/lifecycle.trace, judged in DuckDB, drawn."""
from xml.etree import ElementTree as ET

import pytest

from harness.report.queries import trace_rows
from harness.report.timeline import timeline
from harness.report.trace_pages import traces
from tests.support.traces import HERE, judged_store, load

# trace label -> the state at each request, in request order (a pending transition after "?")
STATES = {
    "in_false_rp": ["unconfigured", "active", "inactive"],  # activate, deactivate, reset
    "in_false_accepted": ["unconfigured"],
    "in_false_after_refused": ["unconfigured", "unconfigured"],  # activate refused, then fibonacci
    "in_pending": ["unconfigured", "unconfigured?activate"],  # fibonacci sent while activate was pending
    "out_true_accepted": ["unconfigured", "inactive", "unconfigured"],  # configure, cleanup, configure
    "out_true_rp": ["unconfigured"],
    "out_false_rp": ["unconfigured", "finalized"],  # shutdown, shutdown
    "out_pending": ["unconfigured", "unconfigured?configure"],
    "out_false_other_r": ["unconfigured", "inactive"],  # configure ok, then configure again
}


@pytest.fixture(scope="module")
def drawn():
    fixture = load(HERE / "lifecycle.trace")
    con = judged_store(fixture, 0.01)
    labels = {i: case.label for i, case in enumerate(fixture.cases, 1)}
    found = {labels[t["trace_id"]]: t for batch in trace_rows(con, list(labels)) for t in traces(batch)}
    con.close()
    return found


def _svg(trace: dict) -> ET.Element:
    root = ET.fromstring(str(timeline(["sequencer"], trace["requests"], trace["verdicts"], [], 3.0, "completed")))
    for element in root.iter():
        element.tag = element.tag.split("}")[-1]
    return root


@pytest.mark.parametrize("label", sorted(STATES))
def test_each_request_names_the_nodes_lifecycle_state(drawn, label):
    requests = sorted(drawn[label]["requests"], key=lambda r: r.rqst_id)
    assert [r.lifecycle + (f"?{r.pending}" if r.pending else "") for r in requests] == STATES[label]
    root = _svg(drawn[label])
    titles = {g.get("data-rqst"): g.find("rect").find("title").text for g in root.iter("g")
              if "request" in g.get("class", "").split()}
    for request in requests:
        assert f"lifecycle state of sequencer at the request: {request.state}" in titles[str(request.rqst_id)]


def test_a_bar_label_shows_the_state_and_a_pending_transition(drawn):
    trace = drawn["in_false_rp"]
    labels = [t.text for t in _svg(trace).iter("text") if "bar-label" in t.get("class", "").split()]
    assert "reset [inactive]" in labels, labels
    pending = next(r for r in drawn["in_pending"]["requests"] if r.service == "fibonacci")
    assert (pending.state, pending.shown) == ("unconfigured (activate pending)", "fibonacci [unconfigured?]")


def test_modules_that_are_no_managed_node_have_no_state():
    con = judged_store(load(HERE / "pc.trace"), 0.01)
    assert con.execute("select count(*) from requests").fetchone()[0] > 0
    assert con.execute("select count(*) from lifecycle_states").fetchone()[0] == 0
    ids = [r[0] for r in con.execute("select trace_id from traces").fetchall()]
    assert all(r.lifecycle is None for batch in trace_rows(con, ids) for t in traces(batch) for r in t["requests"])


def test_a_store_analysed_before_the_view_existed_shows_no_state():
    fixture = load(HERE / "lifecycle.trace")
    con = judged_store(fixture, 0.01)
    con.execute("drop view lifecycle_states")
    drawn = [r for batch in trace_rows(con, [1, 2]) for t in traces(batch) for r in t["requests"]]
    assert drawn and all(r.lifecycle is None and r.state is None for r in drawn)
