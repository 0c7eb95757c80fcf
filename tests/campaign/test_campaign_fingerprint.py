"""The speed work must not change what a campaign computes: a campaign's store is compared, table by
table, with the fingerprint (harness/fingerprint.py) and Tables II-IV that main computed before the
speed work of issue 14 (tests/fingerprints/*.json, made by `expectation` below on main at 6e823b1;
main at 6cfb6e1 computes the same).

The 30-mutant campaign runs in every `make test`; the default campaign (300 mutants, 816 runs)
is checked by `make bench` (bench/campaign_bench.py), which runs it anyway; `make test` recomputes
the part of its expectation that needs no runs (its arguments, scripts and run count).

The value-domain family VAL (issue 25) added verdict rows to every campaign: each expectation keeps,
under `before_val`, what main stored before it (the verdicts' fingerprint and Tables III-IV), and
the tests check that leaving the VAL rows out gives exactly that back: its properties changed
nothing else, and the value operators, not selected, changed no script, trace or event.

Complete alternatives (issue 35) changed the `verdicts` fingerprints, and only them: the columns
`suspicious`, `certain` and `alternatives` of verdicts whose order or taking cannot be observed
(e.g. an omega in a hung trace). Every other table, Tables II-IV, and every verdict's trace, request,
property, C, verdict and margin stayed the same on all three campaigns (compared row by row before
the new digests were written in).
"""
import json

import pytest

from harness import DEFAULT_MISSION_DIR, cli, store
from harness.campaign.config import campaign_config
from harness.files import read_text
from harness.mutator import strategies
from harness.dispatch.description import script_label
from harness.target.mission import load_mission
from harness.fingerprint import fingerprint, table_digest

from tests.support.paths import FINGERPRINTS
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


def before_the_val_family(con) -> dict:
    """The verdicts' fingerprint and Tables III-IV without the VAL family: its rows left out, and
    its counts taken out of the All rows."""
    before = {"verdicts": table_digest(con, "verdicts", "family <> 'VAL'")}
    for name in ("III", "IV"):
        rows = [list(row) for row in con.execute(TABLES[name]).fetchall()]
        val = {row[0]: row[2:] for row in rows if row[1] == "VAL"}
        before[name] = [row[:2] + [n - v for n, v in zip(row[2:], val.get(row[0], [0, 0]))] if row[1] == "All" else row
                        for row in rows if row[1] != "VAL"]
    return before


def check(db, stored: dict) -> None:
    assert expectation(db, stored["arguments"]) == {k: v for k, v in stored.items() if k != "before_val"}
    con = store.connect(db, read_only=True)
    try:
        assert before_the_val_family(con) == stored["before_val"]
    finally:
        con.close()


def expected(name: str) -> dict:
    return json.loads((FINGERPRINTS / f"{name}.json").read_text())


@pytest.mark.slow
def test_a_30_mutant_campaign_stores_what_main_stored_before_the_speed_work(tmp_path):
    stored = expected("campaign-30")
    db = tmp_path / "c.duckdb"
    assert cli.main(["campaign", *stored["arguments"], "--db", str(db)]) == 0
    check(db, stored)


@pytest.mark.slow
def test_dala_on_every_variant_stores_what_main_stored_before_the_layer_became_data(tmp_path):
    """Issue 12 moved the layer's knowledge into missions/dala/layer.toml: Dala's runs and verdicts,
    on all five variants, are those main computed at 0acfa4f (tests/fingerprints/dala-all-variants.json)."""
    stored = expected("dala-all-variants")
    db = tmp_path / "c.duckdb"
    assert cli.main(["campaign", *stored["arguments"], "--db", str(db)]) == 0
    check(db, stored)


def test_the_default_campaign_expectation_is_main_s_default_campaign():
    """The expectation `make bench` checks, recomputed where it needs no runs: its arguments are the
    campaign's defaults, and its scripts (fingerprint) and run count are those this bench generates."""
    stored = expected("campaign-default")
    parser_defaults = cli._parser().parse_args(["campaign"])
    mission = load_mission(DEFAULT_MISSION_DIR)
    assert stored["arguments"] == ["--mutants", str(parser_defaults.mutants), "--sut",
                                   mission.default_suts(), "--seed", str(parser_defaults.seed)]
    args = cli._parser().parse_args(["campaign", *stored["arguments"]])
    golden = mission.golden()
    config = campaign_config(args, mission, golden)
    mutants = strategies.generate(config, golden, mission.interface, mission.properties(), run_golden=None,
                                  name=lambda n: script_label(1 + n))
    con = store.connect()
    store.add_scripts(con, [store.ScriptRow(1, 1, "golden", read_text(mission.golden_file))] + [
        store.ScriptRow(1 + n, 1, "mutant", m.body, 1, m.operations, m.valid, m.invalid_reason)
        for n, m in enumerate(mutants, 1)])
    assert fingerprint(con, ["scripts"]) == {"scripts": stored["fingerprint"]["scripts"]}
    assert stored["runs"] == len(config.sut) * (1 + sum(m.valid for m in mutants)) == \
        sum(row[1] for row in stored["tables"]["II"])
