"""Reading whole views in the order the store keeps as data (variants, families, properties), and
facts about the store's history that several commands state."""
from __future__ import annotations

from harness.errors import StoreError
from harness.store.sql import ENV, VERDICTS
from harness.trace import EVENT_COLUMNS

POSITIONS = {"sut": "variant_positions", "family": "family_positions", "property_id": "property_positions"}


def ordered(con, view: str) -> str:
    """The query of a whole view (or table), its rows in the order of POSITIONS, ties by its columns."""
    names = columns(con, view)
    ranked = [c for c in POSITIONS if c in names]
    joins = " ".join(f"left join (select {c}, position as {c}_rank from {POSITIONS[c]}) using ({c})"
                     for c in ranked)
    order = [f"{c}_rank nulls last" for c in ranked] + [str(n) for n in range(1, len(names) + 1)]
    return f"select v.* from {view} v {joins} order by {', '.join(order)}"


def columns(con, relation: str) -> list[str]:
    """A table's or view's columns, in the order the store defines them (sql/schema.sql and
    sql/views/: the one definition of each table's columns)."""
    return [d[0] for d in con.execute(f"select * from {relation} limit 0").description]


def rows_where(con, table: str, kept: list[str], condition: str, order: str):
    """A cursor over the columns `kept` of the rows of `table` that meet the SQL `condition`, in the
    SQL `order` (to stream them: a table may hold more rows than are worth holding at once)."""
    return con.execute(f"select {', '.join(kept)} from {table} where {condition} order by {order}")


def analyses_made(con) -> int:
    """How many analyses judged the store: with fewer than two, there is nothing to compare."""
    return con.execute("select count(*) from analyses").fetchone()[0] if exists(con, "analyses") else 0


def relations(con, base_tables_only: bool = False) -> set[str]:
    """The names of the store's tables and views (of its base tables only), temporary ones included:
    the one place the bench asks what a store holds (older stores lack newer relations)."""
    kind = " where table_type = 'BASE TABLE'" if base_tables_only else ""
    return {r[0] for r in con.execute(f"select table_name from information_schema.tables{kind}").fetchall()}


def exists(con, name: str) -> bool:
    return name in relations(con)


def holds_rows(con, table: str) -> bool:
    return con.execute(f"select exists (from {table})").fetchone()[0]


def require_analysis(con, db, needed: tuple[str, ...], what: str) -> None:
    """Refuse a store that lacks the relations an analysis makes (`needed`), saying it has no `what`."""
    if not all(exists(con, name) for name in needed):
        raise StoreError(f"{db} has no {what}; run python -m harness analyze --db {db} first")


def read_older_analysis(con) -> None:
    """A store analysed before views trace_scope, trace_badness or findings existed gets them as
    temporary views (sql/older_analysis.sql), and one written before shrink runs were stored an
    empty shrink_runs: the report reads it as it is."""
    missing = {"trace_scope", "trace_badness", "trace_findings", "findings", "shrink_runs"} - relations(con)
    if missing:
        con.execute(ENV.get_template("older_analysis.sql").render(missing=missing, verdict_names=list(VERDICTS)))


def observed_events(con, trace_id: int) -> list[tuple]:
    """A stored trace's observed events as a Trace holds them (EVENT_COLUMNS order)."""
    return con.execute(f"select {', '.join(EVENT_COLUMNS)} from events where trace_id = ? order by seq",
                       [trace_id]).fetchall()


def trace_count(con) -> int:
    """How many traces the store holds, of every campaign."""
    return con.execute("select count(*) from traces").fetchone()[0]


def trace_epsilons(con) -> dict[int, tuple[float, str, float]]:
    """trace id -> the epsilon it is judged with, where that comes from, and the transport's, which
    deadlines are judged with (view trace_epsilon; one made before the transport's was kept has no
    column of it: the same epsilon then)."""
    transport = "transport_epsilon_s" if "transport_epsilon_s" in con.table("trace_epsilon").columns else "epsilon_s"
    return {trace_id: (epsilon, source, deadline) for trace_id, epsilon, source, deadline in
            con.execute(f"select trace_id, epsilon_s, source, {transport} from trace_epsilon").fetchall()}
