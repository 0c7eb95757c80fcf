"""Rendering properties into oracle SQL: every Dala property runs; bad properties are refused by name."""
from dataclasses import replace

import pytest

from harness.errors import PropertyError
from harness.target.interface import Property
from harness.analysis.oracles import Judging, Shared, render_property
from harness.store.database import connect, insert_trace
from harness.trace import Trace

CONTRACT = ["trace_id", "property_id", "family", "rqst_id", "module", "service", "c_holds", "verdict",
            "margin_s", "suspicious", "certain", "alternatives"]
ES = Property(id="ES(ndd.GotoPosition)", family="ES", type="ES", x=("ndd.GotoPosition",),
              y=("antenna.Point",), r_p="disallowed")


@pytest.mark.parametrize("events", ["events", "internal_events"])
def test_every_dala_property_renders_to_a_query_with_the_contract_columns(interface, properties, events):
    con = connect(":memory:")
    for prop in properties:
        sql = render_property(prop, Judging(events, 0.01, interface))
        assert f"from {events}\n" in sql
        cursor = con.execute(sql)
        assert [d[0] for d in cursor.description] == CONTRACT, prop.id
        assert cursor.fetchall() == []


def test_a_missing_parameter_is_refused_naming_the_property():
    with pytest.raises(PropertyError, match=r"property 'ES\(ndd.GotoPosition\)' of type ES: "
                                            r"parameter 'y' was not provided"):
        render_property(replace(ES, y=()))
    with pytest.raises(PropertyError, match=r"'EX\(a\)' of type EX: parameter 'z_p' was not provided"):
        render_property(replace(ES, id="EX(a)", type="EX"))


def test_a_parameter_the_type_does_not_take_is_refused():
    with pytest.raises(PropertyError, match=r"'PC\(a\)' of type PC: macro 'ctes' takes no keyword "
                                            r"argument 'y'.*remove it"):
        render_property(Property(id="PC(a)", family="PC", type="PC", x=("rflex.Stop",), q=("rflex.Init",),
                                 y=("rflex.Init",), r_p="wait_init"))


def test_an_unknown_type_is_refused():
    with pytest.raises(PropertyError, match=r"'ES\(ndd.GotoPosition\)': type 'XX' has no oracle template "
                                            r"oracles/xx.sql"):
        render_property(replace(ES, type="XX"))


def test_a_malformed_request_type_is_refused():
    with pytest.raises(PropertyError, match=r"'ES\(ndd.GotoPosition\)': y names 'Point'; write request "
                                            r"types as \"module.Service\""):
        render_property(replace(ES, y=("Point",)))


def test_the_events_source_and_epsilon_are_checked():
    with pytest.raises(PropertyError, match=r"events source 'events; drop table traces'"):
        render_property(ES, Judging("events; drop table traces"))
    with pytest.raises(PropertyError, match=r"epsilon = -0.5"):
        render_property(ES, Judging(epsilon=-0.5))


def test_text_values_are_quoted_as_sql_literals():
    con = connect(":memory:")
    trace = Trace(sut="x", seed=0, events=[(1, 0.0, "request", 1, "ndd", "GotoPosition", None, None)])
    insert_trace(con, 1, 1, None, trace)
    odd = replace(ES, id="ES(it's)", family="o'clock")
    assert con.execute(f"select property_id, family, verdict from ({render_property(odd)})").fetchall() == [
        ("ES(it's)", "o'clock", "omega")]


def test_composed_types_reuse_the_basic_chains():
    ex = render_property(replace(ES, id="EX", type="EX", z_p="interrupted_excl"))
    assert "p_es_judged as (" in ex and "p_ee_judged as (" in ex
    mx = render_property(replace(ES, id="MX", type="MX_I", r_p=None, z_p="interrupted_excl"))
    assert "p_xy_judged as (" in mx and "p_yx_judged as (" in mx


def test_a_value_domain_property_without_the_interface_is_refused_saying_what_it_needs(properties):
    val = next(p for p in properties if p.type == "VAL")
    with pytest.raises(PropertyError, match=r"property 'VAL\(rflex\)' of type VAL reads the argument domains "
                                            r"of the interface; pass the interface"):
        render_property(val)


def test_in_an_analysis_an_oracle_reads_only_its_own_services_requests(interface, properties):
    """The shared cause search needs whole modules; an oracle reading the shared requests does not
    (on its own, EE searches the causes itself, over its modules and those that may interrupt them)."""
    aib = next(p for p in properties if p.id == "AIB(aspect.Fuse)")
    own = ("((module = 'aspect' and service = 'Fuse') or (module = 'aspect' and service = 'Reset') "
           "or (module = 'aspect' and service = 'Stop'))")
    shared = render_property(aib, Judging("events", 0.01, interface, properties, shared=Shared("r", "c", "e")))
    assert f"with requests as not materialized (select * from r where {own})" in shared
    alone = render_property(aib, Judging("events", 0.01, interface, properties))
    # ndd: EXC(aspect.Reset,ndd.GotoPosition) says a GotoPosition may interrupt an aspect.Reset
    assert "where kind = 'request' and (module in ('aspect', 'ndd'))" in alone
