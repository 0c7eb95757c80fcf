"""Every hand-made trace of tests/traces/*.trace gets exactly the verdict rows written beside it."""
import functools

import pytest

from tests.support.traces import all_fixtures, judged_store

EPSILON = 0.01
FIXTURES = all_fixtures()
CASES = [(i, case) for i, f in enumerate(FIXTURES) for case in f.cases]
# The cells of each type's verdict table (c_holds, verdict) the fixtures must exercise.
PC_CELLS = {(c, v) for c in (True, False) for v in ("op", "omega")} | {
    (True, "TN"), (True, "FP"), (False, "FN"), (False, "TP")}
EE_CELLS = PC_CELLS | {(False, "na"), (None, "op")}
MX_CELLS = {(True, "TN"), (True, "FP"), (False, "FN"), (False, "TP"), (False, "na"), (False, "omega")}
# The ROS 2 types (docs/reference/verdicts.md): RSP's verdict rests on the deadline whatever C; CAN
# and GOAL have an `op` on each side, and CAN and OUTLIVE one for C undefined (no goal, a rejected goal).
RSP_CELLS = {(c, v) for c in (True, False) for v in ("TN", "FN", "omega")}
CAN_CELLS = {(True, "TN"), (True, "FP"), (True, "omega"), (False, "TP"), (False, "FN"), (False, "op"),
             (False, "omega"), (None, "op"), (None, "omega")}
GOAL_CELLS = PC_CELLS
OUTLIVE_CELLS = {(True, "TN"), (True, "omega"), (False, "TN"), (False, "TP"), (False, "FN"), (False, "omega"),
                 (None, "op")}
CELLS = {"PC": PC_CELLS, "ES": PC_CELLS | {(False, "na")}, "EE": EE_CELLS, "EX": EE_CELLS,
         "MX_R": MX_CELLS | {(True, "omega")}, "MX_I": MX_CELLS, "VAL": PC_CELLS | {(False, "na")},
         "IN": PC_CELLS | {(None, "op")}, "OUT": PC_CELLS | {(None, "op")},
         "RSP": RSP_CELLS, "CAN": CAN_CELLS, "GOAL": GOAL_CELLS, "OUTLIVE": OUTLIVE_CELLS}


@functools.cache
def store(index: int):
    """Fixture file `index` judged once, then shared by the tests of its traces."""
    return judged_store(FIXTURES[index], EPSILON)


@pytest.mark.parametrize("index,case", CASES, ids=[f"{FIXTURES[i].path.stem}:{c.label}" for i, c in CASES])
def test_trace_gets_the_expected_verdicts(index, case):
    con = store(index)
    rows = con.execute("""select property_id, rqst_id, verdict, c_holds, margin_s, suspicious
                          from verdicts join traces using (trace_id) where label = ?""", [case.label]).fetchall()
    got = {(p, r): (v, c, None if m is None else round(m, 9)) for p, r, v, c, m, _ in rows}
    assert got == case.expected
    assert len(rows) == len(got), "one row per property and request"
    assert {(p, r) for p, r, *_, suspicious in rows if suspicious} == case.flagged


def test_the_second_targets_fixtures_cover_every_cell_of_es_ex_mx_r_and_val():
    seen = {t: set() for t in ("ES", "EX", "MX_R", "VAL")}
    for fixture in FIXTURES:
        if not fixture.path.name.startswith("manipulator_"):
            continue
        types = {p.id: p.type for p in fixture.properties}
        for case in fixture.cases:
            for (property_id, _), (verdict, c_holds, _) in case.expected.items():
                seen[types[property_id]].add((c_holds, verdict))
    assert {t: CELLS[t] - seen[t] for t in seen} == {t: set() for t in seen}


def test_fixtures_cover_every_cell_of_every_verdict_table():
    seen = {t: set() for t in CELLS}
    roles, suspicious = set(), set()
    for fixture in FIXTURES:
        types = {p.id: p for p in fixture.properties}
        for case in fixture.cases:
            for (property_id, rqst_id), (verdict, c_holds, margin) in case.expected.items():
                prop = types[property_id]
                seen[prop.type].add((c_holds, verdict))
                roles.add((prop.type, "x" if case.services[rqst_id] in prop.x else "y"))
                if (property_id, rqst_id) in case.flagged:
                    suspicious.add(prop.type)
    assert {t: CELLS[t] - seen[t] for t in CELLS} == {t: set() for t in CELLS}
    assert suspicious == set(CELLS), "every type needs a near-coincident (suspicious) verdict"
    assert {("MX_R", "y"), ("MX_I", "y")} <= roles, "mutual properties judge y requests too"


def test_each_form_of_the_value_domain_type_has_every_cell():
    """The static form (no y) on Dala, the state-dependent form (y and domain) on the manipulator."""
    seen = {"static": set(), "state-dependent": set()}
    for fixture in FIXTURES:
        forms = {p.id: "state-dependent" if p.y else "static" for p in fixture.properties if p.type == "VAL"}
        for case in fixture.cases:
            for (property_id, _), (verdict, c_holds, _) in case.expected.items():
                if property_id in forms:
                    seen[forms[property_id]].add((c_holds, verdict))
    assert seen == {"static": PC_CELLS, "state-dependent": PC_CELLS | {(False, "na")}}


# What each verdict could be instead, by reordering the events closer than epsilon (one case per
# rule of docs/analyzer.md and per kind of alternative); a certain verdict has none.
ALTERNATIVES = {
    ("flag", "flag_self_ending_activity", "AIB(ndd.GotoPosition)", 1): ["TN"],
    ("flag", "flag_two_candidate_causes", "AIB(ndd.GotoPosition)", 1): ["FP"],
    ("flag", "flag_na_to_fn", "AIB(ndd.GotoPosition)", 1): ["FN"],
    ("flag", "flag_fn_to_na", "AIB(ndd.GotoPosition)", 1): ["na"],
    ("flag", "flag_tp_to_na", "AIB(ndd.GotoPosition)", 1): ["na"],
    ("flag", "flag_control_is_no_cause", "AIB(ndd.GotoPosition)", 1): [],
    ("flag", "flag_omega_hung", "AIB(ndd.GotoPosition)", 1): ["FN", "FP", "TN", "TP", "op"],
    # the Stop without a reply may never have been taken (TN), or rejected with its reply lost (na)
    ("flag", "flag_untaken_in_hung", "AIB(ndd.GotoPosition)", 1): ["TN", "na"],
    ("causes", "rejected_request_is_no_cause", "AIB(ndd.GotoPosition)", 1): ["op"],
    ("causes", "cause_sent_just_before", "EXC(aspect.Reset,ndd.GotoPosition)", 2): ["FP", "TP"],
    # FP where the Communication came after the end; then the Reset's EXC may be the TP that makes it op
    # (the shared-code rule, rule 6: issue 35 added 'op')
    ("causes", "cause_sent_just_before", "EXC(antenna.Communication,ndd.GotoPosition)", 2): ["FP", "op"],
    ("causes", "cause_sent_just_before", "EXC(antenna.Communication,ndd.GotoPosition)", 3): ["FN"],
    # the ROS 2 types: a reply within epsilon of the deadline; a goal ending, or sent, within epsilon
    # of its cancel (the server may have refused rightly); a goal ending within epsilon of the new one
    # (every fact of GOAL's table is then unsure); a blocked executor's unanswered call in a hung
    # trace, far past its deadline, is a certain FN
    ("ros2_rsp", "rsp_near", "RSP(arm.grip)", 1): ["TN"],
    ("ros2_rsp", "rsp_hung", "RSP(arm.grip)", 2): [],
    ("ros2_can", "can_end_near", "CAN(arm.move)", 2): ["TN"],
    ("ros2_can", "can_sent_together", "CAN(arm.move)", 2): ["TN"],
    ("ros2_can", "can_refused", "CAN(arm.move)", 2): [],
    ("ros2_goal", "goal_end_near", "GOAL(arm.move)", 2): ["FN", "TN"],
    ("ros2_outlive", "outlive_near", "OUTLIVE(arm.move)", 1): ["TN"],
    # a goal without a reply in a hung trace: never taken (C true, omega), or its reply lost (TN, TP)
    ("ros2_outlive", "outlive_hung", "OUTLIVE(arm.move)", 1): ["TN", "TP", "omega"],
}


@pytest.mark.parametrize("key", ALTERNATIVES, ids=[f"{f}:{label}:{p}:{r}" for f, label, p, r in ALTERNATIVES])
def test_a_possible_verdict_lists_what_the_other_orderings_give(key):
    file, label, property_id, rqst_id = key
    con = store(next(i for i, f in enumerate(FIXTURES) if f.path.stem == file))
    certain, alternatives = con.execute(
        """select certain, alternatives from verdicts join traces using (trace_id)
           where label = ? and property_id = ? and rqst_id = ?""", [label, property_id, rqst_id]).fetchone()
    assert (certain, alternatives) == (not ALTERNATIVES[key], ALTERNATIVES[key])


def test_certain_is_exactly_not_suspicious():
    for index in range(len(FIXTURES)):
        assert store(index).execute("""select count(*) from verdicts where certain = suspicious
                                       or certain <> (len(alternatives) = 0)""").fetchone()[0] == 0
