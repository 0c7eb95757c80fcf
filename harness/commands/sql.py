"""`untimely sql QUERY`: ad-hoc SQL against the store, read-only."""
from __future__ import annotations

from dataclasses import dataclass

from harness.commands import options
from harness.store import sqlshell

NAME = "sql"
HELP = "run ad-hoc SQL against the store and print an aligned table"


@dataclass(frozen=True)
class SqlRequest:
    query: str
    db: str = options.DEFAULT_DB_TEXT


Request = SqlRequest


def arguments(c) -> None:
    c.add_argument("query", help="a SQL query, e.g. \"select * from trace_robustness\"")
    options.db(c)


def execute(request: SqlRequest) -> int:
    return sqlshell.main(request.db, request.query)
