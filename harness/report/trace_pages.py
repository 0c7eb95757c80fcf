"""A page per trace: timeline, script diff, world events, verdicts and their explanations, event
log. It works on data already read from the store, so worker processes can write these pages
without DuckDB (see harness/report/build.py)."""
from __future__ import annotations

import difflib
from collections import defaultdict
from pathlib import Path
from typing import NamedTuple

from markupsafe import Markup

from harness.report.html import VERDICTS, render, trace_href
from harness.report.svg import text
from harness.report.timeline import RequestBar, timeline
from harness.target.mission import GOLDEN_FILE


class Rows(NamedTuple):
    """Rows of one kind of data of some traces, as queries.trace_rows reads them."""
    columns: list[str]
    rows: list[tuple]

    def trace_ids(self) -> list[int]:
        key = self.columns.index("trace_id")
        return [row[key] for row in self.rows]

    def by_trace(self) -> dict[int, list[dict]]:
        found = defaultdict(list)
        for row in self.rows:
            record = dict(zip(self.columns, row))
            found[record["trace_id"]].append(record)
        return found


def traces(batch: dict[str, Rows]) -> list[dict]:
    """The records the pages show, one per trace of a batch of queries.trace_rows: the trace
    with its events, requests, verdicts, world events and script diff."""
    events, requests, verdicts, world = (batch[kind].by_trace() for kind in ("events", "requests", "verdicts", "world"))
    found = []
    for row in batch["traces"].rows:
        t = dict(zip(batch["traces"].columns, row))
        i = t["trace_id"]
        t.update(events=events.get(i, []), verdicts=verdicts.get(i, []), world=world.get(i, []),
                 requests=[RequestBar(**{k: v for k, v in r.items() if k != "trace_id"}) for r in requests.get(i, [])],
                 diff=_diff(t))
        found.append(t)
    return found


def _steps(body: str) -> list[str]:
    """The script's step lines: mutants are re-rendered without the golden's comment lines."""
    return [line for line in body.split("\n") if line.strip() and not line.lstrip().startswith("#")]


def _diff(trace: dict) -> list[tuple[str, str]]:
    """The mutant's unified diff against the golden script, each line with its CSS class."""
    if trace["body"] is None or trace["golden"] is None or trace["script_kind"] == "golden":
        return []
    lines = difflib.unified_diff(_steps(trace["golden"]), _steps(trace["body"]), GOLDEN_FILE,
                                 f"script-{trace['script_id']}.mission", lineterm="")
    css = {"@": "hunk", "+": "add", "-": "del"}
    return [(css.get(line[:1], "same"), line) for line in lines]


def event_rows(events: list[dict]) -> Markup:
    """A trace's event log as table rows, built here rather than in the template: a large report
    writes hundreds of thousands of them."""
    return Markup("".join(
        f'<tr><td>{e["seq"]}</td><td>{e["t"]:.4f}</td><td class="text">{text(e["kind"])}</td>'
        f'<td class="text">#{e["rqst_id"]} {text(e["module"])}.{text(e["service"])}</td>'
        f'<td class="text">{text(e["args"] or "")}</td><td class="text">{text(e["reply"] or "")}</td>'
        f'<td>{text(e["class"] or "")}</td></tr>\n' for e in events))


def write_traces(out: Path, batch: dict[str, Rows], modules: list[str], why: dict,
                 shrunk: dict[int, list[dict]]) -> None:
    """A page per trace of a batch of queries.trace_rows. `why`: (trace_id, property_id,
    rqst_id) -> the explanation of a verdict the page explains (queries.explained_verdicts);
    `shrunk`: trace_id -> the reproducers shrunk from it."""
    for t in traces(batch):
        t["shrunk"] = shrunk.get(t["trace_id"], [])
        end_t = t["sim_s"] if t["sim_s"] is not None else 0.0
        svg = timeline(modules, t["requests"], t["verdicts"], t["world"], end_t, t["outcome"])
        shown = [v for v in t["verdicts"] if v["verdict"] != "TN" or v["suspicious"]]
        counts = {v: sum(1 for x in t["verdicts"] if x["verdict"] == v) for v in VERDICTS}
        keys = ((v["trace_id"], v["property_id"], v["rqst_id"]) for v in t["verdicts"])
        render("trace.html.j2", out / trace_href(t["trace_id"]), t=t, timeline=svg, verdicts=shown,
               counts=counts, explained=[why[k] for k in keys if k in why], events=event_rows(t["events"]))
