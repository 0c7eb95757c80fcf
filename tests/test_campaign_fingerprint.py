"""The speed work must not change what a campaign computes: a campaign's store is compared, table by
table, with the fingerprint (harness/fingerprint.py) and Tables II-IV that main computed before the
speed work of issue 14 (tests/fingerprints/*.json, made by `expectation` below on main at 6e823b1;
main at 6cfb6e1 computes the same).

The 30-mutant campaign runs in every `make test`; the default campaign (300 mutants, 816 runs)
is checked by `make bench` (bench/campaign_bench.py), which runs it anyway.
"""
import json
from pathlib import Path

from harness import cli, store
from harness.fingerprint import fingerprint

FINGERPRINTS = Path(__file__).resolve().parent / "fingerprints"
TABLES = {
    "II": "select sut, total, hung, crashed, with_fn, with_fp, bad from trace_robustness order by sut",
    "III": "select sut, family, tp, fn from tp_rates order by sut, family",
    "IV": "select sut, family, fp, tn from fp_rates order by sut, family",
}


def expectation(db, arguments: list[str]) -> dict:
    """What a campaign store holds that the speed work must keep: its fingerprint, Tables II-IV."""
    con = store.connect(db, read_only=True)
    try:
        runs, events = con.execute("select (select count(*) from traces), (select count(*) from events)").fetchone()
        return {"arguments": arguments, "runs": runs, "events": events, "fingerprint": fingerprint(con),
                "tables": {name: [list(row) for row in con.execute(query).fetchall()]
                           for name, query in TABLES.items()}}
    finally:
        con.close()


def expected(name: str) -> dict:
    return json.loads((FINGERPRINTS / f"{name}.json").read_text())


def test_a_30_mutant_campaign_stores_what_main_stored_before_the_speed_work(tmp_path):
    stored = expected("campaign-30")
    db = tmp_path / "c.duckdb"
    assert cli.main(["campaign", *stored["arguments"], "--db", str(db)]) == 0
    assert expectation(db, stored["arguments"]) == stored


def test_dala_on_every_variant_stores_what_main_stored_before_the_layer_became_data(tmp_path):
    """Issue 12 moved the layer's knowledge into missions/dala/layer.toml: Dala's runs and verdicts,
    on all five variants, are those main computed at 0acfa4f (tests/fingerprints/dala-all-variants.json)."""
    stored = expected("dala-all-variants")
    db = tmp_path / "c.duckdb"
    assert cli.main(["campaign", *stored["arguments"], "--db", str(db)]) == 0
    assert expectation(db, stored["arguments"]) == stored


def test_the_default_campaign_expectation_is_main_s_default_campaign():
    stored = expected("campaign-default")
    assert stored["arguments"] == ["--mutants", "300", "--sut", "genom,bip-a,bip-b", "--seed", "2012"]
    assert stored["runs"] == 816 and sum(row[1] for row in stored["tables"]["II"]) == 816
