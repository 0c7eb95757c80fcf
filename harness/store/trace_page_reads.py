"""What a trace page of the report shows, read for a chunk of traces at once: one query per kind of
data (the trace and its scripts, its events, requests, verdicts, world events), each ordered by
trace id so that harness/report/queries.py streams them side by side."""
from __future__ import annotations

from harness.store.reads import exists
from harness.store.sql import sql_id_list

# The ids are written into the query as a list of numbers: DuckDB pushes such a filter through
# the requests view into its scan of the events (a parameter it joins after the whole view).
_WANTED = "trace_id in ({ids})"
_DETAILS = {
    "traces": f"""
        select t.*, s.kind as script_kind, s.body, s.mutations, s.parent, g.body as golden
        from traces t left join scripts s using (script_id)
        left join scripts g on g.campaign_id = t.campaign_id and g.kind = 'golden'
        where t.{_WANTED} order by t.trace_id""",
    "events": f"""
        select e.trace_id, e.seq, e.t, e.kind, e.rqst_id, e.module, e.service, e.args, e.reply, c.class
        from events e left join reply_codes c using (module, service, reply)
        where e.{_WANTED} order by e.trace_id, e.seq""",
    # the analyzer's requests view pairs each request with its final reply as the oracles do;
    # lifecycle_states names a managed ROS 2 node's state at each request sent to it
    "requests": f"""
        select r.trace_id, r.rqst_id, r.module, r.service, e.args, r.t as start, r.final_t as "end",
               r.reply, r.class as reply_class, l.state as lifecycle, l.pending
        from requests r left join events e on e.trace_id = r.trace_id and e.seq = r.seq
        left join ({{lifecycle}}) l on l.trace_id = r.trace_id and l.rqst_id = r.rqst_id
        where r.{_WANTED} order by r.trace_id, r.t, r.seq""",
    "verdicts": f"select * from verdicts where {_WANTED} order by trace_id, rqst_id, property_id",
    "world": f"select * from world_events where {_WANTED} order by trace_id, t",
}


def _lifecycle(con, ids: str) -> str:
    """The lifecycle states of the traces `ids`; none in a store analysed before view
    lifecycle_states existed (a temporary view would not reach the cursors: connections of their own)."""
    if exists(con, "lifecycle_states"):
        return f"select trace_id, rqst_id, state, pending from lifecycle_states where trace_id in ({ids})"
    return "select null::bigint as trace_id, null::bigint as rqst_id, null::varchar as state, null::varchar as pending"


def detail_cursors(con, ids: list[int]) -> dict:
    """Kind of data -> a cursor of its own over the rows the pages of the traces `ids` show, in trace id order."""
    listed = sql_id_list(ids)
    return {name: con.cursor().execute(sql.format(ids=listed, lifecycle=_lifecycle(con, listed)))
            for name, sql in _DETAILS.items()}
