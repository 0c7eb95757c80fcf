"""One query per type (issue 46): the analysis judges the properties of a type with a one-pass form
together (sql/oracles/_parameters.sql), the in-memory judge each on its own with the per-property
chain and its own cause search; both give every fixture's verdicts alike."""
import pytest

from harness.analysis import analyzer
from harness.analysis.judge import Judge
from harness.analysis.oracles import one_pass
from tests.support.traces import all_fixtures, judged_store

EPSILON = 0.01
FIXTURES = [f for f in all_fixtures() if any(one_pass(p) for p in f.properties)]
COLUMNS = "trace_id, property_id, rqst_id, module, service, c_holds, verdict, margin_s, alternatives"


def test_pc_ee_es_mutual_and_val_have_a_one_pass_form():
    assert {f.path.stem for f in FIXTURES} >= {"pc", "ee", "causes", "es", "manipulator_es", "mx", "manipulator_mxr",
                                               "val", "manipulator_val"}


def _no_fallback(oracle, failures):
    raise AssertionError(f"a query failed and was run again property by property: {oracle.sql[:200]}")


@pytest.mark.parametrize("fixture", FIXTURES, ids=[f.path.stem for f in FIXTURES])
def test_the_one_pass_analysis_and_the_per_property_judge_agree(fixture, monkeypatch):
    # a failing one-pass query would fall back to the per-property ones, which agree by themselves
    monkeypatch.setattr(analyzer, "_run", _no_fallback)
    con = judged_store(fixture, EPSILON)
    analysed = sorted(con.execute(f"select {COLUMNS} from verdicts").fetchall())
    judged = Judge(fixture.interface, fixture.properties, EPSILON).verdicts([case.trace for case in fixture.cases])
    alone = sorted((n, v["property_id"], v["rqst_id"], v["module"], v["service"], v["c_holds"], v["verdict"],
                    v["margin_s"], v["alternatives"]) for n, rows in enumerate(judged, 1) for v in rows)
    assert analysed and analysed == alone
