"""Judging traces that are not in a store yet: the analyzer's verdicts table, in memory.

Targeted generation judges the golden run to learn which P-conditions it already falsifies,
shrinking judges every candidate script's run, a focused campaign what each test found. All use
the oracles of `analyze` (the same rendered verdicts table, shared-code rule included, and the
view trace_findings), on a private in-memory DuckDB.
"""
from __future__ import annotations

from harness import DEFAULT_EPSILON_S, store
from harness.target.interface import Interface, Property
from harness.analysis.oracles import oracle_statements
from harness.store import judging_reads
from harness.store.sql import render_view
from harness.trace import Trace

_STAGED = "verdicts_staged"


class Judge:
    def __init__(self, interface: Interface, properties: list[Property], epsilon: float = DEFAULT_EPSILON_S):
        self.con = store.connect(":memory:")
        store.add_reply_codes(self.con, interface)
        self.con.execute(render_view("properties", properties=properties))
        # every oracle's rows staged, then the verdicts table made from them, shared codes applied
        self.sql = "\n".join(s + ";" for s in [render_view("verdicts", target=_STAGED),
                                                *oracle_statements(properties, epsilon, interface, "events", _STAGED),
                                                render_view("verdicts", target="verdicts", source=_STAGED)])
        self.con.execute(render_view("verdicts", target="verdicts"))  # for the view, until verdicts() makes it
        self.con.execute(render_view("trace_findings"))

    def verdicts(self, traces: list[Trace]) -> list[list[dict]]:
        """Per trace, its verdict rows (the verdicts columns but trace_id) in the order of the
        properties, then of the requests."""
        con = self.con
        store.forget_traces(con)
        for n, trace in enumerate(traces, 1):
            store.insert_trace(con, n, 0, None, trace)
        con.execute(self.sql)
        cursor = judging_reads.ordered_verdicts(con)
        names = [d[0] for d in cursor.description]
        judged = [[] for _ in traces]
        for row in cursor.fetchall():
            record = dict(zip(names, row))
            judged[record.pop("trace_id") - 1].append(record)
        return judged

    def findings(self, traces: list[Trace]) -> list[set[tuple[str | None, str]]]:
        """Per trace, the (property_id, kind) that went wrong in it (view trace_findings)."""
        self.verdicts(traces)
        found = [set() for _ in traces]
        for trace_id, property_id, kind in judging_reads.findings(self.con):
            found[trace_id - 1].add((property_id, kind))
        return found
