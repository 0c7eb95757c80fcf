"""The Jinja environment of sql/: every view, oracle and query of the bench is rendered through it."""
from __future__ import annotations

from functools import cache

import jinja2

from harness import SQL_DIR

VERDICTS = ("TN", "TP", "FN", "FP", "op", "na", "omega")


def sql_literal(value) -> str:
    return "'" + str(value).replace("'", "''") + "'"


def sql_id_list(ids) -> str:
    """Ids written as an SQL list of numbers (`trace_id in (...)`): unlike a bound list parameter,
    DuckDB pushes such a filter into a view's scan (the requests view's, for the report)."""
    return ", ".join(str(int(i)) for i in sorted(ids)) or "null"


ENV = jinja2.Environment(loader=jinja2.FileSystemLoader(SQL_DIR), undefined=jinja2.StrictUndefined,
                         trim_blocks=True, lstrip_blocks=True, keep_trailing_newline=True)
ENV.filters["lit"] = sql_literal
ENV.filters["modules"] = lambda services: sorted({s.split(".")[0] for s in services})


def render_view(name: str, **parameters) -> str:
    """The statement creating sql/views/<name>.sql (a view, or the verdicts table)."""
    return ENV.get_template(f"views/{name}.sql").render(verdict_names=list(VERDICTS), **parameters)


@cache
def render_query(name: str) -> str:
    """The read-only query sql/report/<name>.sql, of the report or of a command's summary (a rule
    about stored data that other readers want is a view of sql/views/ instead)."""
    return ENV.get_template(f"report/{name}.sql").render()
