"""Each analysis records what made it; stale files are detected; analyze's defaults."""
import hashlib
import shutil
from pathlib import Path

import pytest

from harness import DEFAULT_MISSION_DIR, SQL_DIR
from harness.analysis.analyzer import materialise
from harness.cli import main
from harness.analysis.provenance import stale_files
from harness.store.database import connect
from tests.support.traces import HERE, INTERFACE, load, judged_store

EPSILON = 0.01
FIXTURE = load(HERE / "tables.trace")


def _mission(tmp_path):
    folder = tmp_path / "mission"
    folder.mkdir()
    for name in ("properties.toml", "interface.toml"):
        shutil.copy(DEFAULT_MISSION_DIR / name, folder / name)
    return folder


def _sha(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_an_analysis_records_epsilon_time_and_the_hash_of_every_file_it_was_made_from(tmp_path):
    mission = _mission(tmp_path)
    con = judged_store(FIXTURE, EPSILON)
    seconds = materialise(con, FIXTURE.properties, 0.02, INTERFACE, mission / "properties.toml")
    assert con.execute("select analysis_id, epsilon, properties, traces from analyses order by 1").fetchall() == [
        (1, EPSILON, 2, 6), (2, 0.02, 2, 6)]
    assert con.execute("select seconds from analysis").fetchone()[0] == seconds > 0
    files = {(role, path): sha for role, path, sha in con.execute(
        "select role, path, sha256 from analysis_files where analysis_id = 2").fetchall()}
    templates = sorted([*SQL_DIR.glob("oracles/*.sql"), *SQL_DIR.glob("views/*.sql")])
    assert files == {("properties", str(mission / "properties.toml")): _sha(mission / "properties.toml"),
                     ("interface", str(mission / "interface.toml")): _sha(mission / "interface.toml"),
                     **{("template", str(t)): _sha(t) for t in templates}}
    assert {t.name for t in templates} >= {"pc.sql", "ee.sql", "_base.sql", "verdicts.sql", "trace_badness.sql"}
    assert not any(Path(path).is_relative_to(SQL_DIR / "report") for _, path in files), \
        "the report's queries change no verdict"


def test_stale_files_are_those_changed_since_the_last_analysis(tmp_path):
    mission = _mission(tmp_path)
    con = judged_store(FIXTURE, EPSILON)
    materialise(con, FIXTURE.properties, EPSILON, INTERFACE, mission / "properties.toml")
    assert stale_files(con) == []
    original = (mission / "properties.toml").read_text()
    (mission / "properties.toml").write_text(original + "\n# refined\n")
    (mission / "interface.toml").unlink()
    assert stale_files(con) == [("properties", str(mission / "properties.toml")),
                                ("interface", str(mission / "interface.toml"))]
    (mission / "properties.toml").write_text(original)
    shutil.copy(DEFAULT_MISSION_DIR / "interface.toml", mission / "interface.toml")
    assert stale_files(con) == []


@pytest.mark.slow
def test_analyze_judges_with_the_campaigns_mission_and_keeps_the_last_epsilon(tmp_path, capsys):
    mission = _mission(tmp_path)
    db = tmp_path / "store.duckdb"
    judged_store(FIXTURE, EPSILON, db).close()
    con = connect(db)
    con.execute("update campaigns set mission = ?", [str(mission)])
    con.close()
    assert main(["analyze", "--db", str(db), "--epsilon", "0.05"]) == 0
    assert f"25 properties of {mission / 'properties.toml'}" in capsys.readouterr().out
    assert main(["analyze", "--db", str(db)]) == 0
    assert "epsilon 0.05 s" in capsys.readouterr().out
    con = connect(db, read_only=True)
    assert con.execute("select epsilon from analyses order by analysis_id").fetchall() == [
        (EPSILON,), (0.05,), (0.05,)]
    assert con.execute("select distinct path from analysis_files where role = 'properties'").fetchall() == [
        (str(mission / "properties.toml"),)]
