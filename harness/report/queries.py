"""The report's tables and trace pages as read from the store: the queries of sql/report/ and whole
views as Tables, and the pages' rows streamed (the other reads are named reads of harness/store/)."""
from __future__ import annotations

import json
from collections.abc import Iterator
from itertools import islice

from harness.store import report_reads
from harness.store.reads import columns, exists, ordered, read_older_analysis, relations
from harness.store.report_reads import as_records
from harness.store.trace_page_reads import detail_cursors
from harness.errors import StoreError
from harness.store.sql import render_query
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


def check_analysed(con, db: str) -> None:
    """Refuse a store whose verdicts were never materialised: the report would be empty. A store
    analysed before view trace_scope existed gets it as a temporary view counting every trace,
    and one analysed before view trace_badness gets that view as a temporary one."""
    have = relations(con)
    missing = [name for name in ("traces", *ANALYSED) if name not in have]
    if "traces" in missing:
        raise StoreError(f"{db!r} is not an Untimely store (no traces table); pass the campaign's --db")
    # an analysis with no verdict (every run crashed before a final reply) is still reported
    if missing or not report_reads.judgements(con, "analyses" in have):  # older stores lack analyses
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
    found = as_records(con, render_query("campaigns"))
    budgets = report_reads.campaign_budgets(con)
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
    found = as_records(con, render_query("verdict_mix"))
    return {(r["sut"], v): r[v.lower()] for r in found for v in VERDICTS}


def analysis(con) -> dict:
    """When the verdicts were made, from how many properties, with which epsilon and files, and
    which of those files changed on disk since (the verdicts no longer match them)."""
    if "analysis_id" not in columns(con, "analysis"):  # judged before analyses were recorded: no provenance
        return dict(report_reads.analysis_row(con, with_provenance=False), analysis_id=None, seconds=None,
                    files=[], stale=[])
    found = report_reads.analysis_row(con, with_provenance=True)
    found["files"] = report_reads.analysis_files(con, found["analysis_id"])
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


def trace_rows(con, ids: list[int], batch: int = 50, chunk: int = 500) -> Iterator[dict[str, Rows]]:
    """Everything the pages of `ids` show, `batch` traces at a time: per kind of data, its
    columns and rows (as tuples, cheap to hand to another process; trace_pages.traces makes the
    pages' records of them). Each kind is one query per `chunk` traces, read as it streams in
    trace id order: only a batch is held as Python objects, and DuckDB holds a chunk's results."""
    ids = sorted(ids)
    for start in range(0, len(ids), chunk):
        yield from _chunk_rows(con, ids[start:start + chunk], batch)


def _chunk_rows(con, ids: list[int], batch: int) -> Iterator[dict[str, Rows]]:
    cursors = detail_cursors(con, ids)
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


def inversions(con) -> Table:
    return query_table(con, "inversions", render_query("inversions"))


def shrunk(con) -> Table:
    return query_table(con, "shrunk_reproducers", render_query("shrunk_reproducers"))
