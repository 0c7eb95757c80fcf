"""`python -m harness analyze`: judge the stored traces with the property oracles (docs/reference/verdicts.md).

Every property is rendered through its type's template; `verdicts` (from the observed
`events`), `verdicts_internal` (the same oracles on the simulator's `internal_events`) and the
views of sql/views/ are rebuilt in one transaction. Then the paper's Tables II-IV are printed
from the views. Nothing is re-run: the store is the only input.
"""
from __future__ import annotations

import re
import time
from dataclasses import dataclass
from pathlib import Path

import duckdb

from harness import SQL_DIR
from harness.analysis import diff
from harness.analysis.oracles import (Judging, Shared, one_pass, render_one_pass, render_property, render_shared,
                                      render_unknown, verdict_values)
from harness.analysis.provenance import default_properties, last_epsilon, sources
from harness.analysis.summary import analysis_summary
from harness.errors import InputFileError, PropertyError, StoreError
from harness.store.analyses import (OracleFailure, drop_staged, keep_previous, publish, record, replace_old_analysis,
                                    stage, staged, try_statement)
from harness.store.judging_reads import analysis_is_current, sizes
from harness.store.appends import transaction
from harness.store.database import connect
from harness.store.reads import holds_rows, relations
from harness.store.sql import render_query, render_view, view_order
from harness.target.interface import Interface, Property, load_interface, load_properties
from harness.target.mission import INTERFACE_FILE
from harness.textable import counted

# (events source, verdicts table): the observed timeline and the ground truth.
SOURCES = (("events", "verdicts"), ("internal_events", "verdicts_internal"))
# What orders the views' rows, by column: variants as the campaign ran them, properties and
# families in the order of the properties file, All last (the store's positions tables and views).
_LINE = re.compile(r"LINE (\d+):")


@dataclass
class Oracle:
    """One property's rendered statement inserting its verdicts from one events source."""
    prop: Property
    source: str
    target: str
    sql: str

    def failure(self, error: duckdb.Error) -> OracleFailure:
        """The failure, naming the template and the line of the rendered statement it comes from."""
        message = str(error).split("\n")[0]
        template = SQL_DIR / "oracles" / f"{self.prop.type.lower()}.sql"
        line = _LINE.search(str(error))
        where = ""
        if line:
            number = int(line.group(1))
            lines = self.sql.splitlines()
            text = lines[number - 1].strip() if 0 < number <= len(lines) else ""
            # the line comes from the type's template or from a template it imports
            found = [t for t in [template, *sorted((SQL_DIR / "oracles").glob("*.sql"))]
                     if text and text in t.read_text()]
            template = found[0] if found else template
            where = f", line {number - 1} of the rendered query: {text!r}"
        return OracleFailure(self.prop.id, self.source, str(template.relative_to(SQL_DIR.parent)),
                             f"{message}{where}")


@dataclass
class OnePass:
    """The statement inserting the verdicts of every property of one type from one events source
    (render_one_pass), and each property's own oracle, which an analysis runs instead when it fails."""
    props: list[Property]
    source: str
    sql: str
    alone: list[Oracle]


def _shared_names(events: str) -> tuple[str, str, str]:
    return events, f"{events}_causes", f"{events}_epsilons"


def _shared(events: str) -> Shared:
    """The tables the oracles on `events` share in an analysis, staged as its verdicts are."""
    return Shared(*map(staged, _shared_names(events)))


@dataclass
class Rendered:
    """An analysis's statements: what its oracles share (made first), then every oracle; and the
    values the verdicts' text columns may hold (verdict_values)."""
    shared: dict[str, str]  # events table -> the statement making what its oracles share
    oracles: list[Oracle | OnePass]
    named: dict[str, set[str]]

    def on(self, events_tables: set[str]) -> Rendered:
        """The statements judging `events_tables` alone."""
        return Rendered({e: sql for e, sql in self.shared.items() if e in events_tables},
                        [o for o in self.oracles if o.source in events_tables], self.named)


def _of_types(properties: list[Property]) -> list[list[Property]]:
    """The properties judged in one query each: every property of a type with a one-pass form
    together (at its first property's place), any other alone."""
    together: dict[str, list[Property]] = {}
    for p in properties:
        together.setdefault(p.type if one_pass(p) else f"alone {p.id}", []).append(p)
    return list(together.values())


def _oracles(properties: list[Property], epsilon: float, interface: Interface | None, events: str,
             target: str) -> list[Oracle | OnePass]:
    judging = Judging(events, epsilon, interface, properties, shared=_shared(events))
    found = []
    for props in _of_types(properties):
        if one_pass(props[0]):
            sql, alone = render_one_pass(props, judging, staged(target))
            found.append(OnePass(props, events, sql, [Oracle(p, events, target, a) for p, a in zip(props, alone)]))
        else:
            found.append(Oracle(props[0], events, target, render_property(props[0], judging, into=staged(target))))
    return found


def render_oracles(properties: list[Property], epsilon: float, interface: Interface | None = None) -> Rendered:
    if not properties:
        raise PropertyError("no properties to judge; give a properties file with [[property]] entries")
    return Rendered({events: render_shared(properties, events, epsilon, interface, _shared(events)) for events, _ in SOURCES},
                    [o for events, target in SOURCES for o in _oracles(properties, epsilon, interface, events, target)],
                    verdict_values(properties))


def _stage(con, rendered: Rendered) -> None:
    """Empty staging tables, and what the oracles share."""
    for _, target in SOURCES:
        stage(con, target, rendered.named)
    for statement in rendered.shared.values():
        con.execute(statement)


def _stage_all(con, rendered: Rendered) -> bool:
    """Every oracle's rows staged in one transaction (committing each statement on its own costs
    some 15% of an analysis); False, with nothing staged, if one failed."""
    try:
        with transaction(con):
            _stage(con, rendered)
            for oracle in rendered.oracles:
                con.execute(oracle.sql)
    except duckdb.Error:
        return False
    return True


def _judge(con, rendered: Rendered) -> list[OracleFailure]:
    """Every oracle's rows staged; when one fails, each oracle again on its own (DuckDB aborts a
    transaction at its first error), a failing one getting 'unknown' rows instead."""
    if _stage_all(con, rendered):
        return []
    failures = []
    _stage(con, rendered)
    for oracle in rendered.oracles:
        _run(con, oracle, failures)
    return failures


def _run(con, oracle: Oracle | OnePass, failures: list[OracleFailure]) -> None:
    """One oracle's rows staged, or 'unknown' rows and its failure; a failing one-pass query is
    replaced by its properties' own queries, so that only a failing property gets 'unknown' rows."""
    error = try_statement(con, oracle.sql)
    if error is None:
        return
    if isinstance(oracle, OnePass):
        for alone in oracle.alone:
            _run(con, alone, failures)
        return
    failures.append(oracle.failure(error))
    con.execute(render_unknown(oracle.prop, oracle.source, staged(oracle.target)))


def materialise(con: duckdb.DuckDBPyConnection, properties: list[Property], epsilon: float,
                interface: Interface | None = None, properties_file: Path | None = None,
                interface_file: Path | None = None) -> float:
    """(Re)build the verdict tables and the views in one transaction, keeping the previous verdicts
    for the diff; a property whose oracle fails gets verdicts 'unknown' and its failure recorded,
    any other failure keeps the old verdicts (failed_oracles reads what failed). Returns the seconds
    it took."""
    started = time.perf_counter()
    rendered = render_oracles(properties, epsilon, interface)  # a property that cannot be rendered stops us here
    try:
        # an events table without events (no ground truth: real-time runs, imports) is judged by no
        # oracle, whose planning alone costs some 10 ms; its verdicts table is made, empty, all the same
        failures = _judge(con, rendered.on({events for events, _ in SOURCES if holds_rows(con, events)}))
        with transaction(con):
            replace_old_analysis(con)
            keep_previous(con)
            for _, target in SOURCES:
                publish(con, target, rendered.named)
            con.execute(render_view("properties", properties=properties))
            for name in view_order():
                con.execute(render_view(name))
            seconds = time.perf_counter() - started
            record(con, epsilon, len(properties), seconds, sources(properties_file, interface_file), failures)
    except duckdb.Error as e:
        raise StoreError(f"the oracle queries failed on this store: {e}; the previous verdicts are kept") from None
    finally:
        for events, target in SOURCES:
            for name in (target, *_shared_names(events)):
                drop_staged(con, name)
    return seconds


def failed_oracles(con) -> list[str]:
    """What failed in the last analysis, one paragraph per failed oracle (table oracle_failures)."""
    if "oracle_failures" not in relations(con):  # a store read as it is, from before the table
        return []
    found = con.execute(render_query("oracle_failures")).fetchall()
    return [f"The oracle of property {p!r} on {source} failed: {error} [template {template}]; its {n} "
            "verdicts are 'unknown' (table oracle_failures), every other property was judged. "
            "Fix the template or the property, then analyze again." for p, source, template, error, n in found]


def judges_every_trace(con: duckdb.DuckDBPyConnection) -> bool:
    """True when the stored verdicts were made after the last trace came in."""
    if not {"verdicts", "analysis"} <= relations(con):
        return False
    return analysis_is_current(con)


def main(db: str, properties: str | None = None, interface: str | None = None,
         epsilon: float | None = None) -> int:
    """`analyze`: the verdicts of every stored trace, and Tables II-IV."""
    con = connect(db, create=False)
    try:
        return _analyze(con, properties, interface, epsilon)
    finally:
        # closed before the caller opens the store again (the CI gate reads it): a connection a
        # failed oracle's traceback still holds would keep it open with another configuration
        con.close()


def _analyze(con, properties: str | None, interface: str | None, epsilon: float | None) -> int:
    """The analysis of `main` on its open store, and what it prints."""
    properties_path = Path(properties) if properties else default_properties(con)
    epsilon = last_epsilon(con) if epsilon is None else epsilon
    interface_path = Path(interface) if interface else properties_path.parent / INTERFACE_FILE
    if not interface_path.exists():
        raise InputFileError(interface_path, "", f"file not found; the properties {properties_path} name services "
                             "of an interface description: pass --interface FILE (default: beside the properties)")
    interface = load_interface(interface_path)
    properties = load_properties(properties_path, interface)
    elapsed = materialise(con, properties, epsilon, interface, properties_path, interface_path)
    traces, events, verdicts = sizes(con)
    print(f"Judged {events} events of {traces} traces against {len(properties)} properties of "
          f"{properties_path} in {elapsed:.2f} s: {counted(verdicts, 'verdict')} in table verdicts.\n")
    if not traces:
        print("The store holds no traces yet: run a campaign or import traces, then analyze again.")
        return 0
    for failure in failed_oracles(con):
        print(failure + "\n")
    print(analysis_summary(con, epsilon))
    print("\n" + diff.changes(con))
    return 0
