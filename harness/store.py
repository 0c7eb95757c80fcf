"""The DuckDB trace store (DESIGN §5): schema, and loading traces through Arrow."""
from __future__ import annotations

import json
from contextlib import contextmanager
from datetime import datetime, timezone
from pathlib import Path

import duckdb
import pyarrow as pa

from harness import SQL_DIR
from harness.errors import StoreError
from harness.interface import Interface
from harness.trace import EVENT_COLUMNS, WORLD_EVENT_COLUMNS, Trace

EVENT_SCHEMA = pa.schema([("trace_id", pa.int32()), ("seq", pa.int32()), ("t", pa.float64()),
                          ("kind", pa.string()), ("rqst_id", pa.int32()), ("module", pa.string()),
                          ("service", pa.string()), ("args", pa.string()), ("reply", pa.string())])
WORLD_SCHEMA = pa.schema([("trace_id", pa.int32()), ("t", pa.float64()), ("kind", pa.string()),
                          ("detail", pa.string())])


def connect(path: str | Path = ":memory:", read_only: bool = False,
            create: bool = True) -> duckdb.DuckDBPyConnection:
    """Open a store, creating it unless it is opened read-only or with create=False (then a
    missing store is refused); a writable store gets the schema, applied idempotently."""
    if str(path) != ":memory:":
        if (read_only or not create) and not Path(path).exists():
            raise StoreError(f"no store at {str(path)!r}; run a campaign or import traces first, or pass --db")
        Path(path).parent.mkdir(parents=True, exist_ok=True)
    try:
        con = duckdb.connect(str(path), read_only=read_only)
    except duckdb.Error as e:
        raise StoreError(f"cannot open the store {str(path)!r}: {e}") from None
    if not read_only:
        con.execute((SQL_DIR / "schema.sql").read_text())
    return con


@contextmanager
def transaction(con):
    """The block's writes commit together, or on any exception are rolled back and it propagates."""
    con.begin()
    try:
        yield
    except BaseException:
        con.rollback()
        raise
    con.commit()


def next_id(con, table: str, column: str) -> int:
    return con.execute(f"select coalesce(max({column}), 0) + 1 from {table}").fetchone()[0]


def add_campaign(con, campaign_id: int, mission: str, seed: int, config: dict) -> None:
    con.execute("insert into campaigns values (?, ?, ?, ?, ?)",
                [campaign_id, datetime.now(timezone.utc).replace(tzinfo=None), mission, seed,
                 json.dumps(config, sort_keys=True)])


def add_reply_codes(con, interface: Interface) -> None:
    """Record the interface's reply catalogue; a code whose class changed is refused."""
    rows = interface.reply_codes()
    codes = pa.table({"position": range(len(rows)), **{  # noqa: F841 (read by DuckDB)
        name: [r[i] for r in rows] for i, name in enumerate(("module", "service", "reply", "class"))}})
    changed = con.execute("""select c.module, c.service, c.reply, c.class, r.class from codes c
                             join reply_codes r using (module, service, reply) where c.class <> r.class
                             order by c.position limit 1""").fetchone()
    if changed:
        module, service, reply, cls, known = changed
        raise StoreError(f"{interface.path}: reply {reply!r} of {module}.{service} has class {cls!r}, "
                         f"but the store already has class {known!r}; use a fresh --db")
    # Set-based, in the interface's order (readers rely on insertion order).
    con.execute("""insert into reply_codes select module, service, reply, class from codes
                   anti join reply_codes using (module, service, reply) order by position""")


def _table(rows: list[tuple], columns: tuple[str, ...], schema: pa.Schema, trace_id: int) -> pa.Table:
    cols = list(zip(*rows)) if rows else [()] * len(columns)
    arrays = [pa.array([trace_id] * len(rows), pa.int32())]
    arrays += [pa.array(list(c), schema.field(name).type) for name, c in zip(columns, cols)]
    return pa.Table.from_arrays(arrays, schema=schema)


def insert_trace(con, trace_id: int, campaign_id: int, script_id: int | None, trace: Trace,
                 label: str | None = None) -> None:
    """Write one trace (row, events, ground truth, world events); the caller owns the transaction."""
    con.execute("insert into traces values (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                [trace_id, campaign_id, script_id, trace.sut, trace.seed, trace.outcome,
                 trace.sim_s, trace.wall_s, trace.error, label])
    for name, rows in (("events", trace.events), ("internal_events", trace.internal_events)):
        if rows:
            arrow = _table(rows, EVENT_COLUMNS, EVENT_SCHEMA, trace_id)  # noqa: F841 (read by DuckDB)
            con.execute(f"insert into {name} select * from arrow")
    if trace.world_events:
        arrow = _table(trace.world_events, WORLD_EVENT_COLUMNS, WORLD_SCHEMA, trace_id)  # noqa: F841
        con.execute("insert into world_events select * from arrow")
    if trace.provenance:
        columns = ", ".join(trace.provenance)
        con.execute(f"insert into trace_runs (trace_id, {columns}) values (?{', ?' * len(trace.provenance)})",
                    [trace_id, *trace.provenance.values()])
