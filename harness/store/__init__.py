"""The store: the one gateway to the DuckDB file (connection, schema, writes, reads, import, export)."""
from harness.store.appends import transaction
from harness.store.database import (SCHEMA_VERSION, add_campaign, add_reply_codes, connect, discard_if_empty,
                                    forget_traces, insert_trace, insert_traces, next_id, next_script_id, place,
                                    schema_version)
from harness.store.scripts import ScriptRow, add_scripts, record_shrink_failure
from harness.store.shrinks import add_shrink_runs

__all__ = ["SCHEMA_VERSION", "ScriptRow", "add_campaign", "add_reply_codes", "add_scripts", "add_shrink_runs",
           "connect", "discard_if_empty", "forget_traces", "insert_trace", "insert_traces", "next_id",
           "next_script_id", "place", "record_shrink_failure", "schema_version", "transaction"]
