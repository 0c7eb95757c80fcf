"""Writing scripts (golden, mutants, shrunk reproducers) and the shrinks that failed."""
from __future__ import annotations

import json
from dataclasses import dataclass
from datetime import datetime, timezone

import duckdb

from harness.errors import StoreError


@dataclass(frozen=True)
class ScriptRow:
    """One row of `scripts` (sql/schema.sql)."""
    script_id: int
    campaign_id: int
    kind: str  # golden, mutant or shrunk
    body: str
    parent: int | None = None
    mutations: list | tuple = ()
    valid: bool = True
    invalid_reason: str | None = None


def add_scripts(con, rows: list[ScriptRow]) -> None:
    """The caller owns the transaction. A store from before a kind of script (shrunk) is refused."""
    try:
        _insert(con, rows)
    except duckdb.ConstraintException as e:
        kinds = ", ".join(sorted({r.kind for r in rows}))
        raise StoreError(f"this store predates {kinds} scripts ({e}); write them into a store made by this "
                         "version (run the campaign again with another --db)") from None


def _insert(con, rows: list[ScriptRow]) -> None:
    con.executemany("insert into scripts (script_id, campaign_id, kind, parent, mutations, body, valid, "
                    "invalid_reason) values (?, ?, ?, ?, ?, ?, ?, ?)",
                    [(r.script_id, r.campaign_id, r.kind, r.parent, json.dumps(list(r.mutations)), r.body,
                      r.valid, r.invalid_reason) for r in rows])


def record_shrink_failure(con, trace_id: int, sut: str, verdict: str, property_id: str | None, error: str) -> None:
    con.execute("insert into shrink_failures (trace_id, sut, verdict, property_id, error, failed_at) "
                "values (?, ?, ?, ?, ?, ?)",
                [trace_id, sut, verdict, property_id, error, datetime.now(timezone.utc).replace(tzinfo=None)])
