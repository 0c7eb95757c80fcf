"""`python -m harness sql QUERY`: ad-hoc SQL on the store, read-only, printed as an aligned table.

Read-only means more than DuckDB's read-only store: a query may not write or read any other file
(`copy ... to`, `attach`, `export database`, `read_csv`, extensions) nor change that setting back."""
from __future__ import annotations

import duckdb

from harness.errors import StoreError
from harness.store.database import connect
from harness.textable import format_table

# Said with every failure, in the bench's words: DuckDB words its refusals differently from one
# version to the next, so the remedy must not depend on its sentence.
READ_ONLY = ("the sql command is read-only: it writes nothing and reaches no file outside the store; "
             "`untimely export FOLDER` writes the store's tables out as files")


def run(con: duckdb.DuckDBPyConnection, query: str) -> str:
    try:
        cursor = con.execute(query)
        if cursor is None:  # DuckDB's answer to a query of blanks or comments only
            raise StoreError(f"no statement in {query!r}; give a query, e.g. \"select * from trace_robustness\"")
        if cursor.description is None:
            return "(no result)"
        columns, rows = [d[0] for d in cursor.description], cursor.fetchall()
    except duckdb.Error as e:
        tables = ", ".join(r[0] for r in con.execute(
            "select table_name from information_schema.tables order by table_name").fetchall())
        raise StoreError(f"query failed: {e}\n{READ_ONLY}\nthe store has: {tables}") from None
    return f"{format_table(columns, rows)}\n({len(rows)} row{'' if len(rows) == 1 else 's'})"


def sealed(con: duckdb.DuckDBPyConnection) -> duckdb.DuckDBPyConnection:
    """The connection with every file outside the store out of reach, for good."""
    con.execute("set enable_external_access = false")
    con.execute("set lock_configuration = true")
    return con


def main(db: str, query: str) -> int:
    print(run(sealed(connect(db, read_only=True)), query))
    return 0
