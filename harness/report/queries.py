"""Everything the report reads from the store: read-only queries over the contract tables and views."""
from __future__ import annotations

import json
from collections.abc import Iterator
from itertools import islice

from harness.store.reads import columns, exists, ordered, read_older_analysis, relations
from harness.errors import StoreError
from harness.store.sql import render_query, sql_id_list
from harness.analysis.provenance import stale_files
from harness.report import configuration
from harness.report.html import VERDICTS
from harness.report.tables import Table, query_table
from harness.report.trace_pages import Rows

# What `python -m harness analyze` materialises and the report reads.
ANALYSED = ("verdicts", "requests", "property_verdicts", "family_verdicts", "trace_robustness",
            "tp_rates", "fp_rates", "inversions", "analysis")
# The rate columns of the coverage view, shown as percentages.
COVERAGE_RATES = frozenset(f"{rate}{end}" for rate in ("tp_rate", "fp_rate") for end in ("", "_low", "_high"))


def rows(con, sql: str, params=()) -> list[dict]:
    cursor = con.execute(sql, list(params))
    names = [d[0] for d in cursor.description]
    return [dict(zip(names, row)) for row in cursor.fetchall()]


def check_analysed(con, db: str) -> None:
    """Refuse a store whose verdicts were never materialised: the report would be empty. A store
    analysed before view trace_scope existed gets it as a temporary view counting every trace,
    and one analysed before view trace_badness gets that view as a temporary one."""
    have = relations(con)
    missing = [name for name in ("traces", *ANALYSED) if name not in have]
    if "traces" in missing:
        raise StoreError(f"{db!r} is not an Untimely store (no traces table); pass the campaign's --db")
    # an analysis with no verdict (every run crashed before a final reply) is still reported
    analyses = "(select count(*) from analyses)" if "analyses" in have else "0"  # older stores lack it
    if missing or not con.execute(f"select (select count(*) from verdicts) + {analyses}").fetchone()[0]:
        lacking = ", ".join(missing) or "any analysis"
        raise StoreError(f"{db!r} has no verdicts yet (lacks {lacking}); "
                         f"run python -m harness analyze --db {db} first")
    read_older_analysis(con)


def per_property(con) -> Table:
    """The coverage view; a store analysed before it had one (read as it is) shows its verdict counts."""
    if exists(con, "coverage"):
        return view(con, "coverage", percent=COVERAGE_RATES)
    return view(con, "property_verdicts")


def module_order(con) -> list[str]:
    """Modules in the order the interface description declares them."""
    return [r[0] for r in con.execute(render_query("module_order")).fetchall()]


def campaigns(con) -> list[dict]:
    """Every campaign, its configuration as the report shows it (harness.report.configuration)."""
    found = rows(con, render_query("campaigns"))
    budgets = {r["campaign_id"]: r for r in rows(con, "select campaign_id, tests, stopped from campaign_budgets")
               } if exists(con, "campaign_budgets") else {}  # a store older than focused campaigns has none
    for c in found:
        c["config"] = configuration.shown(json.loads(c["config"]) if c["config"] else {},
                                          budgets.get(c["campaign_id"]))
    return found


def trace_counts(con) -> Table:
    return query_table(con, "trace_outcomes", render_query("trace_outcomes"))


def crash_reasons(con) -> Table:
    return query_table(con, "crash_reasons", render_query("crash_reasons"))


def invalid_mutants(con) -> Table:
    return query_table(con, "invalid_mutants", render_query("invalid_mutants"))


def view(con, name: str, **options) -> Table:
    """A whole analyzer view, with its own columns, in the order the campaign and properties give."""
    return query_table(con, name, ordered(con, name), **options)


def verdict_mix(con) -> dict[tuple[str, str], int]:
    """(variant, verdict) -> how many verdicts, over all families."""
    found = rows(con, render_query("verdict_mix"))
    return {(r["sut"], v): r[v.lower()] for r in found for v in VERDICTS}


def analysis(con) -> dict:
    """When the verdicts were made, from how many properties, with which epsilon and files, and
    which of those files changed on disk since (the verdicts no longer match them)."""
    if "analysis_id" not in columns(con, "analysis"):  # judged before analyses were recorded: no provenance
        found = rows(con, "select analysed_at::timestamp as analysed_at, epsilon, properties from analysis")[0]
        return dict(found, analysis_id=None, seconds=None, files=[], stale=[])
    found = rows(con, "select analysis_id, analysed_at, epsilon, properties, seconds from analysis")[0]
    found["files"] = rows(con, """select role, path, left(sha256, 12) as sha256 from analysis_files
                                  where analysis_id = ? order by role <> 'properties', role <> 'interface', path""",
                          [found["analysis_id"]])
    found["stale"] = stale_files(con)
    return found


def verdict_transitions(con) -> Table:
    """The verdicts the last analysis changed (a section of stores judged with provenance)."""
    return query_table(con, "verdict_transitions", ordered(con, "verdict_transitions"))


def table_changes(con) -> Table:
    """The cells of Tables II-IV the last analysis changed."""
    return query_table(con, "table_changes", ordered(con, "table_changes") + ", paper_table")


def suspicious(con) -> Table:
    return query_table(con, "suspicious", render_query("suspicious"))


def bad_traces(con) -> Table:
    return query_table(con, "bad_traces", render_query("bad_traces"))


def bad_verdicts(con) -> Table:
    return query_table(con, "bad_trace_verdicts", render_query("bad_trace_verdicts"))


def family_traces(con) -> Table:
    return query_table(con, "family_traces", render_query("family_traces"))


def paged_traces(con, suspicious_shown: int) -> list[int]:
    """The traces that get a page (sql/report/paged_traces.sql) and those of the suspicious
    verdicts the index shows (its first `suspicious_shown` rows), so that each of them is a link."""
    return [r[0] for r in con.execute(f"""select trace_id from ({render_query("paged_traces")})
        union select trace_id from ({render_query("suspicious")} limit {int(suspicious_shown)})
        order by trace_id""").fetchall()]


# What a trace page shows, one query per kind of data for a chunk of pages (ordered by trace id).
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


def explained_verdicts(con, ids: list[int]) -> list[dict]:
    """The verdicts a page of these traces explains: the bad ones and the suspicious ones."""
    return rows(con, f"select trace_id, property_id, rqst_id from verdicts where {_WANTED} "
                     f"and (verdict in ('FN', 'FP') or suspicious)".format(ids=sql_id_list(ids)))


def trace_rows(con, ids: list[int], batch: int = 50, chunk: int = 500) -> Iterator[dict[str, Rows]]:
    """Everything the pages of `ids` show, `batch` traces at a time: per kind of data, its
    columns and rows (as tuples, cheap to hand to another process; trace_pages.traces makes the
    pages' records of them). Each kind is one query per `chunk` traces, read as it streams in
    trace id order: only a batch is held as Python objects, and DuckDB holds a chunk's results."""
    ids = sorted(ids)
    for start in range(0, len(ids), chunk):
        yield from _chunk_rows(con, ids[start:start + chunk], batch)


def _lifecycle(con, ids: str) -> str:
    """The lifecycle states of the traces `ids`; none in a store analysed before view
    lifecycle_states existed (a temporary view would not reach the cursors: connections of their own)."""
    if exists(con, "lifecycle_states"):
        return f"select trace_id, rqst_id, state, pending from lifecycle_states where trace_id in ({ids})"
    return "select null::bigint as trace_id, null::bigint as rqst_id, null::varchar as state, null::varchar as pending"


def _chunk_rows(con, ids: list[int], batch: int) -> Iterator[dict[str, Rows]]:
    listed = sql_id_list(ids)
    cursors = {name: con.cursor().execute(sql.format(ids=listed, lifecycle=_lifecycle(con, listed)))
               for name, sql in _DETAILS.items()}
    columns = {name: [d[0] for d in cursor.description] for name, cursor in cursors.items()}
    streams = {name: _streamed(cursor) for name, cursor in cursors.items()}
    heads = {name: next(stream, None) for name, stream in streams.items() if name != "traces"}

    def rows_until(name: str, last: int) -> list[tuple]:
        """The rows of the traces up to `last` (every kind lists its traces in id order)."""
        key, found = columns[name].index("trace_id"), []
        while heads[name] is not None and heads[name][key] <= last:
            found.append(heads[name])
            heads[name] = next(streams[name], None)
        return found

    while (traces := Rows(columns["traces"], list(islice(streams["traces"], batch)))).rows:
        last = traces.trace_ids()[-1]
        yield {"traces": traces, **{name: Rows(columns[name], rows_until(name, last)) for name in heads}}


def _streamed(cursor) -> Iterator[tuple]:
    """A query's rows, fetched a thousand at a time (`cursor`: a result of its own, read
    alongside the others)."""
    while chunk := cursor.fetchmany(1024):
        yield from chunk


def trace_ids(con, ids: list[int]) -> list[int]:
    return [r[0] for r in con.execute("select trace_id from traces where trace_id in "
                                      "(select unnest(?::integer[]))", [ids]).fetchall()]


def inversions(con) -> Table:
    return query_table(con, "inversions", render_query("inversions"))


def shrunk(con) -> Table:
    return query_table(con, "shrunk_reproducers", render_query("shrunk_reproducers"))
