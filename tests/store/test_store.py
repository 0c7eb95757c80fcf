import duckdb
import pytest

from harness import store
from harness.errors import StoreError
from harness.target.interface import load_interface
from harness.trace import Trace

CONTRACT = {  # docs/reference/store.md: names the oracles and other tools rely on
    "campaigns": ["campaign_id", "created_at", "mission", "seed", "config"],
    "scripts": ["script_id", "campaign_id", "kind", "parent", "mutations", "body", "valid", "invalid_reason"],
    "traces": ["trace_id", "campaign_id", "script_id", "sut", "seed", "outcome", "sim_s", "wall_s"],
    "events": ["trace_id", "seq", "t", "kind", "rqst_id", "module", "service", "args", "reply"],
    "reply_codes": ["module", "service", "reply", "class"],
    "world_events": ["trace_id", "t", "kind", "detail"],
}


def columns(con, table):
    return [r[0] for r in con.execute(f"describe {table}").fetchall()]


def test_schema_has_the_contract_columns_and_is_idempotent(tmp_path):
    path = tmp_path / "s.duckdb"
    store.connect(path).close()
    con = store.connect(path)  # applying the schema twice must not fail
    for table, names in CONTRACT.items():
        assert columns(con, table)[:len(names)] == names
    assert columns(con, "internal_events") == CONTRACT["events"]


def test_insert_trace_round_trips_through_arrow(interface):
    con = store.connect()
    trace = Trace("reference", 7, sim_s=3.0, wall_s=0.01,
                  events=[(1, 0.0, "request", 1, "rflex", "Init", None, None),
                          (2, 0.5, "final", 1, "rflex", "Init", None, "ok")],
                  internal_events=[(1, 0.001, "request", 1, "rflex", "Init", None, None)],
                  world_events=[(0.2, "collision", '{"rock": 3}')])
    store.insert_trace(con, 5, 1, 2, trace)
    assert con.execute("select trace_id, seq, kind, reply from events order by seq").fetchall() == [
        (5, 1, "request", None), (5, 2, "final", "ok")]
    assert con.execute("select count(*) from internal_events").fetchone() == (1,)
    assert con.execute("select detail->>'rock' from world_events").fetchone() == ("3",)
    assert con.execute("select outcome, sut, seed from traces").fetchone() == ("completed", "reference", 7)


def test_events_reject_an_unknown_kind():
    con = store.connect()
    bad = Trace("x", 0, events=[(1, 0.0, "reqest", 1, "rflex", "Init", None, None)])
    with pytest.raises(Exception, match="CHECK constraint"):
        store.insert_trace(con, 1, 1, 1, bad)


def test_reply_codes_come_from_the_interface_and_a_changed_class_is_refused(interface, tmp_path):
    con = store.connect()
    store.add_reply_codes(con, interface)
    store.add_reply_codes(con, interface)  # same catalogue again: nothing changes
    n = len(interface.services) * len(interface.replies)
    assert con.execute("select count(*) from reply_codes").fetchone() == (n,)
    changed = tmp_path / "i.toml"
    changed.write_text(open(interface.path).read().replace('link_lost = "T"', 'link_lost = "R"'))
    with pytest.raises(StoreError, match="reply 'link_lost' of rflex.Init has class 'R'"):
        store.add_reply_codes(con, load_interface(changed))


def test_variants_and_modules_keep_the_order_a_store_first_saw(interface):
    con = store.connect()
    store.add_reply_codes(con, interface)
    modules = [r[0] for r in con.execute("select module from module_positions order by position").fetchall()]
    assert modules == list(dict.fromkeys(m for m, *_ in interface.reply_codes()))
    store.place(con, "variant_positions", "sut", ["genom", "reference"])
    store.insert_traces(con, 1, [(n, None, Trace(sut, 0), None)
                                 for n, sut in enumerate(["bip-b", "reference", "bip-a", "bip-b"], 1)])
    store.place(con, "variant_positions", "sut", ["bip-a", "genom"])
    assert con.execute("select sut, position from variant_positions order by position").fetchall() == [
        ("genom", 1), ("reference", 2), ("bip-b", 3), ("bip-a", 4)]


def test_read_only_open_of_a_missing_store_says_what_to_do(tmp_path):
    with pytest.raises(StoreError, match="no store at .*run a campaign or import traces first, or pass --db"):
        store.connect(tmp_path / "folder" / "missing.duckdb", read_only=True)
    with pytest.raises(StoreError, match="no store at"):
        store.connect(tmp_path / "missing.duckdb", create=False)
    assert list(tmp_path.iterdir()) == [], "a refused store leaves no file and no folder behind"


def test_read_only_open_of_an_empty_database_says_it_holds_no_store(tmp_path):
    """A campaign SIGKILLed between creating its file and writing its schema leaves an empty one."""
    path = tmp_path / "killed.duckdb"
    duckdb.connect(str(path)).close()
    with pytest.raises(StoreError, match="'.*killed.duckdb' holds no store: no traces table .*run the campaign again"):
        store.connect(path, read_only=True)
    con = store.connect(path)
    assert con.execute("select count(*) from traces").fetchall() == [(0,)], "written, it gets its schema"
