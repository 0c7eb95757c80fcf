"""Writes the report's files: index.html, a list page per (variant, family), trace pages, CSV."""
from __future__ import annotations

import json
import re
from pathlib import Path

from jinja2 import Environment, FileSystemLoader, StrictUndefined
from markupsafe import Markup

from harness.report import charts, queries
from harness.report.svg import text
from harness.report.tables import Table, yes_no
from harness.report.timeline import timeline
from harness.shrink import Behaviour, mission_file, original, write_mission
from harness.textable import percent, rate_interval

TEMPLATES = Path(__file__).parent / "templates"
SHOWN_ROWS = 200  # longer tables are cut on the page; their CSV has every row
_env = Environment(loader=FileSystemLoader(TEMPLATES), undefined=StrictUndefined, autoescape=True,
                   trim_blocks=True, lstrip_blocks=True)
_env.filters["percent"] = percent


def duration(seconds: float) -> str:
    """A wall-clock duration with three significant digits: 1.14 ms, 2.31 s."""
    return f"{1000 * seconds:.3g} ms" if seconds < 1 else f"{seconds:.1f} s"


def mutation(operations: str | None) -> str:
    """A script's recorded mutations (JSON) as one line: each operation, where, and the step."""
    found = json.loads(operations) if operations else []
    parts = []
    for o in found:
        where = " ".join(f"{k} {', '.join(map(str, v)) if isinstance(v, list) else v}"
                         for k, v in o.items() if k not in ("op", "step", "steps"))
        step = o.get("step") or " / ".join(o.get("steps", []))
        parts.append(f"{o.get('op', '?')} {where}: {step}" if step else f"{o.get('op', '?')} {where}")
    return "; ".join(parts)


_env.filters.update(yes_no=yes_no, duration=duration, mutation=mutation)


def slug(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]", "_", name)


def trace_href(trace_id: int) -> str:
    return f"traces/trace-{trace_id}.html"


def list_href(sut: str, family: str) -> str:
    return f"traces/{slug(sut)}-{slug(family)}.html"


def bad_href(sut: str) -> str:
    return f"traces/bad-{slug(sut)}.html"


def shrunk_href(script_id: int) -> str:
    return "shrunk/" + mission_file(Path(), script_id).name


_env.globals.update(trace_href=trace_href, list_href=list_href, bad_href=bad_href, shrunk_href=shrunk_href,
                    shown_rows=SHOWN_ROWS)


def _rates(view: Table, rate: str) -> dict[tuple[str, str], float | None]:
    """(family, variant) -> the rate column of a tp_rates or fp_rates view."""
    return {(r["family"], r["sut"]): r[rate] for r in view.records()}


def _intervals(view: Table, rate: str) -> dict[tuple[str, str], tuple[float, float]]:
    """(family, variant) -> the rate's 95% interval, where it has cases."""
    return {(r["family"], r["sut"]): (r[f"{rate}_low"], r[f"{rate}_high"]) for r in view.records() if r.get("n")}


def rate_text(r: dict, rate: str, n: int) -> str:
    """A rate of a tp_rates/fp_rates row with its interval and n (a store analysed before the
    views had intervals: the rate alone)."""
    if f"{rate}_low" not in r:
        return percent(r[rate])
    return rate_interval(r[rate], r[f"{rate}_low"], r[f"{rate}_high"], n)


_env.globals["rate_text"] = rate_text


def pivot(view: Table, rate: str, name: str, suts: list[str], families: list[str]) -> Table:
    """Paper layout of Tables III/IV: a row per family, a column per variant, each cell a link
    showing the rate, its 95% Wilson interval and n."""
    cell = {(r["family"], r["sut"]): rate_text(r, rate, r.get("n")) for r in view.records()}
    families = [f for f in families if any((f, s) in cell for s in suts)]
    suts = [s for s in suts if any((f, s) in cell for f in families)]
    table = Table(name, ["family", *suts], [(f, *(cell.get((f, s)) for s in suts)) for f in families])
    for r, family in enumerate(families):
        for c, sut in enumerate(suts, start=1):
            table.links[(r, c)] = list_href(sut, family)
    return table


def event_rows(events: list[dict]) -> Markup:
    """A trace's event log as table rows, built here rather than in the template: a large report
    writes hundreds of thousands of them."""
    return Markup("".join(
        f'<tr><td>{e["seq"]}</td><td>{e["t"]:.4f}</td><td class="text">{text(e["kind"])}</td>'
        f'<td class="text">#{e["rqst_id"]} {text(e["module"])}.{text(e["service"])}</td>'
        f'<td class="text">{text(e["args"] or "")}</td><td class="text">{text(e["reply"] or "")}</td>'
        f'<td>{text(e["class"] or "")}</td></tr>\n' for e in events))


def render(template: str, path: Path, **context) -> None:
    path.write_text(_env.get_template(template).render(**context), encoding="utf-8")


def write_index(out: Path, context: dict) -> None:
    render("index.html.j2", out / "index.html", shown_rows=SHOWN_ROWS, **context)


def write_lists(out: Path, family_traces: Table, bad: Table, suts: list[str], families: list[str],
                rate_views: tuple[Table, ...], page_ids: set[int]) -> int:
    """The pages a Table II-IV cell links to: per (variant, family), and bad traces per variant.
    A trace without a page is named with the command that writes it."""
    by_cell: dict[tuple[str, str], list[dict]] = {}
    for r in family_traces.records():
        by_cell.setdefault((r["sut"], r["family"]), []).append(r)
    counts: dict[tuple[str, str], dict] = {}
    for view in rate_views:
        for r in view.records():
            counts.setdefault((r["sut"], r["family"]), {}).update(r)
    for sut in suts:
        for family in families:
            traces = by_cell.get((sut, family), [])
            render("list.html.j2", out / list_href(sut, family), sut=sut, family=family, paged=page_ids,
                   flagged=[t for t in traces if t["fn"] or t["fp"]],
                   tp_only=[t for t in traces if not (t["fn"] or t["fp"])], counts=counts.get((sut, family)))
        render("bad.html.j2", out / bad_href(sut), sut=sut, paged=page_ids,
               traces=[r for r in bad.records() if r["sut"] == sut])
    return len(suts) * (len(families) + 1)


def explained(verdict: dict) -> bool:
    """The verdicts a trace page explains: the bad ones and the suspicious ones."""
    return verdict["verdict"] in ("FN", "FP") or verdict["suspicious"]


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
        by_trace.setdefault(r["trace_id"], []).append({**r, "behaviour": str(behaviour)})
    return by_trace


def write_traces(out: Path, details: list[dict], modules: list[str], why: dict,
                 shrunk: dict[int, list[dict]]) -> None:
    """A page per trace; `why`: (trace_id, property_id, rqst_id) -> the explanation of a verdict;
    `shrunk`: trace_id -> the reproducers shrunk from it."""
    for t in details:
        t["shrunk"] = shrunk.get(t["trace_id"], [])
        end_t = t["sim_s"] if t["sim_s"] is not None else 0.0
        svg = timeline(modules, t["requests"], t["verdicts"], t["world"], end_t, t["outcome"])
        shown = [v for v in t["verdicts"] if v["verdict"] != "TN" or v["suspicious"]]
        counts = {v: sum(1 for x in t["verdicts"] if x["verdict"] == v) for v in queries.VERDICTS}
        texts = [why.get((v["trace_id"], v["property_id"], v["rqst_id"])) for v in t["verdicts"] if explained(v)]
        render("trace.html.j2", out / trace_href(t["trace_id"]), t=t, timeline=svg, verdicts=shown,
               counts=counts, explained=[found for found in texts if found], events=event_rows(t["events"]))


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
            chart("Verdict mix per variant", charts.stacked_bars, suts, list(queries.VERDICTS), mix)]
