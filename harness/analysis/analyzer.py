"""`python -m harness analyze`: judge the stored traces with the property oracles (DESIGN §6).

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
from harness.store.reads import ordered
from harness.errors import InputFileError, PropertyError, StoreError
from harness.target.interface import Interface, Property, load_interface, load_properties
from harness.analysis.oracles import VERDICT_COLUMNS, render_property
from harness.store.sql import render_view
from harness.analysis.provenance import default_properties, last_epsilon, record
from harness.store.database import connect, transaction
from harness.textable import format_table, percent, rate_interval

# (events source, verdicts table): the observed timeline and the ground truth.
SOURCES = (("events", "verdicts"), ("internal_events", "verdicts_internal"))
# Creation order: each view reads only tables or views created before it.
VIEWS = ("wilson", "property_positions", "family_positions", "judged_traces", "trace_scope", "requests",
         "activities", "property_verdicts", "family_verdicts", "trace_badness", "trace_robustness",
         "tp_rates", "fp_rates", "inversions", "interface_latency", "coverage", "trace_findings",
         "bad_behaviours", "findings",
         "table_values", "verdict_transitions", "table_changes", "analysis")
# What orders the views' rows, by column: variants as the campaign ran them, properties and
# families in the order of the properties file, All last (the store's positions tables and views).
_LINE = re.compile(r"LINE (\d+):")


@dataclass
class Oracle:
    """One property's rendered query over one events source."""
    prop: Property
    target: str
    sql: str

    def failed(self, error: duckdb.Error) -> StoreError:
        """The error naming the property, the template and the line of its rendered query."""
        message = str(error).split("\n")[0]
        template = SQL_DIR / "oracles" / f"{self.prop.type.lower()}.sql"
        where = ""
        line = _LINE.search(str(error))
        if line:
            number = int(line.group(1)) - 1  # the rendered query comes after "insert into ... (columns)\n"
            lines = self.sql.splitlines()
            text = lines[number - 1].strip() if 0 < number <= len(lines) else ""
            # the line comes from the type's template or from a template it imports
            found = [t for t in [template, *sorted((SQL_DIR / "oracles").glob("*.sql"))]
                     if text and text in t.read_text()]
            template = found[0] if found else template
            where = f", line {number} of the rendered query: {text!r}"
        return StoreError(f"the oracle of property {self.prop.id!r} ({self.target}) failed: {message} "
                          f"[template {template.relative_to(SQL_DIR.parent)}{where}]; fix the template or the "
                          f"property (harness.store.sql.render_property renders its query). "
                          f"The previous verdicts are kept.")


def render_oracles(properties: list[Property], epsilon: float, interface: Interface | None = None) -> list[Oracle]:
    if not properties:
        raise PropertyError("no properties to judge; give a properties file with [[property]] entries")
    return [Oracle(p, target, render_property(p, events, epsilon, interface))
            for events, target in SOURCES for p in properties]


def _exists(con, name: str) -> bool:
    return con.execute("select count(*) from information_schema.tables where table_name = ?", [name]).fetchone()[0] > 0


def _keep_previous(con) -> None:
    """The verdicts and Tables II-IV of the analysis being replaced (empty before the first one),
    for the diff views."""
    if _exists(con, "verdicts"):
        con.execute(render_view("table_values"))
        con.execute("create or replace table verdicts_previous as from verdicts")
        con.execute("create or replace table table_values_previous as from table_values")
    else:
        con.execute(render_view("verdicts", target="verdicts_previous"))
        con.execute("create or replace table table_values_previous (sut varchar, family varchar, "
                    "paper_table varchar, measure varchar, value double)")


def materialise(con: duckdb.DuckDBPyConnection, properties: list[Property], epsilon: float,
                interface: Interface | None = None, properties_file: Path | None = None,
                interface_file: Path | None = None) -> float:
    """(Re)build the verdict tables and the views in one transaction, keeping the previous verdicts
    for the diff; a failure keeps the old ones. Returns the seconds it took."""
    started = time.perf_counter()
    rendered = render_oracles(properties, epsilon, interface)  # a property that cannot be rendered stops us here
    try:
        with transaction(con):
            if con.execute("select count(*) from information_schema.tables where table_name = 'analysis' "
                           "and table_type = 'BASE TABLE'").fetchone()[0]:
                con.execute("drop table analysis")  # a store analysed before the analyses table
            _keep_previous(con)
            for _, target in SOURCES:
                con.execute(render_view("verdicts", target=target))
            for oracle in rendered:
                try:
                    con.execute(f"insert into {oracle.target} ({VERDICT_COLUMNS})\n{oracle.sql}")
                except duckdb.Error as e:
                    raise oracle.failed(e) from None
            for _, target in SOURCES:
                con.execute(render_view("shared_codes", target=target))
            con.execute(render_view("properties", properties=properties))
            for name in VIEWS:
                con.execute(render_view(name))
            seconds = time.perf_counter() - started
            record(con, properties_file, epsilon, len(properties), seconds, interface_file)
    except duckdb.Error as e:
        raise StoreError(f"the oracle queries failed on this store: {e}") from None
    return seconds


def judges_every_trace(con: duckdb.DuckDBPyConnection) -> bool:
    """True when the stored verdicts were made after the last trace came in."""
    if not (_exists(con, "verdicts") and _exists(con, "analysis")):
        return False
    return con.execute("select traces = (select count(*) from traces) from analysis").fetchone()[0]


def sut_order(con) -> list[str]:
    """Variants in the order the campaign ran them."""
    return [r[0] for r in con.execute("select sut from variant_positions semi join traces using (sut) "
                                      "order by position").fetchall()]


def family_order(con) -> list[str]:
    """Families in the order the properties file lists them, then All."""
    return [r[0] for r in con.execute("select family from family_positions order by position").fetchall()]


def _rates_by_family(con, view: str, column: str, suts: list[str]) -> str:
    """Paper layout: one row per family (properties-file order, then All), one column per variant;
    each cell the rate, its 95% Wilson interval and n."""
    cells = {(sut, family): rate_interval(*values) for sut, family, *values in con.execute(
        f"select sut, family, {column}, {column}_low, {column}_high, n from {view}").fetchall()}
    return format_table(["family"] + suts,
                        [[f] + [cells.get((s, f), "-") for s in suts] for f in family_order(con)])


def flag_accuracy(con) -> tuple[int, int, int, int]:
    """Over the traces with a ground truth: (verdicts, inverted verdicts, inverted and flagged,
    flagged). Recall = inverted and flagged / inverted; precision = inverted and flagged / flagged."""
    judged, flagged = con.execute("""select count(*), count(*) filter (where suspicious) from verdicts
                                     semi join (select distinct trace_id from internal_events) using (trace_id)
                                  """).fetchone()
    inverted, caught = con.execute("select count(*), count(*) filter (where suspicious) from inversions").fetchone()
    return judged, inverted, caught, flagged


def summary(con: duckdb.DuckDBPyConnection, epsilon: float) -> str:
    cursor = con.execute(ordered(con, "trace_robustness"))
    columns, robustness = [d[0] for d in cursor.description], cursor.fetchall()
    suts = [r[0] for r in robustness]
    table2 = format_table(columns, [r[:-1] + (percent(r[-1]) + "%",) for r in robustness])
    parts = ["Table II - per trace results\n" + table2,
             "Table III - true positive rates TP/(TP+FN), % [95% Wilson interval] n=TP+FN\n"
             + _rates_by_family(con, "tp_rates", "tp_rate", suts),
             "Table IV - false positive rates FP/(FP+TN), % [95% Wilson interval] n=FP+TN\n"
             + _rates_by_family(con, "fp_rates", "fp_rate", suts)]
    left_out = con.execute("select left_out, count(*) from trace_scope where not counted group by all "
                           "order by all").fetchall()
    if left_out:
        parts.append("Not counted in Tables II-IV (view trace_scope): "
                     + "; ".join(f"{n} trace{'s' * (n != 1)}: {why}" for why, n in left_out) + ".")
    judged, inverted, caught, flagged = flag_accuracy(con)
    if judged:
        parts.append(f"Ground truth: {inverted} of {judged} observed verdicts differ from the verdicts on "
                     f"the internal timeline (view inversions). The suspicious flag (epsilon {epsilon:g} s) "
                     f"caught {caught} of them (recall {percent(caught / inverted if inverted else None)}%) "
                     f"and is raised on {flagged} verdicts in all "
                     f"(precision {percent(caught / flagged if flagged else None)}%).")
    cursor = con.execute("select * exclude (campaign_id) from interface_latency order by campaign_id, sut")
    latency = cursor.fetchall()
    if latency:
        parts.append("Interface latency of the real-time runs (ping round trips, wall s; "
                     "suggested epsilon in mission s)\n" + format_table([d[0] for d in cursor.description], latency))
    parts.append(least_covered(con))
    return "\n\n".join(parts)


def least_covered(con: duckdb.DuckDBPyConnection, shown: int = 5) -> str:
    """The properties whose condition was false on the fewest requests, on their worst variant
    (of equally bad ones, the first by name)."""
    found = con.execute(f"""
        select property_id, min(c_false) as c_false, arg_min(sut, (c_false, sut)) as sut
        from coverage left join property_positions using (property_id) group by property_id
        order by c_false, min(position) limit {int(shown)}""").fetchall()
    listed = ", ".join(f"{p} {n} ({sut})" for p, n, sut in found)
    return (f"Least covered (requests with C false, on the variant with fewest; view coverage): {listed}. "
            "More cases: python -m harness campaign --strategy targeted")


def main(args) -> int:
    con = connect(args.db, create=False)
    properties_path = Path(args.properties) if args.properties else default_properties(con)
    epsilon = last_epsilon(con) if args.epsilon is None else args.epsilon
    interface_path = Path(args.interface) if args.interface else properties_path.parent / "interface.toml"
    if not interface_path.exists():
        raise InputFileError(interface_path, "", f"file not found; the properties {properties_path} name services "
                             "of an interface description: pass --interface FILE (default: beside the properties)")
    interface = load_interface(interface_path)
    properties = load_properties(properties_path, interface)
    elapsed = materialise(con, properties, epsilon, interface, properties_path, interface_path)
    traces, events = con.execute("select (select count(*) from traces), (select count(*) from events)").fetchone()
    verdicts = con.execute("select count(*) from verdicts").fetchone()[0]
    print(f"Judged {events} events of {traces} traces against {len(properties)} properties of "
          f"{properties_path} in {elapsed:.2f} s: {verdicts} verdicts in table verdicts.\n")
    if not traces:
        print("The store holds no traces yet: run a campaign or import traces, then analyze again.")
        return 0
    print(summary(con, epsilon))
    print("\n" + diff.changes(con))
    return 0
