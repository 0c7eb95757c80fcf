"""`untimely explain TRACE PROPERTY [REQUEST]`: the events that decided a verdict."""
from __future__ import annotations

from dataclasses import dataclass

from harness.analysis import explain
from harness.commands import options

NAME = "explain"
HELP = "the events that decided a verdict, its margin and what would flip it"


@dataclass(frozen=True)
class ExplainRequest:
    trace_id: int
    property: str
    rqst_id: int | None = None  # default: every request judged
    db: str = options.DEFAULT_DB_TEXT


Request = ExplainRequest


def arguments(c) -> None:
    c.add_argument("trace_id", type=int, help="a trace id")
    c.add_argument("property", help="a property id, as the properties file spells it")
    c.add_argument("rqst_id", type=int, nargs="?", help="a request id (default: every request judged)")
    options.db(c)


def execute(request: ExplainRequest) -> int:
    return explain.main(request.db, request.trace_id, request.property, request.rqst_id)
