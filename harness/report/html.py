"""The Jinja environment of the report's pages, with their filters and links. It imports neither
DuckDB nor Arrow, so that the processes writing trace pages in parallel stay small."""
from __future__ import annotations

import json
import re
from pathlib import Path

from jinja2 import Environment, FileSystemLoader, StrictUndefined

from harness.report.tables import yes_no
from harness.textable import percent, rate_interval, with_orders

TEMPLATES = Path(__file__).parent / "templates"
SHOWN_ROWS = 200  # longer tables are cut on the page; their CSV has every row
VERDICTS = ("TP", "FN", "FP", "TN", "op", "na", "omega")  # in the order the report shows them
_env = Environment(loader=FileSystemLoader(TEMPLATES), undefined=StrictUndefined, autoescape=True,
                   trim_blocks=True, lstrip_blocks=True)


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


def slug(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]", "_", name)


def trace_href(trace_id: int) -> str:
    return f"traces/trace-{trace_id}.html"


def list_href(sut: str, family: str) -> str:
    return f"traces/{slug(sut)}-{slug(family)}.html"


def bad_href(sut: str) -> str:
    return f"traces/bad-{slug(sut)}.html"


def rate_text(r: dict, rate: str, n: int) -> str:
    """A rate of a tp_rates/fp_rates row with its interval and n, then its interval over the orders
    of the events closer than epsilon (a store analysed before the views had them: the rate alone, or
    without the second interval)."""
    if f"{rate}_low" not in r:
        return percent(r[rate])
    text = rate_interval(r[rate], r[f"{rate}_low"], r[f"{rate}_high"], n)
    return with_orders(text, r[f"{rate}_min"], r[f"{rate}_max"]) if f"{rate}_min" in r else text


_env.filters.update(percent=percent, yes_no=yes_no, duration=duration, mutation=mutation)
_env.globals.update(trace_href=trace_href, list_href=list_href, bad_href=bad_href, rate_text=rate_text,
                    shown_rows=SHOWN_ROWS)


def render(template: str, path: Path, **context) -> None:
    path.write_text(_env.get_template(template).render(**context), encoding="utf-8")
