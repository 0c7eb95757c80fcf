"""What the analyzer and its benches read back from a store after judging it: counts to print,
whether the verdicts are current, the verdict rows and findings of the in-memory judge."""
from __future__ import annotations


def sizes(con) -> tuple[int, int, int]:
    """How many traces, events and verdicts the store holds."""
    return con.execute("select (select count(*) from traces), (select count(*) from events), "
                       "(select count(*) from verdicts)").fetchone()


def event_count(con) -> int:
    return con.execute("select count(*) from events").fetchone()[0]


def analysis_is_current(con) -> bool:
    """Whether the last analysis judged as many traces as the store holds (table analysis)."""
    return con.execute("select traces = (select count(*) from traces) from analysis").fetchone()[0]


def ordered_verdicts(con):
    """A cursor over the verdict rows in the order of the properties (view properties), then of the
    traces and requests."""
    return con.execute("select v.* from verdicts v join properties p using (property_id) "
                       "order by v.trace_id, p.position, v.rqst_id")


def findings(con) -> list[tuple[int, str | None, str]]:
    """(trace_id, property_id, kind) of view trace_findings: what went wrong in each trace."""
    return con.execute("select trace_id, property_id, kind from trace_findings").fetchall()
