"""What a store's runs and judgements came to, as one SHA-256 per table.

Two stores with the same fingerprint hold the same scripts, traces (all but wall times), events,
ground truth, world events and verdicts, float for float: a change meant only to make the bench
faster must leave the fingerprint of a campaign unchanged (tests/campaign/test_campaign_fingerprint.py).
A table's columns are those the store defines (sql/schema.sql, sql/views/verdicts.sql), in their
order, but for LEFT_OUT: a column added to the schema enters the fingerprint by itself.
"""
from __future__ import annotations

import hashlib

from harness.store.reads import columns, rows_where

# The order of each fingerprinted table's rows.
TABLES = {"scripts": "script_id", "traces": "trace_id", "events": "trace_id, seq",
          "internal_events": "trace_id, seq", "world_events": "all", "verdicts": "all"}
# Columns that differ between two runs of the same campaign (its id, wall times), and the name an
# imported file gives a trace (no campaign run has one; the recorded fingerprints predate its use).
LEFT_OUT = frozenset({"campaign_id", "wall_s", "label"})
BATCH_ROWS = 50_000


def table_digest(con, table: str, condition: str = "true") -> str:
    """Hex SHA-256 of the rows of `table` (one of TABLES) that meet the SQL `condition`."""
    kept = [c for c in columns(con, table) if c not in LEFT_OUT]
    digest = hashlib.sha256()
    cursor = rows_where(con, table, kept, condition, TABLES[table])
    while rows := cursor.fetchmany(BATCH_ROWS):
        digest.update("".join(f"{row!r}\n" for row in rows).encode())
    return digest.hexdigest()


def fingerprint(con, tables=tuple(TABLES)) -> dict[str, str]:
    """Table name -> hex SHA-256 of its rows (floats by their exact repr), for `tables`."""
    return {table: table_digest(con, table) for table in tables}
