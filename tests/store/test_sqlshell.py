"""Ad-hoc SQL on the store: an aligned table, read-only, and a clear error on a bad query."""
import pytest

from harness.cli import main
from harness.errors import StoreError
from harness.store.sqlshell import READ_ONLY, run
from harness.store.database import connect
from tests.support.traces import HERE, judged_store, load


@pytest.fixture()
def db(tmp_path):
    path = tmp_path / "store.duckdb"
    judged_store(load(HERE / "tables.trace"), 0.01, path).close()
    return path


def test_a_query_prints_as_an_aligned_table(db):
    out = run(connect(db, read_only=True),
              "select sut, total, t_rob, null as nothing from trace_robustness order by sut")
    assert out.splitlines() == ["sut  total  t_rob  nothing",
                                "---  -----  -----  -------",
                                "A        4   0.25  NULL",
                                "B        2    0.5  NULL",
                                "(2 rows)"]


def test_a_bad_query_names_the_problem_and_the_tables(db):
    with pytest.raises(StoreError, match=r"(?s)query failed: .*verdictz.*the store has: .*trace_robustness"):
        run(connect(db, read_only=True), "select * from verdictz")


def test_the_command_is_read_only(db, capsys):
    assert main(["sql", "--db", str(db), "delete from verdicts"]) == 2
    assert "read-only" in capsys.readouterr().err
    assert main(["sql", "--db", str(db), "select count(*) as n from verdicts"]) == 0
    assert capsys.readouterr().out.splitlines()[2].strip() == "8"


def test_the_command_writes_no_file_and_attaches_nothing(db, tmp_path, capsys):
    """Issue 19: `copy ... to` the store itself once overwrote it with a CSV file."""
    before = db.read_bytes()
    queries = [f"copy verdicts to '{db}'", f"copy verdicts to '{tmp_path / 'out.csv'}'",
               f"attach '{tmp_path / 'other.duckdb'}' as other", f"export database '{tmp_path / 'dump'}'",
               "select * from read_csv('/etc/hostname')", "set enable_external_access = true",
               "reset lock_configuration"]
    for query in queries:
        assert main(["sql", "--db", str(db), query]) == 2, query
        err = capsys.readouterr().err
        assert err.startswith("error: query failed: ") and "Traceback" not in err, err
        assert READ_ONLY in err, err
    assert db.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == [db.name]
    assert main(["sql", "--db", str(db), "select count(*) as n from verdicts"]) == 0


def test_a_missing_store_is_refused(tmp_path, capsys):
    assert main(["sql", "--db", str(tmp_path / "none.duckdb"), "select 1"]) == 2
    assert "no store at" in capsys.readouterr().err
