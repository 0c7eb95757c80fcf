"""The Jinja environment of sql/: every view, oracle and query of the bench is rendered through it."""
from __future__ import annotations

import re
from functools import cache

import jinja2

from harness import SQL_DIR
from harness.errors import StoreError

VERDICTS = ("TN", "TP", "FN", "FP", "op", "na", "omega", "unknown")


def sql_literal(value) -> str:
    """A value as an SQL string literal: for templates (the `lit` filter) and for the statements
    DuckDB takes no parameters in (attach, copy)."""
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


def render_bench(name: str, **parameters) -> str:
    """The statements of sql/bench/<name>.sql that a benchmark (bench/) runs: those that build its
    stores, kept in sql/ like every statement that writes outside harness/store/, and its queries
    that are more than a count."""
    return ENV.get_template(f"bench/{name}.sql").render(**parameters)


_COMMENTS = re.compile(r"\{#.*?#\}|--[^\n]*", re.S)
_DEFINES = re.compile(r"create\s+or\s+replace\s+(?:\{\{[^}]*\}\}\s*)?(?:temp\s+)?(?:view|table|macro)\s+(\w+)"
                      r"(?:\s*\([^)]*\))?\s+as\b", re.I)
_WORD = re.compile(r"\w+")


@cache
def view_order() -> tuple[str, ...]:
    """The views of sql/views/ that the analyzer (re)creates after the verdicts, each after the
    relations it reads: a file that defines relations `as` a query, sorted by the names of the
    other such files' relations its text mentions (ties by name). Files that take parameters
    (verdicts, shared_codes, properties) define nothing this way and are rendered by name."""
    defines, mentions = {}, {}
    for path in sorted((SQL_DIR / "views").glob("*.sql")):
        text = _COMMENTS.sub(" ", path.read_text())
        names = _DEFINES.findall(text)
        if names:
            defines[path.stem] = set(names)
            mentions[path.stem] = set(_WORD.findall(text)) - set(names)
    provider = {name: view for view, names in defines.items() for name in names}
    needs = {view: {provider[w] for w in words if w in provider} for view, words in mentions.items()}
    ordered: list[str] = []
    while len(ordered) < len(needs):
        ready = sorted(v for v in needs if v not in ordered and needs[v] <= set(ordered))
        if not ready:
            stuck = sorted(set(needs) - set(ordered))
            raise StoreError(f"the views {', '.join(stuck)} of sql/views/ read each other in a cycle; "
                             "a view may read only views that do not read it: fix one of them")
        ordered.append(ready[0])
    return tuple(ordered)
