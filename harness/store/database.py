"""The DuckDB trace store (docs/reference/store.md): schema, and loading traces through Arrow."""
from __future__ import annotations

import os
import re
import sys
from contextlib import contextmanager
from datetime import datetime, timezone
from pathlib import Path
from typing import TYPE_CHECKING

import duckdb

from harness import SQL_DIR, __version__
from harness.errors import StoreError
from harness.files import make_folder
from harness.target.interface import Interface
from harness.store.appends import append, schema
from harness.store.record import Record, stored_json
from harness.store.sql import ENV, sql_literal
from harness.trace import EVENT_COLUMNS, TAKEN_EVENT_COLUMNS, WORLD_EVENT_COLUMNS, Trace

if TYPE_CHECKING:
    import pyarrow as pa

# DuckDB 2.0 writes its newest storage format unless told otherwise, and no 1.x client reads
# that; DuckDB 1.0 cannot read the primary keys 2.0 writes. So stores are written for 1.1.
STORAGE_VERSION = "v1.1.0"
# The layout of sql/schema.sql; each store lists the versions it went through in schema_version.
SCHEMA_VERSION = 3
POSITIONS_SINCE = 3  # the first schema version with variant_positions and module_positions
# The tables stored per trace.
PER_TRACE = ("traces", "events", "internal_events", "world_events", "taken_events", "trace_runs")


def connect(path: str | Path = ":memory:", read_only: bool = False,
            create: bool = True) -> duckdb.DuckDBPyConnection:
    """Open a store, creating it unless it is opened read-only or with create=False (then a
    missing store is refused); a writable store gets the schema, applied idempotently, and a
    store from before schema versions is migrated. Read-only, such a store is read as is."""
    if str(path) != ":memory:":
        if (read_only or not create) and not Path(path).exists():
            raise StoreError(f"no store at {str(path)!r}; run a campaign or import traces first, or pass --db")
        make_folder(Path(path).parent, "the store")
    con = _open(path, read_only)
    found = schema_version(con)
    if found is not None and found > SCHEMA_VERSION:
        con.close()
        raise StoreError(f"the store {str(path)!r} has schema version {found}, written by a newer Untimely "
                         f"than this one (schema version {SCHEMA_VERSION}); update the bench to open it")
    if read_only:
        if found is None:
            con.close()
            raise StoreError(f"{str(path)!r} holds no store: no traces table (a campaign stopped before it "
                             "wrote its schema, or another DuckDB database); run the campaign again with "
                             "this --db (it starts afresh), or pass another --db")
        _older_positions(con, _missing_positions(con), temp=True)
        return con
    if found == 0:
        con.close()
        backup = _migrate(Path(path))
        con, found = _open(path, read_only), SCHEMA_VERSION
        print(f"migrated the store {str(path)!r} from schema version 0 to {SCHEMA_VERSION}: rewritten in "
              f"the storage format of DuckDB {STORAGE_VERSION}, which DuckDB clients from {STORAGE_VERSION} on "
              f"open; the original is kept as {str(backup)!r} (delete it when you no longer need it)",
              file=sys.stderr)
    _apply_schema(con, found)
    return con


def _apply_schema(con, found: int | None) -> None:
    """The schema on the current database, idempotently; the version is recorded when it changes
    (or when another version of Untimely writes the store),
    and a store from before positions were kept gets them, derived as its bench ordered its rows."""
    missing = _missing_positions(con) if found is not None and found < POSITIONS_SINCE else set()
    con.execute((SQL_DIR / "schema.sql").read_text())
    writer = con.execute("select untimely from schema_version order by applied_at desc limit 1").fetchall()
    if found != SCHEMA_VERSION or writer != [(__version__,)]:
        note = ("created" if found is None else f"migrated from schema version {found}" if found != SCHEMA_VERSION
                else f"written by Untimely {__version__}")
        con.execute("insert into schema_version (version, applied_at, note, untimely) values (?, ?, ?, ?)",
                    [SCHEMA_VERSION, datetime.now(timezone.utc).replace(tzinfo=None), note, __version__])
    _older_positions(con, missing, temp=False)


def _missing_positions(con) -> set[str]:
    """Which positions relations (and their sources) a store lacks."""
    have = {r[0] for r in con.execute("select table_name from information_schema.tables "
                                      "where table_catalog = current_database()").fetchall()}
    return {"variant_positions", "module_positions", "property_positions", "family_positions",
            "properties", "verdicts"} - have


def _older_positions(con, missing: set[str], temp: bool) -> None:
    """The positions of variants, modules, properties and families that a store written or analysed
    by an earlier bench lacks (sql/older_positions.sql): for good, or as temporary views."""
    if missing - {"properties", "verdicts"}:
        con.execute(ENV.get_template("older_positions.sql").render(missing=missing, temp=temp))


def _open(path: str | Path, read_only: bool) -> duckdb.DuckDBPyConnection:
    try:
        return duckdb.connect(str(path), read_only=read_only,
                              config={"storage_compatibility_version": STORAGE_VERSION})
    except duckdb.Error as e:
        raise StoreError(_open_problem(str(path), e)) from None


def schema_version(con) -> int | None:
    """The store's schema version: 0 for a store from before versions, None for an empty database."""
    tables = {r[0] for r in con.execute("select table_name from duckdb_tables() "
                                        "where database_name = current_database()").fetchall()}
    if "schema_version" in tables:
        # fetchall: a result left open by fetchone breaks the next con.sql on this connection
        return con.execute("select max(version) from schema_version").fetchall()[0][0]
    return 0 if "traces" in tables else None


def _migrate(path: Path) -> Path:
    """Replace a schema-0 store by a copy in the STORAGE_VERSION format with the current schema;
    the original is moved aside (returned), and a failure leaves it where it was."""
    backup = path.with_name(f"{path.stem}.schema0{path.suffix}")
    if backup.exists():
        raise StoreError(f"cannot migrate the store {str(path)!r}: {str(backup)!r}, where its original "
                         f"would be kept, already exists; move that file away and retry")
    fresh = path.with_name(path.name + ".migrating")
    leftovers = (fresh, fresh.with_name(fresh.name + ".wal"))
    for leftover in leftovers:
        leftover.unlink(missing_ok=True)
    try:
        with duckdb.connect() as con:
            con.execute(f"attach {sql_literal(path)} as original (read_only)")
            con.execute(f"attach {sql_literal(fresh)} as migrated (storage_version '{STORAGE_VERSION}')")
            con.execute("copy from database original to migrated")
            con.execute("use migrated")
            _apply_schema(con, 0)
    except duckdb.Error as e:
        for leftover in leftovers:
            leftover.unlink(missing_ok=True)
        raise StoreError(f"cannot migrate the store {str(path)!r}: {e}; it is left as it was") from None
    os.replace(path, backup)
    os.replace(fresh, path)
    return backup


def _open_problem(path: str, error: duckdb.Error) -> str:
    """Why a store cannot be opened, and what to do; DuckDB's lock message names the holder's PID."""
    holder = re.search(r"Conflicting lock is held in (.*) \(PID (\d+)\)", str(error))
    if holder:
        return (f"{path!r} is being written by another process ({holder[1]}, PID {holder[2]}), e.g. a "
                "campaign still running; wait for it to finish (or stop it: a campaign resumes), "
                "or work on a copy of the store, or pass another --db")
    return f"cannot open the store {path!r}: {error}"


def discard_if_empty(path: str | Path) -> None:
    """Remove a store that holds no campaign and no trace (one a failed command just created)."""
    if not Path(path).exists():
        return
    try:
        con = duckdb.connect(str(path))
        empty = con.execute("select (select count(*) from campaigns) + (select count(*) from traces) = 0").fetchone()[0]
        con.close()
    except duckdb.Error:
        return  # not a store this command made, or not readable: leave it
    if empty:
        for leftover in (Path(path), Path(f"{path}.wal")):
            leftover.unlink(missing_ok=True)


@contextmanager
def snapshot(con):
    """The block's reads see one state of the store; it writes nothing there, so its errors (a full
    disk where the reads are written) are the caller's to word."""
    con.begin()
    try:
        yield
    finally:
        try:
            con.rollback()
        except duckdb.TransactionException:
            pass  # DuckDB already ended the transaction of a failed statement


def next_id(con, table: str, column: str) -> int:
    # fetchall: fetchone leaves the result open, and DuckDB 2 then refuses the next con.sql
    return con.execute(f"select coalesce(max({column}), 0) + 1 from {table}").fetchall()[0][0]


def next_script_id(con, variants: int) -> int:
    """The next script id of a campaign whose script s owns trace ids (s - 1) * variants + 1 ..
    s * variants: past every stored script, and owning no stored trace (a shrink run, stored under
    the next trace id, may lie beyond the scripts' trace ids)."""
    traces = next_id(con, "traces", "trace_id") - 1
    return max(next_id(con, "scripts", "script_id"), -(-traces // variants) + 1)


def add_campaign(con, campaign_id: int, mission: str, seed: int, record: Record) -> None:
    con.execute("insert into campaigns (campaign_id, created_at, mission, seed, config) values (?, ?, ?, ?, ?)",
                [campaign_id, datetime.now(timezone.utc).replace(tzinfo=None), mission, seed, stored_json(record)])


def add_reply_codes(con, interface: Interface) -> None:
    """Record the interface's reply catalogue and its modules' order; a code whose class changed
    is refused."""
    rows = interface.reply_codes()
    columns = ("module", "service", "reply", "class")
    codes, lists = _listed(columns), {name: [r[i] for r in rows] for i, name in enumerate(columns)}
    changed = con.execute(f"""select c.module, c.service, c.reply, c.class, r.class from {codes} c
                              join reply_codes r using (module, service, reply) where c.class <> r.class
                              order by c.given limit 1""", lists).fetchone()
    if changed:
        module, service, reply, cls, known = changed
        raise StoreError(f"{interface.path}: reply {reply!r} of {module}.{service} has class {cls!r}, "
                         f"but the store already has class {known!r}; use a fresh --db")
    con.execute(f"""insert into reply_codes (module, service, reply, class)
                    select module, service, reply, class from {codes}
                    anti join reply_codes using (module, service, reply) order by given""", lists)
    place(con, "module_positions", "module", [r[0] for r in rows])


def place(con, table: str, column: str, names: list[str]) -> None:
    """Give the names a positions table (variant_positions, module_positions) does not hold yet
    the next positions, in the order given: the first order a store saw is the one it keeps."""
    con.execute(f"""insert into {table} ({column}, position)
                    select name, (select coalesce(max(position), 0) from {table}) + row_number() over (order by given)
                    from {_listed(("name",))} where name not in (select {column} from {table})""",
                {"name": list(dict.fromkeys(names))})


def _listed(columns: tuple[str, ...]) -> str:
    """A subquery of the rows given as one list parameter per column (named as the column), with
    `given`, each row's place in the lists. Lists, not an Arrow table in a local that DuckDB's
    replacement scan finds: a signal arriving while that scan walks Python's frames made it report
    "table not found" (a crash where a stop was due)."""
    unnested = ", ".join(f"unnest(${c}::varchar[]) as {c}" for c in columns)
    return f"(select {unnested}, generate_subscripts(${columns[0]}::varchar[], 1) as given)"


def _table(rows: list[tuple], columns: tuple[str, ...], schema: pa.Schema, trace_ids: list[int]) -> pa.Table:
    """Rows (without their trace id) of several traces as one Arrow table of the table's `schema`
    (its other columns are left to their defaults); `trace_ids` row by row."""
    import pyarrow as pa
    fields = [schema.field(name) for name in ("trace_id", *columns)]
    arrays = [pa.array(values, f.type) for f, values in zip(fields, [trace_ids, *zip(*rows)])]
    return pa.Table.from_arrays(arrays, schema=pa.schema(fields))


def forget_traces(con) -> None:
    """Empty the trace tables (of an in-memory store that judges one batch of traces after another)."""
    for table in PER_TRACE:
        con.execute(f"delete from {table}")


def insert_trace(con, trace_id: int, campaign_id: int, script_id: int | None, trace: Trace,
                 label: str | None = None) -> None:
    """Write one trace; the caller owns the transaction."""
    insert_traces(con, campaign_id, [(trace_id, script_id, trace, label)])


def insert_traces(con, campaign_id: int, runs: list[tuple[int, int | None, Trace, str | None]]) -> None:
    """Write traces, given as (trace_id, script_id, trace, label): their rows, events, ground truth,
    world events and provenance, one `append` per table; the caller owns the transaction."""
    if not runs:  # e.g. a shard that runs none of the golden runs
        return
    rows = [dict(trace_id=trace_id, campaign_id=campaign_id, script_id=script_id, label=label,
                 **{c: getattr(t, c) for c in schema(con, "traces").names if hasattr(t, c)})
            for trace_id, script_id, t, label in runs]
    place(con, "variant_positions", "sut", [t.sut for _, _, t, _ in sorted(runs, key=lambda run: run[0])])
    append(con, "traces", rows)
    for table, columns in (("events", EVENT_COLUMNS), ("internal_events", EVENT_COLUMNS),
                           ("world_events", WORLD_EVENT_COLUMNS), ("taken_events", TAKEN_EVENT_COLUMNS)):
        rows, trace_ids = [], []
        for trace_id, _, trace, _ in runs:
            these = getattr(trace, table)
            rows += these
            trace_ids += [trace_id] * len(these)
        if rows:
            append(con, table, _table(rows, columns, schema(con, table), trace_ids))
    append(con, "trace_runs", [dict(trace_id=trace_id, **trace.provenance) for trace_id, _, trace, _ in runs
                               if trace.provenance])
