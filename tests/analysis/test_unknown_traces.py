"""Unknown is not good (issue 45): a trace whose verdicts include 'unknown' (an oracle failed) and
that is not bad on the others is neither good nor bad in Table II, as Jepsen ranks :unknown
between false and true; tests/traces/unknown.trace, judged with the EE template broken."""
import jinja2
import pytest

from harness import SQL_DIR
from harness.store import sql as templates
from tests.support.traces import HERE, judged_store, load

EPSILON = 0.01
FIXTURE = load(HERE / "unknown.trace")
TABLE_II = """select sut, total, hung, with_fn, bad, unknown, t_rob, bad_min, bad_max, unknown_min, unknown_max,
                     t_rob_min, t_rob_max from trace_robustness order by sut"""


@pytest.fixture(scope="module")
def broken_ee():
    """The store of unknown.trace judged with an EE template that renders but fails in DuckDB."""
    source, column = (SQL_DIR / "oracles" / "ee.sql").read_text(), "y_class is not distinct from 'R' as conflict_rejected"
    assert column in source
    with pytest.MonkeyPatch.context() as patch:
        broken = jinja2.DictLoader({"oracles/ee.sql": source.replace(column, "no_such_flag as conflict_rejected")})
        patch.setattr(templates.ENV, "loader", jinja2.ChoiceLoader([broken, templates.ENV.loader]))
        con = judged_store(FIXTURE, EPSILON)
    return con


def test_the_broken_oracle_gives_unknown_verdicts_only_to_its_property(broken_ee):
    assert broken_ee.execute("select distinct property_id, verdict from verdicts where verdict = 'unknown'"
                             ).fetchall() == [("AIB(ndd.GotoPosition)", "unknown")]


def test_a_trace_bad_on_its_other_verdicts_or_its_outcome_stays_bad_and_the_rest_is_unknown(broken_ee):
    rows = broken_ee.execute("""select label, bad, unknown, unknown_min, unknown_max
                                from trace_badness join traces using (trace_id) order by trace_id""").fetchall()
    assert rows == [("a_good", False, False, False, False), ("a_unknown", False, True, True, True),
                    ("a_fn_unknown", True, False, False, False), ("a_hung_unknown", True, False, False, False),
                    ("b_unknown", False, True, True, True)]


def test_t_rob_counts_an_unknown_trace_neither_good_nor_bad(broken_ee):
    # A: 1 good of the 3 judged good or bad; B: its one trace is unknown, so no fraction at all
    assert broken_ee.execute(TABLE_II).fetchall() == [
        ("A", 4, 1, 1, 2, 1, pytest.approx(1 / 3), 2, 2, 1, 1, pytest.approx(1 / 3), pytest.approx(1 / 3)),
        ("B", 1, 0, 0, 0, 1, None, 0, 0, 1, 1, None, None)]


def test_judged_normally_the_same_traces_have_no_unknown():
    assert judged_store(FIXTURE, EPSILON).execute(TABLE_II).fetchall() == [
        ("A", 4, 1, 1, 2, 0, 0.5, 2, 2, 0, 0, 0.5, 0.5), ("B", 1, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0, 1.0)]
