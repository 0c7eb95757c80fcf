"""campaigns.config: one typed record per kind (harness/store/record.py), the only Python that
reads or writes it; and the bench's code identity stored with a campaign and compared on resume."""
import json
import re
from pathlib import Path
from typing import Literal

import pytest

from harness import DEFAULT_MISSION_DIR, store
from harness.cli import main
from harness.errors import StoreError
from harness.dispatch import cluster
from harness.store.database import insert_trace
from harness.store.record import (CampaignRecord, ImportRecord, Record, RunRecord, ShrinkRecord, record_of,
                                  records, stored_json)
from harness.sut.executive import run_script
from harness.target.mission import load_mission
from tests.support.paths import ROOT

HARNESS = ROOT / "harness"
# A campaign's record as main at 58d696f stored it (tests/stores/schema0-main-58d696f.duckdb.gz),
# before --strategy, --shard, --operators, --budget, --value-mutations, external SUTs, code identities.
SCHEMA0 = ('{"files": {"golden.mission": "9192"}, "jobs": 1, "kind": "campaign", "max_delay": 0.003, '
           '"mission": "/m/dala", "mutants": 3, "ops_per_mutant": 1, "seed": 2012, "sut": ["reference", "genom"], '
           '"time_mutations": false}')
# One record of each other kind, as this bench writes them.
WRITTEN = [
    '{"kind": "run", "max_delay": 0.003, "sut": "genom", "target": "/m/dala"}',
    '{"kind": "shrink", "max_delay": 0.003, "op": "shrink", "property": null, "runs": 12, "seed": 5, '
    '"steps_before": 9, "sut": "genom", "trace": 4, "verdict": "hung"}',
    '{"imported": "/data/run.csv", "interface": "/m/dala/interface.toml", "kind": "import", "sha256": "ab12"}',
]


def test_an_older_campaign_reads_with_its_defaults_and_is_written_back_as_it_was():
    record = record_of(SCHEMA0)
    assert isinstance(record, CampaignRecord)
    assert (record.strategy, record.external, record.shard, record.operators, record.budget_s,
            record.value_mutations, record.code_identity) == ("random", {}, None, None, None, False, None)
    assert stored_json(record) == SCHEMA0  # no default is written into a record that lacked it


def test_a_mission_file_the_target_lacks_is_recorded_as_none():
    text = SCHEMA0.replace('{"golden.mission": "9192"}', '{"golden.mission": "9192", "world.toml": null}')
    assert record_of(text).files == {"golden.mission": "9192", "world.toml": None}
    assert stored_json(record_of(text)) == text


@pytest.mark.parametrize("text", WRITTEN)
def test_every_kind_reads_as_its_own_model_and_writes_back_unchanged(text):
    record = record_of(text)
    assert type(record).__name__.lower().startswith(json.loads(text)["kind"])
    assert stored_json(record) == text


def test_the_target_folder_of_each_kind():
    run, shrink, imported = (record_of(t) for t in WRITTEN)
    assert run.target("golden.mission") == Path("/m/dala")
    assert RunRecord(sut="genom").target("/m/x/golden.mission") == Path("/m/x")  # a run stored before `target`
    assert imported.target("/data/run.csv") == Path("/m/dala")
    assert shrink.target(str(DEFAULT_MISSION_DIR)) == DEFAULT_MISSION_DIR
    assert record_of(SCHEMA0).target("/m/dala") == Path("/m/dala")


@pytest.mark.parametrize("config, named", [('{"runs": 3}', "it has no kind"),
                                           ('{"kind": "sweep"}', "kind 'sweep'"),
                                           ('{"kind": "run", "sut": 7}', "sut = 7")])
def test_a_config_no_bench_wrote_is_refused_naming_the_campaign_and_the_value(config, named):
    con = store.connect()
    con.execute("insert into campaigns values (4, now(), 'm', 0, ?)", [config])
    with pytest.raises(StoreError) as refused:
        records(con)
    assert "campaign 4's config" in str(refused.value) and named in str(refused.value)
    assert "one of campaign, run, shrink, import" in str(refused.value)


def test_records_of_one_kind_in_campaign_order():
    con = store.connect()
    for campaign_id, text in enumerate([WRITTEN[1], SCHEMA0, WRITTEN[0]], 1):
        store.add_campaign(con, campaign_id, "m", 0, record_of(text))
    assert [(i, type(r)) for i, _, r in records(con)] == [(1, ShrinkRecord), (2, CampaignRecord), (3, RunRecord)]
    assert [i for i, _, _ in records(con, CampaignRecord)] == [2]
    assert records(con, ImportRecord) == []


def test_no_python_but_the_record_reads_campaigns_config():
    """SQL in sql/ reads its keys; Python goes through harness/store/record.py."""
    reads = re.compile(r"config\s*->|\bconfig\b[^\n]*\bfrom\s+campaigns")
    found = [f"{path.relative_to(HARNESS)}:{n}" for path in HARNESS.rglob("*.py") if path.name != "record.py"
             for n, line in enumerate(path.read_text().splitlines(), 1) if reads.search(line)]
    assert found == []


CAMPAIGN = ["campaign", "--mutants", "1", "--sut", "genom", "--jobs", "1", "--seed", "3"]
ELSEWHERE = {"version": "0.0.9", "code": "feedfacefeedface"}


def test_a_resume_by_other_code_is_refused_then_allowed_when_told(tmp_path, monkeypatch, capsys):
    db = tmp_path / "c.duckdb"
    made_by = cluster.code_identity()
    assert main([*CAMPAIGN, "--db", str(db)]) == 0
    con = store.connect(db, read_only=True)
    ((_, _, stored),) = records(con)
    con.close()
    assert stored.code_identity == made_by
    capsys.readouterr()
    monkeypatch.setattr(cluster, "code_identity", lambda: ELSEWHERE)  # the bench's code changed since
    assert main([*CAMPAIGN, "--db", str(db)]) == 2
    err = capsys.readouterr().err
    assert f"code {made_by['code']}" in err and "code feedfacefeedface" in err and str(db) in err
    assert "--allow-code-change" in err and "another --db" in err
    assert main([*CAMPAIGN, "--db", str(db), "--allow-code-change"]) == 0
    out, err = capsys.readouterr()
    assert "resuming it anyway (--allow-code-change)" in err and "is complete" in out


def test_a_new_campaign_kind_is_one_class_and_the_store_analysis_and_report_take_it(tmp_path, monkeypatch, capsys):
    """A toy kind, `replay` (the golden mission played on one variant under several seeds), defined
    here as a user would in a module of their own: stored, read back, analysed and reported with
    no other change (its target folder found through `Record.target`)."""
    monkeypatch.setattr(Record, "KINDS", dict(Record.KINDS))  # the toy kind leaves with the test

    class ReplayRecord(Record):
        kind: Literal["replay"] = "replay"
        sut: str
        seeds: list[int]

        def target(self, mission: str) -> Path:
            return Path(mission)

    mission = load_mission(DEFAULT_MISSION_DIR)
    record = ReplayRecord(sut="genom", seeds=[1, 2])
    db = tmp_path / "replay.duckdb"
    con = store.connect(db)
    with store.transaction(con):
        store.add_campaign(con, 1, str(mission.folder), 0, record)
        for trace_id, seed in enumerate(record.seeds, 1):
            trace = run_script(mission.golden(), record.sut, seed, mission.interface, mission.world_file)
            insert_trace(con, trace_id, 1, None, trace)
    assert records(con) == [(1, str(mission.folder), record)]
    assert "one of campaign, run, shrink, import, replay" in refusal_of('{"kind": "sweep"}')
    con.close()
    assert main(["analyze", "--db", str(db)]) == 0
    assert main(["report", "--db", str(db), "--out", str(tmp_path / "report")]) == 0
    assert (tmp_path / "report" / "index.html").is_file()
    con = store.connect(db, read_only=True)
    assert con.execute("select count(*) from trace_scope where counted").fetchone() == (2,)
    con.close()


def test_a_kind_is_defined_once():
    with pytest.raises(TypeError, match="kind 'run' is RunRecord's already; give it a kind of its own"):
        class AnotherRun(Record):
            kind: Literal["run"] = "run"


def refusal_of(config: str) -> str:
    with pytest.raises(StoreError) as refused:
        record_of(config)
    return str(refused.value)
