"""`python -m harness export --format parquet|csv DIR`: every table and view of the store as files,
for the tools that are not DuckDB (Polars, pandas, Spark, a spreadsheet).

One file per table or view, `DIR/NAME.parquet` or `DIR/NAME.csv` (with a header row), rows in the
order the report shows them, all read in one snapshot of the store. `DIR/manifest.json` names the
store, its schema version, the export time and, per table or view, its kind, file and row count.
Exporting again into the same folder first removes the files of the previous export: only the
NAME.parquet or NAME.csv files its manifest lists in the folder itself, never anything else.

An export's events file imports back (`python -m harness import DIR/events.parquet`); the traces
file beside it gives each trace its sut and outcome, so hung and crashed traces stay so.
"""
from __future__ import annotations

import json
from collections import Counter
from datetime import datetime, timezone
from pathlib import Path

import duckdb
import pyarrow as pa

from harness.store.reads import ordered
from harness.errors import StoreError
from harness.files import make_folder
from harness.store.database import connect, schema_version, snapshot
from harness.store.sql import sql_literal

FORMATS = {"parquet": "(format parquet)", "csv": "(format csv, header)"}
MANIFEST = "manifest.json"


def relations(con) -> list[tuple[str, str]]:
    """Every table and view of the store, by name: (name, 'table' or 'view')."""
    return con.execute("""select table_name, if(table_type = 'VIEW', 'view', 'table')
                          from information_schema.tables
                          where table_catalog = current_database() and table_schema = 'main'
                          order by table_name""").fetchall()


def _ours(out: Path, name: object) -> bool:
    """Whether `name` is a file an export writes in `out`: NAME.parquet or NAME.csv in the folder
    itself, a plain file or none (never a link, a folder, a path that leaves the folder)."""
    if not isinstance(name, str) or Path(name).name != name or Path(name).suffix not in (".parquet", ".csv"):
        return False
    path = out / name
    return not path.is_symlink() and (path.is_file() or not path.exists())


def _clear_previous(out: Path) -> None:
    """Remove an earlier export's files from `out`; a folder holding anything else is refused.
    A manifest is a file of the user's folder, never trusted: only plain NAME.parquet and NAME.csv
    files of `out` itself are ever removed, whatever it names (`../store.duckdb`, `.`, a link)."""
    if not out.exists():
        return
    if not out.is_dir():
        raise StoreError(f"cannot export to {str(out)!r}: it is a file; give a folder")
    manifest = out / MANIFEST
    try:
        previous = json.loads(manifest.read_text())["tables"] if manifest.is_file() else []
        named = [entry["file"] for entry in previous]
    except (ValueError, KeyError, TypeError):
        raise StoreError(f"{str(manifest)!r} is not the manifest of an export; "
                         f"export to a new or empty folder") from None
    foreign = [n for n in named if not _ours(out, n)] + ([MANIFEST] if manifest.is_symlink() else [])
    if foreign:
        raise StoreError(f"cannot export to {str(out)!r}: {MANIFEST} names {foreign[0]!r}, which is no file an "
                         "export writes (NAME.parquet or NAME.csv in the folder itself, no link); nothing was "
                         "removed: export to a new or empty folder")
    files = {out / name for name in named} | {manifest}
    others = sorted(p.name for p in out.iterdir() if p not in files)
    if others:
        raise StoreError(f"cannot export to {str(out)!r}: it holds {others[0]!r}, which no earlier export "
                         f"wrote; export to a new or empty folder")
    for path in files:
        path.unlink(missing_ok=True)


def _as_text_json(con, name: str) -> str:
    """The query of a table or view in the report's order, its JSON columns as plain text: in
    Parquet, DuckDB's JSON type is bytes to readers that do not know it (Polars, Spark)."""
    json_columns = [r[0] for r in con.execute(f"describe {name}").fetchall() if r[1] == "JSON"]
    if not json_columns:
        return ordered(con, name)
    return (f"select * replace ({', '.join(f'{c}::varchar as {c}' for c in json_columns)}) "
            f"from ({ordered(con, name)})")


def export(con, store: str | Path, out: Path, fmt: str) -> dict:
    """Write every table and view of `con` under `out` in `fmt`, then the manifest; returns it."""
    _clear_previous(out)
    make_folder(out, "the export")
    entries = []
    try:
        with snapshot(con):
            for name, kind in relations(con):
                file = out / f"{name}.{fmt}"
                query = _as_text_json(con, name)
                rows = con.execute(f"copy ({query}) to {sql_literal(file)} {FORMATS[fmt]}").fetchone()[0]
                entries.append({"name": name, "kind": kind, "file": file.name, "rows": rows})
            version = schema_version(con)
    except duckdb.Error as e:
        raise StoreError(f"cannot export the store {str(store)!r} to {str(out)!r}: {e}; the store is only read "
                         "and unchanged: free space or pass another folder") from None
    manifest = {"store": str(Path(store).resolve()), "schema_version": version, "format": fmt,
                "exported_at": datetime.now(timezone.utc).isoformat(timespec="seconds"), "tables": entries}
    try:
        (out / MANIFEST).write_text(json.dumps(manifest, indent=2) + "\n")
    except OSError as e:
        raise StoreError(f"cannot write {str(out / MANIFEST)!r}: {e.strerror}; free space or pass another "
                         "folder") from None
    return manifest


def with_exported_traces(path: Path, events: pa.Table) -> pa.Table:
    """An export's events file (text columns, as the importer reads it) with the sut and outcome of
    each trace from the traces file beside it; any other file is returned unchanged."""
    traces = path.with_name("traces" + path.suffix)
    if (path.stem != "events" or not (path.parent / MANIFEST).is_file() or not traces.is_file()
            or {"sut", "outcome"} & set(events.column_names)):
        return events
    reader = "read_parquet" if path.suffix == ".parquet" else "read_csv"
    con = duckdb.connect()
    try:
        known = con.sql(f"select trace_id::varchar as trace_id, sut, outcome "
                        f"from {reader}({sql_literal(traces)})").to_arrow_table()
    except duckdb.Error as e:
        raise StoreError(f"cannot read {str(traces)!r}, the traces of the export {str(path)!r}: {e}") from None
    finally:
        con.close()
    twice = [t for t, n in Counter(known.column("trace_id").to_pylist()).items() if n > 1]
    if twice:  # else every event of that trace would be doubled, and blamed on the events file
        raise StoreError(f"{str(traces)!r} lists the trace {twice[0]!r} twice; an export lists each trace once: "
                         "keep one row per trace_id, or import the events file alone")
    return events.join(known, "trace_id", join_type="left outer").sort_by("line")


def main(db: str, folder: str, format: str = "parquet") -> int:
    out = Path(folder)
    con = connect(db, read_only=True)
    try:
        manifest = export(con, db, out, format)
    finally:
        con.close()
    rows = sum(entry["rows"] for entry in manifest["tables"])
    print(f"Exported {len(manifest['tables'])} tables and views ({rows} rows) of {db} to {out} "
          f"as {format}; {out / MANIFEST} lists them.")
    return 0
