"""The store: the one gateway to the DuckDB file (connection, schema, writes, reads, import, export)."""
from harness.store.database import (SCHEMA_VERSION, add_campaign, add_reply_codes, connect, discard_if_empty,
                                    insert_trace, insert_traces, next_id, place, quoted, schema_version,
                                    transaction)

__all__ = ["SCHEMA_VERSION", "add_campaign", "add_reply_codes", "connect", "discard_if_empty", "insert_trace",
           "insert_traces", "next_id", "place", "quoted", "schema_version", "transaction"]
