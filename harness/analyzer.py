"""`python -m harness analyze`: judge the stored traces with the property oracles (DESIGN §6).

Every property is rendered through its type's template; `verdicts` (from the observed
`events`), `verdicts_internal` (the same oracles on the simulator's `internal_events`) and the
views of sql/views/ are rebuilt in one transaction. Then the paper's Tables II-IV are printed
from the views. Nothing is re-run: the store is the only input.
"""
from __future__ import annotations

import time
from pathlib import Path

import duckdb

from harness.errors import PropertyError, StoreError
from harness.interface import Property, load_interface, load_properties
from harness.oracles import render_property, render_view
from harness.store import connect, transaction
from harness.textable import format_table, percent

# (events source, verdicts table): the observed timeline and the ground truth.
SOURCES = (("events", "verdicts"), ("internal_events", "verdicts_internal"))
# Creation order: each view reads only tables or views created before it.
VIEWS = ("requests", "activities", "property_verdicts", "family_verdicts", "trace_robustness",
         "tp_rates", "fp_rates", "inversions", "interface_latency")
# Rank queries ordering the views' rows: variants as they were run, properties and families in
# the order of the properties file (the verdicts table is filled in that order); All comes last.
RANKS = {"sut": "select sut, min(trace_id) as sut_rank from traces group by sut",
         "family": "select family, min(rowid) as family_rank from verdicts group by family",
         "property_id": "select property_id, min(rowid) as property_id_rank from verdicts group by property_id"}


def statements(properties: list[Property], epsilon: float) -> list[str]:
    if not properties:
        raise PropertyError("no properties to judge; give a properties file with [[property]] entries")
    tables = [render_view("verdicts", target=target,
                          oracles=[render_property(p, events, epsilon) for p in properties])
              for events, target in SOURCES]
    return tables + [render_view(name) for name in VIEWS]


def materialise(con: duckdb.DuckDBPyConnection, properties: list[Property], epsilon: float) -> None:
    """(Re)build the verdict tables and the views in one transaction; a failure keeps the old ones."""
    sql = statements(properties, epsilon)  # a property that cannot be rendered stops us here
    try:
        with transaction(con):
            for statement in sql:
                con.execute(statement)
            con.execute("create or replace table analysis as select now() as analysed_at, "
                        "?::double as epsilon, ?::integer as properties, "
                        "(select count(*) from traces) as traces", [epsilon, len(properties)])
    except duckdb.Error as e:
        raise StoreError(f"the oracle queries failed on this store: {e}") from None


def judges_every_trace(con: duckdb.DuckDBPyConnection) -> bool:
    """True when the stored verdicts were made after the last trace came in."""
    tables = {r[0] for r in con.execute("select table_name from information_schema.tables").fetchall()}
    if not {"verdicts", "analysis"} <= tables:
        return False
    return con.execute("select traces = (select count(*) from traces) from analysis").fetchone()[0]


def sut_order(con) -> list[str]:
    """Variants in the order the campaign ran them."""
    return [r[0] for r in con.execute(f"select sut from ({RANKS['sut']}) order by sut_rank").fetchall()]


def family_order(con) -> list[str]:
    """Families in the order the properties file lists them (verdict insertion order), then All."""
    found = con.execute(f"select family from ({RANKS['family']}) order by family_rank").fetchall()
    return [r[0] for r in found] + ["All"]


def ordered(con, view: str) -> str:
    """The query of a whole view (or table), its rows in the order of RANKS, ties by its columns."""
    columns = [d[0] for d in con.execute(f"select * from {view} limit 0").description]
    ranked = [c for c in RANKS if c in columns]
    joins = " ".join(f"left join ({RANKS[c]}) using ({c})" for c in ranked)
    order = [f"{c}_rank nulls last" for c in ranked] + [str(n) for n in range(1, len(columns) + 1)]
    return f"select v.* from {view} v {joins} order by {', '.join(order)}"


def _rates_by_family(con, view: str, column: str, suts: list[str]) -> str:
    """Paper layout: one row per family (properties-file order, then All), one column per variant."""
    rate = {(sut, family): value for sut, family, value
            in con.execute(f"select sut, family, {column} from {view}").fetchall()}
    return format_table(["family"] + suts,
                        [[f] + [percent(rate.get((s, f))) for s in suts] for f in family_order(con)])


def summary(con: duckdb.DuckDBPyConnection, epsilon: float) -> str:
    cursor = con.execute(ordered(con, "trace_robustness"))
    columns, robustness = [d[0] for d in cursor.description], cursor.fetchall()
    suts = [r[0] for r in robustness]
    table2 = format_table(columns, [r[:-1] + (percent(r[-1]) + "%",) for r in robustness])
    parts = ["Table II - per trace results\n" + table2,
             "Table III - true positive rates TP/(TP+FN), %\n" + _rates_by_family(con, "tp_rates", "tp_rate", suts),
             "Table IV - false positive rates FP/(FP+TN), %\n" + _rates_by_family(con, "fp_rates", "fp_rate", suts)]
    judged, flagged = con.execute("""select count(*), count(*) filter (where suspicious) from verdicts
                                     semi join (select distinct trace_id from internal_events) using (trace_id)
                                  """).fetchone()
    if judged:
        inverted, caught = con.execute("select count(*), count(*) filter (where suspicious) "
                                       "from inversions").fetchone()
        parts.append(f"Ground truth: {inverted} of {judged} observed verdicts differ from the verdicts on "
                     f"the internal timeline (view inversions); the suspicious flag (margin < {epsilon:g} s) "
                     f"caught {caught} of them and is raised on {flagged} verdicts in all.")
    cursor = con.execute("select * exclude (campaign_id) from interface_latency order by campaign_id, sut")
    latency = cursor.fetchall()
    if latency:
        parts.append("Interface latency of the real-time runs (ping round trips, wall s; "
                     "suggested epsilon in mission s)\n" + format_table([d[0] for d in cursor.description], latency))
    return "\n\n".join(parts)


def main(args) -> int:
    con = connect(args.db, create=False)
    properties_path = Path(args.properties)
    interface = load_interface(properties_path.parent / "interface.toml")
    properties = load_properties(properties_path, interface)
    started = time.perf_counter()
    materialise(con, properties, args.epsilon)
    elapsed = time.perf_counter() - started
    traces, events = con.execute("select (select count(*) from traces), (select count(*) from events)").fetchone()
    verdicts = con.execute("select count(*) from verdicts").fetchone()[0]
    print(f"Judged {events} events of {traces} traces against {len(properties)} properties "
          f"in {elapsed:.2f} s: {verdicts} verdicts in table verdicts.\n")
    print(summary(con, args.epsilon) if traces else
          "The store holds no traces yet: run a campaign or import traces, then analyze again.")
    return 0
