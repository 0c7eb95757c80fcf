"""`untimely report`: the HTML report and CSV tables, from the store alone."""
from __future__ import annotations

from dataclasses import dataclass, field

from harness.commands import options
from harness.report import build

NAME = "report"
HELP = "write the HTML report and CSV tables from the store alone"


@dataclass(frozen=True)
class ReportRequest:
    out: str | None = None  # default: the store's folder
    trace: list[int] = field(default_factory=list)  # only these trace pages
    db: str = options.DEFAULT_DB_TEXT


Request = ReportRequest


def arguments(c) -> None:
    c.add_argument("--out", help="output folder (default: the folder of the --db store)")
    c.add_argument("--trace", type=int, action="append", default=[],
                   help="write only the page of this trace id into the report, on demand (repeatable)")
    options.db(c)


def execute(request: ReportRequest) -> int:
    return build.main(request.db, request.out, request.trace)
