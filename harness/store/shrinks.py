"""Writing the runs of a shrink: each a trace of the shrink's campaign, linked to the trace it shrinks
(table shrink_runs)."""
from __future__ import annotations

from harness.store.appends import append
from harness.store.database import insert_traces, next_id
from harness.store.record import CampaignRecord, records
from harness.trace import Trace


def add_shrink_runs(con, campaign_id: int, original: int, runs: list[tuple[str, Trace]]) -> None:
    """Store (body, trace) runs, in order, under the next free trace ids; the caller owns the transaction."""
    if not runs:
        return
    first = _first_free(con)
    insert_traces(con, campaign_id, [(first + i, None, trace, None) for i, (_, trace) in enumerate(runs)])
    append(con, "shrink_runs", [dict(trace_id=first + i, original=original, body=body)
                                for i, (body, _) in enumerate(runs)])


def _first_free(con) -> int:
    """The first trace id past every stored trace and every id a stored test script owns (script s of
    a campaign of V variants owns (s - 1) * V + 1 .. s * V): a campaign stopped after storing a
    round's scripts, before their runs, runs them under those ids when it resumes."""
    owned = [(con.execute("""select coalesce(max(script_id), 0) from scripts
                             where campaign_id = ? and kind in ('golden', 'mutant')""", [i]).fetchone()[0], len(r.sut))
             for i, _, r in records(con, CampaignRecord)]
    return max([next_id(con, "traces", "trace_id")] + [last * variants + 1 for last, variants in owned])
