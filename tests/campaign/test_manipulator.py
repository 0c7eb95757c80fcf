"""The second target (missions/manipulator) end to end: its campaign's Tables II-IV show each
variant's pattern as its layer.toml predicts.

- safe (every protection, no defect): no hung trace; every family detects (TP rate >= 90%); an FN or
  FP is only ever a false observation, flagged suspicious.
- careless (PEX, AIB, EXC and the static argument checks only): SPEED (ES), BLUR (EX) and GRASP
  (MX_R) are never enforced: TP rate 0; nor is SLOW (VAL's state-dependent domain): FN; the families
  it protects still detect.
- quirky (every protection; an Init interrupts its module's activities): unexplained interruptions,
  FPs in AIB (EE) and nowhere else.
- stuck (every protection; a preemption in a start phase deadlocks): hung traces.

The observation delay is 0 so that near-coincidences stay few; the ones left (a request observed
before its module's control task takes it) are flagged suspicious.
"""
import duckdb
import pytest

from harness import MISSIONS_DIR
from harness.cli import main as cli

pytestmark = pytest.mark.slow

MISSION = MISSIONS_DIR / "manipulator"
PROTECTED_BY_CARELESS = {"PEX", "AIB", "EXC"}
FAMILIES = {"PEX", "AIB", "SPEED", "BLUR", "GRASP", "EXC"}


@pytest.fixture(scope="module")
def tables(tmp_path_factory):
    db = tmp_path_factory.mktemp("manipulator") / "c.duckdb"
    assert cli(["campaign", "--mission", str(MISSION), "--mutants", "60", "--strategy", "targeted",
                "--seed", "5", "--max-delay", "0", "--jobs", "2", "--db", str(db)]) == 0
    con = duckdb.connect(str(db), read_only=True)
    yield con
    con.close()


def rows(con, query):
    return con.execute(query).fetchall()


def test_the_properties_use_all_seven_basic_types():
    from harness.target.mission import load_mission
    assert {p.type for p in load_mission(MISSION).properties()} == {"PC", "ES", "EE", "EX", "MX_R", "MX_I", "VAL"}


def test_table_ii_only_the_deadlocking_variant_hangs(tables):
    hung = dict(rows(tables, "select sut, hung from trace_robustness"))
    assert set(hung) == {"safe", "careless", "quirky", "stuck"}
    assert hung["stuck"] > 0 and hung["safe"] == hung["careless"] == hung["quirky"] == 0
    t_rob = dict(rows(tables, "select sut, t_rob from trace_robustness"))
    assert t_rob["careless"] == min(t_rob.values())


def test_table_iii_careless_misses_exactly_the_protections_it_lacks(tables):
    rate = {(sut, family): r for sut, family, r in rows(tables, "select sut, family, tp_rate from tp_rates")}
    for sut in ("safe", "careless", "quirky", "stuck"):
        for family in FAMILIES:
            if sut == "careless" and family not in PROTECTED_BY_CARELESS:
                assert rate[(sut, family)] == 0.0, (sut, family)
            else:
                assert rate[(sut, family)] >= 0.9, (sut, family)


def test_table_iv_only_quirky_raises_false_alarms_and_only_in_aib(tables):
    rate = {(sut, family): r for sut, family, r in rows(tables, "select sut, family, fp_rate from fp_rates")}
    assert rate[("quirky", "AIB")] > 0
    unflagged = rows(tables, """select distinct t.sut, v.family, v.verdict from verdicts v join traces t
                                using (trace_id) where v.verdict in ('FN', 'FP') and not v.suspicious""")
    expected = {("careless", f, "FN") for f in FAMILIES - PROTECTED_BY_CARELESS} | {("quirky", "AIB", "FP")}
    expected.add(("careless", "VAL", "FN"))  # SLOW(base.Move): careless lets fast moves with the arm out through
    assert set(unflagged) == expected
