"""The views' numbers (paper Tables II-IV) on the small hand-made store of tests/traces/tables.trace."""
import pytest

from harness.analysis.analyzer import materialise
from tests.support.traces import HERE, load, judged_store

EPSILON = 0.01


@pytest.fixture(scope="module")
def con():
    return judged_store(load(HERE / "tables.trace"), EPSILON)


def test_trace_robustness_is_table_ii(con):
    rows = con.execute("select * from trace_robustness order by sut").fetchall()
    assert [d[0] for d in con.description] == ["sut", "total", "hung", "crashed", "with_fn", "with_fp",
                                               "bad", "unknown", "t_rob", "with_fn_min", "with_fn_max", "with_fp_min",
                                               "with_fp_max", "bad_min", "bad_max", "unknown_min", "unknown_max",
                                               "t_rob_min", "t_rob_max"]
    assert rows == [("A", 4, 1, 0, 1, 1, 3, 0, 0.25, 1, 1, 1, 1, 3, 3, 0, 0, 0.25, 0.25),
                    ("B", 2, 0, 1, 0, 0, 1, 0, 0.5, 0, 0, 0, 0, 1, 1, 0, 0, 0.5, 0.5)]


def test_trace_badness_is_the_one_rule_of_a_bad_trace(con):
    rows = con.execute("""select label, hung, crashed, with_fn, with_fp, bad, fn, fp, tp
                          from trace_badness join traces using (trace_id) order by trace_id""").fetchall()
    assert rows == [("a_good", False, False, False, False, False, 0, 0, 0),
                    ("a_fn", False, False, True, False, True, 1, 0, 0),
                    ("a_fp", False, False, False, True, True, 0, 1, 1),
                    ("a_hung", True, False, False, False, True, 0, 0, 1),
                    ("b_good", False, False, False, False, False, 0, 0, 1),
                    ("b_crashed", False, True, False, False, True, 0, 0, 0)]
    per_variant = con.execute("select sut, count(*) filter (where bad) from trace_badness group by sut "
                              "order by sut").fetchall()
    assert per_variant == con.execute("select sut, bad from trace_robustness order by sut").fetchall()


def test_tp_rates_are_table_iii(con):
    rows = con.execute("select sut, family, tp, fn, tp_rate from tp_rates order by sut, family").fetchall()
    assert rows == [("A", "AIB", 1, 0, 1.0), ("A", "All", 2, 1, pytest.approx(2 / 3)), ("A", "PEX", 1, 1, 0.5),
                    ("B", "AIB", 0, 0, None), ("B", "All", 1, 0, 1.0), ("B", "PEX", 1, 0, 1.0)]


def test_fp_rates_are_table_iv(con):
    rows = con.execute("select sut, family, fp, tn, fp_rate from fp_rates order by sut, family").fetchall()
    assert rows == [("A", "AIB", 0, 1, 0.0), ("A", "All", 1, 2, pytest.approx(1 / 3)), ("A", "PEX", 1, 1, 0.5),
                    ("B", "AIB", 0, 1, 0.0), ("B", "All", 0, 1, 0.0), ("B", "PEX", 0, 0, None)]


def test_property_verdicts_break_down_each_property(con):
    rows = con.execute("""select sut, property_id, verdicts, tn, tp, fn, fp, op, na, omega, suspicious
                          from property_verdicts order by sut, property_id""").fetchall()
    assert rows == [("A", "AIB(ndd.GotoPosition)", 2, 1, 1, 0, 0, 0, 0, 0, 0),
                    ("A", "PEX(rflex)", 4, 1, 1, 1, 1, 0, 0, 0, 0),
                    ("B", "AIB(ndd.GotoPosition)", 1, 1, 0, 0, 0, 0, 0, 0, 0),
                    ("B", "PEX(rflex)", 1, 0, 1, 0, 0, 0, 0, 0, 0)]


def test_requests_and_activities(con):
    # a_fp: Init ok, Stop rejected (wait_init), GotoPosition interrupted, Stop ok
    rows = con.execute("""select rqst_id, service, t, final_t, reply, class from requests
                          join traces using (trace_id) where label = 'a_fp' order by rqst_id""").fetchall()
    assert rows == [(1, "Init", 0.0, 0.5, "ok", "T"), (2, "Stop", 1.0, 1.1, "wait_init", "R"),
                    (3, "GotoPosition", 2.0, 2.6, "interrupted", "Z"), (4, "Stop", 2.5, 2.7, "ok", "T")]
    ran = con.execute("""select rqst_id, start_t, end_t, round(duration_s, 6) from activities
                         join traces using (trace_id) where label = 'a_fp' order by rqst_id""").fetchall()
    assert ran == [(1, 0.0, 0.5, 0.5), (3, 2.0, 2.6, 0.6), (4, 2.5, 2.7, 0.2)]


def test_a_rejected_request_is_no_activity_and_an_unanswered_one_has_no_end():
    con = judged_store(load(HERE / "pc.trace"), EPSILON)
    ran = dict(con.execute("""select label, end_t from activities join traces using (trace_id)
                              where service = 'TrackSpeedStart' and label in
                              ('pc_true_none', 'pc_true_rp', 'pc_true_accepted')""").fetchall())
    assert ran == {"pc_true_none": None, "pc_true_accepted": 2.0}


def test_properties_and_families_keep_the_properties_file_order_as_data(con):
    assert con.execute("select property_id, family, position from property_positions order by position").fetchall() \
        == [("PEX(rflex)", "PEX", 1), ("AIB(ndd.GotoPosition)", "AIB", 2)]
    assert con.execute("select family, position from family_positions order by position").fetchall() == [
        ("PEX", 1), ("AIB", 2), ("All", 3)]


def test_rates_carry_n_and_the_wilson_interval(con):
    rows = con.execute("""select sut, family, n, round(tp_rate_low, 4), round(tp_rate_high, 4) from tp_rates
                          order by sut, family""").fetchall()
    # textbook 95% Wilson intervals: 1/1 -> [0.2065, 1], 2/3 -> [0.2077, 0.9385], 1/2 -> [0.0945, 0.9055]
    assert rows == [("A", "AIB", 1, 0.2065, 1.0), ("A", "All", 3, 0.2077, 0.9385), ("A", "PEX", 2, 0.0945, 0.9055),
                    ("B", "AIB", 0, None, None), ("B", "All", 1, 0.2065, 1.0), ("B", "PEX", 1, 0.2065, 1.0)]
    fp = con.execute("select n, fp_rate_low, round(fp_rate_high, 4) from fp_rates where sut = 'B' and family = 'All'")
    assert fp.fetchall() == [(1, 0.0, 0.7935)]  # 0/1: clamped at 0, not a rounding error below it


def test_coverage_counts_conditions_and_cells_per_property_and_variant(con):
    rows = con.execute("""select sut, property_id, c_false, c_true, tp, fn, tn, fp, tp_n, fp_n
                          from coverage order by sut, property_id""").fetchall()
    assert rows == [("A", "AIB(ndd.GotoPosition)", 1, 1, 1, 0, 1, 0, 1, 1),
                    ("A", "PEX(rflex)", 2, 2, 1, 1, 1, 1, 2, 2),
                    ("B", "AIB(ndd.GotoPosition)", 0, 1, 0, 0, 1, 0, 0, 1),
                    ("B", "PEX(rflex)", 1, 0, 1, 0, 0, 0, 1, 0)]
    judged = con.execute("select count(*) filter (where c_holds = false), count(*) filter (where c_holds) "
                         "from verdicts").fetchone()
    assert con.execute("select sum(c_false), sum(c_true) from coverage").fetchone() == judged


def test_coverage_lists_every_property_even_without_relevant_requests(interface, properties):
    store = judged_store(load(HERE / "tables.trace"), EPSILON)
    materialise(store, properties, EPSILON, interface)  # all 25, most of which no request of the fixture concerns
    rows = store.execute("select property_id, c_false + c_true, tp_rate from coverage where sut = 'A'").fetchall()
    assert [r[0] for r in rows] == [p.id for p in properties]  # in the properties file's order
    assert ("PRE(sick.OneShot)", 0, None) in rows


def test_bad_behaviours_are_distinct_per_variant_property_and_verdict(con):
    rows = con.execute("select sut, property_id, verdict, traces from bad_behaviours order by all").fetchall()
    assert rows == [("A", "PEX(rflex)", "FN", 1), ("A", "PEX(rflex)", "FP", 1), ("A", None, "hung", 1)]


def test_tables_ii_to_iv_give_each_figure_its_interval_over_the_orders_of_events():
    """tests/traces/flag.trace: 4 TP (2 certain), 4 FN of which only the until-stopped one is certain (the
    others may be a TN or an na), an na that may be an FN, an omega of a hung trace that may be any of
    TP, FN, FP, TN; two hung traces. The lowest TP rate counts every possible FN as one and a TP only
    where it is certain (2/8); the highest the other way round (5/6)."""
    flag = judged_store(load(HERE / "flag.trace"), EPSILON)
    counts = flag.execute("select tp_can, tp_must, fn_can, fn_must, fp_can, fp_must, tn_can, tn_must "
                          "from family_verdicts where family = 'AIB'").fetchone()
    assert counts == (5, 2, 6, 1, 2, 0, 4, 1)
    assert flag.execute("select tp, fn, tp_rate, tp_rate_min, tp_rate_max from tp_rates where family = 'AIB'"
                        ).fetchone() == (4, 4, 0.5, pytest.approx(2 / 8), pytest.approx(5 / 6))
    assert flag.execute("select fp, tn, fp_rate, fp_rate_min, fp_rate_max from fp_rates where family = 'AIB'"
                        ).fetchone() == (0, 1, 0.0, 0.0, pytest.approx(2 / 3))
    # 14 traces: 2 hung, 1 with a certain FN (bad in any order), 4 more that may hold an FN or FP
    assert flag.execute("""select total, hung, with_fn, bad, with_fn_min, with_fn_max, bad_min, bad_max,
                                  t_rob_min, t_rob, t_rob_max from trace_robustness""").fetchone() == (
        14, 2, 4, 5, 1, 6, 3, 7, pytest.approx(7 / 14), pytest.approx(9 / 14), pytest.approx(11 / 14))


def test_views_are_created_after_the_views_they_read(tmp_path, monkeypatch):
    from harness.store import sql
    order = sql.view_order()
    assert set(order) >= {"requests", "trace_scope", "trace_badness", "trace_robustness", "tp_rates", "wilson"}
    before = {name: set(order[:i]) for i, name in enumerate(order)}
    assert {"trace_badness", "trace_scope"} <= before["trace_robustness"] and "wilson" in before["tp_rates"]
    assert not {"verdicts", "shared_codes", "properties"} & set(order)  # rendered by name, with parameters
    views = tmp_path / "views"
    views.mkdir()
    (views / "a.sql").write_text("create or replace view a as select * from b\n")
    (views / "b.sql").write_text("-- reads a\ncreate or replace view b as select * from a\n")
    (views / "c.sql").write_text("create or replace view c as select 1\n")
    monkeypatch.setattr(sql, "SQL_DIR", tmp_path)
    sql.view_order.cache_clear()
    try:
        with pytest.raises(sql.StoreError, match="the views a, b of sql/views/ read each other in a cycle"):
            sql.view_order()
    finally:
        sql.view_order.cache_clear()
