"""The reads the benchmarks (bench/) make of the stores they build, each by a name that says what it
reads, so that no SQL text lives outside harness/store/ and sql/ (their longer queries are files of
sql/bench/)."""
from __future__ import annotations

from harness.store.sql import sql_literal


def event_count(con) -> int:
    """How many observed events the store holds, of every trace."""
    return con.execute("select count(*) from events").fetchone()[0]


def events_in_order(con, columns: list[str], label: str):
    """A cursor over the observed events' `columns` in their order (a one-trace store), each row
    headed by `label` (in place of the trace id, for a CSV of them)."""
    return con.execute(f"select {sql_literal(label)}, {', '.join(columns)} from events order by seq")


def run_totals(con) -> tuple[int, float | None]:
    """How many runs the store holds (traces), and their mission seconds."""
    return con.execute("select count(*), sum(sim_s) from traces").fetchone()


def trace_span(con) -> tuple[int, int | None]:
    """How many traces the store holds, and the largest trace id."""
    return con.execute("select count(*), max(trace_id) from traces").fetchone()


def bad_behaviour_keys(con) -> set[tuple[str, str, str | None]]:
    """(sut, verdict, property_id) of every distinct bad behaviour (view bad_behaviours)."""
    return set(con.execute("select sut, verdict, property_id from bad_behaviours").fetchall())


def findings_in_order(con) -> list[tuple[int, str, str | None, str]]:
    """(trace_id, sut, property_id, kind) of every finding of a trace (view trace_findings), by trace."""
    return con.execute("select trace_id, sut, property_id, kind from trace_findings order by trace_id").fetchall()


def test_seconds_until(con, last_trace_id: int) -> float:
    """The mission seconds of the campaign's own runs (not its shrinks') up to trace `last_trace_id`."""
    return con.execute("select sum(sim_s) from traces anti join shrink_runs using (trace_id) where trace_id <= ?",
                       [last_trace_id]).fetchone()[0]


def why_stopped(con) -> str | None:
    """Why the store's focused campaign stopped (table campaign_budgets)."""
    return con.execute("select stopped from campaign_budgets").fetchone()[0]


def realtime_runs(con) -> tuple[int, float | None]:
    """How many real-time runs the store holds (table trace_runs), and the median wall seconds each
    took beyond its mission time."""
    return con.execute("select count(*), median(wall_s - sim_s / time_scale) from traces "
                       "join trace_runs using (trace_id)").fetchone()


def slot_seconds(con) -> tuple[float | None, float | None, int]:
    """Over the real-time runs: their wall seconds, the part of those beyond their mission time, and
    how many runs hung."""
    return con.execute("select sum(wall_s), sum(wall_s - sim_s / time_scale), "
                       "count(*) filter (where outcome = 'hung') from traces "
                       "join trace_runs using (trace_id)").fetchone()


def run_spans(con) -> list[tuple[float, float]]:
    """(start as epoch seconds, wall seconds) of every real-time run."""
    return con.execute("select epoch(started_at), wall_s from traces join trace_runs using (trace_id)").fetchall()


def node_starts(con) -> tuple[int, float | None]:
    """How many ROS 2 nodes were started (a run that was its node's first), and the median seconds
    one took to start and be discovered (its adapter's `up in` text)."""
    return con.execute("select count(*), median(regexp_extract(sut_info, 'up in ([0-9.]+) s', 1)::double) "
                       "from trace_runs where sut_info like '%run 1 of this node)'").fetchone()
