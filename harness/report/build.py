"""Writes the whole report, or the pages of some traces (`--trace ID`).

Layout of --out (default: the store's folder): index.html and one CSV per table; traces/ holds a
page per (variant, family) cell of Tables III/IV, a page of bad traces per variant, and a page
per trace worth reading (see docs/report.md). The report is written into a folder beside --out
and swapped in at the end, so a report killed while writing leaves the previous one whole.
`--trace ID` writes only those trace pages, into the existing report (on demand).
"""
from __future__ import annotations

import os
import shutil
import sys
import tempfile
import time
from collections import deque
from concurrent.futures import ProcessPoolExecutor
from contextlib import nullcontext
from multiprocessing import get_context
from pathlib import Path

import duckdb

from harness.store.analysis_reads import family_order, sut_order
from harness.errors import StoreError, UntimelyError
from harness.analysis.explain import explanations
from harness.files import make_folder
from harness.report import html, pages, queries, sections, trace_pages
from harness.report.index_tables import IndexTables
from harness.store import report_reads
from harness.store.database import connect
from harness.store.reads import analyses_made, relations, trace_count

PARALLEL_FROM = 400  # trace pages per worker process; fewer are not worth starting one for
# DuckDB's memory for the report's queries, from the store's size: beyond it, their hash tables
# spill to a temporary folder (a read-only store has none of its own); the trace pages' queries
# and the lists' ordered string_agg cannot spill. Measured (docs/report.md): 24-48 MB for 15
# traces, 48-64 MB for 732 (a default campaign has 903), so a floor of 4 times that and a share
# per trace; a store that needs more still gets its report (_within_memory). One thread: the
# worker processes use the other cores.
MEMORY_FLOOR_MB, MEMORY_PER_TRACE_KB, THREADS = 256, 64, 1


def memory_limit_mb(traces: int) -> int:
    """DuckDB's memory for the report of a store of `traces` traces."""
    return MEMORY_FLOOR_MB + traces * MEMORY_PER_TRACE_KB // 1024


def main(db: str, out: str | None = None, traces: list[int] = ()) -> int:
    started = time.perf_counter()
    out = Path(out) if out else Path(db).resolve().parent
    con = connect(db, read_only=True)
    spill = tempfile.TemporaryDirectory(prefix="untimely-report-")
    try:
        queries.check_analysed(con, db)
        limit = memory_limit_mb(trace_count(con))
        con.execute(f"set memory_limit = '{limit}MB'; set threads = {THREADS}; set temp_directory = '{spill.name}'")
        make_folder(out, "the report")
        if traces:
            written = _within_memory(con, limit, lambda: write_pages(con, out, traces))
            print(f"wrote {', '.join(str(out / html.trace_href(i)) for i in written)} "
                  f"in {time.perf_counter() - started:.1f} s")
            return 0
        written = _within_memory(con, limit, lambda: write_report(con, out))
    except OSError as e:
        where = f" ({e.filename})" if e.filename else ""
        raise UntimelyError(f"cannot write the report in {str(out)!r}: {e.strerror}{where}; the store is only "
                            "read and unchanged: free space or pass another --out") from None
    finally:
        con.close()
        spill.cleanup()
    print(f"wrote {out / 'index.html'}: {written['traces']} trace pages, {written['lists']} list pages, "
          f"{written['csv']} CSV files in {time.perf_counter() - started:.1f} s")
    return 0


def _within_memory(con, limit_mb: int, write):
    """write() within `limit_mb`; a store whose queries need more is written again with DuckDB's
    default limit (most of the machine's memory)."""
    try:
        return write()
    except duckdb.OutOfMemoryException:
        con.execute("reset memory_limit")
        print(f"the report needs more than {limit_mb} MB of DuckDB memory for this store; "
              "writing it again without that limit", file=sys.stderr)
        return write()


def write_pages(con, out: Path, trace_ids: list[int]) -> list[int]:
    """The pages of the traces asked for, into out/traces (on demand, the rest untouched)."""
    missing = set(trace_ids) - set(report_reads.stored_trace_ids(con, trace_ids))
    if missing:
        raise StoreError(f"no trace {sorted(missing)} in the store; pick ids from "
                         f"python -m harness sql \"select trace_id, sut, outcome from traces\"")
    make_folder(out / "traces", "the trace pages")
    wanted = sorted(set(trace_ids))
    _write_trace_pages(con, out, wanted)
    return wanted


def _write_trace_pages(con, out: Path, trace_ids: list[int], pool=None, workers: int = 0) -> list:
    """Reads the pages' data batch by batch and writes them here, or hands them to the `workers`
    processes of `pool` (returns their futures, at most 2 batches per worker are in flight)."""
    modules, shrunk = queries.module_order(con), pages.reproducers(queries.shrunk(con))
    # one explainer pass for all the pages: each pass runs every property's oracle once
    why = explanations(con, report_reads.explained_verdicts(con, trace_ids))
    pending = deque()
    for batch in queries.trace_rows(con, trace_ids):
        ids = set(batch["traces"].trace_ids())
        share = (out, batch, modules, {k: text for k, text in why.items() if k[0] in ids},
                 {i: shrunk[i] for i in ids & shrunk.keys()})
        if pool is None:
            trace_pages.write_traces(*share)
            continue
        if len(pending) >= 2 * workers:
            pending.popleft().result()
        pending.append(pool.submit(trace_pages.write_traces, *share))
    return list(pending)


def write_report(con, out: Path) -> dict[str, int]:
    """Write the whole report beside `out`, then swap it in; returns how many files of each sort."""
    staging = out / ".report-writing"  # a killed report's leftovers go at the next run
    shutil.rmtree(staging, ignore_errors=True)
    try:
        written = _write_all(con, staging)
        _swap_in(staging, out)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return written


FOLDERS = ("traces", "shrunk")  # swapped in whole: no page outlives the verdicts it showed


def _swap_in(staging: Path, out: Path) -> None:
    """Replace the old report by the new one: CSV files, then the folders, then index.html last."""
    for csv in staging.glob("*.csv"):
        os.replace(csv, out / csv.name)
    for folder in FOLDERS:
        if (out / folder).exists():
            os.replace(out / folder, staging / f"old-{folder}")
        if (staging / folder).exists():
            os.replace(staging / folder, out / folder)
    os.replace(staging / "index.html", out / "index.html")


def _write_all(con, out: Path) -> dict[str, int]:
    """Many trace pages are written by worker processes (spawned: this one holds a DuckDB
    connection), one per core with PARALLEL_FROM pages or more each, from the rows this one reads
    (they import neither DuckDB nor Arrow; this one's reading and the rest of the report take
    about as much CPU as the pages, and on a machine busy with other work a process more gets
    a larger share of it); meanwhile this one writes the rest."""
    page_ids = sorted(report_reads.paged_trace_ids(con, html.SHOWN_ROWS))
    make_folder(out / "traces", "the trace pages")
    workers = min(len(os.sched_getaffinity(0)), len(page_ids) // PARALLEL_FROM)
    parallel = workers > 0
    with ProcessPoolExecutor(workers, mp_context=get_context("spawn")) if parallel else nullcontext() as pool:
        shares = _write_trace_pages(con, out, page_ids, pool, workers)
        written = _write_rest(con, out, set(page_ids))
        for share in shares:
            share.result()
    return written


def _write_rest(con, out: Path, page_ids: set[int]) -> dict[str, int]:
    """Everything but the trace pages: index (its sections: sections.toml), lists, CSV files."""
    suts, families = sut_order(con), family_order(con)
    tables = IndexTables(con, suts, families, page_ids)
    shown = sections.shown(relations(con))
    pages.write_shrunk(con, out, tables["shrunk"])
    csv_tables = [tables[name] for section in shown for name in section.csv]
    for table in csv_tables:
        table.write_csv(out)
    tp, fp = tables["tp_rates"], tables["fp_rates"]
    lists = pages.write_lists(out, tables)
    pages.write_index(out, dict(
        sections=shown, campaigns=queries.campaigns(con), analysis=queries.analysis(con), tables=tables,
        suts=suts, first_analysis=analyses_made(con) < 2,
        charts=pages.index_charts(suts, families, tp, fp, tables["table2"], queries.verdict_mix(con)),
        csv=[t.name for t in csv_tables], pages=len(page_ids)))
    return {"traces": len(page_ids), "lists": lists, "csv": len(csv_tables)}
