"""The analysis's writes: verdict rows staged oracle by oracle, then published with the record of
the analysis (`analyses`, `analysis_files`, `oracle_failures` of sql/schema.sql).

Each oracle inserts into a temporary staging table outside any transaction, so that one failing
oracle aborts nothing but its own statement (DuckDB aborts a whole transaction on any error);
the analyzer then publishes every staged table in one transaction.
"""
from __future__ import annotations

from dataclasses import dataclass

import duckdb

from harness.store.reads import exists, relations
from harness.store.sql import render_view


@dataclass(frozen=True)
class OracleFailure:
    """An oracle that could not be run: its property's verdicts are 'unknown'."""
    property_id: str
    source: str  # the events table it read
    template: str  # the template the failing line comes from, relative to the project
    error: str


def staged(name: str) -> str:
    """The temporary table an analysis stages for `name`: a verdicts table's rows before they are
    published, or what the oracles on an events table share (its requests, their causes)."""
    return f"{name}_staged"


def stage(con, target: str, named: dict[str, set[str]]) -> None:
    """The empty temporary table the oracles insert the verdicts `target` into; `named`: as publish's."""
    con.execute(render_view("verdicts", target=staged(target), temp=True, named=named))


def try_statement(con, statement: str) -> duckdb.Error | None:
    """Run one rendered statement on its own; its error, if it failed (nothing else is undone)."""
    try:
        con.execute(statement)
    except duckdb.Error as e:
        return e
    return None


def publish(con, target: str, named: dict[str, set[str]]) -> None:
    """The verdicts table `target` with its staged rows, shared codes applied (sql/views/shared_codes.sql),
    its text columns of `named` (column -> every value it may hold) stored as enums; the caller owns
    the transaction."""
    con.execute(render_view("verdicts", target=target, source=staged(target), named=named))


def drop_staged(con, target: str) -> None:
    con.execute(f"drop table if exists {staged(target)}")


def record(con, epsilon: float, properties: int, seconds: float,
           files: list[tuple[str, str, str | None]], failures: list[OracleFailure]) -> int:
    """Add the analysis just made to `analyses`, with the files it was made from ((role, path,
    sha256), none for properties given in code) and its failed oracles; returns its id. The
    caller owns the transaction."""
    analysis_id = con.execute("select coalesce(max(analysis_id), 0) + 1 from analyses").fetchone()[0]
    con.execute("insert into analyses (analysis_id, analysed_at, epsilon, properties, traces, seconds) "
                "select ?, now()::timestamp, ?, ?, (select count(*) from traces), ?",
                [analysis_id, epsilon, properties, seconds])
    if files:
        con.executemany("insert into analysis_files (analysis_id, role, path, sha256) values (?, ?, ?, ?)",
                        [[analysis_id, *source] for source in files])
    if failures:
        con.executemany("insert into oracle_failures (analysis_id, property_id, source, template, error) "
                        "values (?, ?, ?, ?, ?)",
                        [[analysis_id, f.property_id, f.source, f.template, f.error] for f in failures])
    return analysis_id


def replace_old_analysis(con) -> None:
    """A store analysed before the `analyses` table kept its one analysis in a table `analysis`,
    where the view of the same name now goes."""
    if "analysis" in relations(con, base_tables_only=True):
        con.execute("drop table analysis")


def keep_previous(con) -> None:
    """The verdicts and Tables II-IV of the analysis being replaced (empty before the first one),
    for the diff views; the caller owns the transaction."""
    if exists(con, "verdicts"):
        con.execute(render_view("table_values"))
        con.execute("create or replace table table_values_previous as from table_values")
        # renamed, not copied: the new verdicts are published under the name right after
        con.execute("drop table if exists verdicts_previous")
        con.execute("alter table verdicts rename to verdicts_previous")
    else:
        con.execute(render_view("verdicts", target="verdicts_previous"))
        con.execute("create or replace table table_values_previous (sut varchar, family varchar, "
                    "paper_table varchar, measure varchar, value double)")
