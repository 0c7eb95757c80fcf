"""Reading a file of events to import (CSV, JSON lines or Parquet; an `export` folder's events
too) into one Arrow table of text columns, each row with its line: harness/store/importer.py then
checks the rows and stores them."""
from __future__ import annotations

import csv
import io
import json
from pathlib import Path

import pyarrow as pa
import pyarrow.csv as pacsv
import pyarrow.parquet as pq

from harness.errors import InputFileError
from harness.files import read_bytes, read_text
from harness.schema import cut
from harness.store.export import with_exported_traces
from harness.trace import IMPORTED_COLUMNS

OPTIONAL = ("args", "reply", "outcome", "sut")
REQUIRED = tuple(c for c in IMPORTED_COLUMNS if c not in OPTIONAL)


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
