"""Writing the runs of a shrink: each a trace of the shrink's campaign, linked to the trace it shrinks
(table shrink_runs)."""
from __future__ import annotations

from harness.store.appends import append
from harness.store.database import insert_traces, next_id
from harness.trace import Trace


def add_shrink_runs(con, campaign_id: int, original: int, runs: list[tuple[str, Trace]]) -> None:
    """Store (body, trace) runs, in order, under the next trace ids; the caller owns the transaction."""
    if not runs:
        return
    first = next_id(con, "traces", "trace_id")
    insert_traces(con, campaign_id, [(first + i, None, trace, None) for i, (_, trace) in enumerate(runs)])
    append(con, "shrink_runs", [dict(trace_id=first + i, original=original, body=body)
                                for i, (body, _) in enumerate(runs)])
