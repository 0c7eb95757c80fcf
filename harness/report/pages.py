"""Writes the report's index.html, a list page per (variant, family), the shrunk reproducers; the
trace pages are harness/report/trace_pages.py's."""
from __future__ import annotations

from pathlib import Path

from markupsafe import Markup

from harness.report import charts
from harness.report.html import SHOWN_ROWS, VERDICTS, bad_href, list_href, render
from harness.report.index_tables import IndexTables, shrunk_href
from harness.report.tables import Table
from harness.campaign.shrink import Behaviour, original, write_mission


def _rates(view: Table, rate: str) -> dict[tuple[str, str], float | None]:
    """(family, variant) -> the rate column of a tp_rates or fp_rates view."""
    return {(r["family"], r["sut"]): r[rate] for r in view.records()}


def _intervals(view: Table, rate: str) -> dict[tuple[str, str], tuple[float, float]]:
    """(family, variant) -> the rate's 95% interval, where it has cases."""
    return {(r["family"], r["sut"]): (r[f"{rate}_low"], r[f"{rate}_high"]) for r in view.records() if r.get("n")}


def write_index(out: Path, context: dict) -> None:
    render("index.html.j2", out / "index.html", shown_rows=SHOWN_ROWS, **context)


def write_lists(out: Path, tables: IndexTables) -> int:
    """The pages a Table II-IV cell links to: per (variant, family), and bad traces per variant.
    A trace without a page is named with the command that writes it."""
    by_cell: dict[tuple[str, str], list[dict]] = {}
    for r in tables["family_traces"].records():
        by_cell.setdefault((r["sut"], r["family"]), []).append(r)
    counts: dict[tuple[str, str], dict] = {}
    for view in (tables["tp_rates"], tables["fp_rates"]):
        for r in view.records():
            counts.setdefault((r["sut"], r["family"]), {}).update(r)
    suts, families, page_ids, bad = tables.suts, tables.families, tables.page_ids, tables["bad_traces"]
    for sut in suts:
        for family in families:
            traces = by_cell.get((sut, family), [])
            render("list.html.j2", out / list_href(sut, family), sut=sut, family=family, paged=page_ids,
                   flagged=[t for t in traces if t["fn"] or t["fp"]],
                   tp_only=[t for t in traces if not (t["fn"] or t["fp"])], counts=counts.get((sut, family)))
        render("bad.html.j2", out / bad_href(sut), sut=sut, paged=page_ids,
               traces=[r for r in bad.records() if r["sut"] == sut])
    return len(suts) * (len(families) + 1)


def write_shrunk(con, out: Path, table: Table) -> None:
    """Each shrunk reproducer's .mission file under out/shrunk (replayable with `run`)."""
    for r in table.records():
        behaviour = Behaviour(r["sut"], r["verdict"], r["property_id"])
        write_mission(out / "shrunk", original(con, r["trace_id"]), behaviour, r["script_id"], r["body"], r["runs"])


def reproducers(table: Table) -> dict[int, list[dict]]:
    """The shrunk reproducers (queries.shrunk) by the trace they were shrunk from."""
    by_trace: dict[int, list[dict]] = {}
    for r in table.records():
        behaviour = Behaviour(r["sut"], r["verdict"], r["property_id"])
        by_trace.setdefault(r["trace_id"], []).append({**r, "behaviour": str(behaviour), "href": shrunk_href(r["script_id"])})
    return by_trace


def index_charts(suts: list[str], families: list[str], tp: Table, fp: Table, table2: Table,
                 mix: dict) -> list[tuple[str, Markup]]:
    t_rob = {("T_ROB", r["sut"]): r["t_rob"] for r in table2.records()}

    def chart(title, draw, *data, **options):
        return title, draw(title, *data, **options)

    return [chart("Trace robustness per variant", charts.grouped_bars, ["T_ROB"], suts, t_rob),
            chart("True positive rate per family (95% interval)", charts.grouped_bars, families, suts,
                  _rates(tp, "tp_rate"), intervals=_intervals(tp, "tp_rate")),
            chart("False positive rate per family (95% interval)", charts.grouped_bars, families, suts,
                  _rates(fp, "fp_rate"), full_scale=False, intervals=_intervals(fp, "fp_rate")),
            chart("Verdict mix per variant", charts.stacked_bars, suts, list(VERDICTS), mix)]
