"""A seventh basic type added as data (issue 20): a template in sql/oracles/ and its fixtures
(tests/traces/toy_type/) are all it takes to validate, judge and target properties of that type."""
import shutil

import jinja2
import pytest

from harness import DEFAULT_MISSION_DIR, SQL_DIR
from harness.analysis import analyzer
from harness.cli import main
from harness.analysis.oracles import interrupters
from harness.errors import InputFileError, PropertyError
from harness.mutator.targeted import Falsifier, disturbers, falsifiers
from harness.store import sql as templates
from harness.store.database import connect
from harness.target import property_types
from harness.target.interface import load_properties
from tests.support import traces as fixtures
from tests.support.traces import HERE, INTERFACE, judged_store

TOY = HERE / "toy_type"
EPSILON = 0.01


@pytest.fixture
def sql_with_toy_type(tmp_path, monkeypatch):
    sql = tmp_path / "sql"
    shutil.copytree(SQL_DIR, sql)
    shutil.copy(TOY / "nr.sql", sql / "oracles" / "nr.sql")
    monkeypatch.setattr(templates.ENV, "loader", jinja2.FileSystemLoader(sql))
    monkeypatch.setattr(property_types, "TEMPLATES", sql / "oracles")
    monkeypatch.setattr(analyzer, "SQL_DIR", sql)
    return sql


def test_a_type_without_its_template_is_refused_naming_the_types_there_are():
    with pytest.raises(InputFileError, match=r"type 'NR' is not one of CAN, EE, ES, EX, GOAL, IN, MX_I, MX_R, OUT, OUTLIVE, PC, RSP, VAL \(the templates"):
        load_properties(TOY / "properties.toml", INTERFACE)


def test_the_toy_type_declares_its_parameters_and_its_traces_get_their_verdicts(sql_with_toy_type, monkeypatch):
    assert property_types.property_types()["NR"] == ("x", "r_p")
    toy = {p.id: p for p in load_properties(TOY / "properties.toml", INTERFACE)}
    monkeypatch.setattr(fixtures, "PROPERTIES", {**fixtures.PROPERTIES, **toy})
    fixture = fixtures.load(TOY / "nr.trace")
    con = judged_store(fixture, EPSILON)
    assert {v for case in fixture.cases for v, _, _ in case.expected.values()} == {"TN", "FP", "op", "omega"}
    for case in fixture.cases:
        rows = con.execute("""select property_id, rqst_id, verdict, c_holds, margin_s from verdicts
                              join traces using (trace_id) where label = ?""", [case.label]).fetchall()
        assert {(p, r): (v, c, m) for p, r, v, c, m in rows} == case.expected, case.label
    assert con.execute("select count(*) from oracle_failures").fetchone()[0] == 0
    # targeted generation aims at it without an entry of its own
    assert falsifiers(toy["NR(ndd.GotoPosition)"]) == [
        Falsifier("during", send=("ndd.GotoPosition",), running=("ndd.GotoPosition",))]


@pytest.mark.slow
def test_a_targeted_campaign_runs_with_the_toy_type(sql_with_toy_type, tmp_path):
    mission = tmp_path / "mission"
    shutil.copytree(DEFAULT_MISSION_DIR, mission)
    with open(mission / "properties.toml", "a") as properties:
        properties.write("\n" + (TOY / "properties.toml").read_text())
    db = tmp_path / "c.duckdb"
    assert main(["campaign", "--mission", str(mission), "--strategy", "targeted", "--mutants", "3",
                 "--sut", "genom", "--db", str(db), "--jobs", "1"]) == 0
    con = connect(db, read_only=True)
    assert con.execute("select count(*) from verdicts where property_id = 'NR(ndd.GotoPosition)' "
                       "and verdict = 'TN'").fetchone()[0] >= 4


BY_ANY = """{% import 'oracles/ee.sql' as ee with context %}
{% set interrupts = [['x', 'y']] %}
{% macro ctes(name, x, y, z_p) -%}
{{ ee.ctes(name, x, y, z_p) }}
{%- endmacro %}
"""
STOPPED = """[[property]]
id = "STOP(rflex.TrackSpeedStart)"
family = "STOP"
type = "STOP"
x = ["rflex.TrackSpeedStart"]
y = ["rflex.Stop"]
z_p = "interrupted"
"""


def test_a_type_whose_template_declares_interrupts_gets_its_causes_and_disturbers(sql_with_toy_type, tmp_path):
    (sql_with_toy_type / "oracles" / "stop.sql").write_text(BY_ANY)
    (tmp_path / "properties.toml").write_text(STOPPED)
    stop = load_properties(tmp_path / "properties.toml", INTERFACE)[0]
    assert property_types.interruptions()["STOP"] == (("x", "y"),)
    # the analyzer searches an interruption's cause among its y, as for EE ...
    assert interrupters([stop]) == [("rflex.TrackSpeedStart", "interrupted", "rflex.Stop")]
    # ... and targeted generation sends other services of x's module while x runs
    assert disturbers(stop, INTERFACE) and all(f.disturb and f.running == ("rflex.TrackSpeedStart",)
                                               for f in disturbers(stop, INTERFACE))
    # a type that does not declare it (NR) has neither
    nr = load_properties(TOY / "properties.toml", INTERFACE)[0]
    assert interrupters([nr]) == [] and disturbers(nr, INTERFACE) == []


def test_a_template_declaring_interrupts_wrongly_is_refused_naming_it(sql_with_toy_type):
    (sql_with_toy_type / "oracles" / "stop.sql").write_text(BY_ANY.replace("['x', 'y']", "['x', 'q']"))
    with pytest.raises(PropertyError, match=r"stop.sql sets interrupts to .*write e.g. \{% set interrupts"):
        property_types.interruptions()
