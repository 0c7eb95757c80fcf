"""Appending rows to the store's tables, and the transaction that commits them.

Every row a campaign, a shrink, an import or a merge adds to the trace tables (and to shrink_runs,
and to the tables a merge copies) reaches them through `append`: this module and sql/schema.sql
are what a second storage backend would replace (docs/store.md, "A second backend").
"""
from __future__ import annotations

from contextlib import contextmanager
from typing import TYPE_CHECKING

import duckdb

from harness.errors import StoreError

if TYPE_CHECKING:
    import pyarrow as pa

_SCHEMAS: dict[str, pa.Schema] = {}


def schema(con, table: str) -> pa.Schema:
    """A table's Arrow schema, as DuckDB gives it from sql/schema.sql (the one definition of its
    columns), read once per process. pyarrow is imported by the functions that write a store: a
    process that only reads one, such as the report, is some 50 MB smaller without it."""
    if table not in _SCHEMAS:
        _SCHEMAS[table] = con.sql(f"select * from {table} limit 0").to_arrow_table().schema
    return _SCHEMAS[table]


def append(con, table: str, rows: list[dict] | pa.Table | duckdb.DuckDBPyRelation) -> None:
    """Add `rows` to `table`, matched by column name (a column they lack is null): dicts, an Arrow
    table, or a relation of `con` (the rows of a query, which stay in DuckDB however many they
    are). The caller owns the transaction."""
    if isinstance(rows, list):
        if not rows:
            return
        names = schema(con, table).names
        unknown = sorted({key for row in rows for key in row} - set(names))
        if unknown:  # from_pylist would drop them silently
            raise StoreError(f"{table} has no column {', '.join(unknown)} (its columns: {', '.join(names)})")
        import pyarrow as pa
        rows = pa.Table.from_pylist(rows, schema=schema(con, table))
    con.execute(f"insert into {table} by name select * from rows")  # DuckDB reads the local `rows` by its name


def _write_problem(error: duckdb.Error) -> StoreError:
    return StoreError(f"could not write the store: {error}; every transaction committed before is kept. "
                      "Free disk space (or fix the cause) and rerun the same command: a campaign resumes")


@contextmanager
def transaction(con):
    """The block's writes commit together, or on any exception are rolled back and it propagates."""
    committing = False
    try:
        # begin and commit inside the try: a stop signal's exception raised just after begin
        # returns, or just before commit (Python runs handlers between bytecodes), must roll the
        # transaction back too, or the interrupted shrink stored next cannot begin its own
        con.begin()
        yield
        committing = True
        con.commit()
    except BaseException as e:
        try:
            con.rollback()
        except duckdb.TransactionException:
            pass  # no transaction left: DuckDB ended the one whose write or commit failed, or none began
        if isinstance(e, duckdb.IOException) or (committing and isinstance(e, duckdb.Error)):
            raise _write_problem(e) from None  # a full disk shows at commit, when the write-ahead log is written
        raise
