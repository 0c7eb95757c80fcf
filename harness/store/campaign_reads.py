"""The reads a campaign makes of the store, each by a name that says what it reads: its scripts and
traces while it runs, resumes, shrinks or is merged (harness/campaign/), so that no SQL text lives
outside harness/store/ and sql/."""
from __future__ import annotations

from harness.store.sql import render_query


def script_counts(con, campaign_id: int) -> tuple[int, int, int]:
    """A campaign's scripts: how many, how many valid, how many distinct bodies."""
    return con.execute("select count(*), count(*) filter (where valid), count(distinct body) from scripts "
                       "where campaign_id = ?", [campaign_id]).fetchone()


def golden_script_id(con, campaign_id: int) -> int:
    """The id of a campaign's golden script (its first)."""
    return con.execute("select min(script_id) from scripts where campaign_id = ?", [campaign_id]).fetchone()[0]


def valid_scripts(con, campaign_id: int) -> list[tuple[int, str]]:
    """(script_id, body) of a campaign's valid scripts (those it runs), by id."""
    return con.execute("select script_id, body from scripts where campaign_id = ? and valid order by script_id",
                       [campaign_id]).fetchall()


def all_crashed(con, campaign_id: int) -> list[tuple[str, str | None]]:
    """(sut, its first run's error) of each variant every run of which crashed in a campaign."""
    return con.execute("""select sut, arg_min(error, trace_id) from traces where campaign_id = ?
                          group by sut having bool_and(outcome = 'crashed')""", [campaign_id]).fetchall()


def trace_owners(con, first_trace_id: int) -> dict[int, int]:
    """trace_id -> campaign_id of every stored trace from `first_trace_id` on."""
    return dict(con.execute("select trace_id, campaign_id from traces where trace_id >= ?",
                            [first_trace_id]).fetchall())


def campaign_trace_ids(con, campaign_id: int) -> set[int]:
    return {t for (t,) in con.execute("select trace_id from traces where campaign_id = ?", [campaign_id]).fetchall()}


def is_stored(con, trace_id: int) -> bool:
    return con.execute("select count(*) from traces where trace_id = ?", [trace_id]).fetchone()[0] > 0


def trace_count(con) -> int:
    return con.execute("select count(*) from traces").fetchone()[0]


def event_count(con, first_trace_id: int, last_trace_id: int) -> int:
    """How many events the traces `first_trace_id` to `last_trace_id` (both included) hold."""
    return con.execute("select count(*) from events where trace_id between ? and ?",
                       [first_trace_id, last_trace_id]).fetchone()[0]


def representatives(con) -> list[tuple[str, str | None, str, int]]:
    """(sut, property_id, verdict, representative trace) of every distinct bad behaviour (view
    bad_behaviours), in the order the campaign shrinks them: variants in their order, hangs first."""
    return con.execute("select sut, property_id, verdict, representative from bad_behaviours "
                       "join variant_positions using (sut) "
                       "order by position, verdict = 'hung' desc, verdict, property_id").fetchall()


def trace_to_shrink(con, trace_id: int) -> tuple | None:
    """(trace_id, script_id, sut, seed, outcome, body, mission, config) of a stored trace, with its
    script's body (None: an imported trace) and its campaign's mission and config; None if none."""
    return con.execute("""select t.trace_id, t.script_id, t.sut, t.seed, t.outcome, s.body, c.mission, c.config
                          from traces t left join scripts s using (script_id) join campaigns c
                          on c.campaign_id = t.campaign_id where t.trace_id = ?""", [trace_id]).fetchone()


def findings(con) -> list[tuple]:
    """(variant, property, kind, first trace, traces, reproducer, its steps) of each finding (view findings)."""
    return con.execute("select sut, coalesce(property_id, '-'), kind, first_trace, traces, reproducer, "
                       "reproducer_steps from findings").fetchall()


def spent_s(con, campaign_id: int) -> tuple[float, float]:
    """The mission seconds a campaign has spent: its own traces', and its shrinks' runs' (sql/report/
    campaign_spent.sql); a focused campaign's --budget bounds their sum."""
    return con.execute(render_query("campaign_spent"), {"campaign": campaign_id}).fetchone()


def budget_stopped(con, campaign_id: int) -> str | None:
    """Why a focused campaign stopped (table campaign_budgets); None while it has not, or before its budget is stored."""
    (stopped,) = con.execute("select stopped from campaign_budgets where campaign_id = ?",
                             [campaign_id]).fetchone() or (None,)
    return stopped


def mutant_scripts(con, campaign_id: int) -> list[tuple[int, str, str]]:
    """(script_id, mutations as JSON, body) of a campaign's mutants."""
    return con.execute("select script_id, mutations, body from scripts where campaign_id = ? and kind = 'mutant'",
                       [campaign_id]).fetchall()


def campaign_findings(con, campaign_id: int) -> list[tuple[int, str | None, str]]:
    """(trace_id, property_id, kind) of the findings of a campaign's traces (view trace_findings)."""
    return con.execute("select trace_id, property_id, kind from trace_findings join traces using (trace_id) "
                       "where campaign_id = ?", [campaign_id]).fetchall()
