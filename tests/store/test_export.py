"""`export`: every table and view as Parquet or CSV with a manifest; the events import back."""
from __future__ import annotations

import csv
import json
from datetime import datetime, timedelta, timezone

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from harness import DEFAULT_MISSION_DIR, cli, store
from harness.analysis.analyzer import materialise
from harness.store.reads import ordered
from harness.errors import StoreError
from harness.store.export import export, relations
from harness.store.importer import import_file
from harness.target.interface import load_interface, load_properties

TABLES_II_TO_IV = ("trace_robustness", "tp_rates", "fp_rates")


def view_rows(db, name: str) -> list[dict]:
    con = store.connect(db, read_only=True)
    try:
        return con.sql(ordered(con, name)).to_arrow_table().to_pylist()
    finally:
        con.close()


def test_parquet_export_reads_back_in_pyarrow_equal_to_tables_2_to_4(campaign_store, tmp_path):
    out = tmp_path / "out"
    assert cli.main(["export", "--format", "parquet", "--db", str(campaign_store), str(out)]) == 0
    for view in TABLES_II_TO_IV:
        assert pq.read_table(out / f"{view}.parquet").to_pylist() == view_rows(campaign_store, view)
    assert pq.read_schema(out / "events.parquet").field("args").type == pa.string(), "JSON as text, not bytes"
    bip_a = [r for r in view_rows(campaign_store, "trace_robustness") if r["sut"] == "bip-a"][0]
    assert bip_a["hung"] == 1 and bip_a["with_fn"] >= 1, "the store shows what the tables are for"


def test_the_manifest_lists_every_table_and_view_with_its_rows(campaign_store, tmp_path, capsys):
    out = tmp_path / "out"
    assert cli.main(["export", "--format", "csv", "--db", str(campaign_store), str(out)]) == 0
    manifest = json.loads((out / "manifest.json").read_text())
    con = store.connect(campaign_store, read_only=True)
    everything = relations(con)
    counts = {name: con.execute(f"select count(*) from {name}").fetchone()[0] for name, _ in everything}
    con.close()
    assert [(e["name"], e["kind"]) for e in manifest["tables"]] == everything
    kinds = {e["name"]: e["kind"] for e in manifest["tables"]}
    assert {kinds[n] for n in ("events", "verdicts", "schema_version")} == {"table"}
    assert {kinds[n] for n in ("trace_robustness", "tp_rates", "fp_rates")} == {"view"}
    for entry in manifest["tables"]:
        with open(out / entry["file"], newline="") as f:  # csv.reader: a script body spans lines
            assert sum(1 for _ in csv.reader(f)) - 1 == entry["rows"] == counts[entry["name"]], entry
    files = [e["file"] for e in manifest["tables"]]
    assert sorted(p.name for p in out.iterdir()) == sorted(files + ["manifest.json"])
    assert manifest["store"] == str(campaign_store.resolve())
    assert manifest["schema_version"] == store.SCHEMA_VERSION and manifest["format"] == "csv"
    exported_at = datetime.fromisoformat(manifest["exported_at"])
    assert timedelta(0) <= datetime.now(timezone.utc) - exported_at < timedelta(minutes=10)
    rows = sum(counts.values())
    assert capsys.readouterr().out == (f"Exported {len(everything)} tables and views ({rows} rows) of "
                                       f"{campaign_store} to {out} as csv; {out / 'manifest.json'} lists them.\n")


@pytest.mark.parametrize("fmt", ["parquet", "csv"])
def test_exported_events_import_back_and_judge_the_same(campaign_store, tmp_path, fmt, interface, properties):
    out = tmp_path / "out"
    con = store.connect(campaign_store, read_only=True)
    export(con, campaign_store, out, fmt)
    original = {name: con.sql(ordered(con, name)).to_arrow_table().to_pylist()
                for name in ("events", "traces") + TABLES_II_TO_IV}
    con.close()
    again = store.connect(tmp_path / "again.duckdb")
    import_file(again, out / f"events.{fmt}", interface)
    materialise(again, properties, 0.01, interface)
    events = again.sql("select t.label::integer as trace_id, e.* exclude (trace_id) from events e "
                       "join traces t using (trace_id) order by t.label::integer, e.seq").to_arrow_table()
    assert events.to_pylist() == original["events"]
    traces = again.sql("select label::integer as trace_id, sut, outcome from traces order by trace_id").fetchall()
    assert traces == sorted((t["trace_id"], t["sut"], t["outcome"]) for t in original["traces"])
    for view in TABLES_II_TO_IV:
        assert again.sql(ordered(again, view)).to_arrow_table().to_pylist() == original[view], view


def test_exporting_again_replaces_the_previous_export_and_nothing_else(campaign_store, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "old_view.parquet").write_text("from an earlier export")
    (out / "manifest.json").write_text(json.dumps({"tables": [{"name": "old_view", "file": "old_view.parquet"}]}))
    con = store.connect(campaign_store, read_only=True)
    manifest = export(con, campaign_store, out, "parquet")
    assert not (out / "old_view.parquet").exists()
    assert len(list(out.iterdir())) == len(manifest["tables"]) + 1
    (out / "notes.txt").write_text("mine")
    with pytest.raises(StoreError, match=r"cannot export to '.*out': it holds 'notes.txt', which no earlier "
                                         r"export wrote; export to a new or empty folder"):
        export(con, campaign_store, out, "parquet")
    assert (out / "notes.txt").read_text() == "mine" and (out / "events.parquet").exists()
    (out / "manifest.json").write_text("not json")
    with pytest.raises(StoreError, match=r"'.*manifest.json' is not the manifest of an export; export to a new"):
        export(con, campaign_store, out, "parquet")
    con.close()


def test_export_of_a_missing_store_says_what_to_do(tmp_path, capsys):
    assert cli.main(["export", "--db", str(tmp_path / "none.duckdb"), str(tmp_path / "out")]) == 2
    assert "error: no store at" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_a_folder_whose_name_holds_a_quote_is_exported_to(campaign_store, tmp_path):
    # copy takes no parameters: the path goes into the statement through the store's one quoter
    out = tmp_path / "robot's export"
    assert cli.main(["export", "--format", "csv", "--db", str(campaign_store), str(out)]) == 0
    assert (out / "events.csv").read_text().startswith("trace_id")
