"""Stores open in the DuckDB 1.x clients people have, and stores of earlier benches open in this one."""
from __future__ import annotations

import gzip
import hashlib
import json
import shutil
import subprocess
import sys
from pathlib import Path

import pyarrow as pa
import pytest

from harness import cli, store
from harness.store.reads import ordered
from harness.errors import StoreError
from harness.store.export import relations
from tests.support.paths import STORES

# Written by main at 58d696f, before schema versions, in DuckDB 2.0's own storage format:
# campaign --mutants 3 --sut reference,genom --seed 2012 --jobs 1.
SCHEMA0_STORE = STORES / "schema0-main-58d696f.duckdb.gz"
POSITIONS = ("variant_positions", "module_positions", "property_positions", "family_positions")
V1_FORMAT = "v1.0.0+"  # storage version 64: DuckDB 1.0 and 1.1 write it, every later version reads it
DUCKDB_CLI = Path(sys.executable).parent / "duckdb"  # PyPI's duckdb-cli, a dev dependency


def duckdb_cli(path: Path, sql: str, mode: str = "-json") -> str:
    if not DUCKDB_CLI.exists():
        pytest.fail(f"no DuckDB command-line client at {DUCKDB_CLI}; pip install -e '.[dev]' installs it")
    done = subprocess.run([str(DUCKDB_CLI), "-readonly", mode, str(path), sql],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and not done.stderr, done.stderr
    return done.stdout


def contents(path: Path) -> dict[str, pa.Table]:
    """Every table and view of a store, its rows in the report's order, as this bench reads them."""
    con = store.connect(path, read_only=True)
    try:
        return {name: con.sql(ordered(con, name)).to_arrow_table() for name, _ in relations(con)}
    finally:
        con.close()


def storage_format(path: Path) -> str:
    """DuckDB's name of a store's storage format: the first DuckDB version that writes it."""
    con = store.connect(path, read_only=True)
    try:
        return con.execute("select tags['storage_version'] from duckdb_databases() "
                           "where database_name = current_database()").fetchone()[0]
    finally:
        con.close()


def assert_a_1x_client_reads_every_table_and_view(path: Path) -> None:
    version = subprocess.run([str(DUCKDB_CLI), "--version"], capture_output=True, text=True).stdout
    assert version.startswith("v1.5."), version
    expected = {name: table.num_rows for name, table in contents(path).items()}
    counts = " union all ".join(f"select '{name}' as name, count(*) as n from {name}" for name in expected)
    found = {row["name"]: row["n"] for row in json.loads(duckdb_cli(path, counts))}
    assert found == expected
    for view in ("trace_robustness", "tp_rates", "fp_rates"):
        con = store.connect(path, read_only=True)
        query = ordered(con, view)
        cursor = con.execute(query)
        columns, rows = [d[0] for d in cursor.description], cursor.fetchall()
        con.close()
        assert json.loads(duckdb_cli(path, query)) == [dict(zip(columns, row)) for row in rows]


@pytest.fixture
def schema0_store(tmp_path) -> Path:
    path = tmp_path / "old.duckdb"
    with gzip.open(SCHEMA0_STORE) as packed, open(path, "wb") as plain:
        shutil.copyfileobj(packed, plain)
    return path


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.mark.slow
def test_the_duckdb_1_5_client_reads_every_table_and_view_of_a_campaign_store(campaign_store):
    assert storage_format(campaign_store) == V1_FORMAT
    assert {"verdicts", "trace_robustness", "tp_rates", "fp_rates", "inversions", "events"} <= set(
        contents(campaign_store))
    assert_a_1x_client_reads_every_table_and_view(campaign_store)


def test_a_new_store_records_its_schema_version_once(tmp_path):
    path = tmp_path / "new.duckdb"
    store.connect(path).close()
    con = store.connect(path)
    assert store.schema_version(con) == store.SCHEMA_VERSION == 3
    assert con.execute("select version, note from schema_version").fetchall() == [(3, "created")]


def test_a_store_from_before_schema_versions_is_read_as_is_without_writing_it(schema0_store, tmp_path):
    before = digest(schema0_store)
    con = store.connect(schema0_store, read_only=True)
    assert store.schema_version(con) == 0
    assert con.execute(ordered(con, "trace_robustness")).fetchall() == [
        ("reference", 4, 0, 0, 0, 0, 0, 1.0), ("genom", 4, 0, 0, 2, 0, 2, 0.5)]
    con.close()
    assert cli.main(["report", "--db", str(schema0_store), "--out", str(tmp_path / "report")]) == 0
    assert cli.main(["export", "--db", str(schema0_store), str(tmp_path / "export")]) == 0
    assert json.loads((tmp_path / "export" / "manifest.json").read_text())["schema_version"] == 0
    assert digest(schema0_store) == before
    assert storage_format(schema0_store) == "v2.0.0+", "the fixture is in the format 1.x clients refuse"


def read_positions(path: Path) -> dict[str, list[dict]]:
    """The order of variants, modules, properties and families as the store gives it (temporary
    views on an old store)."""
    con = store.connect(path, read_only=True)
    try:
        return {name: con.sql(f"select * from {name} order by position").to_arrow_table().to_pylist()
                for name in POSITIONS}
    finally:
        con.close()


def test_writing_to_it_migrates_it_for_1x_clients_and_keeps_the_original(schema0_store, capsys):
    original, read_before = contents(schema0_store), read_positions(schema0_store)
    before = digest(schema0_store)
    store.connect(schema0_store).close()
    backup = schema0_store.with_name("old.schema0.duckdb")
    assert capsys.readouterr().err == (
        f"migrated the store {str(schema0_store)!r} from schema version 0 to 3: rewritten in the storage "
        f"format of DuckDB v1.1.0, which DuckDB clients from v1.1.0 on open; the original is kept as "
        f"{str(backup)!r} (delete it when you no longer need it)\n")
    assert digest(backup) == before
    migrated = contents(schema0_store)
    versions = migrated.pop("schema_version").select(["version", "note"]).to_pylist()
    assert versions == [{"version": 3, "note": "migrated from schema version 0"}]
    positions = {name: sorted(migrated.pop(name).to_pylist(), key=lambda r: r["position"])
                 for name in POSITIONS}
    assert positions == read_before, "the order the original was read in, kept as data"
    assert [r["sut"] for r in positions["variant_positions"]] == ["reference", "genom"]
    assert [r["family"] for r in positions["family_positions"]][-1] == "All"
    added = {name: migrated.pop(name) for name in set(migrated) - set(original)}
    fresh = {r[0] for r in store.connect().execute("select table_name from duckdb_tables()").fetchall()}
    assert set(added) <= fresh and all(t.num_rows == 0 for t in added.values()), "new tables of the schema"
    assert migrated == original
    assert storage_format(schema0_store) == V1_FORMAT
    assert_a_1x_client_reads_every_table_and_view(schema0_store)
    store.connect(schema0_store).close()
    assert capsys.readouterr().err == "", "a migrated store is not migrated again"


def test_migration_never_overwrites_a_kept_original(schema0_store):
    taken = schema0_store.with_name("old.schema0.duckdb")
    taken.write_text("someone's file")
    before = digest(schema0_store)
    with pytest.raises(StoreError, match=r"cannot migrate the store '.*old.duckdb': '.*old.schema0.duckdb', "
                                         r"where its original would be kept, already exists; move that file"):
        store.connect(schema0_store)
    assert digest(schema0_store) == before and taken.read_text() == "someone's file"


def test_a_store_from_a_newer_bench_is_refused_not_misread(tmp_path):
    path = tmp_path / "future.duckdb"
    con = store.connect(path)
    con.execute("insert into schema_version (version, applied_at, note) values (4, now()::timestamp, 'a later layout')")
    con.close()
    for read_only in (True, False):
        with pytest.raises(StoreError, match=r"the store '.*future.duckdb' has schema version 4, written by a "
                                             r"newer Untimely than this one \(schema version 3\); update the bench"):
            store.connect(path, read_only=read_only)



def test_a_schema_1_store_gains_the_analyses_tables_when_written(tmp_path):
    path = tmp_path / "v1.duckdb"
    con = store.connect(path)
    con.execute("drop table analyses; drop table analysis_files; delete from schema_version")
    con.execute("insert into schema_version (version, applied_at, note) values (1, now()::timestamp, 'created')")
    con.close()
    con = store.connect(path)
    assert con.execute("select version, note from schema_version order by version").fetchall() == [
        (1, "created"), (3, "migrated from schema version 1")]
    assert con.execute("select count(*) from analyses").fetchone()[0] == 0
    assert con.execute("select count(*) from analysis_files").fetchone()[0] == 0


def test_a_schema_2_store_is_read_in_its_order_and_keeps_it_when_migrated(campaign_store, tmp_path):
    path = tmp_path / "v2.duckdb"
    shutil.copy(campaign_store, path)
    con = store.connect(path, read_only=True)
    expected = {view: con.execute(ordered(con, view)).fetchall() for view in ("trace_robustness", "tp_rates")}
    expected_order = read_positions(path)
    con.close()
    con = store.connect(path)  # as the bench of schema version 2 left it: no positions
    con.execute("drop table variant_positions; drop table module_positions; drop view family_positions; "
                "drop view property_positions; alter table properties drop column position; "
                "delete from schema_version; insert into schema_version (version, applied_at, note) "
                "values (2, now()::timestamp, 'created')")
    con.close()
    con = store.connect(path, read_only=True)
    assert {view: con.execute(ordered(con, view)).fetchall() for view in expected} == expected
    assert [r[0] for r in con.execute("select sut from variant_positions order by position").fetchall()] == [
        "genom", "bip-a"]
    assert {r[0] for r in con.execute("select view_name from duckdb_views() where temporary and not internal")
            .fetchall()} == set(POSITIONS), "derived for reading, the file untouched"
    con.close()
    assert read_positions(path) == expected_order
    store.connect(path).close()
    con = store.connect(path, read_only=True)
    assert con.execute("select version, note from schema_version order by version").fetchall() == [
        (2, "created"), (3, "migrated from schema version 2")]
    assert con.execute("select count(*) from duckdb_views() where temporary and not internal").fetchone()[0] == 0, \
        "the migrated store holds its positions itself"
    con.close()
    assert read_positions(path) == expected_order
