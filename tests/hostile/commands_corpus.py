"""Hostile inputs over the commands added since issue 19 (issue 36): export's manifest, --budget,
--shard, merge, --junit, --fail-on, --operators and mission arguments. Cases in the manner of
corpus.py (test_corpus.py runs them): a refusal naming the file or flag and the value, or the right
outcome, checked on what the command left behind."""
from __future__ import annotations

import json
from typing import Callable

import duckdb
import pyarrow as pa
import pyarrow.parquet as pq

from corpus import Case, Place, _keep, analyze, campaign, run_hostile, script

VICTIM = "a file the bench never wrote\n"


def _tampered(file: Callable[[Place], str], link: bool = False) -> Callable[[Place], None]:
    """A store, a victim file beside it and an export folder whose manifest names `file(p)`
    (with `link`: a link named events.parquet, listed, that points at the victim)."""
    def prepare(p: Place) -> None:
        _keep(p)
        (p.root / "victim.txt").write_text(VICTIM)
        out = p.root / "out"
        out.mkdir()
        if link:
            (out / "events.parquet").symlink_to(p.root / "victim.txt")
        (out / "manifest.json").write_text(json.dumps({"tables": [{"name": "events", "file": file(p)}]}))
        p.before = sorted(x.name for x in out.iterdir())
    return prepare


def _nothing_removed(p: Place) -> None:
    assert (p.root / "victim.txt").read_text() == VICTIM
    assert p.db.read_bytes() == p.kept, "the store changed"
    assert sorted(x.name for x in (p.root / "out").iterdir()) == p.before


def _export(p: Place) -> list[str]:
    return ["export", str(p.root / "out"), "--db", str(p.db)]


EXPORTS = [
    *(Case(f"export: a manifest naming {shown}", _export, f"{named}, which is no file an export writes (NAME.parquet "
           "or NAME.csv in the folder itself, no link); nothing was removed", prepare=_tampered(file), check=_nothing_removed)
      for shown, named, file in (
          ("../victim.txt", "names '../victim.txt'", lambda p: "../victim.txt"),
          ("../store.duckdb", "names '../store.duckdb'", lambda p: "../store.duckdb"),
          (".", "names '.'", lambda p: "."),
          ("the victim's absolute path", "/victim.txt'", lambda p: str(p.root / "victim.txt")))),
    Case("export: a listed file that is a link to a file outside", _export, "manifest.json names 'events.parquet', "
         "which is no file an export writes", prepare=_tampered(lambda p: "events.parquet", link=True),
         check=_nothing_removed),
]


def _stored(p: Place) -> None:
    p.run_store()


def _golden(text: str) -> Callable[[Place], object]:
    return lambda p: (p.target / "golden.mission").write_text(text)


def _budget(p: Place, budget: str, *more: str) -> list[str]:
    return campaign(p, "--strategy", "focused", "--budget", budget, *more)


FLAGS = [
    Case("--fail-on ','", lambda p: analyze(p) + ["--fail-on", ","], "--fail-on ',' names no kind of bad behaviour; "
         "give a comma-separated list among fn, fp, hung, crashed", prepare=_stored),
    Case("--junit an existing folder", lambda p: analyze(p) + ["--junit", str(p.target)], "dala' is a folder; give "
         "the path of the XML file to write", prepare=_stored),
    Case("--junit an unwritable place", lambda p: analyze(p) + ["--junit", "/proc/untimely.xml"],
         "--junit '/proc/untimely.xml': cannot write it", prepare=_stored),
    Case("--budget 10^400 s", lambda p: _budget(p, "1" + "0" * 400 + "s"), "give mission time as a positive number "
         "followed by s, m or h (4000s, 40m, 1h)"),
    Case("--budget smaller than the golden runs", lambda p: _budget(p, "1s"), "--budget 1s: the golden script's runs "
         "alone, on 3 variant(s), take at least 21 mission s (its sleeps); give a budget of more than 21s"),
    Case("--shard on a focused campaign", lambda p: _budget(p, "4000s", "--shard", "1/2"), "--shard 1/2 applies to "
         "random and targeted campaigns"),
    Case("--operators replace_value on a golden without arguments", lambda p: campaign(p, "--operators",
         "replace_value"), "--operators replace_value: none of them finds a step to change in the golden script",
         prepare=_golden("send rflex.Init as r\nwait r\n")),
    Case("script: an argument of 1e400", run_hostile, "hostile.mission:1: argument x='1e400' overflows a 64-bit "
         "float", prepare=script("send ndd.GotoPosition x=1e400 y=1\n")),
]


def _shards(edit: Callable[[duckdb.DuckDBPyConnection], object]) -> Callable[[Place], None]:
    """Two shards of one small campaign, each edited by `edit` before the merge."""
    def prepare(p: Place) -> None:
        for i in (1, 2):
            shard = p.root / f"s{i}.duckdb"
            assert p.cli(campaign(p, "--sut", "genom,bip-a", "--shard", f"{i}/2")[:-1] + [str(shard)]) == 0
            con = duckdb.connect(str(shard))
            edit(con)
            con.close()
    return prepare


def _merge(p: Place) -> list[str]:
    return ["merge", str(p.db), str(p.root / "s1.duckdb"), str(p.root / "s2.duckdb")]


def _lose_trace_1(con) -> None:
    for table in ("events", "internal_events", "world_events", "taken_events", "trace_runs", "traces"):
        con.execute(f"delete from {table} where trace_id = 1")


def _no_merged_store(p: Place) -> None:
    assert not p.db.exists(), "merge left a store behind"


def _merged_all(p: Place) -> None:
    con = duckdb.connect(str(p.db), read_only=True)
    try:
        assert con.execute("select count(*) from traces").fetchone()[0] == 4  # (golden + 1 mutant) x 2 variants
    finally:
        con.close()


MERGES = [
    Case("merge: a shard missing a trace", _merge, "s1.duckdb lacks 1 of the 2 traces of shard 1/2 (trace ids 1): "
         "its campaign did not finish; rerun its campaign command", prepare=_shards(_lose_trace_1),
         check=_no_merged_store),
    Case("merge: shards written before taken_events existed", _merge, "merged 2 shards into", code=0,
         prepare=_shards(lambda con: con.execute("drop table taken_events cascade")), check=_merged_all),
]

def _traces_twice(p: Place) -> None:
    """An export whose traces.parquet lists its one trace twice."""
    _keep(p)
    assert p.cli(["export", str(p.root / "out"), "--db", str(p.db)]) == 0
    traces = pq.read_table(p.root / "out" / "traces.parquet")
    pq.write_table(pa.concat_tables([traces, traces]), p.root / "out" / "traces.parquet")


UNCLEAR = [
    Case("import: an export's traces.parquet listing a trace twice", lambda p: [
        "import", str(p.root / "out" / "events.parquet"), "--interface", str(p.target / "interface.toml"),
        "--db", str(p.root / "again.duckdb")], "traces.parquet' lists the trace '1' twice; an export lists each "
         "trace once", prepare=_traces_twice),
]

CASES = EXPORTS + FLAGS + MERGES + UNCLEAR

