"""Analyzer speed: a campaign-sized store (~900 traces) should be judged in <= 3 s, and the
events judged per second are measured on a synthetic store of >= 10 million events.

The synthetic stores are built in SQL, set-based: every choice (service, timing, reply) is a
hash of (seed, trace, request), so the same seed gives the same store. They are judged with
the 21 Dala properties, exactly as `python -m harness analyze` does. Not a test:

    .venv/bin/python bench/analyzer_bench.py [--events 10000000] [--campaign reports/campaign.duckdb]
"""
from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from harness import DEFAULT_MISSION_DIR  # noqa: E402
from harness.analysis.analyzer import materialise  # noqa: E402
from harness.target.interface import load_interface, load_properties  # noqa: E402
from harness.store.database import add_campaign, add_reply_codes, connect, place  # noqa: E402

# Reply shares (percent, cumulative): mostly ok, some interruptions and rejections, some unanswered.
REPLIES = [(70, "ok"), (78, "interrupted"), (82, "interrupted_excl"), (87, "wait_init"),
           (92, "disallowed"), (95, "too_many_activities"), (98, "bad_params")]  # the rest: no final reply


def synthesise(con, interface, traces: int, requests: int, seed: int) -> int:
    """`traces` traces of `requests` requests each over the interface's services; returns the event count."""
    add_campaign(con, 1, "synthetic", seed, {"traces": traces, "requests": requests})
    add_reply_codes(con, interface)
    services = ", ".join(f"('{s.module}', '{s.name}')" for s in interface.services.values())
    replies = " ".join(f"when u_reply < {p} then '{code}'" for p, code in REPLIES)
    con.execute(f"""
        insert into traces (trace_id, campaign_id, sut, seed, outcome)
        select trace_id, 1, 'variant-' || (trace_id % 3), {seed}, 'completed' from range(1, {traces} + 1) r(trace_id)""")
    place(con, "variant_positions", "sut", [f"variant-{n % 3}" for n in range(1, 4)])  # as their first traces
    con.execute(f"""
        create temporary table synthetic_requests as
        with drawn as (
            select trace_id, rqst_id, hash({seed}, trace_id, rqst_id) as h
            from range(1, {traces} + 1) a(trace_id), range(1, {requests} + 1) b(rqst_id)
        ),
        services(position, module, service) as (
            select row_number() over () - 1, * from (values {services})
        )
        select d.trace_id, d.rqst_id, s.module, s.service,
               -- a request every 0.5 s with jitter; activities last up to 3 s, so they overlap
               d.rqst_id * 0.5 + (d.h >> 8) % 400 / 1000 as t,
               (d.h >> 20) % 3000 / 1000 as duration,
               case {replies.replace('u_reply', '(d.h >> 32) % 100')} end as reply
        from drawn d join services s on s.position = d.h % (select count(*) from services)""")
    con.execute("""
        insert into events (trace_id, seq, t, kind, rqst_id, module, service, args, reply)
        with logged as (
            select trace_id, t, 'request' as kind, rqst_id, module, service, null as reply from synthetic_requests
            union all
            select trace_id, t + duration, 'final', rqst_id, module, service, reply
            from synthetic_requests where reply is not null
        )
        select trace_id, row_number() over (partition by trace_id order by t, kind desc, rqst_id)::integer,
               t, kind, rqst_id, module, service, null, reply
        from logged""")
    con.execute("drop table synthetic_requests")
    return con.execute("select count(*) from events").fetchone()[0]


def judge(path: Path, properties) -> tuple[int, int, float]:
    con = connect(path)
    started = time.perf_counter()
    materialise(con, properties, 0.01, load_interface(DEFAULT_MISSION_DIR / "interface.toml"))
    elapsed = time.perf_counter() - started
    traces, events = con.execute("select (select count(*) from traces), (select count(*) from events)").fetchone()
    con.close()
    return traces, events, elapsed


def report(what: str, traces: int, events: int, elapsed: float, limit: float | None = None) -> None:
    verdict = "" if limit is None else ("  (<= %.0f s: %s)" % (limit, "yes" if elapsed <= limit else "NO"))
    print(f"{what}: {traces:,} traces, {events:,} events judged in {elapsed:.2f} s "
          f"= {events / elapsed:,.0f} events/s{verdict}")


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--events", type=int, default=10_000_000, help="size of the large store (default: %(default)s)")
    p.add_argument("--seed", type=int, default=2012)
    p.add_argument("--campaign", help="also time a copy of this real campaign store")
    args = p.parse_args()
    interface = load_interface(DEFAULT_MISSION_DIR / "interface.toml")
    properties = load_properties(DEFAULT_MISSION_DIR / "properties.toml", interface)
    with tempfile.TemporaryDirectory() as tmp:
        if args.campaign:
            copy = Path(tmp) / "campaign.duckdb"
            shutil.copy(args.campaign, copy)
            report("real campaign", *judge(copy, properties), limit=3)
        # ~900 traces shaped like the golden mission's (~30 requests, ~60 events each)
        small = Path(tmp) / "small.duckdb"
        con = connect(small)
        synthesise(con, interface, 900, 30, args.seed)
        con.close()
        report("campaign-sized store", *judge(small, properties), limit=3)
        big = Path(tmp) / "big.duckdb"
        con = connect(big)
        started = time.perf_counter()
        requests = 100
        events = synthesise(con, interface, -(-args.events // (2 * requests) * 100 // 98), requests, args.seed)
        con.close()
        print(f"(built the large store, {events:,} events, in {time.perf_counter() - started:.1f} s)")
        report("large store", *judge(big, properties))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
