"""Faults isolated (issue 20): a property whose oracle fails gets verdicts 'unknown' and its failure
recorded and shown; every other property's verdicts are those of a normal analysis."""
import shutil

import jinja2
import pytest

from harness import DEFAULT_MISSION_DIR, SQL_DIR
from harness.analysis import analyzer
from harness.cli import main
from harness.store import sql as oracles
from tests.support.traces import all_fixtures, judged_store

EPSILON = 0.01
# A template broken on purpose: (file, text replaced, by), and the property types it breaks.
BREAKS = {
    "pc": ("pc.sql", "false as conflict_rejected", "no_such_flag as conflict_rejected", {"PC"}),
    "mx_i": ("mx_i.sql", "{{ parameters.swapped(name, way) }}",
             "{{ parameters.swapped(name, way) | replace('_services\\n', '_services where no_such_role\\n') }}", {"MX_I"}),
}
FIXTURES = all_fixtures()
# Each broken template with every fixture that has properties of the types it breaks.
CASES = [(f, name) for f in FIXTURES for name, (*_, types) in BREAKS.items() if {p.type for p in f.properties} & types]


def _broken_sql(tmp_path, monkeypatch, name: str) -> set[str]:
    file, old, new, types = BREAKS[name]
    sql = tmp_path / "sql"
    shutil.copytree(SQL_DIR, sql)
    template = sql / "oracles" / file
    assert old in template.read_text()
    template.write_text(template.read_text().replace(old, new))
    monkeypatch.setattr(oracles.ENV, "loader", jinja2.FileSystemLoader(sql))
    monkeypatch.setattr(analyzer, "SQL_DIR", sql)
    return types


def _rows(con, where: str):
    return con.execute(f"select * from verdicts where {where} order by all").fetchall()


@pytest.mark.parametrize("fixture,broken", CASES, ids=[f"{f.path.stem}-{name}" for f, name in CASES])
def test_one_broken_template_leaves_every_other_verdict_as_a_normal_analysis_gives(
        tmp_path, monkeypatch, fixture, broken):
    normal = judged_store(fixture, EPSILON)
    types = _broken_sql(tmp_path, monkeypatch, broken)
    failing = sorted(p.id for p in fixture.properties if p.type in types)
    con = judged_store(fixture, EPSILON)
    others = f"property_id not in ({', '.join(repr(p) for p in failing)})"
    assert _rows(con, others) == _rows(normal, others)
    for target in ("verdicts", "verdicts_internal"):
        # the failing properties' rows: the same requests as a normal analysis, each 'unknown'
        keys = f"select trace_id, property_id, rqst_id, module, service, verdict from {target} where not ({others})"
        assert con.execute(keys + " order by all").fetchall() == [
            row[:5] + ("unknown",) for row in normal.execute(keys + " order by all").fetchall()]
    # an events table without events (a fixture without ground truth) is judged by no oracle
    sources = [s for s in ("events", "internal_events") if con.execute(f"select count(*) from {s}").fetchone()[0]]
    assert con.execute("select distinct property_id, source from oracle_failures order by all").fetchall() == [
        (p, source) for p in failing for source in sources]
    # not counted as TN (or anything): Tables III and IV are those without the failing properties
    tn, fp = con.execute("select coalesce(sum(tn), 0), coalesce(sum(fp), 0) from property_verdicts").fetchone()
    assert (tn, fp) == normal.execute(f"select coalesce(sum(tn), 0), coalesce(sum(fp), 0) from property_verdicts where {others}").fetchone()
    unknown = con.execute("select sum(unknown) from property_verdicts").fetchone()[0]
    assert unknown == con.execute("select count(*) from verdicts v join trace_scope t using (trace_id) "
                                  "where t.counted and verdict = 'unknown'").fetchone()[0]


def test_analyze_shows_the_failure_and_judges_the_rest(tmp_path, monkeypatch, capsys):
    fixture = next(f for f in FIXTURES if f.path.stem == "pc")
    db = tmp_path / "store.duckdb"
    judged_store(fixture, EPSILON, db).close()
    _broken_sql(tmp_path, monkeypatch, "pc")
    assert main(["analyze", "--db", str(db), "--epsilon", str(EPSILON),
                 "--properties", str(DEFAULT_MISSION_DIR / "properties.toml")]) == 0
    out = capsys.readouterr().out
    # the fixture holds no internal events, on which no oracle runs
    assert "The oracle of property 'PEX(rflex)' on events failed: Binder Error: " in out
    assert "[template sql/oracles/pc.sql]; its " in out and "Table II - per trace results" in out


def test_a_one_pass_query_that_fails_falls_back_to_each_property_alone(tmp_path, monkeypatch):
    """PC judges its properties in one query (sql/oracles/_parameters.sql); broken for rflex's
    requests alone, that query fails, and each PC property is judged on its own: PEX(rflex) gets
    'unknown' rows, PRE(antenna.Communication), of the same type, its normal verdicts."""
    fixture = next(f for f in FIXTURES if f.path.stem == "pc")
    assert sorted(p.id for p in fixture.properties if p.type == "PC") == ["PEX(rflex)", "PRE(antenna.Communication)"]
    normal = judged_store(fixture, EPSILON)
    sql = tmp_path / "sql"
    shutil.copytree(SQL_DIR, sql)
    pc = sql / "oracles" / "pc.sql"
    pc.write_text(pc.read_text().replace(
        "false as conflict_rejected",
        "coalesce(case when x.module = 'rflex' then error('rflex broken') end, false) as conflict_rejected"))
    monkeypatch.setattr(oracles.ENV, "loader", jinja2.FileSystemLoader(sql))
    monkeypatch.setattr(analyzer, "SQL_DIR", sql)
    con = judged_store(fixture, EPSILON)
    antenna = "property_id = 'PRE(antenna.Communication)'"
    assert _rows(con, antenna) == _rows(normal, antenna) and _rows(con, antenna)
    assert con.execute("select distinct verdict from verdicts where property_id = 'PEX(rflex)'").fetchall() == [("unknown",)]
    assert con.execute("select property_id, source, template from oracle_failures").fetchall() == [
        ("PEX(rflex)", "events", "sql/oracles/pc.sql")]
    assert "rflex broken" in con.execute("select error from oracle_failures").fetchone()[0]
