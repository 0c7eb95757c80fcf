"""The suspicious flag (= not certain) against the ground truth, on real campaigns (issue 23).

Each campaign runs once per module; the true inversions are computed here from the verdicts the
same oracles give on `internal_events` (the layer's own timeline, which the observed verdicts
never read): an observed verdict is inverted when the request has a verdict on both timelines
and they differ. Recall = inverted and flagged / inverted; precision = inverted and flagged / flagged.
"""
import contextlib
import io

import pytest

from harness.cli import main
from harness.report import paper
from harness.store.database import connect
from tests.support.paths import ROOT

pytestmark = pytest.mark.slow

CAMPAIGNS = {
    "dala-random": [],
    "dala-targeted": ["--strategy", "targeted", "--mutants", "300", "--sut", "reference,genom,bip-a"],
    "manipulator-random": ["--mission", "missions/manipulator", "--mutants", "300",
                           "--sut", "safe,careless,quirky,stuck"],
    "manipulator-targeted": ["--mission", "missions/manipulator", "--strategy", "targeted", "--mutants", "300",
                             "--sut", "safe,careless,quirky,stuck"],
}
TRUTH = """
    select o.trace_id, o.property_id, o.rqst_id, o.suspicious, o.verdict <> i.verdict as inverted
    from verdicts o join verdicts_internal i using (trace_id, property_id, module, service, rqst_id)
"""


@pytest.fixture(scope="module", params=list(CAMPAIGNS))
def campaign(request, tmp_path_factory):
    db = tmp_path_factory.mktemp(request.param) / "c.duckdb"
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        assert main(["campaign", "--db", str(db), "--jobs", "1", *CAMPAIGNS[request.param]]) == 0
    con = connect(db, read_only=True)  # as harness.report.paper opens it, so both may be open at once
    yield request.param, con
    con.close()


def accuracy(con) -> tuple[int, int, int]:
    """(inverted, flagged, inverted and flagged) from the two timelines' verdicts."""
    return con.execute(f"""select count(*) filter (where inverted), count(*) filter (where suspicious),
                                  count(*) filter (where inverted and suspicious) from ({TRUTH})""").fetchone()


def test_the_flag_catches_every_inversion(campaign):
    name, con = campaign
    inverted, flagged, caught = accuracy(con)
    assert inverted > 0, f"{name}: a campaign with inversions to catch"
    assert caught == inverted, f"{name}: {inverted - caught} of {inverted} inversions not flagged"


def test_the_inversions_view_holds_exactly_the_requests_judged_differently_on_both_timelines(campaign):
    _, con = campaign
    truth = set(con.execute(f"select trace_id, property_id, rqst_id from ({TRUTH}) where inverted").fetchall())
    assert set(con.execute("select trace_id, property_id, rqst_id from inversions").fetchall()) == truth


@pytest.mark.xfail(strict=True, reason="issue 23: precision 67-78% (docs/analyzer.md): near-simultaneous "
                   "requests to a layer without the protection are a coin flip a black-box flag cannot settle")
def test_most_flagged_verdicts_are_inversions(campaign):
    name, con = campaign
    inverted, flagged, caught = accuracy(con)
    assert caught / flagged >= 0.8, f"{name}: precision {caught / flagged:.1%} ({caught} of {flagged})"


@pytest.mark.parametrize("campaign", [n for n in CAMPAIGNS if n.startswith("dala")], indirect=True)
def test_bad_verdicts_are_certain_only_where_a_protection_is_missing(campaign):
    """reference has every protection: each FN and FP it shows may be a false observation. genom lacks
    PRE and EXC, bip-a PRE (and leaks PEX): those still show certain FNs."""
    name, con = campaign
    certain = dict(con.execute("""select t.sut || ' ' || v.family, count(*) from verdicts v join traces t using (trace_id)
                                  where v.verdict in ('FN', 'FP') and v.certain group by all""").fetchall())
    assert not any(k.startswith("reference ") for k in certain)
    assert not any(k.startswith("bip-b ") for k in certain)
    missing = {"genom": ["PRE", "EXC"], "bip-a": ["PRE", "PEX"]}
    suts = {r[0] for r in con.execute("select distinct sut from traces").fetchall()}
    for sut in suts & missing.keys():
        for family in missing[sut]:
            assert certain.get(f"{sut} {family}", 0) > 0, f"{sut} {family}: no certain FN"


@pytest.mark.parametrize("campaign", ["dala-random"], indirect=True)  # the paper's campaign is the default one
def test_make_paper_writes_the_committed_comparison_from_a_fresh_default_campaign(campaign, tmp_path):
    """docs/paper.md is what `make paper` writes from the default campaign (seed 2012, 300 mutants):
    the same run gives the same text, every differing cell has its reason, and the page names no
    file outside the repository."""
    name, con = campaign
    db = con.execute("select path from duckdb_databases() where database_name = current_database()").fetchone()[0]
    out = tmp_path / "paper.md"
    assert paper.write(db, out) == []
    text = out.read_text()
    assert text == (ROOT / "docs" / "paper.md").read_text()
    assert "shared" not in text
    assert "| BIP-B | paper | 293 | 1 | 11 | 0 | 12 | 95.9% |" in text
