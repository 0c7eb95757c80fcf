"""The ROS 2 types RSP, CAN, GOAL and OUTLIVE (sql/oracles/rsp.sql, can.sql, goal.sql, outlive.sql;
docs/reference/verdicts.md#ros-2-types) beyond their hand-made traces (tests/traces/ros2_*.trace):
the deadline parameter, explain, and a fuzz of both timelines proving that no reordering within
epsilon leaves a verdict certain that the server's own timeline contradicts."""
import re
from datetime import datetime

import pytest

from harness import ROOT
from harness.analysis.analyzer import materialise
from harness.analysis.explain import Explainer
from harness.errors import InputFileError
from harness.store.database import add_campaign, add_reply_codes, connect, insert_trace
from harness.store.record import RunRecord
from harness.target.interface import load_properties
from harness.target.mission import load_mission
from harness.trace import Trace
from tests.support.intervals_truth import missed, outside
from tests.support.ros2_fuzz import random_arm_trace
from tests.support.traces import HERE, judged_store, judged_traces, load

ARM = load_mission(ROOT / "tests/traces/ros2_arm")
EPSILON = 0.01
TYPES = {"RSP", "CAN", "GOAL", "OUTLIVE"}
ENTRY = '[[property]]\nid = "R"\nfamily = "R"\ntype = "{type}"\nx = ["arm.grip"]\ny = ["arm.move"]\n{extra}'


@pytest.mark.parametrize("type_, extra, message", [
    ("RSP", "deadline = 0\n", "deadline = 0; give the deadline in seconds, a number > 0"),
    ("RSP", "deadline = -1.5\n", "deadline = -1.5; give the deadline in seconds"),
    ("RSP", 'deadline = "2"\n', "deadline = '2'; give the deadline in seconds"),
    ("ES", 'r_p = "refused"\ndeadline = 1\n', "key(s) ['deadline'] do not apply to type ES; it takes x, y, r_p"),
])
def test_a_bad_deadline_or_one_the_type_does_not_take_is_refused(tmp_path, type_, extra, message):
    path = tmp_path / "properties.toml"
    path.write_text(ENTRY.format(type=type_, extra=extra))
    with pytest.raises(InputFileError, match=re.escape(message)):
        load_properties(path, ARM.interface)


def test_a_deadline_is_seconds_and_may_be_left_out(tmp_path):
    path = tmp_path / "properties.toml"
    path.write_text(ENTRY.format(type="RSP", extra="deadline = 2\n") + ENTRY.format(type="RSP", extra="")
                    .replace('"R"', '"S"'))
    assert [p.deadline for p in load_properties(path, ARM.interface)] == [2.0, None]


def test_the_example_has_one_property_of_each_type_and_every_one_is_judged():
    assert {p.type for p in ARM.properties()} == TYPES
    con = judged_store(load(HERE / "ros2_can.trace"), EPSILON)
    assert con.execute("select count(*) from oracle_failures").fetchone()[0] == 0


@pytest.mark.parametrize("file, label, property_id, shown", [
    ("ros2_rsp.trace", "rsp_busy_late", "RSP(arm.grip)",
     "sent at 0.500000 s, due by 1.000000 s (deadline 0.5 s), answered at 1.900000 s: late"),
    ("ros2_can.trace", "can_refused", "CAN(arm.move)",
     "cancel sent at 0.500000 s: goal 1 due to end canceled by 1.500000 s (deadline 1 s); it ended at 1.800000 s: late"),
    ("ros2_goal.trace", "goal_parallel", "GOAL(arm.move)", "before it moves (at 0.600000 s); the last ended at 2.000000 s"),
    ("ros2_outlive.trace", "outlive_runs_on", "OUTLIVE(arm.move)",
     "the node left the state at 0.600000 s: due to end by 1.600000 s (deadline 1 s); no end; the trace ended at "
     "3.100000 s: late"),
])
def test_explain_shows_the_deadline_in_words_beside_the_requests(file, label, property_id, shown):
    fixture = load(HERE / file)
    con = judged_store(fixture, EPSILON)
    trace_id, rqst_id, verdict = con.execute("""select trace_id, rqst_id, verdict from verdicts join traces using (trace_id)
                                                where label = ? and property_id = ? and verdict = 'FN'""",
                                             [label, property_id]).fetchone()
    text = Explainer(con, fixture.interface, {p.id: p for p in fixture.properties}).explain(
        [(trace_id, property_id, rqst_id)])[(trace_id, property_id, rqst_id)]
    assert text.startswith(f"{property_id} on request {rqst_id} of trace {trace_id}: FN")
    assert "y arm." in text and shown in text


def test_explain_says_why_a_cancels_condition_is_undefined():
    fixture = load(HERE / "ros2_can.trace")
    con = judged_store(fixture, EPSILON)
    trace_id = next(n for n, case in enumerate(fixture.cases, 1) if case.label == "can_no_goal")
    text = Explainer(con, fixture.interface, {p.id: p for p in fixture.properties}).explain(
        [(trace_id, "CAN(arm.move)", 1)])[(trace_id, "CAN(arm.move)", 1)]
    assert "C is undefined (no goal to cancel)" in text and text.endswith("nothing in the trace could make C false")


DERIVED = """
[[property]]
id = "G"
family = "G"
type = "GOAL"
x = ["arm.move"]

[[property]]
id = "O"
family = "O"
type = "OUTLIVE"
x = ["arm.move"]
y = ["arm.deactivate"]
"""


def _arm_trace(rows: list[tuple]) -> Trace:
    """A trace of the arm from (t, kind, rqst_id, service, reply) rows."""
    events = [(seq, t, kind, rqst_id, "arm", service, "{}" if kind == "request" else None, reply)
              for seq, (t, kind, rqst_id, service, reply) in enumerate(rows, 1)]
    return Trace(sut="arm", seed=0, events=events)


def test_goal_and_outlive_derive_their_deadlines_from_the_first_reply_and_from_the_transitions(tmp_path):
    """GOAL: 10 x the golden goal's time to its first feedback (0.15 s: 1.5 s); OUTLIVE: 10 x the
    golden deactivate's latency (0.2 s: 2 s), not the goal's 5 s run."""
    (tmp_path / "p.toml").write_text(DERIVED)
    golden = [(0.0, "request", 1, "move", None), (0.15, "intermediate", 1, "move", None),
              (5.0, "final", 1, "move", "ok"), (5.1, "request", 2, "deactivate", None),
              (5.3, "final", 2, "deactivate", "ok")]
    # a second move while the first runs, the first ending 1.4 s (trace 2) or 1.6 s (trace 3) after it;
    # a deactivate whose ok leaves the first one running 1.9 s (trace 2) or 2.1 s (trace 3)
    mutants = [[(0.0, "request", 1, "move", None), (1.0, "request", 2, "move", None),
                (1.0 + end, "final", 1, "move", "aborted"), (3.0, "final", 2, "move", "ok"),
                (3.5, "request", 3, "move", None), (4.0, "request", 4, "deactivate", None),
                (4.1, "final", 4, "deactivate", "ok"), (4.1 + left, "final", 3, "move", "ok")]
               for end, left in ((1.4, 1.9), (1.6, 2.1))]
    con = judged_traces("derived", [(_arm_trace(golden), "golden"), *[(_arm_trace(m), None) for m in mutants]],
                        load_properties(tmp_path / "p.toml", ARM.interface), EPSILON,
                        interface=ARM.interface, golden=frozenset({1}))
    verdicts = con.execute("""select trace_id, property_id, verdict from verdicts
                              where trace_id > 1 and (property_id, rqst_id) in (('G', 2), ('O', 3))
                              order by all""").fetchall()
    assert verdicts == [(2, "G", "TP"), (2, "O", "TN"), (3, "G", "FN"), (3, "O", "FN")]


@pytest.fixture(scope="module")
def fuzzed():
    return judged_traces("ros2 fuzz", [(random_arm_trace(seed), None) for seed in range(400)], ARM.properties(),
                         EPSILON, interface=ARM.interface)


@pytest.mark.slow
def test_every_verdict_of_the_servers_timeline_is_the_observed_one_or_an_alternative(fuzzed):
    con = fuzzed
    assert con.execute("select count(*) from oracle_failures").fetchone()[0] == 0
    cells = {(t, v) for t, v in con.execute("""select p.type, v.verdict from verdicts v join properties p
                                               using (property_id) group by all""").fetchall()}
    # the fuzz reaches the cells that matter: each type's finding, its right verdicts and omega
    assert {("RSP", "TN"), ("RSP", "FN"), ("CAN", "TP"), ("CAN", "FN"), ("CAN", "FP"), ("GOAL", "TP"),
            ("GOAL", "FN"), ("OUTLIVE", "FN"), ("OUTLIVE", "TP")} <= cells
    inverted, flagged = con.execute("""select count(*) filter (where o.verdict <> i.verdict),
                                              count(*) filter (where o.suspicious)
                                       from verdicts o join verdicts_internal i
                                       using (trace_id, property_id, rqst_id)""").fetchone()
    assert inverted > 0 and flagged >= inverted  # near events do change verdicts here
    assert missed(con) == []
    assert outside(con) == []


@pytest.mark.slow
def test_the_fuzz_catches_an_oracle_that_trusts_every_order():
    """With epsilon 0 every observed order counts as sure: the server's timeline then contradicts
    some certain verdicts, so the check above can fail."""
    con = judged_traces("ros2 fuzz", [(random_arm_trace(seed), None) for seed in range(400)], ARM.properties(),
                        0.0, interface=ARM.interface)
    assert {property_id.split("(")[0] for _, _, property_id, *_ in missed(con)} >= {"RSP", "CAN", "GOAL"}


def test_a_hand_mission_run_by_untimely_run_derives_no_deadline(tmp_path):
    """`untimely run` stores any script it runs as a golden one: the fib_pkg trial's hand mission,
    its service answered 7 s late behind a blocked executor, set its own deadline to 70 s and was
    judged a certain TN. Only a run of the target's golden.mission (or a campaign's golden) counts."""
    con = connect(tmp_path / "store.duckdb")
    add_reply_codes(con, ARM.interface)
    runs = [("golden.mission", [(0.0, "request", 1, "grip", None), (0.05, "final", 1, "grip", "ok")]),
            ("blocked.mission", [(0.0, "request", 1, "move", None), (1.0, "request", 2, "grip", None),
                                 (8.0, "final", 1, "move", "ok"), (8.0, "final", 2, "grip", "ok")])]
    for n, (name, rows) in enumerate(runs, 1):
        add_campaign(con, n, str(tmp_path / name), 0, RunRecord(sut="arm", target=str(tmp_path)))
        con.execute("insert into scripts values (?, ?, 'golden', null, '[]', '', true, null)", [n, n])
        insert_trace(con, n, n, n, _arm_trace(rows))
    prop = [p for p in ARM.properties() if p.id == "RSP(arm.grip,derived)"]
    materialise(con, prop, EPSILON, ARM.interface)
    assert con.execute("select trace_id, rqst_id, verdict, round(margin_s, 6) from verdicts order by 1").fetchall() == [
        (1, 1, "TN", 0.95), (2, 2, "FN", 6.0)]  # the golden's 0.05 s: the 1 s floor, not 10 x 7 s


def entry(name: str, type_: str, x: str, y: str, extra: str) -> str:
    return f'[[property]]\nid = "{name}"\nfamily = "{name}"\ntype = "{type_}"\nx = ["{x}"]\ny = ["{y}"]\n{extra}\n'


BLOCKED = (entry("R", "RSP", "arm.grip", "arm.move", "deadline = 0.5")
           + entry("C", "CAN", "arm.move_cancel", "arm.move", 'z_p = "canceled"\ndeadline = 0.5')
           + entry("O", "OUTLIVE", "arm.move", "arm.deactivate", "deadline = 0.5"))


def _run(transport_max_s: float | None) -> dict:
    """A real-time run's provenance whose slowest ping took 2 s (held for the node's blocked executor)."""
    return {"host": "here", "started_at": datetime(2026, 12, 3, 12), "time_scale": 1.0, "sut_info": "arm", "pings": 3,
            "rtt_p50_s": 2.0, "rtt_p95_s": 2.0, "rtt_max_s": 2.0, "transport_max_s": transport_max_s}


# Each ends 1.4 to 1.6 s past its deadline, and the order it is judged in is sure at any epsilon
# below 2.1 s: the grip's while a goal runs (RSP), a cancelled goal's ended canceled late (CAN), a goal's
# that outlived a deactivate (OUTLIVE).
BLOCKED_TRACES = {
    "R": [(0.0, "request", 1, "move", None), (0.5, "request", 2, "grip", None), (2.5, "final", 2, "grip", "ok"),
          (4.0, "final", 1, "move", "ok")],
    "C": [(0.0, "request", 1, "move", None), (2.5, "request", 2, "move_cancel", None),
          (2.6, "final", 2, "move_cancel", "ok"), (4.6, "final", 1, "move", "canceled")],
    "O": [(0.0, "request", 1, "move", None), (2.5, "request", 2, "deactivate", None),
          (2.6, "final", 2, "deactivate", "ok"), (4.7, "final", 1, "move", "ok")],
}


@pytest.mark.parametrize("transport_max_s, suspicious", [
    (0.002, False),  # the transport took 2 ms: late in every order
    (None, True),  # no measure of the transport (a store or an SUT from before held_s): the pings' 2 s
])
def test_a_deadline_is_judged_with_the_transports_epsilon_not_the_executors_wait(tmp_path, transport_max_s,
                                                                                  suspicious):
    """In runs whose pings waited 2 s for the node's executor, a reply or a goal's end 1.4-1.6 s
    past its deadline is an FN, certain once the transport's own round trip is known."""
    (tmp_path / "p.toml").write_text(BLOCKED)
    traces = []
    for rows in BLOCKED_TRACES.values():
        traces.append((_arm_trace(rows), None))
        traces[-1][0].provenance = _run(transport_max_s)
    con = judged_traces("blocked", traces, load_properties(tmp_path / "p.toml", ARM.interface), EPSILON,
                        interface=ARM.interface)
    assert con.execute("select count(*) from oracle_failures").fetchone()[0] == 0
    judged = con.execute("""select property_id, verdict, suspicious from verdicts
                            where (trace_id, property_id, rqst_id) in ((1, 'R', 2), (2, 'C', 2), (3, 'O', 1))
                            order by trace_id""").fetchall()
    assert judged == [(name, "FN", suspicious) for name in BLOCKED_TRACES]
    assert con.execute("select distinct epsilon_s, transport_epsilon_s from trace_epsilon").fetchall() == [
        (2.0, 2.0 if transport_max_s is None else 0.002)]
    properties = {p.id: p for p in load_properties(tmp_path / "p.toml", ARM.interface)}
    text = Explainer(con, ARM.interface, properties).explain([(1, "R", 2)])[(1, "R", 2)]
    deadline = next(line for line in text.splitlines() if line.strip().startswith("deadline"))
    assert deadline.rstrip().endswith("yes" if suspicious else "no"), text
    assert ("deadlines 0.002 s, the transport's" in text) is not suspicious, text


# A ROS 2 rejection carries no reason: the grip interlock (ES) and the lifecycle's gating (IN) both
# reject with `rejected`. A grip sent while the activation is pending and rejected: the node may
# have taken it before activating (IN's TP), so ES's FP may be the gating's rejection, not an
# unasked one: uncertain. The same grip rejected once the node is active is both properties' FP.
GATED = (entry("ACTIVE", "IN", "arm.grip", "arm.deactivate", 'q = ["arm.activate"]\nr_p = "rejected"')
         + entry("NO_GRIP", "ES", "arm.grip", "arm.move", 'r_p = "rejected"'))
GATED_TRACES = {
    "pending": [(0.0, "request", 1, "activate", None), (0.1, "request", 2, "grip", None),
                (0.2, "final", 2, "grip", "rejected"), (0.3, "final", 1, "activate", "ok")],
    "active": [(0.0, "request", 1, "activate", None), (0.1, "final", 1, "activate", "ok"),
               (0.5, "request", 2, "grip", None), (0.6, "final", 2, "grip", "rejected")],
}


def test_a_rejection_another_property_may_have_called_for_is_no_certain_fp(tmp_path):
    (tmp_path / "p.toml").write_text(GATED)
    con = judged_traces("gated", [(_arm_trace(rows), None) for rows in GATED_TRACES.values()],
                        load_properties(tmp_path / "p.toml", ARM.interface), EPSILON, interface=ARM.interface)
    judged = con.execute("""select trace_id, property_id, verdict, certain, alternatives from verdicts
                            where rqst_id = 2 order by all""").fetchall()
    assert judged == [(1, "ACTIVE", "op", False, ["FP", "TP"]), (1, "NO_GRIP", "FP", False, ["op"]),
                      (2, "ACTIVE", "FP", True, []), (2, "NO_GRIP", "FP", True, [])]
