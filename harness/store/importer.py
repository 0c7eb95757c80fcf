"""Traces from elsewhere into the store (`import`, docs/reference/store.md; the command is
harness/campaign/importing.py).

The file (CSV, JSON lines or Parquet) holds the events columns, one event per row, plus
optionally `outcome` and `sut` per trace. Every row is checked against the interface first;
bad rows are reported with their line and value and nothing is written. Then one transaction
adds a campaign (mission = the file, seed 0), the traces (integer ids; the file's own trace
name kept as traces.label) and their events. ROS bags reach the store as the same rows (`ImportRows`,
parsed by harness/sut/bags: one trace per bag) and are checked alike; their header stamps, the
SUT's own clock, go to internal_events.
"""
from __future__ import annotations

import hashlib
from pathlib import Path
from typing import NamedTuple

import duckdb
import pyarrow as pa

from harness.errors import InputFileError
from harness.store.event_files import REQUIRED, read
from harness.files import read_bytes
from harness.target.interface import Interface
from harness.store.appends import append, transaction
from harness.store.database import add_campaign, add_reply_codes, next_id, place
from harness.store.record import ImportRecord, records
from harness.trace import OUTCOMES

SHOWN = 10  # problems listed in one error message
MAX_T_S = 1e9  # a trace's times are seconds since it started: beyond this the file is not one

# (column, condition on the raw text of a row, what is wrong) - checked before anything else.
ROW_CHECKS = [(c, f"nullif(trim({c}), '') is null", "every event needs one") for c in REQUIRED] + [
    ("seq", "try_cast(seq as hugeint) is null", "is not an integer; number each trace's events 1, 2, 3..."),
    ("rqst_id", "try_cast(rqst_id as hugeint) is null", "is not an integer request id"),
    *((c, f"try_cast({c} as hugeint) is not null and try_cast({c} as integer) is null",
       f"is out of range: the store keeps {c} as a 32-bit integer (at most 2147483647); renumber them")
      for c in ("seq", "rqst_id")),
    ("t", "not isfinite(coalesce(try_cast(t as double), 'nan'))", "is not a time in seconds"),
    ("t", f"abs(try_cast(t as double)) > {MAX_T_S:g}",
     f"is not a time in seconds since the trace started (at most {MAX_T_S:g} s, about 31 years)"),
    ("kind", "kind not in ('request', 'intermediate', 'final')", "is not one of request, intermediate, final"),
    ("module", "module not in (select module from known_services)", "is not a module of the interface"),
    ("service", "module in (select module from known_services) and (module, service) not in "
                "(select (module, service) from known_services)", "is not a service of that module"),
    ("reply", "kind = 'final' and reply is null", "a final reply needs its reply code"),
    ("reply", "kind = 'final' and reply not in (select reply from known_replies)",
     "is not in the reply catalogue of the interface"),
    ("reply", "kind = 'request' and reply is not null", "is not allowed on a request; leave reply empty"),
    ("args", "args is not null and not coalesce(json_valid(args), false)", "is not JSON"),
    # JSON has no NaN or Infinity (DuckDB accepts them); string literals are removed first
    ("args", r"""regexp_matches(regexp_replace(args, '"(\\.|[^"\\])*"', '', 'g'), '\b(NaN|Infinity)\b')""",
     "holds NaN or Infinity, which are no JSON numbers; give finite argument values"),
    ("outcome", f"outcome not in {OUTCOMES}", f"is not one of {', '.join(OUTCOMES)}"),
]

# Checks across the rows of a trace, on typed rows in file order; each gives (line, problem).
ORDER_CHECKS = """
with typed as (
    select line, trace_id, seq::integer as seq, t::double as t, kind, rqst_id::integer as rqst_id,
           module, service, outcome, sut
    from staged
),
placed as (
    select *, lag(seq) over w as prev_seq, lag(t) over w as prev_t, lag(line) over w as prev_line,
           count(*) filter (where kind = 'request') over (partition by trace_id, rqst_id order by line)
               as requests_so_far,
           count(*) filter (where kind = 'final') over (partition by trace_id, rqst_id order by line)
               as finals_so_far,
           first(case when kind = 'request' then module || '.' || service end ignore nulls)
               over (partition by trace_id, rqst_id order by line) as requested,
           count(distinct outcome) over (partition by trace_id) as outcomes,
           count(distinct sut) over (partition by trace_id) as suts
    from typed
    window w as (partition by trace_id order by line)
)
select line, format('seq = {} does not increase after seq = {} (line {}) in trace ''{}''',
                    seq, prev_seq, prev_line, trace_id) from placed where seq <= prev_seq
union all
select line, format('t = {} goes backwards from t = {} (line {}) in trace ''{}''', t, prev_t, prev_line, trace_id)
from placed where t < prev_t
union all
select line, format('request {} of trace ''{}'' is sent a second time', rqst_id, trace_id)
from placed where kind = 'request' and requests_so_far > 1
union all
select line, format('{} reply to request {} of trace ''{}'' comes without an earlier request',
                    kind, rqst_id, trace_id)
from placed where kind <> 'request' and requests_so_far = 0
union all
select line, format('{} reply names {}.{} but request {} of trace ''{}'' is {}',
                    kind, module, service, rqst_id, trace_id, requested)
from placed where kind <> 'request' and requested <> module || '.' || service
union all
select line, format('request {} of trace ''{}'' gets a second final reply', rqst_id, trace_id)
from placed where kind = 'final' and finals_so_far > 1
union all
select min(line), format('trace ''{}'' has several outcomes or suts; give one per trace', trace_id)
from placed where outcomes > 1 or suts > 1 group by trace_id
"""


def problems(con) -> list[tuple[int, str]]:
    """The bad rows of the registered `staged` table, up to SHOWN per check: (line, what is wrong)."""
    found = []
    for column, condition, advice in ROW_CHECKS:
        for line, value in con.execute(f"select line, {column} from staged where {condition} "
                                       f"order by line limit {SHOWN}").fetchall():
            found.append((line, f"{column} = {value!r} {advice}" if value and value.strip()
                          else f"{column} is empty: {advice}"))
    if not found:  # order checks need well-typed rows
        found = con.execute(f"select * from ({ORDER_CHECKS}) order by 1 limit {SHOWN}").fetchall()
    return sorted(found)


def _refuse(path: Path, unit: str, found: list[tuple[int, str]], interface: Interface) -> None:
    (line, problem), rest = found[0], found[1:SHOWN]
    more = "".join(f"\n{path}:{unit} {n}: {p}" for n, p in rest)
    raise InputFileError(path, f"{unit} {line}", f"{problem}{more}\nnothing was imported; fix the file "
                         f"(checked against the interface {interface.path}) and retry")


def _refuse_a_second_import(con, path: Path, digest: str) -> None:
    same = [i for i, _, r in records(con, ImportRecord) if r.sha256 == digest]
    earlier = con.execute("""select c.campaign_id, c.created_at, min(t.trace_id), max(t.trace_id)
                             from campaigns c join traces t using (campaign_id)
                             where c.campaign_id = ? group by all""", [same[0]]).fetchone() if same else None
    if earlier:
        campaign_id, created, first, last = earlier
        raise InputFileError(path, "", f"these events were already imported on {created:%Y-%m-%d %H:%M} as "
                             f"campaign {campaign_id} (trace ids {first}-{last}); nothing was imported. "
                             "To judge them again run analyze; to keep two copies use another --db")


def _digest(path: Path) -> str:
    """SHA-256 of the file, or of every file in a folder (a rosbag2 bag, a folder of bags), by name."""
    files = sorted(p for p in path.rglob("*") if p.is_file()) if path.is_dir() else [path]
    sha = hashlib.sha256()
    for file in files:
        sha.update(str(file.relative_to(path) if path.is_dir() else "").encode() + file.read_bytes())
    return sha.hexdigest()


def load(con, path: Path, interface: Interface, sut_clock: bool = False) -> tuple[int, int, int]:
    """Campaign, traces and events in one transaction: (campaign_id, first trace id, traces); with
    `sut_clock`, the registered `sut_clock` rows too, as internal_events. A file whose contents
    the store already holds is refused (the campaign records its SHA-256)."""
    digest = _digest(path)
    with transaction(con):
        _refuse_a_second_import(con, path, digest)
        campaign_id = next_id(con, "campaigns", "campaign_id")
        add_campaign(con, campaign_id, str(path), 0, ImportRecord(imported=str(path), interface=interface.path,
                                                                  sha256=digest))
        add_reply_codes(con, interface)
        first = next_id(con, "traces", "trace_id")
        con.execute("""create temporary table imported_ids as
                       select trace_id as label, ? - 1 + row_number() over (order by min(line)) as id,
                              coalesce(any_value(sut), ?) as sut, coalesce(any_value(outcome), 'completed') as outcome,
                              max(t::double) as sim_s
                       from staged group by trace_id""", [first, path.stem])
        append(con, "traces", con.sql("""select id as trace_id, ? as campaign_id, sut, outcome, sim_s, label
                                         from imported_ids order by id""", params=[campaign_id]))
        place(con, "variant_positions", "sut",
              [r[0] for r in con.execute("select sut from imported_ids group by sut order by min(id)").fetchall()])
        append(con, "events", _events(con, "staged"))
        if sut_clock:
            append(con, "internal_events", _events(con, "sut_clock"))
        count = con.execute("select count(*) from imported_ids").fetchone()[0]
        con.execute("drop table imported_ids")
    return campaign_id, first, count


def _events(con, staged: str) -> duckdb.DuckDBPyRelation:
    """The typed events of the registered table `staged`, under their traces' new ids."""
    return con.sql(f"""select i.id as trace_id, s.seq::integer as seq, s.t::double as t, s.kind,
                              s.rqst_id::integer as rqst_id, s.module, s.service, s.args::json as args, s.reply
                       from {staged} s join imported_ids i on i.label = s.trace_id order by i.id, s.line""")


class ImportRows(NamedTuple):
    """What the store receives to import: the events as text columns (REQUIRED and OPTIONAL) plus
    `line`, what a line is called in messages, and the events on the SUT's own clock (bags) or None."""
    events: pa.Table
    unit: str
    sut_clock: pa.Table | None = None


def import_file(con, path: str | Path, interface: Interface) -> tuple[int, int, int]:
    """Events from a file of events (CSV, JSON lines, Parquet)."""
    path = Path(path)
    return import_rows(con, path, interface, ImportRows(*read(path)))


def import_rows(con, path: Path, interface: Interface, rows: ImportRows) -> tuple[int, int, int]:
    """The rows read from `path`, checked against the interface, then stored as one campaign:
    (campaign_id, first trace id, traces)."""
    sut_clock = rows.sut_clock
    known = {"staged": rows.events, **({"sut_clock": sut_clock} if sut_clock is not None else {}),
             "known_services": pa.table({"module": [s.module for s in interface.services.values()],
                                         "service": [s.name for s in interface.services.values()]}),
             "known_replies": pa.table({"reply": list(interface.replies)})}
    cursor = con.cursor()  # its own connection to the store: the registered tables stay local to it
    for name, relation in known.items():
        cursor.register(name, relation)
    try:
        found = problems(cursor)
        if found:
            _refuse(path, rows.unit, found, interface)
        return load(cursor, path, interface, sut_clock is not None)
    except duckdb.Error as e:
        raise InputFileError(path, "", f"cannot import: {e}") from None
    finally:
        cursor.close()
