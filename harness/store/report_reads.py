"""The reads the report makes of the store that are not whole views or queries of sql/report/, each
by a name that says what it reads: what a trace page shows, the analysis it was judged by, what
`analyze --junit` and the paper's comparison count (harness/report/), so that no SQL text lives
outside harness/store/ and sql/."""
from __future__ import annotations

from harness.store.reads import exists
from harness.store.sql import render_query, sql_id_list


def as_records(con, sql: str, params=()) -> list[dict]:
    """The rows of a query as dicts, column name -> value."""
    cursor = con.execute(sql, list(params))
    names = [d[0] for d in cursor.description]
    return [dict(zip(names, row)) for row in cursor.fetchall()]


def whole(con, view: str) -> list[dict]:
    """Every row of a view (or table), as dicts, in the order DuckDB gives them."""
    return as_records(con, f"select * from {view}")


def judgements(con, analyses_recorded: bool) -> int:
    """How many verdicts the store holds, plus its analyses when it records them (older stores do not):
    an analysis that made no verdict (every run crashed before a final reply) still counts."""
    analyses = "(select count(*) from analyses)" if analyses_recorded else "0"
    return con.execute(f"select (select count(*) from verdicts) + {analyses}").fetchone()[0]


def campaign_budgets(con) -> dict[int, dict]:
    """campaign_id -> its focused budget's tests and why it stopped; none in a store older than focused campaigns."""
    if not exists(con, "campaign_budgets"):
        return {}
    return {r["campaign_id"]: r for r in as_records(con, "select campaign_id, tests, stopped from campaign_budgets")}


def analysis_row(con, with_provenance: bool) -> dict:
    """The analysis the stored verdicts were made by (view analysis): when, with which epsilon, from how
    many properties, and, `with_provenance` (a store that records analyses), its id and seconds."""
    if not with_provenance:
        return as_records(con, "select analysed_at::timestamp as analysed_at, epsilon, properties from analysis")[0]
    return as_records(con, "select analysis_id, analysed_at, epsilon, properties, seconds from analysis")[0]


def analysis_files(con, analysis_id: int) -> list[dict]:
    """The files an analysis was made from (role, path, the start of its sha256): properties, interface, templates."""
    return as_records(con, """select role, path, left(sha256, 12) as sha256 from analysis_files
                              where analysis_id = ? order by role <> 'properties', role <> 'interface', path""",
                      [analysis_id])


def paged_trace_ids(con, suspicious_shown: int) -> list[int]:
    """The traces that get a page (sql/report/paged_traces.sql) and those of the first `suspicious_shown`
    suspicious verdicts (sql/report/suspicious.sql), in id order."""
    return [r[0] for r in con.execute(f"""select trace_id from ({render_query("paged_traces")})
        union select trace_id from ({render_query("suspicious")} limit {int(suspicious_shown)})
        order by trace_id""").fetchall()]


def stored_trace_ids(con, ids: list[int]) -> list[int]:
    """Those of `ids` that are traces of the store."""
    return [r[0] for r in con.execute("select trace_id from traces where trace_id in "
                                      "(select unnest(?::integer[]))", [ids]).fetchall()]


def explained_verdicts(con, ids: list[int]) -> list[dict]:
    """(trace_id, property_id, rqst_id) of the verdicts a page of these traces explains: the bad ones
    and the suspicious ones."""
    return as_records(con, f"select trace_id, property_id, rqst_id from verdicts where trace_id in "
                           f"({sql_id_list(ids)}) and (verdict in ('FN', 'FP') or suspicious)")


def bad_trace_sums(con, columns: list[str]) -> list[int]:
    """The sums of Table II's (view trace_robustness) `columns` over every variant (0 for none)."""
    return list(con.execute(f"select {', '.join(f'coalesce(sum({c}), 0)' for c in columns)} "
                            "from trace_robustness").fetchone())


def mutant_counts(con) -> tuple[int, int]:
    """How many mutants the store's scripts hold, and how many of them are valid."""
    return con.execute("select count(*) filter (where kind = 'mutant'), count(*) filter (where kind = 'mutant' "
                       "and valid) from scripts").fetchone()
