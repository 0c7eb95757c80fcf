"""The tables the report's index shows and writes as CSV, by the names sections.toml uses: each is
built the first time a section or a page asks for it. A name without a builder below is the store's
relation of that name, whole, in the store's order (so a section may show a view with no code)."""
from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from harness.campaign.shrink import mission_file
from harness.report import html, queries
from harness.report.html import list_href, rate_text
from harness.report.tables import Table
from harness.textable import rate_interval, with_orders


def shrunk_href(script_id: int | None) -> str | None:
    """The link to a shrunk reproducer's page; none where a finding has no reproducer yet."""
    return None if script_id is None else "shrunk/" + mission_file(Path(), script_id).name


class IndexTables:
    """Name -> Table, built on first use (`tables.findings` in a template, `tables["findings"]` here)."""

    def __init__(self, con, suts: list[str], families: list[str], page_ids: set[int]):
        self.con, self.suts, self.families, self.page_ids = con, suts, families, page_ids
        self._built: dict[str, Table] = {}

    def page_link(self, trace_id: int) -> str | None:
        return html.trace_href(trace_id) if trace_id in self.page_ids else None

    def __getitem__(self, name: str) -> Table:
        if name not in self._built:
            build = _BUILDERS.get(name)
            self._built[name] = build(self) if build else queries.view(self.con, name)
        return self._built[name]


def pivot(view: Table, rate: str, name: str, suts: list[str], families: list[str]) -> Table:
    """Paper layout of Tables III/IV: a row per family, a column per variant, each cell a link
    showing the rate, its 95% Wilson interval and n."""
    cell = {(r["family"], r["sut"]): rate_text(r, rate, r.get("n")) for r in view.records()}
    families = [f for f in families if any((f, s) in cell for s in suts)]
    suts = [s for s in suts if any((f, s) in cell for f in families)]
    no_case = with_orders(rate_interval(None, None, None, 0), None, None)  # a variant with no verdict of the family
    table = Table(name, ["family", *suts], [(f, *(cell.get((f, s), no_case) for s in suts)) for f in families])
    for r, family in enumerate(families):
        for c, sut in enumerate(suts, start=1):
            table.links[(r, c)] = list_href(sut, family)
    return table


def _rates(view: str, rate: str) -> Callable[[IndexTables], Table]:
    return lambda t: queries.view(t.con, view, percent=frozenset({rate, f"{rate}_min", f"{rate}_max"}))


_BUILDERS: dict[str, Callable[[IndexTables], Table]] = {
    "findings": lambda t: queries.view(t.con, "findings").link_column("reproducer", shrunk_href)
                                                          .link_column("first_trace", t.page_link),
    "trace_outcomes": lambda t: queries.trace_counts(t.con),
    "invalid_mutants": lambda t: queries.invalid_mutants(t.con),
    "crash_reasons": lambda t: queries.crash_reasons(t.con),
    "table2": lambda t: queries.view(t.con, "trace_robustness", percent=frozenset({"t_rob", "t_rob_min", "t_rob_max"}))
                               .link_column("sut", html.bad_href),
    "order_doubt": lambda t: queries.view(t.con, "order_doubt",
                                          percent=frozenset({"t_rob_width", "tp_rate_width", "fp_rate_width"})),
    "tp_rates": _rates("tp_rates", "tp_rate"),
    "fp_rates": _rates("fp_rates", "fp_rate"),
    "table3": lambda t: pivot(t["tp_rates"], "tp_rate", "table3", t.suts, t.families),
    "table4": lambda t: pivot(t["fp_rates"], "fp_rate", "table4", t.suts, t.families),
    "properties": lambda t: queries.per_property(t.con),
    "verdict_transitions": lambda t: queries.verdict_transitions(t.con),
    "table_changes": lambda t: queries.table_changes(t.con),
    "suspicious": lambda t: queries.suspicious(t.con).link_column("trace_id", t.page_link),
    "inversions": lambda t: queries.inversions(t.con).link_column("trace_id", t.page_link),
    "shrunk": lambda t: queries.shrunk(t.con).link_column("script_id", shrunk_href)
                                             .link_column("trace_id", t.page_link),
    "bad_traces": lambda t: queries.bad_traces(t.con),
    "bad_trace_verdicts": lambda t: queries.bad_verdicts(t.con),
    "family_traces": lambda t: queries.family_traces(t.con),
}
