"""A target is a folder: a toy one written here (two modules, three properties, a golden script,
no world) runs, is judged and reported with nothing changed outside its folder."""
import duckdb
import pytest

from harness.cli import main as cli
from tests.support.toy_target import GOLDEN, INTERFACE, LAYER, PROPERTIES

pytestmark = pytest.mark.slow


def test_a_toy_target_folder_runs_end_to_end(tmp_path):
    toy = tmp_path / "toy"
    toy.mkdir()
    for name, text in (("interface.toml", INTERFACE), ("layer.toml", LAYER), ("properties.toml", PROPERTIES),
                       ("golden.mission", GOLDEN)):
        (toy / name).write_text(text)
    db = tmp_path / "toy.duckdb"
    assert cli(["campaign", "--mission", str(toy), "--mutants", "30", "--strategy", "targeted", "--seed", "3",
                "--max-delay", "0", "--jobs", "1", "--db", str(db)]) == 0
    assert cli(["report", "--db", str(db), "--out", str(tmp_path / "report")]) == 0
    con = duckdb.connect(str(db), read_only=True)
    outcomes = con.execute("select sut, count(*), count(*) filter (outcome = 'completed') from traces "
                           "group by sut order by sut").fetchall()
    assert [(sut, n == done) for sut, n, done in outcomes] == [("good", True), ("leaky", True)]
    golden = con.execute("""select t.sut, count(*) filter (verdict in ('FN', 'FP')) from verdicts v
                            join traces t using (trace_id) join scripts s using (script_id)
                            where s.kind = 'golden' group by t.sut order by t.sut""").fetchall()
    assert golden == [("good", 0), ("leaky", 0)]
    rates = dict(((s, f), r) for s, f, r in con.execute("select sut, family, tp_rate from tp_rates").fetchall())
    assert rates[("leaky", "DRY")] == 0.0 and rates[("good", "DRY")] == 1.0  # the protection leaky lacks
    assert "pump.Run" in (tmp_path / "report" / "index.html").read_text()
