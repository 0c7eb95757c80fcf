"""`python -m harness report`: HTML pages and CSV tables from the DuckDB store alone (read-only).

Layout of --out: index.html and one CSV per table; traces/ holds a page per (variant, family)
cell of Tables III/IV, a page of bad traces per variant, and a page per trace worth reading
(hung, with an FN, FP or TP, or asked for with --trace).
"""
from __future__ import annotations

import time
from pathlib import Path

from harness.analyzer import family_order, sut_order
from harness.errors import StoreError
from harness.explain import explanations
from harness.report import pages, queries
from harness.store import connect


def main(args) -> int:
    started = time.perf_counter()
    con = connect(args.db, read_only=True)
    try:
        queries.check_analysed(con, args.db)
        written = write_report(con, Path(args.out), args.trace)
    finally:
        con.close()
    print(f"wrote {Path(args.out) / 'index.html'}: {written['traces']} trace pages, "
          f"{written['lists']} list pages, {written['csv']} CSV files "
          f"in {time.perf_counter() - started:.1f} s")
    return 0


def write_report(con, out: Path, extra_traces: list[int]) -> dict[str, int]:
    """Write the whole report under `out`; returns how many files of each sort it wrote."""
    suts, families = sut_order(con), family_order(con)
    table2 = queries.view(con, "trace_robustness", percent=frozenset({"t_rob"}))
    tp = queries.view(con, "tp_rates", percent=frozenset({"tp_rate"}))
    fp = queries.view(con, "fp_rates", percent=frozenset({"fp_rate"}))
    bad = queries.bad_traces(con)
    family_traces = queries.family_traces(con)
    page_ids = set(bad.column("trace_id")) | {r["trace_id"] for found in family_traces.values()
                                               for r in found}
    missing = set(extra_traces) - set(queries.trace_ids(con, list(extra_traces)))
    if missing:
        raise StoreError(f"no trace {sorted(missing)} in the store; pick ids from "
                         f"python -m harness sql \"select trace_id, sut, outcome from traces\"")
    page_ids |= set(extra_traces)

    tables = {
        "trace_outcomes": queries.trace_counts(con),
        "invalid_mutants": queries.invalid_mutants(con),
        "table2": table2.link_column("sut", pages.bad_href),
        "table3": pages.pivot(tp, "tp_rate", "table3", suts, families),
        "table4": pages.pivot(fp, "fp_rate", "table4", suts, families),
        "properties": queries.per_property(con),
        "shrunk": queries.shrunk(con),
        "suspicious": queries.suspicious(con),
        "inversions": queries.inversions(con),
    }
    tables["verdict_transitions"], tables["table_changes"] = queries.changes(con)
    tables["suspicious"].link_column("trace_id", lambda i: pages.trace_href(i) if i in page_ids else None)
    shrunk = pages.write_shrunk(con, out, tables["shrunk"])
    tables["shrunk"].link_column("script_id", pages.shrunk_href)
    tables["shrunk"].link_column("trace_id", lambda i: pages.trace_href(i) if i in page_ids else None)
    csv_tables = [table2, tp, fp, tables["properties"], tables["suspicious"], tables["invalid_mutants"],
                  tables["trace_outcomes"], bad, queries.bad_verdicts(con), tables["inversions"],
                  tables["verdict_transitions"], tables["table_changes"], tables["shrunk"]]

    (out / "traces").mkdir(parents=True, exist_ok=True)
    for stale in (out / "traces").glob("*.html"):  # pages of traces no longer bad would mislead
        stale.unlink()
    for table in csv_tables:
        table.write_csv(out)
    lists = pages.write_lists(out, family_traces, bad, suts, families, (tp, fp))
    details = queries.trace_details(con, sorted(page_ids))
    why = explanations(con, [v for t in details for v in t["verdicts"] if pages.explained(v)])
    pages.write_traces(out, details, queries.module_order(con), why, shrunk)
    pages.write_index(out, dict(
        campaigns=queries.campaigns(con), analysis=queries.analysis(con), tables=tables, bad=bad, suts=suts,
        charts=pages.index_charts(suts, families, tp, fp, table2, queries.verdict_mix(con)),
        csv=[t.name for t in csv_tables]))
    return {"traces": len(page_ids), "lists": lists, "csv": len(csv_tables)}
