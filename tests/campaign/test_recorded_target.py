"""Issue 19, item 2: `run` records its target folder; analyze, explain and shrink read it from the
store, so a target outside the repository is never judged against Dala's properties."""
import duckdb

from harness import DEFAULT_MISSION_DIR
from harness.cli import main as cli
from tests.support.toy_target import GOLDEN, INTERFACE, LAYER, PROPERTIES
from tests.support.paths import ADAPTERS


def _toy(folder):
    folder.mkdir()
    for name, text in (("interface.toml", INTERFACE), ("layer.toml", LAYER), ("properties.toml", PROPERTIES),
                       ("golden.mission", GOLDEN)):
        (folder / name).write_text(text)
    return folder


def test_analyze_after_run_judges_the_runs_own_target(tmp_path, capsys):
    toy = _toy(tmp_path / "toy")
    scripts = tmp_path / "elsewhere"  # a script away from its interface: the target is the interface's folder
    scripts.mkdir()
    (scripts / "mine.mission").write_text(GOLDEN)
    db = tmp_path / "run.duckdb"
    assert cli(["run", str(scripts / "mine.mission"), "--interface", str(toy / "interface.toml"),
                "--world", str(toy / "world.toml"), "--sut", "leaky", "--db", str(db)]) == 0
    capsys.readouterr()
    assert cli(["analyze", "--db", str(db)]) == 0
    out = capsys.readouterr().out
    assert f"3 properties of {toy / 'properties.toml'}" in out
    con = duckdb.connect(str(db), read_only=True)
    judged = {r[0] for r in con.execute("select distinct property_id from verdicts").fetchall()}
    assert judged == {"READY(pump)", "HALT(pump.Run)", "DRY(pump.Run)"}
    con.close()
    assert cli(["explain", "1", "HALT(pump.Run)", "--db", str(db)]) == 0
    assert "HALT(pump.Run)" in capsys.readouterr().out


def test_a_store_without_any_target_asks_for_the_properties(tmp_path, capsys):
    toy = _toy(tmp_path / "toy")
    db = tmp_path / "run.duckdb"
    assert cli(["run", str(toy / "golden.mission"), "--sut", "good", "--db", str(db)]) == 0
    (toy / "properties.toml").unlink()
    capsys.readouterr()
    assert cli(["analyze", "--db", str(db)]) == 2
    err = capsys.readouterr().err
    assert err == (f"error: the store records no target folder with a properties file ({toy / 'properties.toml'}); "
                   "pass --properties FILE\n")


def test_least_covered_counts_what_the_tables_count_and_knows_a_targeted_campaign(tmp_path, capsys):
    """Issue 19, item 6: an ad-hoc run of another variant beside a campaign was listed as least
    covered, and a targeted campaign was told to use --strategy targeted."""
    toy = _toy(tmp_path / "toy")
    db = tmp_path / "toy.duckdb"
    assert cli(["campaign", "--mission", str(toy), "--sut", "good", "--mutants", "3", "--strategy", "targeted",
                "--max-delay", "0", "--jobs", "1", "--db", str(db)]) == 0
    assert cli(["run", str(toy / "golden.mission"), "--sut", "leaky", "--db", str(db)]) == 0
    capsys.readouterr()
    assert cli(["analyze", "--db", str(db)]) == 0
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("Least covered"))
    assert "(good)" in line and "(leaky)" not in line
    assert line.endswith("More cases: more --mutants, or another --seed, of the targeted campaign")


def test_an_external_sut_that_crashes_on_every_run_of_the_default_target_is_told_of_mission(tmp_path, capsys):
    """Issue 19, item 2: forgetting --mission with an external SUT used Dala silently."""
    adapter = ADAPTERS / "other_target.py"
    db = tmp_path / "q.duckdb"
    assert cli(["campaign", "--sut", f"quad=cmd:{{python}} {adapter}", "--mutants", "1", "--time-scale", "50",
                "--jobs", "2", "--db", str(db)]) == 0
    err = capsys.readouterr().err
    assert f"every run of quad crashed on the default target {DEFAULT_MISSION_DIR} (first: " in err
    assert "no module rflex on this quadcopter" in err
    assert "if quad is made for another target, pass --mission FOLDER" in err
