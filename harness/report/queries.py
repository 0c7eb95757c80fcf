"""Everything the report reads from the store: read-only queries over the contract tables and views."""
from __future__ import annotations

import difflib
import json
from collections import defaultdict

from harness.analyzer import ordered
from harness.errors import StoreError
from harness.provenance import stale_files
from harness.report.tables import Table, query_table
from harness.report.timeline import Request

VERDICTS = ("TP", "FN", "FP", "TN", "op", "na", "omega")
# What `python -m harness analyze` materialises and the report reads.
ANALYSED = ("verdicts", "requests", "property_verdicts", "family_verdicts", "trace_robustness",
            "tp_rates", "fp_rates", "inversions", "analysis")
# What an analysis by a bench with provenance (schema version 2) adds; a store judged before is
# read as is, without them.
CHANGES = ("verdict_transitions", "table_changes")
# The rate columns of the coverage view, shown as percentages.
COVERAGE_RATES = frozenset(f"{rate}{end}" for rate in ("tp_rate", "fp_rate") for end in ("", "_low", "_high"))


def rows(con, sql: str, params=()) -> list[dict]:
    cursor = con.execute(sql, list(params))
    names = [d[0] for d in cursor.description]
    return [dict(zip(names, row)) for row in cursor.fetchall()]


def check_analysed(con, db: str) -> None:
    """Refuse a store whose verdicts were never materialised: the report would be empty."""
    have = _names(con)
    missing = [name for name in ("traces", *ANALYSED) if name not in have]
    if "traces" in missing:
        raise StoreError(f"{db!r} is not an Untimely store (no traces table); pass the campaign's --db")
    if missing or not con.execute("select count(*) from verdicts").fetchone()[0]:
        lacking = ", ".join(missing) or "any verdict row"
        raise StoreError(f"{db!r} has no verdicts yet (lacks {lacking}); "
                         f"run python -m harness analyze --db {db} first")


def per_property(con) -> Table:
    """The coverage view; a store analysed before it had one (read as it is) shows its verdict counts."""
    if con.execute("select count(*) from information_schema.tables where table_name = 'coverage'").fetchall()[0][0]:
        return view(con, "coverage", percent=COVERAGE_RATES)
    return view(con, "property_verdicts")


def module_order(con) -> list[str]:
    """Modules in the order the interface description declares them (reply_codes insertion order)."""
    return [r[0] for r in con.execute("select module from reply_codes group by module "
                                      "order by min(rowid)").fetchall()]


def campaigns(con) -> list[dict]:
    found = rows(con, """
        select c.campaign_id, c.created_at, c.mission, c.seed, c.config,
               count(*) filter (where s.kind = 'golden') as golden,
               count(*) filter (where s.kind = 'mutant') as mutants,
               count(*) filter (where s.kind = 'mutant' and not s.valid) as invalid
        from campaigns c left join scripts s using (campaign_id)
        where c.config->>'kind' is distinct from 'shrink'  -- listed with the shrunk reproducers
        group by all order by c.campaign_id""")
    for c in found:
        c["config"] = json.loads(c["config"]) if c["config"] else {}
    return found


def trace_counts(con) -> Table:
    return query_table(con, "trace_outcomes", """
        select campaign_id, sut, count(*) as traces,
               count(*) filter (where outcome = 'completed') as completed,
               count(*) filter (where outcome = 'hung') as hung,
               count(*) filter (where outcome = 'crashed') as crashed,
               count(*) filter (where trace_id not in (select trace_id from verdicts)) as without_verdicts
        from traces group by all order by campaign_id, min(trace_id)""")


def invalid_mutants(con) -> Table:
    return query_table(con, "invalid_mutants", """
        select script_id, campaign_id, mutations, invalid_reason
        from scripts where not valid order by script_id""")


def view(con, name: str, **options) -> Table:
    """A whole analyzer view, with its own columns, in the order the campaign and properties give."""
    return query_table(con, name, ordered(con, name), **options)


def verdict_mix(con) -> dict[tuple[str, str], int]:
    """(variant, verdict) -> how many verdicts, over all families."""
    found = rows(con, "select * from family_verdicts where family = 'All'")
    return {(r["sut"], v): r[v.lower()] for r in found for v in VERDICTS}


def _names(con) -> set[str]:
    return {r[0] for r in con.execute("select table_name from information_schema.tables").fetchall()}


def analysis(con) -> dict:
    """When the verdicts were made, from how many properties, with which epsilon and files, and
    which of those files changed on disk since (the verdicts no longer match them)."""
    columns = [d[0] for d in con.execute("select * from analysis limit 0").description]
    if "analysis_id" not in columns:  # judged before analyses were recorded: no provenance
        found = rows(con, "select analysed_at::timestamp as analysed_at, epsilon, properties from analysis")[0]
        return dict(found, analysis_id=None, seconds=None, files=[], stale=[])
    found = rows(con, "select analysis_id, analysed_at, epsilon, properties, seconds from analysis")[0]
    found["files"] = rows(con, """select role, path, left(sha256, 12) as sha256 from analysis_files
                                  where analysis_id = ? order by role <> 'properties', role <> 'interface', path""",
                          [found["analysis_id"]])
    found["stale"] = stale_files(con)
    return found


def changes(con) -> tuple[Table, ...]:
    """What the last analysis changed: verdict transitions and the changed cells of Tables II-IV
    (empty for a store judged before they were kept)."""
    if not set(CHANGES) <= _names(con):
        return tuple(Table(name, [], []) for name in CHANGES)
    return (query_table(con, "verdict_transitions", ordered(con, "verdict_transitions")),
            query_table(con, "table_changes", ordered(con, "table_changes") + ", paper_table"))


def suspicious(con) -> Table:
    return query_table(con, "suspicious", """
        select v.trace_id, t.sut, v.property_id, v.rqst_id, v.module, v.service, v.c_holds,
               v.verdict, v.margin_s
        from verdicts v join traces t using (trace_id)
        where v.suspicious order by v.trace_id, v.rqst_id, v.property_id""")


def bad_traces(con) -> Table:
    """Table II's bad traces (hung, with FN, with FP) and crashed runs, with their world events."""
    return query_table(con, "bad_traces", """
        with judged as (
            select t.trace_id, t.sut, t.outcome, t.script_id,
                   count(*) filter (where v.verdict = 'FN') as fn,
                   count(*) filter (where v.verdict = 'FP') as fp,
                   count(*) filter (where v.verdict = 'TP') as tp,
                   count(*) filter (where v.suspicious and v.verdict in ('FN', 'FP')) as suspicious
            from traces t left join verdicts v using (trace_id) group by all)
        select j.*, (select count(*) from world_events w where w.trace_id = j.trace_id) as world_events
        from judged j where outcome <> 'completed' or fn > 0 or fp > 0 order by trace_id""")


def bad_verdicts(con) -> Table:
    return query_table(con, "bad_trace_verdicts", """
        select v.trace_id, t.sut, t.outcome, v.property_id, v.family, v.rqst_id, v.module, v.service,
               v.c_holds, v.verdict, v.margin_s, v.suspicious
        from verdicts v join traces t using (trace_id)
        where v.verdict in ('FN', 'FP') order by v.trace_id, v.rqst_id, v.property_id""")


def family_traces(con) -> dict[tuple[str, str], list[dict]]:
    """Per (variant, family or All): the traces with a TP, FN or FP in that family, worst first."""
    found = rows(con, """
        select t.sut, coalesce(v.family, 'All') as family, v.trace_id, any_value(t.outcome) as outcome,
               count(*) filter (where v.verdict = 'FN') as fn, count(*) filter (where v.verdict = 'TP') as tp,
               count(*) filter (where v.verdict = 'FP') as fp, count(*) filter (where v.verdict = 'TN') as tn
        from verdicts v join traces t using (trace_id)
        group by grouping sets ((t.sut, v.family, v.trace_id), (t.sut, v.trace_id))
        having fn + tp + fp > 0
        order by fn desc, fp desc, tp desc, v.trace_id""")
    return _grouped(found, lambda r: (r["sut"], r["family"]))


def trace_details(con, ids: list[int]) -> list[dict]:
    """Everything a trace page shows, fetched for all pages at once."""
    wanted = "trace_id in (select unnest(?::integer[]))"
    traces = rows(con, f"""
        select t.*, s.kind as script_kind, s.body, s.mutations, s.parent, g.body as golden
        from traces t left join scripts s using (script_id)
        left join scripts g on g.campaign_id = t.campaign_id and g.kind = 'golden'
        where t.{wanted} order by t.trace_id""", [ids])
    events = _by_trace(rows(con, f"""
        select e.trace_id, e.seq, e.t, e.kind, e.rqst_id, e.module, e.service, e.args, e.reply, c.class
        from events e left join reply_codes c using (module, service, reply)
        where e.{wanted} order by e.trace_id, e.seq""", [ids]))
    # the analyzer's requests view pairs each request with its final reply as the oracles do
    requests = _by_trace(rows(con, f"""
        select r.trace_id, r.rqst_id, r.module, r.service, e.args, r.t as start, r.final_t as "end",
               r.reply, r.class as reply_class
        from requests r left join events e on e.trace_id = r.trace_id and e.seq = r.seq
        where r.{wanted} order by r.trace_id, r.t, r.seq""", [ids]))
    verdicts = _by_trace(rows(con, f"""
        select * from verdicts where {wanted} order by trace_id, rqst_id, property_id""", [ids]))
    world = _by_trace(rows(con, f"select * from world_events where {wanted} order by trace_id, t",
                           [ids]))
    for t in traces:
        i = t["trace_id"]
        t.update(events=events.get(i, []), verdicts=verdicts.get(i, []), world=world.get(i, []),
                 requests=[Request(**{k: v for k, v in r.items() if k != "trace_id"})
                           for r in requests.get(i, [])],
                 diff=_diff(t))
    return traces


def _grouped(found: list[dict], key) -> dict:
    grouped = defaultdict(list)
    for r in found:
        grouped[key(r)].append(r)
    return grouped


def _by_trace(found: list[dict]) -> dict[int, list[dict]]:
    return _grouped(found, lambda r: r["trace_id"])


def _steps(body: str) -> list[str]:
    """The script's step lines: mutants are re-rendered without the golden's comment lines."""
    return [line for line in body.splitlines() if line.strip() and not line.lstrip().startswith("#")]


def _diff(trace: dict) -> list[tuple[str, str]]:
    """The mutant's unified diff against the golden script, each line with its CSS class."""
    if trace["body"] is None or trace["golden"] is None or trace["script_kind"] == "golden":
        return []
    lines = difflib.unified_diff(_steps(trace["golden"]), _steps(trace["body"]), "golden.mission",
                                 f"script-{trace['script_id']}.mission", lineterm="")
    css = {"@": "hunk", "+": "add", "-": "del"}
    return [(css.get(line[:1], "same"), line) for line in lines]


def trace_ids(con, ids: list[int]) -> list[int]:
    return [r[0] for r in con.execute("select trace_id from traces where trace_id in "
                                      "(select unnest(?::integer[]))", [ids]).fetchall()]


def inversions(con) -> Table:
    return query_table(con, "inversions", """
        select t.sut, i.* from inversions i join traces t using (trace_id)
        order by i.trace_id, i.rqst_id, i.property_id""")


def shrunk(con) -> Table:
    """Every shrunk reproducer: the behaviour, the trace it was shrunk from, steps before and after."""
    return query_table(con, "shrunk_reproducers", """
        with records as (
            select script_id, body, unnest(from_json(mutations, '["json"]')) as r from scripts where kind = 'shrunk'
        )
        select script_id, r->>'sut' as sut, r->>'verdict' as verdict, r->>'property' as property_id,
               (r->>'trace')::integer as trace_id, (r->>'steps_before')::integer as steps_before,
               (r->>'steps_after')::integer as steps_after, (r->>'runs')::integer as runs, body
        from records order by script_id""")
