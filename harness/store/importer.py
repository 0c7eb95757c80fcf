"""Traces from elsewhere into the store (`import`, docs/reference/store.md; the command is
harness/campaign/importing.py).

The file (CSV, JSON lines or Parquet) holds the events columns, one event per row, plus
optionally `outcome` and `sut` per trace. Every row is checked against the interface first;
bad rows are reported with their line and value and nothing is written. Then one transaction
adds a campaign (mission = the file, seed 0), the traces (integer ids; the file's own trace
name kept as traces.label) and their events. ROS bags reach the store as the same rows (`Rows`,
parsed by harness/sut/bags: one trace per bag) and are checked alike; their header stamps, the
SUT's own clock, go to internal_events.
"""
from __future__ import annotations

import csv
import hashlib
import io
import json
from pathlib import Path
from typing import NamedTuple

import duckdb
import pyarrow as pa
import pyarrow.csv as pacsv
import pyarrow.parquet as pq

from harness.errors import InputFileError
from harness.store.export import with_exported_traces
from harness.files import read_bytes, read_text
from harness.schema import cut
from harness.target.interface import Interface
from harness.store.appends import append, transaction
from harness.store.database import add_campaign, add_reply_codes, next_id, place
from harness.store.record import ImportRecord, records
from harness.trace import OUTCOMES

REQUIRED = ("trace_id", "seq", "t", "kind", "rqst_id", "module", "service")
OPTIONAL = ("args", "reply", "outcome", "sut")
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


def _text(value) -> str | None:
    if value is None or isinstance(value, str):
        return value
    return json.dumps(value, allow_nan=False) if isinstance(value, (dict, list)) else str(value)


def _column(path: Path, name: str, values: list, unit: str, lines: list[int]) -> pa.Array:
    """A column's values as text; a value JSON cannot hold (a timestamp, bytes) is refused naming its line."""
    texts = []
    for n, value in zip(lines, values):
        try:
            texts.append(_text(value))
        except (TypeError, ValueError) as e:
            raise InputFileError(path, f"{unit} {n}", f"{name} holds {cut(value)}, which is no JSON value ({e}); "
                                 "give arguments as numbers, strings, lists or objects") from None
    return pa.array(texts, pa.string())


def _read_jsonl(path: Path) -> tuple[pa.Table, str]:
    rows, lines = [], []
    for n, line in enumerate(read_text(path).split("\n"), 1):  # a JSON string may hold U+2028
        if not line.strip():
            continue
        try:
            row = json.loads(line)
        except json.JSONDecodeError as e:
            raise InputFileError(path, f"line {n}", f"not valid JSON ({e.msg}); write one event object per line") from None
        except RecursionError:
            raise InputFileError(path, f"line {n}", "JSON nested too deeply to be an event; write one flat event "
                                 "object per line") from None
        if not isinstance(row, dict):
            raise InputFileError(path, f"line {n}", f"{line.strip()[:60]!r} is not a JSON object of the events columns")
        rows.append(row)
        lines.append(n)
    names = list(dict.fromkeys(k for row in rows for k in row))
    columns = {k: _column(path, k, [row.get(k) for row in rows], "line", lines) for k in names}
    return pa.table({"line": pa.array(lines, pa.int64()), **columns}), "line"


def _read_csv(path: Path) -> tuple[pa.Table, str]:
    header = next(csv.reader(io.StringIO(read_text(path), newline="")), [])
    twice = sorted({name for name in header if header.count(name) > 1})
    if twice:
        raise InputFileError(path, 1, f"the header names the column {cut(twice[0])} twice; keep one")
    try:
        table = pacsv.read_csv(path, convert_options=pacsv.ConvertOptions(
            column_types={name: pa.string() for name in header}, strings_can_be_null=True))
    except (pa.ArrowInvalid, ValueError) as e:
        raise InputFileError(path, "", f"not valid CSV: {e}") from None
    # Line 1 is the header; quoted values must not span lines for these numbers to hold.
    return table.add_column(0, "line", pa.array(range(2, table.num_rows + 2), pa.int64())), "line"


def _read_parquet(path: Path) -> tuple[pa.Table, str]:
    try:
        table = pq.read_table(path)
    except (pa.ArrowInvalid, OSError) as e:
        raise InputFileError(path, "", f"not a readable Parquet file: {e}") from None
    rows = list(range(1, table.num_rows + 1))
    columns = {name: _column(path, name, table.column(name).to_pylist(), "row", rows) for name in table.column_names}
    return pa.table({"line": pa.array(rows, pa.int64()), **columns}), "row"


READERS = {".csv": _read_csv, ".jsonl": _read_jsonl, ".ndjson": _read_jsonl, ".parquet": _read_parquet}


def read(path: Path) -> tuple[pa.Table, str]:
    """The file's rows as text columns (all of REQUIRED and OPTIONAL) plus `line`, and what a line is called."""
    if not path.is_file():  # missing, a folder or a symbolic link that loops: say which
        read_bytes(path, "file not found; pass an existing .csv, .jsonl or .parquet file")
    reader = READERS.get(path.suffix.lower())
    if reader is None:
        raise InputFileError(path, "", f"unknown format {path.suffix!r}; use .csv, .jsonl (JSON lines) or .parquet")
    table, unit = reader(path)
    table = with_exported_traces(path, table)
    missing = [c for c in REQUIRED if c not in table.column_names]
    if missing:
        raise InputFileError(path, "columns", f"missing {', '.join(missing)}; the events columns are "
                             f"{', '.join(REQUIRED + OPTIONAL)} (the last four optional)")
    if table.num_rows == 0:
        raise InputFileError(path, "", "no events; nothing to import")
    for name in OPTIONAL:
        if name not in table.column_names:
            table = table.append_column(name, pa.nulls(table.num_rows, pa.string()))
    return table.select(["line", *REQUIRED, *OPTIONAL]), unit


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


class Rows(NamedTuple):
    """What the store receives to import: the events as text columns (REQUIRED and OPTIONAL) plus
    `line`, what a line is called in messages, and the events on the SUT's own clock (bags) or None."""
    events: pa.Table
    unit: str
    sut_clock: pa.Table | None = None


def import_file(con, path: str | Path, interface: Interface) -> tuple[int, int, int]:
    """Events from a file of events (CSV, JSON lines, Parquet)."""
    path = Path(path)
    return import_rows(con, path, interface, Rows(*read(path)))


def import_rows(con, path: Path, interface: Interface, rows: Rows) -> tuple[int, int, int]:
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
