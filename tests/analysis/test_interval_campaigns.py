"""On the default, targeted and value-mutation campaigns of both targets (issue 35), every cell of
Tables II-IV has its true figure (the oracles on `internal_events`) in its interval, and every
verdict's internal one is among its alternatives; on the variant without defects (Dala's `reference`,
the manipulator's `safe`), every FN and FP interval includes 0. Small campaigns here (MUTANTS each); docs/analyzer.md gives the
numbers of the 300-mutant ones."""
import contextlib
import io

import pytest

from harness.cli import main
from harness.store.database import connect
from tests.support.intervals_truth import missed, outside

pytestmark = pytest.mark.slow

MUTANTS = "12"
DALA = ["--sut", "reference,genom,bip-a,bip-b"]
MANIPULATOR = ["--mission", "missions/manipulator", "--sut", "safe,careless,quirky,stuck"]
CAMPAIGNS = {
    "dala-random": DALA,
    "dala-targeted": ["--strategy", "targeted", *DALA],
    "dala-values": ["--value-mutations", *DALA],
    "manipulator-random": MANIPULATOR,
    "manipulator-targeted": ["--strategy", "targeted", *MANIPULATOR],
    "manipulator-values": ["--value-mutations", *MANIPULATOR],
}


@pytest.fixture(scope="module", params=list(CAMPAIGNS))
def campaign(request, tmp_path_factory):
    db = tmp_path_factory.mktemp(request.param) / "c.duckdb"
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        assert main(["campaign", "--db", str(db), "--jobs", "1", "--mutants", MUTANTS,
                     *CAMPAIGNS[request.param]]) == 0
    con = connect(db, read_only=True)
    yield request.param, con
    con.close()


def test_every_true_figure_lies_in_its_interval(campaign):
    name, con = campaign
    assert con.execute("select count(*) from verdicts_internal").fetchone()[0] > 0
    assert missed(con) == [], name
    assert outside(con) == [], name


def test_without_defects_every_fn_and_fp_interval_includes_0(campaign):
    name, con = campaign
    sut = "safe" if name.startswith("manipulator") else "reference"
    tp_max = con.execute("select min(tp_rate_max) from tp_rates where sut = ?", [sut]).fetchone()[0]
    fp_min = con.execute("select max(fp_rate_min) from fp_rates where sut = ?", [sut]).fetchone()[0]
    with_fn, with_fp = con.execute("select with_fn_min, with_fp_min from trace_robustness where sut = ?",
                                   [sut]).fetchone()
    assert (tp_max in (None, 1.0), fp_min in (None, 0.0), with_fn, with_fp) == (True, True, 0, 0), name
