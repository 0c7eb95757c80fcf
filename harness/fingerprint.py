"""What a store's runs and judgements came to, as one SHA-256 per table.

Two stores with the same fingerprint hold the same scripts, traces (all but wall times), events,
ground truth, world events and verdicts, float for float: a change meant only to make the bench
faster must leave the fingerprint of a campaign unchanged (tests/test_campaign_fingerprint.py).
"""
from __future__ import annotations

import hashlib

# Each table's columns in a canonical order, and the order of its rows; wall_s, created_at and
# campaign ids are left out: they differ between two runs of the same campaign.
TABLES = {
    "scripts": ("script_id, kind, parent, mutations, body, valid, invalid_reason", "script_id"),
    "traces": ("trace_id, script_id, sut, seed, outcome, sim_s, error", "trace_id"),
    "events": ("trace_id, seq, t, kind, rqst_id, module, service, args, reply", "trace_id, seq"),
    "internal_events": ("trace_id, seq, t, kind, rqst_id, module, service, args, reply", "trace_id, seq"),
    "world_events": ("trace_id, t, kind, detail", "all"),
    "verdicts": ("trace_id, property_id, family, rqst_id, module, service, c_holds, verdict, margin_s, "
                 "suspicious, certain, alternatives", "all"),
}
BATCH_ROWS = 50_000


def table_digest(con, table: str, condition: str = "true") -> str:
    """Hex SHA-256 of the rows of `table` (one of TABLES) that meet the SQL `condition`."""
    columns, order = TABLES[table]
    digest = hashlib.sha256()
    cursor = con.execute(f"select {columns} from {table} where {condition} order by {order}")
    while rows := cursor.fetchmany(BATCH_ROWS):
        digest.update("".join(f"{row!r}\n" for row in rows).encode())
    return digest.hexdigest()


def fingerprint(con, tables=tuple(TABLES)) -> dict[str, str]:
    """Table name -> hex SHA-256 of its rows (floats by their exact repr), for `tables`."""
    return {table: table_digest(con, table) for table in tables}
