"""The reads of an analysis's results and provenance, each by a name that says what it reads: what
`analyze` and `diff` print, what `explain` explains a verdict from, which files an analysis was
made from (harness/analysis/), so that no SQL text lives outside harness/store/ and sql/."""
from __future__ import annotations

from harness.store.sql import sql_id_list


def sut_order(con) -> list[str]:
    """Variants in the order the campaign ran them."""
    return [r[0] for r in con.execute("select sut from variant_positions semi join traces using (sut) "
                                      "order by position").fetchall()]


def family_order(con) -> list[str]:
    """Families in the order the properties file lists them, then All."""
    return [r[0] for r in con.execute("select family from family_positions order by position").fetchall()]


def last_analyses(con) -> list[tuple]:
    """(analysis_id, analysed_at, epsilon) of the last two analyses, the last first."""
    return con.execute("select analysis_id, analysed_at, epsilon from analyses "
                       "order by analysis_id desc limit 2").fetchall()


def last_analysis_epsilon(con) -> float | None:
    """The epsilon of the last analysis; None before the first one."""
    found = con.execute("select epsilon from analyses order by analysis_id desc limit 1").fetchone()
    return found[0] if found else None


def analysis_epsilon(con) -> float:
    """The epsilon of the analysis the stored verdicts were made with (view analysis)."""
    return con.execute("select epsilon from analysis").fetchone()[0]


def last_analysis_files(con) -> list[tuple[str, str, str]]:
    """(role, path, sha256) of every file the last analysis was made from."""
    return con.execute("""select role, path, sha256 from analysis_files
                          where analysis_id = (select max(analysis_id) from analyses)""").fetchall()


def rate_cells(con, view: str, column: str) -> list[tuple]:
    """(sut, family, lowest, highest, rate, low, high, n) of a rates view (tp_rates, fp_rates) whose
    rate column is `column`: lowest and highest over the orders of events closer than epsilon."""
    return con.execute(f"select sut, family, {column}_min, {column}_max, {column}, {column}_low, {column}_high, n "
                       f"from {view}").fetchall()


def judged_both_ways(con) -> tuple[int, int]:
    """How many verdicts were judged on both timelines, and how many of those were flagged suspicious."""
    return con.execute("""select count(*), count(*) filter (where suspicious) from verdicts
                          semi join verdicts_internal using (trace_id, property_id, module, service, rqst_id)
                       """).fetchone()


def inverted(con) -> tuple[int, int]:
    """How many verdicts the internal timeline inverts (view inversions), and how many of those were flagged."""
    return con.execute("select count(*), count(*) filter (where suspicious) from inversions").fetchone()


def left_out(con) -> list[tuple[str, int]]:
    """(why, how many traces) of the traces Tables II-IV leave out (view trace_scope)."""
    return con.execute("select left_out, count(*) from trace_scope where not counted group by all "
                       "order by all").fetchall()


def interface_latency(con):
    """The interface latency of the real-time runs (view interface_latency), as a cursor: its columns
    and rows, by campaign and variant."""
    return con.execute("select * exclude (campaign_id) from interface_latency order by campaign_id, sut")


def epsilon_sources(con) -> list[tuple[str, int, float, float]]:
    """(source, traces, lowest, highest epsilon) of the epsilons the traces were judged with (view trace_epsilon)."""
    return con.execute("""select source, count(*), min(epsilon_s), max(epsilon_s) from trace_epsilon
                          group by source order by source""").fetchall()


def least_covered(con, shown: int) -> list[tuple[str, int, str]]:
    """(property, requests with C false, variant) of the `shown` properties whose condition was false
    on the fewest requests, on their worst variant (of equally bad ones, the first by name)."""
    return con.execute(f"""
        select property_id, min(c_false) as c_false, arg_min(sut, (c_false, sut)) as sut
        from coverage left join property_positions using (property_id) group by property_id
        order by c_false, min(position) limit {int(shown)}""").fetchall()


def judged_file_paths(con) -> dict[str, str]:
    """role -> path of the last analysis's properties and interface files."""
    return dict(con.execute("""select role, path from analysis_files where role in ('properties', 'interface')
                               and analysis_id = (select max(analysis_id) from analyses)""").fetchall())


def explained_requests(con, trace_ids, taken: bool) -> list[tuple]:
    """(trace_id, rqst_id, service, t, final_t, reply, class, args, sent at, placed at taken) of every
    request of the traces `trace_ids` (view requests). With `taken` (a store with taken_events), a
    request the SUT replied `taken` to stands at that reply: it was sent at its request event's instant."""
    join, placed = (("left join taken_events k on k.trace_id = r.trace_id and k.rqst_id = r.rqst_id",
                     "k.t is not null") if taken else ("", "false"))
    return con.execute(f"""select r.trace_id, r.rqst_id, r.module || '.' || r.service as service, r.t,
                                  r.final_t, r.reply, r.class, e.args, e.t, {placed}
                           from requests r left join events e
                             on e.trace_id = r.trace_id and e.rqst_id = r.rqst_id and e.kind = 'request'
                           {join} where r.trace_id in ({sql_id_list(trace_ids)})""").fetchall()


def verdict_rows(con, keys: list[tuple[int, str, int]]) -> list[tuple]:
    """(trace_id, property_id, rqst_id, verdict, c_holds, margin_s, suspicious) of the verdicts `keys`
    ((trace_id, property_id, rqst_id) each)."""
    return con.execute(
        """select trace_id, property_id, rqst_id, verdict, c_holds, margin_s, suspicious from verdicts
           semi join (select unnest(?::integer[]) as trace_id, unnest(?::varchar[]) as property_id,
                             unnest(?::integer[]) as rqst_id) using (trace_id, property_id, rqst_id)""",
        [list(column) for column in zip(*keys)]).fetchall()


def judged_requests(con, trace_id: int, property_id: str) -> list[int]:
    """The ids of the requests of a trace that have a verdict of a property, in order."""
    return [r for r, in con.execute(
        "select rqst_id from verdicts where trace_id = ? and property_id = ? order by rqst_id",
        [trace_id, property_id]).fetchall()]
